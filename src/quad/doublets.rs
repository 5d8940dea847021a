//! Doublets: an inside vertex with only two quads round it (they share both of its edges).
//! The grid makes one where a layout node of two curves is a corner of both faces beside it
//! (a curve that turns at a node, as automatic layouts of thin parts leave). The two quads
//! are flat there (180° at the vertex) and, split into triangles along their 0–2 diagonals as
//! the readers split them, can put four triangles on one edge, so the mesh would not read
//! back (on camel, cow and elk of CGAL's data). Dissolving the vertex merges the two quads
//! into one, the standard clean-up of quad meshes.

use super::QuadMesh;

/// Merges the two quads of every inside vertex of valence 2 into one and drops the vertex;
/// `quad_face` (the layout face of each quad) follows the quads, and the merged quad keeps
/// the first one's face. Returns the vertices dissolved, each numbered as it was when it was
/// removed (so other per-vertex lists can follow, one removal after the other).
pub fn dissolve(mesh: &mut QuadMesh, quad_face: &mut Vec<u32>) -> Vec<u32> {
    let mut dissolved = Vec::new();
    // A merge can leave a neighbour with two quads: go on until none is left.
    while let Some((v, [a, b])) = first_doublet(mesh) {
        let (qa, qb) = (mesh.quads[a], mesh.quads[b]);
        // qa = (v, x, p, y) from v; qb runs the other way round v: (v, y, r, x).
        let ka = qa.iter().position(|&u| u == v).unwrap_or(0);
        let kb = qb.iter().position(|&u| u == v).unwrap_or(0);
        let [_, x, p, y] = [0, 1, 2, 3].map(|i| qa[(ka + i) % 4]);
        let r = qb[(kb + 2) % 4];
        mesh.quads[a] = [x, p, y, r];
        mesh.quads.swap_remove(b);
        quad_face.swap_remove(b);
        remove_vertex(mesh, v);
        dissolved.push(v);
    }
    dissolved
}

/// An inside vertex with exactly two quads, which share both of its edges, and the two. (Two
/// quads that share both edges of a vertex close the fan round it: it is inside.)
fn first_doublet(mesh: &QuadMesh) -> Option<(u32, [usize; 2])> {
    let mut round: Vec<Vec<usize>> = vec![Vec::new(); mesh.positions.len()];
    for (q, quad) in mesh.quads.iter().enumerate() {
        for &v in quad {
            round[v as usize].push(q);
        }
    }
    let neighbours = |q: &[u32; 4], v: u32| -> Option<[u32; 2]> {
        let k = q.iter().position(|&u| u == v)?;
        let (n, p) = (q[(k + 1) % 4], q[(k + 3) % 4]);
        Some([n.min(p), n.max(p)])
    };
    (0..mesh.positions.len() as u32).find_map(|v| {
        let [a, b] = round[v as usize][..] else { return None };
        let (na, nb) = (neighbours(&mesh.quads[a], v)?, neighbours(&mesh.quads[b], v)?);
        (na == nb && na[0] != na[1]).then_some((v, [a, b]))
    })
}

/// Removes vertex `v` (used by no quad) and renumbers the ones after it.
fn remove_vertex(mesh: &mut QuadMesh, v: u32) {
    mesh.positions.remove(v as usize);
    mesh.vertex_node.remove(v as usize);
    for quad in &mut mesh.quads {
        for u in quad.iter_mut() {
            debug_assert_ne!(*u, v);
            if *u > v {
                *u -= 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::NONE;
    use crate::quad::check_reads_back;

    /// The square 0 1 2 3 cut along 0–4–2 (4 at its centre) into two quads that share both
    /// edges of 4, inside a ring of four quads: 4 is dissolved, the square is one quad again.
    #[test]
    fn a_vertex_of_two_quads_is_dissolved() {
        let mut positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 0.0]];
        positions.extend([[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [2.0, 2.0, 0.0], [-1.0, 2.0, 0.0]]);
        let quads = vec![[4, 2, 3, 0], [4, 0, 1, 2], [0, 5, 6, 1], [1, 6, 7, 2], [2, 7, 8, 3], [3, 8, 5, 0]];
        let mut mesh = QuadMesh { positions, quads, vertex_node: vec![NONE; 9] };
        let mut faces = vec![0, 1, 2, 3, 4, 5];
        assert_eq!(dissolve(&mut mesh, &mut faces), vec![4]);
        assert_eq!(mesh.quads.len(), 5);
        assert_eq!(mesh.positions.len(), 8);
        assert_eq!(faces.len(), 5);
        // The merged quad is the square 0 1 2 3 (renumbered: 4 is gone, 5..8 are 4..7).
        let mut merged = mesh.quads[0];
        let k = merged.iter().position(|&u| u == 0).unwrap();
        merged.rotate_left(k);
        assert_eq!(merged, [0, 1, 2, 3]);
        check_reads_back(&mesh).unwrap();
    }
}
