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
/// the first one's face. Returns, per vertex as numbered before, whether it was dropped (the
/// others keep their order), so other per-vertex lists can follow ([`remove_marked`]).
pub fn dissolve(mesh: &mut QuadMesh, quad_face: &mut Vec<u32>) -> Vec<bool> {
    // Each pass merges the doublets that share no quad, in one sweep of the mesh; a merge can
    // leave a neighbour with two quads, which the next pass finds.
    in_passes(mesh, quad_face, |mesh, round, gone, dropped| {
        let mut touched = vec![false; mesh.quads.len()];
        for v in 0..mesh.positions.len() as u32 {
            let [a, b] = round[v as usize][..] else { continue };
            let (a, b) = (a as usize, b as usize);
            if touched[a] || touched[b] || !is_doublet(&mesh.quads[a], &mesh.quads[b], v) {
                continue;
            }
            // quads[a] = (v, x, p, y) from v; quads[b] runs the other way round v: (v, y, r, x).
            let (qa, qb) = (mesh.quads[a], mesh.quads[b]);
            let ka = qa.iter().position(|&u| u == v).unwrap_or(0);
            let kb = qb.iter().position(|&u| u == v).unwrap_or(0);
            let [x, p, y] = [1, 2, 3].map(|i| qa[(ka + i) % 4]);
            mesh.quads[a] = [x, p, y, qb[(kb + 2) % 4]];
            (touched[a], touched[b], gone[b]) = (true, true, true);
            dropped[v as usize] = true;
        }
    })
}

/// Runs `pass` over `mesh` until one removes no quad, then drops the vertices the passes
/// marked ([`drop_vertices`]); returns those marks, per vertex as numbered before. Each pass
/// gets the quads round every vertex as it starts, marks the quads it removes (`gone`: they
/// go after it, with their `quad_face`) and the vertices no quad uses any more (`dropped`).
/// The clean-ups of the extracted mesh ([`dissolve`], [`super::diagonals::collapse`]) are
/// such passes: each change alters its neighbours' valences, so the quads round it wait for
/// the next pass.
pub fn in_passes(
    mesh: &mut QuadMesh,
    quad_face: &mut Vec<u32>,
    mut pass: impl FnMut(&mut QuadMesh, &[Vec<u32>], &mut [bool], &mut [bool]),
) -> Vec<bool> {
    let mut dropped = vec![false; mesh.positions.len()];
    loop {
        let mut round: Vec<Vec<u32>> = vec![Vec::new(); mesh.positions.len()];
        for (q, quad) in mesh.quads.iter().enumerate() {
            for &v in quad {
                round[v as usize].push(q as u32);
            }
        }
        let mut gone = vec![false; mesh.quads.len()];
        pass(mesh, &round, &mut gone, &mut dropped);
        if !gone.contains(&true) {
            break;
        }
        remove_marked(&mut mesh.quads, &gone);
        remove_marked(quad_face, &gone);
    }
    drop_vertices(mesh, &dropped);
    dropped
}

/// Removes the `dropped` vertices (used by no quad) and renumbers the others in their order.
pub fn drop_vertices(mesh: &mut QuadMesh, dropped: &[bool]) {
    let mut index = vec![0u32; dropped.len()];
    let mut next = 0;
    for (v, &d) in dropped.iter().enumerate() {
        index[v] = next;
        next += u32::from(!d);
    }
    for quad in &mut mesh.quads {
        quad.iter_mut().for_each(|u| *u = index[*u as usize]);
    }
    remove_marked(&mut mesh.positions, dropped);
    remove_marked(&mut mesh.vertex_node, dropped);
}

/// Removes the items whose mark is set, keeping the order of the others.
pub fn remove_marked<T>(items: &mut Vec<T>, marked: &[bool]) {
    let mut marks = marked.iter();
    items.retain(|_| !marks.next().copied().unwrap_or(false));
}

/// Whether quads `a` and `b`, the only two at `v`, share both of its edges (then they close
/// the fan round it: `v` is inside).
fn is_doublet(a: &[u32; 4], b: &[u32; 4], v: u32) -> bool {
    let neighbours = |q: &[u32; 4]| -> Option<[u32; 2]> {
        let k = q.iter().position(|&u| u == v)?;
        let (n, p) = (q[(k + 1) % 4], q[(k + 3) % 4]);
        Some([n.min(p), n.max(p)])
    };
    matches!((neighbours(a), neighbours(b)), (Some(na), Some(nb)) if na == nb && na[0] != na[1])
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
        let dropped = dissolve(&mut mesh, &mut faces);
        assert_eq!((0..9).filter(|&v| dropped[v]).collect::<Vec<_>>(), vec![4]);
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
