//! Diagonal collapses: a quad whose opposite corners `a` and `c` are irregular in a way that
//! merging them makes regular (Tarini, Pietroni, Cignoni, Panozzo, Puppo 2010, *Practical
//! quad mesh simplification*). Merging `a` and `c` removes the quad and leaves one vertex with
//! `val(a) + val(c) − 2` quads, and takes one quad from each of the two other corners `b` and
//! `d`. So two valence-3 corners across a quad whose other corners have valence 5 all become
//! regular; a valence-3 and a regular corner across one whose other corners have valence 5
//! leave one valence-5 vertex where there were three irregular ones.
//!
//! The grid puts irregular vertices only at layout nodes, and such a quad is where two nodes
//! ended one quad apart: faces and T-vertices of an automatic layout that the sample counts
//! squeezed to a single quad. A collapse is made only where it leaves fewer irregular vertices
//! and every valence between 3 and 5, away from the boundary, with neither merged vertex on a
//! tagged curve (the edge loops asked for stay), and where no quad round the merged vertex
//! turns over.

use super::doublets::in_passes;
use super::quality::{boundary_vertices, quad_normal};
use super::relax::Surface;
use super::QuadMesh;
use crate::geom::{add, dot, scale};
use crate::mesh::NONE;

/// Collapses the diagonals described in the module documentation, one pass over the quads
/// (a collapse changes its neighbours' valences: the quads round it wait for another pass),
/// until none is left. `kept[v]`: `v` must not move (a sample of a tagged curve). The merged
/// vertex goes to the point of `surface` nearest the middle of the diagonal. `quad_face` and
/// the vertices' order follow as in [`super::doublets::dissolve`]; returns, per vertex as
/// numbered before, whether it was dropped.
pub fn collapse(mesh: &mut QuadMesh, quad_face: &mut Vec<u32>, kept: &[bool], surface: &Surface) -> Vec<bool> {
    let mut leaf = 0;
    in_passes(mesh, quad_face, |mesh, round, gone, dropped| {
        let boundary = boundary_vertices(mesh.positions.len(), &mesh.quads);
        let mut touched = vec![false; mesh.quads.len()];
        for q in 0..mesh.quads.len() {
            for k in 0..2 {
                let quad = mesh.quads[q];
                let [a, b, c, d] = [0, 1, 2, 3].map(|i| quad[(k + i) % 4] as usize);
                let fresh = |v: usize| round[v].iter().all(|&r| !touched[r as usize]);
                if [a, b, c, d].iter().any(|&v| boundary[v] || !fresh(v)) || kept[a] || kept[c] {
                    continue;
                }
                let val = |v: usize| round[v].len();
                let irregular = |valence: usize| usize::from(valence != 4);
                let before = irregular(val(a)) + irregular(val(b)) + irregular(val(c)) + irregular(val(d));
                let after = [val(a) + val(c) - 2, val(b) - 1, val(d) - 1];
                if after.iter().any(|v| !(3..=5).contains(v)) || after.iter().map(|&v| irregular(v)).sum::<usize>() >= before {
                    continue;
                }
                let Some((at, _)) = surface.project(scale(0.5, add(mesh.positions[a], mesh.positions[c])), &mut leaf) else { continue };
                if !merges_cleanly(mesh, round, q, a, c) || turns_over(mesh, round, q, a, c, at) {
                    continue;
                }
                for &r in round[a].iter().chain(&round[c]) {
                    touched[r as usize] = true;
                    mesh.quads[r as usize].iter_mut().filter(|u| **u as usize == c).for_each(|u| *u = a as u32);
                }
                round[b].iter().chain(&round[d]).for_each(|&r| touched[r as usize] = true);
                mesh.positions[a] = at;
                if mesh.vertex_node[a] == NONE {
                    mesh.vertex_node[a] = mesh.vertex_node[c];
                }
                gone[q] = true;
                dropped[c] = true;
                break;
            }
        }
    })
}

