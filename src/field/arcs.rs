//! Arcs that cut a face the traces leave as a ring: round a limb, a horn or a handle the
//! streamlines can spiral for ever without closing, and crosses of traces seeded inside such a
//! face keep missing (CGAL's bull and femur: 40 rounds of crosses, still not disks).
//!
//! An arc runs from the face's deepest vertex along shortest edge paths to the nearest vertex
//! of two different pieces of the face's boundary. On a ring (two boundary loops) the first
//! arc joins the loops and leaves the face a disk whose two sides along the arc are the same
//! face (a slit, which the reader refuses); a second arc, from the deepest vertex left to the
//! two pieces of the boundary that the first one's vertices part, makes two disks. Shortest
//! paths, not streamlines, because they always arrive; across a limb they run along it, much
//! as the field does. A face with a handle and one boundary loop is cut round the handle.

use super::faces::Faces;
use super::graph::CurveGraph;
use crate::geom::{norm, sub};
use crate::layout::curve::Entry;
use crate::mesh::topology::vertex_regions;
use crate::mesh::{Mesh, NONE};
use std::collections::BinaryHeap;

/// The arc across face `face` of `faces` from its deepest vertex (`deepest`, as
/// [`Faces::deepest`] gives them) to the nearest vertices of
/// two different pieces of its boundary, leaving out the boundary vertices `excluded` (slits':
/// the pieces are then the stretches between their sides); `None` if the face has no vertex
/// inside or its boundary is one piece. (Starting the arc that parts a slit from the vertex
/// farthest from the slit, or farthest from it and the other curves, made halves more alike
/// on a plain ring but worse layouts on CGAL's meshes: bull failed, knot1 and dino missed
/// their surfaces by 2–5 times more.)
pub fn arc_across(mesh: &Mesh, g: &CurveGraph, faces: &Faces, deepest: &[Option<u32>], face: u32, excluded: &[u32]) -> Option<Vec<u32>> {
    let start = deepest[face as usize]?;
    let piece = boundary_pieces(mesh, g, faces, face, excluded);
    let mut nearest: Vec<u32> = Vec::new();
    let (via, _) = shortest_paths(mesh, g, &[start], |v| {
        let p = piece[v as usize];
        if p != NONE && !nearest.iter().any(|&u| piece[u as usize] == p) {
            nearest.push(v);
        }
        nearest.len() == 2
    });
    let [a, b] = nearest[..] else { return None };
    let (mut from_a, mut from_b) = (chain(&via, a), chain(&via, b));
    // Both chains end at the start: keep one copy of the part they share.
    while from_a.len() > 1 && from_b.len() > 1 && from_a[from_a.len() - 2] == from_b[from_b.len() - 2] {
        from_a.pop();
        from_b.pop();
    }
    from_b.pop();
    from_a.extend(from_b.into_iter().rev());
    Some(from_a)
}

/// The shortest arc round a handle of face `face` whose boundary is one piece: from the
/// boundary and back without parting the face. The greedy system of loops (Erickson and
/// Whittlesey 2005): a tree of shortest paths from the boundary, a spanning tree of the
/// triangles across the other edges taking the longest loops first, and of the edges left
/// over (one per handle and per extra boundary piece) the one whose loop is shortest.
pub fn arc_round_handle(mesh: &Mesh, g: &CurveGraph, faces: &Faces, face: u32) -> Option<Vec<u32>> {
    let in_face = |h: u32| {
        let t = mesh.face(h);
        t != NONE && faces.of_triangle[t as usize] == face
    };
    let roots: Vec<u32> = (0..mesh.n_vertices() as u32).filter(|&v| g.taken(v) && mesh.outgoing(v).any(in_face)).collect();
    if roots.is_empty() {
        // A closed surface without curves: no boundary to arc from.
        return None;
    }
    let (via, dist) = shortest_paths(mesh, g, &roots, |_| false);
    let is_tree = |a: u32, b: u32| via[a as usize] == b || via[b as usize] == a;
    let mut across: Vec<(f64, u32)> = Vec::new();
    for t in (0..mesh.n_faces() as u32).filter(|&t| faces.of_triangle[t as usize] == face) {
        for k in 0..3 {
            let h = mesh.face_halfedge(t, k);
            let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
            if h < mesh.twin(h) && in_face(mesh.twin(h)) && faces.cut_by[mesh.edge(h) as usize] == NONE && !is_tree(a, b) {
                let loop_length = dist[a as usize] + dist[b as usize] + norm(sub(mesh.position(a), mesh.position(b)));
                across.push((loop_length, h));
            }
        }
    }
    across.sort_by(|x, y| y.0.total_cmp(&x.0));
    let mut set: Vec<u32> = (0..mesh.n_faces() as u32).collect();
    let mut left: Option<u32> = None;
    for &(_, h) in &across {
        let (x, y) = (find(&mut set, mesh.face(h)), find(&mut set, mesh.face(mesh.twin(h))));
        if x == y {
            left = Some(h);
        } else {
            set[x as usize] = y;
        }
    }
    let h = left?;
    let (mut from_a, from_b) = (chain(&via, mesh.from_vertex(h)), chain(&via, mesh.to_vertex(h)));
    from_a.reverse();
    from_a.extend(from_b);
    let mut seen = vec![false; mesh.n_vertices()];
    // Two branches of one tree path: the loop never reaches the boundary; a closed curve.
    if let Some(k) = from_a.iter().position(|&v| std::mem::replace(&mut seen[v as usize], true)) {
        let first = from_a.iter().position(|&v| v == from_a[k]).unwrap_or(0);
        return Some(from_a[first..=k].to_vec());
    }
    Some(from_a)
}

