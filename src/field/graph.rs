//! The curve graph of a proposed layout: nodes on mesh vertices and the segments between
//! them, each a path of mesh edges (a piece of a trace or of a feature line).
//!
//! Segments share no vertex except their end nodes, so their curves meet only at nodes. The
//! boundary is not stored: its vertices are taken, and the nodes on it are kept here.

use crate::geom::{dot, sub, unit};
use crate::mesh::adjacency::Adjacency;
use crate::mesh::geometry::{edge_lengths, triangle_areas};
use crate::mesh::{Mesh, NONE};
use std::sync::Arc;

/// Two segments meeting at a node turn there (a bend) when they turn by more than this.
const BEND: f64 = std::f64::consts::FRAC_PI_4;
/// Vertices back along a segment from which its direction at a node is taken.
const BEND_REACH: usize = 3;

/// A path of mesh vertices from node to node.
#[derive(Debug, Clone)]
pub struct Segment {
    pub path: Vec<u32>,
    /// Along a sharp feature line: tagged for alignment, never removed.
    pub feature: bool,
}

/// Nodes and segments; see the module documentation.
#[derive(Debug, Clone)]
pub struct CurveGraph {
    pub node: Vec<bool>,
    /// Nodes kept even where only two segments meet (feature and boundary corners): they
    /// are corners of the layout.
    pub pinned: Vec<bool>,
    /// Removed segments have an empty path.
    pub segments: Vec<Segment>,
    /// Per vertex: the segment it lies inside of (not at its ends), or [`NONE`].
    inside: Vec<u32>,
    boundary: Vec<bool>,
    /// The mesh's triangle areas and edge lengths, which [`super::faces::analyze`] sums every
    /// repair round: computed once, shared by the graph's clones.
    pub measures: Arc<MeshMeasures>,
    /// The curves started from Voronoi cells ([`super::cells`]), whose many small faces two
    /// repairs treat otherwise than the traces' (over 26 meshes each made as many of the
    /// traces' layouts worse as better: eight 2.9 → 4.8 %, CGAL's camel and armadillo refused
    /// at 4000 quads): a face without a vertex inside merges with a neighbour across a side
    /// that leaves the two a disk ([`super::faces::Faces::merges_cleanly`]) before a shorter
    /// one, which joined cells into rings too thin to cut again (CGAL's femur); and a face
    /// that the written curves leave without a vertex inside has them follow their paths, then
    /// loses one, instead of ending the attempt. (A ring whose boundary is one piece is cut
    /// where it meets itself for every graph now: `propose::cut_rings`.)
    pub from_cells: bool,
}

/// Per triangle its area, per edge its length, and who neighbours whom ([`Adjacency`]).
#[derive(Debug)]
pub struct MeshMeasures {
    pub areas: Vec<f64>,
    pub lengths: Vec<f64>,
    pub adjacency: Adjacency,
}

impl CurveGraph {
    /// An empty graph on `mesh`.
    pub fn new(mesh: &Mesh) -> CurveGraph {
        let nv = mesh.n_vertices();
        let boundary = (0..nv as u32).map(|v| mesh.is_boundary_vertex(v)).collect();
        let measures = Arc::new(MeshMeasures { areas: triangle_areas(mesh), lengths: edge_lengths(mesh), adjacency: Adjacency::new(mesh) });
        CurveGraph { node: vec![false; nv], pinned: vec![false; nv], segments: Vec::new(), inside: vec![NONE; nv], boundary, measures, from_cells: false }
    }

    /// Whether `v` is taken: a node, inside a segment, or on the boundary.
    pub fn taken(&self, v: u32) -> bool {
        self.node[v as usize] || self.inside[v as usize] != NONE || self.boundary[v as usize]
    }

    /// Whether `v` lies inside a segment.
    pub fn inside(&self, v: u32) -> Option<u32> {
        let s = self.inside[v as usize];
        (s != NONE).then_some(s)
    }

    pub fn is_boundary(&self, v: u32) -> bool {
        self.boundary[v as usize]
    }

    /// Makes `v` a node, splitting the segment it lies inside of.
    pub fn add_node(&mut self, v: u32, pinned: bool) {
        self.pinned[v as usize] |= pinned;
        if self.node[v as usize] {
            return;
        }
        self.node[v as usize] = true;
        let s = self.inside[v as usize];
        if s == NONE {
            return;
        }
        self.inside[v as usize] = NONE;
        let seg = &mut self.segments[s as usize];
        let k = seg.path.iter().position(|&x| x == v).unwrap_or(0);
        let tail: Vec<u32> = seg.path[k..].to_vec();
        seg.path.truncate(k + 1);
        let feature = seg.feature;
        self.push(Segment { path: tail, feature });
    }

    fn push(&mut self, seg: Segment) {
        let id = self.segments.len() as u32;
        for &v in &seg.path[1..seg.path.len() - 1] {
            self.inside[v as usize] = id;
        }
        self.segments.push(seg);
    }

