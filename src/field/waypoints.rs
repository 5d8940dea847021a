//! Sparse waypoints for a trace: the few vertices of its path that a layout curve (a geodesic
//! through them, layout-format.md "via") needs to follow it.
//!
//! A trace is a path of mesh vertices that zig-zags about the field's streamline by up to
//! half an edge. With every vertex a waypoint the curve zig-zags too, and the turns of half
//! an edge over one edge are what the layout's corners, sides and the parameterization's
//! charts then see (faces of reflex angles, sides whose lengths do not match). The curve
//! keeps only the vertices where the path leaves a sleeve about the straight chord from the
//! last kept one: the chord then runs down the middle of the zig-zag, as the streamline did.

use crate::geom::{dot, norm, sub};
use crate::mesh::Mesh;

/// The sleeve's half-width, in mean edge lengths of the path: the zig-zag about a straight
/// streamline stays within about half an edge of it.
const SLEEVE: f64 = 0.75;
/// At most this many path edges between waypoints, so the geodesic between two of them
/// cannot take a different way round a bump.
const MAX_SPAN: usize = 12;

/// Distance of `p` from the segment `a`–`b`.
fn distance_to_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    let t = if l2 > 0.0 { (dot(sub(p, a), ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    norm(sub(p, [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]]))
}

/// The interior vertices of `path` to keep as waypoints (in order); see the module
/// documentation. Paths of up to two edges keep their middle vertex.
pub fn sparse_waypoints(mesh: &Mesh, path: &[u32]) -> Vec<u32> {
    let n = path.len();
    if n <= 3 {
        return path[1..n.saturating_sub(1).max(1)].to_vec();
    }
    let pos = |k: usize| mesh.position(path[k]);
    let mean = (1..n).map(|k| norm(sub(pos(k), pos(k - 1)))).sum::<f64>() / (n - 1) as f64;
    let tolerance = SLEEVE * mean;
    let fits = |i: usize, j: usize| (i + 1..j).all(|k| distance_to_segment(pos(k), pos(i), pos(j)) <= tolerance);
    let mut kept = Vec::new();
    let mut i = 0;
    while i < n - 1 {
        // The farthest vertex the chord from i reaches with the path inside the sleeve (not
        // the first that fails: a chord between the zig-zag's two sides fails where a longer
        // one down its middle fits).
        let j = (i + 1..=(i + MAX_SPAN).min(n - 1)).rev().find(|&j| fits(i, j)).unwrap_or(i + 1);
        if j == n - 1 {
            break;
        }
        kept.push(path[j]);
        i = j;
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::embedding::tests::grid;

    #[test]
    fn a_zig_zag_along_a_straight_line_keeps_few_waypoints() {
        // Vertices of a unit grid; the path steps right and up and right again.
        let m = grid(20);
        let id = |i: u32, j: u32| j * 21 + i;
        let mut path = Vec::new();
        for i in 0..=16 {
            path.push(id(i, (i / 2) % 2 + 4));
        }
        path.dedup();
        let kept = sparse_waypoints(&m, &path);
        assert!(kept.len() <= 2, "{kept:?}");
        assert!(kept.iter().all(|v| path.contains(v)));
    }

    #[test]
    fn a_right_angle_keeps_its_corner() {
        let m = grid(20);
        let id = |i: u32, j: u32| j * 21 + i;
        let path: Vec<u32> = (0..=8).map(|i| id(i, 2)).chain((3..=10).map(|j| id(8, j))).collect();
        let kept = sparse_waypoints(&m, &path);
        assert!(kept.contains(&id(8, 2)), "{kept:?}");
    }
}