/// The vertices where face `face` meets itself: round each, its triangles form two fans or
/// more, parted by curves or other faces' triangles. A slit's vertices are such, and so is a
/// node the face's boundary passes twice (a disk pinched into a ring: Euler characteristic
/// 0, yet its boundary is one piece, so neither [`arc_across`] nor [`arc_round_handle`] finds
/// an arc until these are left out).
pub fn self_touching(mesh: &Mesh, faces: &Faces, face: u32) -> Vec<u32> {
    let in_face = |t: u32| t != NONE && faces.of_triangle[t as usize] == face;
    let mut out = Vec::new();
    let mut seen = vec![false; mesh.n_vertices()];
    for t in (0..mesh.n_faces() as u32).filter(|&t| in_face(t)) {
        for k in 0..3 {
            let v = mesh.from_vertex(mesh.face_halfedge(t, k));
            if std::mem::replace(&mut seen[v as usize], true) {
                continue;
            }
            // A fan starts at an edge with the face's triangle on its left and, on its right,
            // no triangle of the face or one across a curve.
            let starts = mesh
                .outgoing(v)
                .filter(|&h| {
                    let right = mesh.face(mesh.twin(h));
                    in_face(mesh.face(h)) && (!in_face(right) || faces.cut_by[mesh.edge(h) as usize] != NONE)
                })
                .count();
            if starts >= 2 {
                out.push(v);
            }
        }
    }
    out
}

/// The root of `x` in the disjoint sets `set`, halving the path there.
fn find(set: &mut [u32], mut x: u32) -> u32 {
    while set[x as usize] != x {
        set[x as usize] = set[set[x as usize] as usize];
        x = set[x as usize];
    }
    x
}

/// `v` and the vertices back along `via` to the start of the search.
fn chain(via: &[u32], mut v: u32) -> Vec<u32> {
    let mut out = vec![v];
    while via[v as usize] != NONE {
        v = via[v as usize];
        out.push(v);
    }
    out
}

/// Shortest edge paths from `sources` through free vertices: the previous vertex and the
/// distance of each vertex reached. A taken vertex reached (not a source) is not passed
/// through; `stop(v)` is asked about it, and ends the search when true.
fn shortest_paths(mesh: &Mesh, g: &CurveGraph, sources: &[u32], mut stop: impl FnMut(u32) -> bool) -> (Vec<u32>, Vec<f64>) {
    let nv = mesh.n_vertices();
    let mut dist = vec![f64::INFINITY; nv];
    let mut via = vec![NONE; nv];
    let mut heap = BinaryHeap::new();
    for &s in sources {
        dist[s as usize] = 0.0;
        heap.push(Entry(0.0, s));
    }
    while let Some(Entry(d, v)) = heap.pop() {
        if d > dist[v as usize] {
            continue;
        }
        if g.taken(v) && via[v as usize] != NONE {
            if stop(v) {
                break;
            }
            continue;
        }
        for u in mesh.neighbors(v) {
            let du = d + norm(sub(mesh.position(u), mesh.position(v)));
            if du < dist[u as usize] {
                dist[u as usize] = du;
                via[u as usize] = v;
                heap.push(Entry(du, u));
            }
        }
    }
    (via, dist)
}