    /// Adds a path whose vertices are free except its two ends (which become nodes) and any
    /// interior vertex that is already a node. A closed path gets a node halfway.
    pub fn add_path(&mut self, path: &[u32], feature: bool) {
        if path.len() < 2 {
            return;
        }
        let (first, last) = (path[0], path[path.len() - 1]);
        self.add_node(first, false);
        self.add_node(last, false);
        let mut start = 0;
        for k in 1..path.len() {
            if self.node[path[k] as usize] {
                let piece = &path[start..=k];
                // A single edge between two nodes may already be a segment (two traces
                // leaving adjacent nodes towards each other): one curve is enough.
                if !(piece.len() == 2 && self.joins(piece[0], piece[1])) {
                    self.push(Segment { path: piece.to_vec(), feature });
                }
                start = k;
            }
        }
        self.split_loops();
    }

    /// Whether a live segment is the single mesh edge from `a` to `b` (either way).
    fn joins(&self, a: u32, b: u32) -> bool {
        self.live().any(|s| {
            let p = &self.segments[s as usize].path;
            p.len() == 2 && ((p[0] == a && p[1] == b) || (p[0] == b && p[1] == a))
        })
    }

    /// Gives every segment that starts and ends at one node a node halfway.
    fn split_loops(&mut self) {
        for s in 0..self.segments.len() {
            let p = &self.segments[s].path;
            if p.len() >= 3 && p[0] == p[p.len() - 1] {
                let mid = p[p.len() / 2];
                self.add_node(mid, false);
            }
        }
    }

    /// Removes segment `s` (its vertices become free; its end nodes stay).
    pub fn remove(&mut self, s: u32) {
        let path = std::mem::take(&mut self.segments[s as usize].path);
        if path.len() > 2 {
            for &v in &path[1..path.len() - 1] {
                self.inside[v as usize] = NONE;
            }
        }
    }

