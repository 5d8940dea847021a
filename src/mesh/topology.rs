//! Global topology of a [`Mesh`]: boundary loops, connected components, Euler
//! characteristic and genus per component.

use super::{Mesh, NONE};
use serde::Serialize;

/// One connected component of the mesh's faces.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Component {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    pub boundary_loops: usize,
    /// V − E + F.
    pub euler_characteristic: i64,
    /// From χ = 2 − 2g − b for an orientable surface.
    pub genus: i64,
}

/// Components, boundary loops, and for each vertex its component.
#[derive(Debug, Clone)]
pub struct Topology {
    pub components: Vec<Component>,
    /// Each boundary loop as its halfedges (faces on their right, `next` order).
    pub boundary_loops: Vec<Vec<u32>>,
    /// Component of each vertex; [`NONE`] for unreferenced vertices.
    pub vertex_component: Vec<u32>,
}

/// The connected regions of the vertices for which `member` holds, joined along the outgoing
/// halfedges for which `joins` holds: the region of each vertex ([`NONE`] off them) and their
/// count, numbered in the order of their first vertex.
pub fn vertex_regions(mesh: &Mesh, member: impl Fn(u32) -> bool, joins: impl Fn(u32) -> bool) -> (Vec<u32>, usize) {
    let mut region = vec![NONE; mesh.n_vertices()];
    let mut count = 0u32;
    let mut stack = Vec::new();
    for seed in 0..mesh.n_vertices() as u32 {
        if region[seed as usize] != NONE || !member(seed) {
            continue;
        }
        region[seed as usize] = count;
        stack.push(seed);
        while let Some(v) = stack.pop() {
            for h in mesh.outgoing(v) {
                let w = mesh.to_vertex(h);
                if region[w as usize] == NONE && joins(h) && member(w) {
                    region[w as usize] = count;
                    stack.push(w);
                }
            }
        }
        count += 1;
    }
    (region, count as usize)
}

/// Walks every boundary loop and floods every component.
pub fn topology(mesh: &Mesh) -> Topology {
    let nv = mesh.n_vertices();
    let mut vertex_component = vec![NONE; nv];
    let mut components = Vec::new();
    let mut stack = Vec::new();
    for seed in 0..nv as u32 {
        if vertex_component[seed as usize] != NONE || mesh.is_isolated(seed) {
            continue;
        }
        let id = components.len() as u32;
        vertex_component[seed as usize] = id;
        stack.push(seed);
        let (mut v_count, mut valence_sum) = (0usize, 0usize);
        while let Some(v) = stack.pop() {
            v_count += 1;
            for w in mesh.neighbors(v) {
                valence_sum += 1;
                if vertex_component[w as usize] == NONE {
                    vertex_component[w as usize] = id;
                    stack.push(w);
                }
            }
        }
        components.push(Component {
            vertices: v_count,
            edges: valence_sum / 2,
            faces: 0,
            boundary_loops: 0,
            euler_characteristic: 0,
            genus: 0,
        });
    }
    for t in mesh.triangles() {
        components[vertex_component[t[0] as usize] as usize].faces += 1;
    }
    let mut boundary_loops = Vec::new();
    let mut seen = vec![false; mesh.n_halfedges()];
    for h in 0..mesh.n_halfedges() as u32 {
        if !mesh.is_boundary_halfedge(h) || seen[h as usize] {
            continue;
        }
        let mut lp = Vec::new();
        let mut x = h;
        while !seen[x as usize] {
            seen[x as usize] = true;
            lp.push(x);
            x = mesh.next(x);
        }
        components[vertex_component[mesh.to_vertex(h) as usize] as usize].boundary_loops += 1;
        boundary_loops.push(lp);
    }
    for c in &mut components {
        c.euler_characteristic = c.vertices as i64 - c.edges as i64 + c.faces as i64;
        c.genus = (2 - c.euler_characteristic - c.boundary_loops as i64) / 2;
    }
    Topology { components, boundary_loops, vertex_component }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{build_mesh, TriangleSoup};

    fn tetra_and_square() -> Mesh {
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [5.0, 0.0, 0.0],
            [6.0, 0.0, 0.0],
            [6.0, 1.0, 0.0],
            [5.0, 1.0, 0.0],
            [9.0, 9.0, 9.0],
        ];
        let triangles = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3], [4, 5, 6], [4, 6, 7]];
        build_mesh(TriangleSoup { positions, triangles, ..Default::default() }).unwrap().mesh
    }

    #[test]
    fn components_loops_and_genus() {
        let m = tetra_and_square();
        let t = topology(&m);
        assert_eq!(t.components.len(), 2);
        assert_eq!(t.components[0].euler_characteristic, 2);
        assert_eq!((t.components[0].genus, t.components[0].boundary_loops), (0, 0));
        assert_eq!((t.components[1].genus, t.components[1].boundary_loops), (0, 1));
        assert_eq!(t.boundary_loops.len(), 1);
        assert_eq!(t.boundary_loops[0].len(), 4);
        assert_eq!(t.vertex_component[8], NONE);
    }
}
