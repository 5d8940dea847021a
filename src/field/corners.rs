//! Chart corners for all faces of a proposed layout together.
//!
//! Each face takes four of its nodes as chart corners; the others are its T-vertices
//! (paper, Section 3.3). At a node the quads meet once per face it is a corner of and twice
//! per face it lies on a side of, so the node's valence in the quad mesh is
//! `Σ (1 if corner else 2)` over its faces. Chosen face by face (the four sharpest turns),
//! a node where the faces' angles are near 135° can come out with valence 3 next to one with
//! valence 5 a face away, two irregular vertices the field does not ask for. Their sum is
//! fixed by the Euler characteristic, so such pairs cancel only together: a chain of faces
//! each passing a corner on from one of its nodes to the next carries the missing corner from
//! the one node to the other.

use std::collections::BinaryHeap;

use crate::layout::curve::Entry;

/// A face's boundary as the choice of corners sees it.
#[derive(Debug, Clone)]
pub struct FaceTurns {
    /// Its nodes in order round it.
    pub nodes: Vec<u32>,
    /// The face's angle at each node, in radians (π/2 at a corner, π on a straight side).
    pub turns: Vec<f64>,
}

/// The valence quads have at a node where the surface is smooth and the field regular.
const REGULAR: u32 = 4;

/// The chart corners of every face: positions in its `nodes`, increasing. Each face starts
/// from its four sharpest turns; then, while some chain of faces moves a corner from a node
/// of valence below four to one above for a total change of turn (the corner's new turn less
/// its old, summed over the chain) below `budget`, the cheapest such chain is applied.
/// Only nodes with `regular[node]` count as irregular; a face changes once at most.
///
/// Precondition: every face has at least four nodes.
pub fn choose(faces: &[FaceTurns], regular: &[bool], budget: f64) -> Vec<[usize; 4]> {
    let mut corners: Vec<[usize; 4]> = faces.iter().map(sharpest).collect();
    let mut used = vec![false; faces.len()];
    while let Some(chain) = cheapest_chain(faces, &corners, &used, regular, budget) {
        for step in chain {
            let c = &mut corners[step.face];
            // A face met twice in one chain (a node twice on its boundary) may have moved
            // the corner already; the chain's other steps still hold.
            if let (Some(k), false) = (c.iter().position(|&p| p == step.from), c.contains(&step.to)) {
                c[k] = step.to;
                c.sort_unstable();
            }
            used[step.face] = true;
        }
    }
    corners
}

/// The positions of the four smallest turns of a face, increasing.
fn sharpest(f: &FaceTurns) -> [usize; 4] {
    let mut order: Vec<usize> = (0..f.nodes.len()).collect();
    order.sort_by(|&a, &b| f.turns[a].total_cmp(&f.turns[b]).then(a.cmp(&b)));
    let mut c = [order[0], order[1], order[2], order[3]];
    c.sort_unstable();
    c
}

/// The quad-mesh valence at every node.
fn valences(faces: &[FaceTurns], corners: &[[usize; 4]], n_nodes: usize) -> Vec<u32> {
    let mut valence = vec![0u32; n_nodes];
    for (f, c) in faces.iter().zip(corners) {
        for (k, &node) in f.nodes.iter().enumerate() {
            valence[node as usize] += if c.contains(&k) { 1 } else { 2 };
        }
    }
    valence
}

/// One face's part in a chain: its corner at position `from` moves to position `to`.
#[derive(Debug, Clone, Copy)]
struct Step {
    face: usize,
    from: usize,
    to: usize,
}

