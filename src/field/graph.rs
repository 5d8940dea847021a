//! The curve graph of a proposed layout: nodes on mesh vertices and the segments between
//! them, each a path of mesh edges (a piece of a trace or of a feature line).
//!
//! Segments share no vertex except their end nodes, so their curves meet only at nodes. The
//! boundary is not stored: its vertices are taken, and the nodes on it are kept here.

use crate::geom::sub;
use crate::mesh::{Mesh, NONE};

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
}

impl CurveGraph {
    /// An empty graph on `mesh`.
    pub fn new(mesh: &Mesh) -> CurveGraph {
        let nv = mesh.n_vertices();
        let boundary = (0..nv as u32).map(|v| mesh.is_boundary_vertex(v)).collect();
        CurveGraph { node: vec![false; nv], pinned: vec![false; nv], segments: Vec::new(), inside: vec![NONE; nv], boundary }
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
    /// (see [`CurveGraph::dangling_feature_ends`]).
    pub fn prune(&mut self) {
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
                } else if dv == 2 && !self.pinned[v] && !self.boundary[v] {
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