/// Whether `a` and `c`, opposite corners of quad `q`, share no quad but `q` and no neighbour
/// but `q`'s two other corners: merged, they then make no quad with a repeated corner and no
/// two quads with the same two corners on an edge.
fn merges_cleanly(mesh: &QuadMesh, round: &[Vec<u32>], q: usize, a: usize, c: usize) -> bool {
    let neighbours = |v: usize| -> Vec<u32> {
        let mut out: Vec<u32> = round[v]
            .iter()
            .flat_map(|&r| {
                let quad = mesh.quads[r as usize];
                let k = quad.iter().position(|&u| u as usize == v).unwrap_or(0);
                [quad[(k + 1) % 4], quad[(k + 3) % 4]]
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    };
    let quad = mesh.quads[q];
    let others: Vec<u32> = quad.iter().copied().filter(|&u| u as usize != a && u as usize != c).collect();
    let shared_quads = round[a].iter().filter(|r| round[c].contains(r)).count();
    let na = neighbours(a);
    shared_quads == 1 && neighbours(c).iter().all(|u| !na.contains(u) || others.contains(u))
}

/// Whether a quad round `a` or `c` (but `q`, which goes) would turn over with both at `at`:
/// its normal would point against the one it has.
fn turns_over(mesh: &QuadMesh, round: &[Vec<u32>], q: usize, a: usize, c: usize, at: [f64; 3]) -> bool {
    round[a].iter().chain(&round[c]).filter(|&&r| r as usize != q).any(|&r| {
        let quad = mesh.quads[r as usize];
        let old = quad.map(|u| mesh.positions[u as usize]);
        let new = quad.map(|u| if u as usize == a || u as usize == c { at } else { mesh.positions[u as usize] });
        dot(quad_normal(&old), quad_normal(&new)) <= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quad::check_reads_back;

    /// A 4 × 4 grid of unit quads (z = 0) whose middle vertex m = (2, 2) is split in two along
    /// the row y = 2: m moves down to (2, 1.6) with the two quads below, a new vertex c at
    /// (2, 2.4) takes the two above, and the quad (m, (3,2), c, (1,2)) fills the gap. Then m
    /// and c have three quads, (1,2) and (3,2) five.
    fn split_grid() -> QuadMesh {
        let n = 4;
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut positions: Vec<[f64; 3]> = (0..=n).flat_map(|j| (0..=n).map(move |i| [f64::from(i), f64::from(j), 0.0])).collect();
        let mut quads: Vec<[u32; 4]> = (0..n).flat_map(|j| (0..n).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])).collect();
        let (m, c) = (id(2, 2), positions.len() as u32);
        positions.push([2.0, 2.4, 0.0]);
        positions[m as usize] = [2.0, 1.6, 0.0];
        for quad in &mut quads {
            if quad.iter().map(|&u| positions[u as usize][1]).sum::<f64>() > 8.0 {
                quad.iter_mut().filter(|u| **u == m).for_each(|u| *u = c);
            }
        }
        quads.push([m, id(3, 2), c, id(1, 2)]);
        QuadMesh { vertex_node: vec![NONE; positions.len()], positions, quads }
    }

    /// Inside vertices with other than four quads.
    fn irregular(mesh: &QuadMesh) -> usize {
        let boundary = boundary_vertices(mesh.positions.len(), &mesh.quads);
        let mut valence = vec![0; mesh.positions.len()];
        mesh.quads.iter().flatten().for_each(|&v| valence[v as usize] += 1);
        (0..valence.len()).filter(|&v| !boundary[v] && valence[v] != 4).count()
    }

    fn plane() -> Surface {
        Surface::new(&[[-1.0, -1.0, 0.0], [9.0, -1.0, 0.0], [-1.0, 9.0, 0.0]], vec![[0, 1, 2]])
    }

    #[test]
    fn two_valence_three_corners_across_two_valence_five_ones_merge_into_a_regular_grid() {
        let mut mesh = split_grid();
        check_reads_back(&mesh).unwrap();
        assert_eq!(irregular(&mesh), 4);
        let mut faces: Vec<u32> = (0..mesh.quads.len() as u32).collect();
        let kept = vec![false; mesh.positions.len()];
        let dropped = collapse(&mut mesh, &mut faces, &kept, &plane());
        assert_eq!(dropped.iter().filter(|&&d| d).count(), 1);
        assert_eq!((mesh.quads.len(), faces.len(), mesh.positions.len()), (16, 16, 25));
        assert_eq!(irregular(&mesh), 0);
        check_reads_back(&mesh).unwrap();
        // The merged vertex is at the middle of the diagonal it replaced: the grid is whole.
        assert_eq!(mesh.positions[12], [2.0, 2.0, 0.0]);
    }

    /// Where a merged vertex must stay (a tagged curve's sample), nothing collapses.
    #[test]
    fn a_kept_corner_is_not_merged() {
        let mut mesh = split_grid();
        let mut kept = vec![false; mesh.positions.len()];
        kept[12] = true;
        let mut faces = vec![0; mesh.quads.len()];
        let dropped = collapse(&mut mesh, &mut faces, &kept, &plane());
        assert!(!dropped.contains(&true));
        assert_eq!(irregular(&mesh), 4);
    }
}