/// Per vertex, which connected piece of face `face`'s boundary it is on ([`NONE`] off it):
/// its taken vertices next to its triangles, joined by the curve and mesh-boundary edges
/// the face lies beside, without the vertices `excluded`.
fn boundary_pieces(mesh: &Mesh, g: &CurveGraph, faces: &Faces, face: u32, excluded: &[u32]) -> Vec<u32> {
    let in_face = |h: u32| {
        let t = mesh.face(h);
        t != NONE && faces.of_triangle[t as usize] == face
    };
    let on_boundary = |v: u32| g.taken(v) && !excluded.contains(&v) && mesh.outgoing(v).any(in_face);
    let along_face = |h: u32| {
        let along = faces.cut_by[mesh.edge(h) as usize] != NONE || mesh.face(h) == NONE || mesh.face(mesh.twin(h)) == NONE;
        along && (in_face(h) || in_face(mesh.twin(h)))
    };
    vertex_regions(mesh, on_boundary, along_face).0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::faces::analyze;
    use crate::field::tests::torus;
    use crate::mesh::primitives::quad_grid;

    /// A square ring of curves inside a 20 × 20 grid leaves a ring-shaped face between it and
    /// the grid's border. The first arc joins the two loops (a slit: the ring's face on both
    /// sides); the second parts its sides: two disks and the square inside, no slit.
    #[test]
    fn two_arcs_cut_a_ring_into_two_disks() {
        let n = 20;
        let mesh = quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], n);
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut square: Vec<u32> = (7..13).map(|i| at(i, 7)).collect();
        square.extend((7..13).map(|j| at(13, j)));
        square.extend((8..=13).rev().map(|i| at(i, 13)));
        square.extend((8..=13).rev().map(|j| at(7, j)));
        square.push(at(7, 7));
        let mut g = CurveGraph::new(&mesh);
        g.add_path(&square, false);
        let fa = analyze(&mesh, &g);
        let ring = fa.faces.iter().position(|f| f.euler == 0).expect("a ring") as u32;
        let first = arc_across(&mesh, &g, &fa, &fa.deepest(&mesh, &g), ring, &[]).expect("an arc across the ring");
        let on_border = |v: u32| mesh.is_boundary_vertex(v);
        assert_ne!(on_border(first[0]), on_border(first[first.len() - 1]), "{first:?} joins the two loops");
        assert!(first[1..first.len() - 1].iter().all(|&v| !g.taken(v)), "{first:?} runs through free vertices");
        g.add_path(&first, false);
        let fa = analyze(&mesh, &g);
        assert_eq!(fa.slits.len(), 1, "one arc leaves a slit");
        let mut touching = self_touching(&mesh, &fa, ring);
        touching.sort_unstable();
        let mut slit = first.clone();
        slit.sort_unstable();
        assert_eq!(touching, slit, "the ring's face meets itself along the slit");
        let second = arc_across(&mesh, &g, &fa, &fa.deepest(&mesh, &g), ring, &first).expect("an arc parting the slit");
        g.add_path(&second, false);
        let fa = analyze(&mesh, &g);
        assert!(fa.slits.is_empty());
        assert_eq!(fa.faces.iter().map(|f| f.euler).collect::<Vec<_>>(), vec![1, 1, 1]);
    }

    /// A torus cut along one meridian is one face whose boundary is one loop: the shortest
    /// arc round its handle is the inner equator (length 2π · 0.65), from the meridian back
    /// to it.
    #[test]
    fn the_arc_round_a_handle_is_the_shortest_loop_round_it() {
        let (n, m) = (48, 16);
        let mesh = torus(n, m, 1.0, 0.35);
        let mut g = CurveGraph::new(&mesh);
        let mut meridian: Vec<u32> = (0..m).map(|j| j * n).collect();
        meridian.push(0);
        g.add_path(&meridian, false);
        let fa = analyze(&mesh, &g);
        assert_eq!(fa.faces.len(), 1);
        assert!(arc_across(&mesh, &g, &fa, &fa.deepest(&mesh, &g), 0, &[]).is_none(), "one loop: no arc across");
        let arc = arc_round_handle(&mesh, &g, &fa, 0).expect("an arc round the handle");
        assert!(g.taken(arc[0]) && g.taken(arc[arc.len() - 1]));
        assert!(arc[1..arc.len() - 1].iter().all(|&v| !g.taken(v)));
        let length: f64 = arc.windows(2).map(|w| norm(sub(mesh.position(w[0]), mesh.position(w[1])))).sum();
        let inner = std::f64::consts::TAU * 0.65;
        assert!((length - inner).abs() < 0.05 * inner, "length {length}, inner equator {inner}");
    }
}
