//! The faces a curve graph cuts the surface into, measured the way the layout reader will
//! judge them (layout-format.md, "patches"): each must be a disk (Euler characteristic 1, which
//! also rules out a boundary that passes a node twice), have at least four nodes and a mesh
//! vertex inside, and no segment may have the same face on both sides.

use super::graph::CurveGraph;
use crate::mesh::{Mesh, NONE};
use std::collections::VecDeque;

/// One face of the cut surface.
#[derive(Debug, Clone, Default)]
pub struct FaceInfo {
    pub area: f64,
    /// The length of its boundary: curves and the mesh boundary.
    pub perimeter: f64,
    /// V − E + F of its triangles.
    pub euler: i64,
    /// The nodes on its boundary.
    pub nodes: Vec<u32>,
    /// Its vertices on no curve, the boundary included.
    pub inside: usize,
    /// The live segments on its boundary.
    pub segments: Vec<u32>,
}

/// The faces, the face of every triangle, and the segments with one face on both sides.
#[derive(Debug, Clone)]
pub struct Faces {
    pub faces: Vec<FaceInfo>,
    pub of_triangle: Vec<u32>,
    pub slits: Vec<u32>,
    /// Per mesh edge: the live segment along it, or [`NONE`].
    pub cut_by: Vec<u32>,
}

impl Faces {
    /// Per face: its inside vertex farthest (in edges) from every curve of `graph` (the one
    /// these faces were cut by), if it has one. Apart from [`analyze`], which runs every
    /// repair round: a walk over the whole mesh that only the repairs of faces that are not
    /// disks, and the splits `--patches` asks for, need.
    pub fn deepest(&self, mesh: &Mesh, graph: &CurveGraph) -> Vec<Option<u32>> {
        let on_curve = |v: u32| graph.taken(v);
        let mut dist = vec![u32::MAX; mesh.n_vertices()];
        let mut queue: VecDeque<u32> = (0..mesh.n_vertices() as u32).filter(|&v| !mesh.is_isolated(v) && on_curve(v)).collect();
        for &v in &queue {
            dist[v as usize] = 0;
        }
        while let Some(v) = queue.pop_front() {
            for u in mesh.neighbors(v) {
                if dist[u as usize] == u32::MAX {
                    dist[u as usize] = dist[v as usize] + 1;
                    queue.push_back(u);
                }
            }
        }
        let mut best = vec![0u32; self.faces.len()];
        let mut deepest = vec![None; self.faces.len()];
        for v in 0..mesh.n_vertices() as u32 {
            if mesh.is_isolated(v) || on_curve(v) {
                continue;
            }
            let Some(f) = mesh.outgoing(v).map(|h| mesh.face(h)).find(|&f| f != NONE) else { continue };
            let x = self.of_triangle[f as usize] as usize;
            if dist[v as usize] > best[x] {
                best[x] = dist[v as usize];
                deepest[x] = Some(v);
            }
        }
        deepest
    }

    /// Whether removing segment `s` of `graph` merges the two faces beside it into a disk:
    /// they have no other segment and no node in common but its ends. Two faces that also
    /// meet along another segment would leave it a slit, and then a ring once the slit goes;
    /// two that also touch at a node would make a face pinched there.
    pub fn merges_cleanly(&self, graph: &CurveGraph, s: u32) -> bool {
        let mut beside = self.faces.iter().filter(|f| f.segments.contains(&s));
        let (Some(a), Some(b), None) = (beside.next(), beside.next(), beside.next()) else { return false };
        let p = &graph.segments[s as usize].path;
        let ends = [p[0], p[p.len() - 1]];
        a.segments.iter().all(|t| *t == s || !b.segments.contains(t)) && a.nodes.iter().filter(|n| b.nodes.contains(n)).all(|n| ends.contains(n))
    }
}