/// The cheapest chain of unused faces from a regular node of valence below four to one above,
/// if it costs less than `budget` (Dijkstra from all such nodes at once; each step costs the
/// turn at its new corner less that at its old, never negative in a face still at its
/// sharpest four).
fn cheapest_chain(faces: &[FaceTurns], corners: &[[usize; 4]], used: &[bool], regular: &[bool], budget: f64) -> Option<Vec<Step>> {
    let n = regular.len();
    let valence = valences(faces, corners, n);
    // Per node, the unused faces round it with its positions there.
    let mut round: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for (fi, f) in faces.iter().enumerate().filter(|(fi, _)| !used[*fi]) {
        for (k, &node) in f.nodes.iter().enumerate() {
            round[node as usize].push((fi, k));
        }
    }
    let mut cost = vec![f64::INFINITY; n];
    let mut came: Vec<Option<(u32, Step)>> = vec![None; n];
    let mut heap = BinaryHeap::new();
    for v in 0..n {
        if regular[v] && valence[v] < REGULAR {
            cost[v] = 0.0;
            heap.push(Entry(0.0, v as u32));
        }
    }
    while let Some(Entry(d, v)) = heap.pop() {
        if d > cost[v as usize] {
            continue;
        }
        if regular[v as usize] && valence[v as usize] > REGULAR {
            let mut chain = Vec::new();
            let mut at = v;
            while let Some((prev, step)) = came[at as usize] {
                chain.push(step);
                at = prev;
            }
            chain.reverse();
            return Some(chain);
        }
        for &(fi, from) in &round[v as usize] {
            if !corners[fi].contains(&from) {
                continue;
            }
            let f = &faces[fi];
            for to in (0..f.nodes.len()).filter(|k| !corners[fi].contains(k)) {
                let next = d + (f.turns[to] - f.turns[from]).max(0.0);
                let u = f.nodes[to] as usize;
                if next < budget && next < cost[u] {
                    cost[u] = next;
                    came[u] = Some((v, Step { face: fi, from, to }));
                    heap.push(Entry(next, u as u32));
                }
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn face(nodes: &[u32], degrees: &[f64]) -> FaceTurns {
        FaceTurns { nodes: nodes.to_vec(), turns: degrees.iter().map(|d| d.to_radians()).collect() }
    }

    /// Face 0 is a pentagon whose two last nodes turn 130° and 140°: taken alone it makes
    /// node 3 its corner. Node 3 lies on a side of face 1 as well (valence 1 + 2 = 3), node 4
    /// on a side of face 0 and of face 2 and at a corner of face 3 (valence 2 + 2 + 1 = 5).
    /// Passing face 0's corner from node 3 to node 4 makes both regular, for 10° of turn.
    fn faces() -> Vec<FaceTurns> {
        vec![
            face(&[0, 1, 2, 3, 4], &[90.0, 90.0, 90.0, 130.0, 140.0]),
            face(&[5, 3, 6, 7, 8], &[90.0, 180.0, 90.0, 90.0, 90.0]),
            face(&[9, 4, 10, 11, 12], &[90.0, 180.0, 90.0, 90.0, 90.0]),
            face(&[4, 13, 14, 15], &[90.0; 4]),
        ]
    }

    fn regular_at(nodes: &[u32]) -> Vec<bool> {
        (0..16).map(|v| nodes.contains(&v)).collect()
    }

    #[test]
    fn a_corner_moves_between_a_valence_three_and_a_valence_five_node() {
        let faces = faces();
        let regular = regular_at(&[3, 4]);
        let alone = choose(&faces, &regular, 0.0);
        assert_eq!(alone[0], [0, 1, 2, 3]);
        assert_eq!(valences(&faces, &alone, 16)[3..5], [3, 5]);
        let together = choose(&faces, &regular, 20f64.to_radians());
        assert_eq!(together[0], [0, 1, 2, 4]);
        assert_eq!(together[1..], alone[1..]);
        assert_eq!(valences(&faces, &together, 16)[3..5], [4, 4]);
    }

    #[test]
    fn a_chain_dearer_than_the_budget_or_between_nodes_not_regular_is_left() {
        let faces = faces();
        assert_eq!(choose(&faces, &regular_at(&[3, 4]), 5f64.to_radians())[0], [0, 1, 2, 3]);
        assert_eq!(choose(&faces, &regular_at(&[3]), PI)[0], [0, 1, 2, 3]);
    }

    /// Node 3 (valence 3) reaches node 16 (valence 5) only through face 0 and then face 4,
    /// where node 4 passes the corner on: the valence of node 4 stays as it was.
    #[test]
    fn a_chain_crosses_faces() {
        let mut faces = faces();
        faces[2] = face(&[9, 4, 10, 11, 12], &[90.0, 90.0, 90.0, 90.0, 180.0]);
        faces[3] = face(&[4, 13, 14, 15, 16], &[90.0, 90.0, 90.0, 90.0, 135.0]);
        faces.push(face(&[17, 16, 18, 19, 20], &[90.0, 180.0, 90.0, 90.0, 90.0]));
        faces.push(face(&[16, 21, 22, 23], &[90.0; 4]));
        let regular: Vec<bool> = (0..24).map(|v| v == 3 || v == 4 || v == 16).collect();
        let alone = choose(&faces, &regular, 0.0);
        let v = valences(&faces, &alone, 24);
        assert_eq!((v[3], v[4], v[16]), (3, 4, 5));
        let together = choose(&faces, &regular, 60f64.to_radians());
        let v = valences(&faces, &together, 24);
        assert_eq!((v[3], v[4], v[16]), (4, 4, 4));
        assert_eq!(together[0], [0, 1, 2, 4]);
        assert_eq!(together[3], [1, 2, 3, 4]);
    }
}