    /// The live segments' ids.
    pub fn live(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.segments.len() as u32).filter(|&s| !self.segments[s as usize].path.is_empty())
    }

    /// Segment ends at each vertex.
    pub fn degrees(&self) -> Vec<u32> {
        let mut d = vec![0u32; self.node.len()];
        for s in self.live() {
            let p = &self.segments[s as usize].path;
            d[p[0] as usize] += 1;
            d[p[p.len() - 1] as usize] += 1;
        }
        d
    }

    /// Removes dangling traces (an end node reached by nothing else), joins the two
    /// segments at an unpinned node where only they meet, and drops nodes nothing reaches.
    /// Boundary nodes count the two boundary pieces at them. Dangling feature segments stay
    /// (see [`CurveGraph::dangling_feature_ends`]). `bends_kept_on`: the mesh on which the
    /// two segments of a bend ([`CurveGraph::bends`]) are not joined, to be continued.
    pub fn prune(&mut self, bends_kept_on: Option<&Mesh>) {
        loop {
            let d = self.degrees();
            let mut changed = false;
            for s in self.live().collect::<Vec<_>>() {
                let p = &self.segments[s as usize].path;
                let dangling = [p[0], p[p.len() - 1]].iter().any(|&v| self.dangles(&d, v));
                if dangling && !self.segments[s as usize].feature {
                    self.remove(s);
                    changed = true;
                }
            }
            if changed {
                continue;
            }
            for (v, &dv) in d.iter().enumerate() {
                if !self.node[v] {
                    continue;
                }
                if dv == 0 && !(self.boundary[v] && self.pinned[v]) {
                    self.node[v] = false;
                    self.pinned[v] = false;
                    changed = true;
                } else if self.passes_through(&d, v as u32) && bends_kept_on.is_none_or(|mesh| self.turn(mesh, v as u32).is_none()) {
                    changed |= self.join_at(v as u32);
                }
            }
            if !changed {
                return;
            }
        }
    }

    /// Whether a segment ending at `v` ends there alone (`d`: [`CurveGraph::degrees`]); the
    /// boundary's pieces reach its vertices.
    fn dangles(&self, d: &[u32], v: u32) -> bool {
        d[v as usize] == 1 && !self.boundary[v as usize]
    }

    /// The ends of feature segments that nothing else reaches, with the direction the
    /// feature arrives in (from the segment's second-to-last vertex): where a trace must
    /// continue the line, or the line will be a slit.
    pub fn dangling_feature_ends(&self, mesh: &Mesh) -> Vec<(u32, [f64; 3])> {
        let d = self.degrees();
        let mut ends = Vec::new();
        for s in self.live() {
            let seg = &self.segments[s as usize];
            if !seg.feature {
                continue;
            }
            let p = &seg.path;
            for (end, inner) in [(p[0], p[1]), (p[p.len() - 1], p[p.len() - 2])] {
                if self.dangles(&d, end) {
                    ends.push((end, sub(mesh.position(end), mesh.position(inner))));
                }
            }
        }
        ends
    }

    /// The unpinned nodes inside the surface where two trace segments meet and turn (a trace
    /// cut by a repair where another ended on it: 90° on one side, 270° on the other), each
    /// with the directions that continue its two segments straight on. Joined, the curve would
    /// turn inside a face's side and the face would be no quad; a trace continuing one of
    /// them through the node makes it a T-junction again.
    pub fn bends(&self, mesh: &Mesh) -> Vec<(u32, [[f64; 3]; 2])> {
        let d = self.degrees();
        (0..self.node.len() as u32).filter(|&v| self.passes_through(&d, v)).filter_map(|v| Some((v, self.turn(mesh, v)?))).collect()
    }

    /// Whether node `v` is where one curve passes through rather than a corner: two segment
    /// ends there (`d`: [`CurveGraph::degrees`]), not pinned, not on the boundary.
    fn passes_through(&self, d: &[u32], v: u32) -> bool {
        let v = v as usize;
        self.node[v] && d[v] == 2 && !self.pinned[v] && !self.boundary[v]
    }

    /// At a node where exactly two trace segments end: the directions in which they arrive
    /// there (so, continue straight on), if they turn by more than [`BEND`].
    fn turn(&self, mesh: &Mesh, v: u32) -> Option<[[f64; 3]; 2]> {
        let mut arriving = Vec::with_capacity(2);
        for s in self.live() {
            let seg = &self.segments[s as usize];
            let p = &seg.path;
            // A few vertices back: a vertex path zigzags round the streamline by half an edge.
            let back = BEND_REACH.min(p.len() - 1);
            let from = if p[0] == v {
                p[back]
            } else if p[p.len() - 1] == v {
                p[p.len() - 1 - back]
            } else {
                continue;
            };
            if seg.feature {
                return None;
            }
            arriving.push(unit(sub(mesh.position(v), mesh.position(from))));
        }
        let [a, b] = arriving[..] else { return None };
        // Straight on, a arrives where b leaves: a = −b.
        (dot(a, b) > -BEND.cos()).then_some([a, b])
    }

    /// Joins the two segments that end at `v` into one, if they are of one kind and distinct.
    fn join_at(&mut self, v: u32) -> bool {
        let at: Vec<u32> = self
            .live()
            .filter(|&s| {
                let p = &self.segments[s as usize].path;
                p[0] == v || p[p.len() - 1] == v
            })
            .collect();
        let [a, b] = at[..] else { return false };
        if self.segments[a as usize].feature != self.segments[b as usize].feature {
            return false;
        }
        let mut pa = self.segments[a as usize].path.clone();
        let mut pb = self.segments[b as usize].path.clone();
        if pa[0] == v {
            pa.reverse();
        }
        if pb[pb.len() - 1] == v {
            pb.reverse();
        }
        if pa[0] == pb[pb.len() - 1] {
            // The two make a loop through v: keep v.
            return false;
        }
        let feature = self.segments[a as usize].feature;
        self.remove(a);
        self.remove(b);
        self.node[v as usize] = false;
        pa.extend_from_slice(&pb[1..]);
        self.push(Segment { path: pa, feature });
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::primitives::quad_grid;

    /// A 10 × 10 grid of the unit square; vertex (i, j) of it.
    fn grid() -> (Mesh, impl Fn(u32, u32) -> u32) {
        (quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], 10), |i, j| j * 11 + i)
    }

    /// Two traces from the boundary, meeting at the unpinned node (5, 5): one from (0, 5),
    /// one from `second_end`.
    fn two_traces(mesh: &Mesh, v: &impl Fn(u32, u32) -> u32, second_end: (u32, u32)) -> CurveGraph {
        let mut g = CurveGraph::new(mesh);
        g.add_path(&(0..=5).map(|i| v(i, 5)).collect::<Vec<_>>(), false);
        let (i1, j1) = second_end;
        let second: Vec<u32> = if j1 == 5 { (5..=i1).map(|i| v(i, 5)).collect() } else { (5..=j1).map(|j| v(5, j)).collect() };
        g.add_path(&second, false);
        g
    }

    #[test]
    fn a_trace_turning_at_a_node_is_a_bend_kept_apart_unless_asked_to_join() {
        let (mesh, v) = grid();
        let mut g = two_traces(&mesh, &v, (5, 10));
        g.prune(Some(&mesh));
        assert!(g.node[v(5, 5) as usize]);
        let bends = g.bends(&mesh);
        assert_eq!(bends.len(), 1);
        let (at, [a, b]) = bends[0];
        assert_eq!(at, v(5, 5));
        // The two arrive along +x and −y: continued straight on, they leave along them.
        let mut arriving = [a, b].map(|d| [d[0].round(), d[1].round()]);
        arriving.sort_by(|p, q| p.partial_cmp(q).unwrap());
        assert_eq!(arriving, [[0.0, -1.0], [1.0, 0.0]]);
        g.prune(None);
        assert!(!g.node[v(5, 5) as usize], "joined into one curve");
        assert_eq!(g.live().count(), 1);
    }

    #[test]
    fn a_trace_running_straight_through_a_node_is_joined() {
        let (mesh, v) = grid();
        let mut g = two_traces(&mesh, &v, (10, 5));
        assert!(g.bends(&mesh).is_empty());
        g.prune(Some(&mesh));
        assert!(!g.node[v(5, 5) as usize]);
        assert_eq!(g.live().count(), 1);
    }
}