/// Cuts `mesh` along the segments of `graph` and its boundary and measures the pieces.
pub fn analyze(mesh: &Mesh, graph: &CurveGraph) -> Faces {
    let ne = mesh.n_edges();
    let mut cut_by = vec![NONE; ne];
    for s in graph.live() {
        for w in graph.segments[s as usize].path.windows(2) {
            if let Some(h) = mesh.find_halfedge(w[0], w[1]) {
                cut_by[mesh.edge(h) as usize] = s;
            }
        }
    }
    // Faces: the triangles reached from each across uncut edges.
    let adjacency = &graph.measures.adjacency;
    let (of_triangle, count) = adjacency.regions(|e| cut_by[e as usize] != NONE);
    let mut faces = vec![FaceInfo::default(); count];
    let nf = mesh.n_faces();
    let (areas, lengths) = (&graph.measures.areas, &graph.measures.lengths);
    for t in 0..nf {
        let f = &mut faces[of_triangle[t] as usize];
        f.area += areas[t];
        f.euler += 1;
    }
    // Edges: one per distinct face beside it.
    let mut slit = vec![false; graph.segments.len()];
    for e in 0..ne as u32 {
        let (f, g) = (mesh.face(2 * e), mesh.face(2 * e + 1));
        let (a, b) = (if f == NONE { NONE } else { of_triangle[f as usize] }, if g == NONE { NONE } else { of_triangle[g as usize] });
        for x in [a, b] {
            if x != NONE {
                faces[x as usize].euler -= 1;
            }
        }
        if a != b || cut_by[e as usize] != NONE {
            for x in [a, b] {
                if x != NONE {
                    faces[x as usize].perimeter += lengths[e as usize];
                }
            }
        }
        if a == b && a != NONE {
            faces[a as usize].euler += 1;
            if cut_by[e as usize] != NONE {
                slit[cut_by[e as usize] as usize] = true;
            }
        }
        let s = cut_by[e as usize];
        if s != NONE {
            for x in [a, b] {
                if x != NONE && !faces[x as usize].segments.contains(&s) {
                    faces[x as usize].segments.push(s);
                }
            }
        }
    }
    // Vertices: one per distinct face around it; nodes and inside vertices.
    let mut around = Vec::new();
    for v in 0..mesh.n_vertices() as u32 {
        if mesh.is_isolated(v) {
            continue;
        }
        around.clear();
        for &f in adjacency.round(v) {
            if !around.contains(&of_triangle[f as usize]) {
                around.push(of_triangle[f as usize]);
            }
        }
        for &x in &around {
            faces[x as usize].euler += 1;
            if graph.node[v as usize] {
                faces[x as usize].nodes.push(v);
            }
        }
        if !graph.taken(v) {
            if let Some(&x) = around.first() {
                faces[x as usize].inside += 1;
            }
        }
    }
    let slits = (0..graph.segments.len() as u32).filter(|&s| slit[s as usize]).collect();
    Faces { faces, of_triangle, slits, cut_by }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::primitives::quad_grid;

    /// A line across a grid parts two faces that meet along it alone: removing it merges them
    /// into a disk. A square ring inside the grid is two segments (a closed curve gets a node
    /// halfway), both between the square's face and the face round it: removing either leaves
    /// the other a slit.
    #[test]
    fn only_faces_that_meet_along_one_side_alone_merge_cleanly() {
        let n = 20;
        let mesh = quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], n);
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut g = CurveGraph::new(&mesh);
        g.add_path(&(0..=n).map(|i| at(i, 3)).collect::<Vec<_>>(), false);
        let fa = analyze(&mesh, &g);
        assert_eq!(fa.faces.len(), 2);
        let line: Vec<u32> = g.live().collect();
        assert!(line.iter().all(|&s| fa.merges_cleanly(&g, s)), "{line:?}");

        let mut square: Vec<u32> = (7..13).map(|i| at(i, 7)).collect();
        square.extend((7..13).map(|j| at(13, j)));
        square.extend((8..=13).rev().map(|i| at(i, 13)));
        square.extend((8..=13).rev().map(|j| at(7, j)));
        square.push(at(7, 7));
        g.add_path(&square, false);
        let fa = analyze(&mesh, &g);
        assert_eq!(fa.faces.len(), 3);
        let ring: Vec<u32> = g.live().filter(|s| !line.contains(s)).collect();
        assert_eq!(ring.len(), 2);
        assert!(ring.iter().all(|&s| !fa.merges_cleanly(&g, s)), "{ring:?}");
        assert!(line.iter().all(|&s| fa.merges_cleanly(&g, s)), "{line:?}");
    }
}
