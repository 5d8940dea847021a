//! Sliver faces: two traces that run side by side, close together, cut a long thin strip
//! between them. A strip of quads keeps its width from face to face (opposite sides have
//! equal counts), so a strip one quad wide here and seven wide where its traces part makes
//! one of the two places skewed and stretched whatever the counts; removing one of the
//! strip's long sides merges it into a neighbour (the issue's "drop traces that only make
//! slivers").

use super::faces::{analyze, FaceInfo};
use super::graph::CurveGraph;
use crate::mesh::Mesh;

/// A face whose isoperimetric ratio 16·area/perimeter² (1 for a square, about 4w/l for a
/// strip of width w and length l) is below this is a sliver: a strip of about 1:8.
const SLIVER_RATIO: f64 = 0.4;

/// 16·area/perimeter²: 1 for a square, small for a strip.
fn roundness(f: &FaceInfo) -> f64 {
    if f.perimeter > 0.0 { 16.0 * f.area / (f.perimeter * f.perimeter) } else { 1.0 }
}

/// The traces along the long sides of the slivers of `g` (the two longest of each), the
/// thinnest sliver's first; feature lines are never among them.
pub fn sliver_sides(mesh: &Mesh, g: &CurveGraph) -> Vec<u32> {
    let fa = analyze(mesh, g);
    let mut thin: Vec<&FaceInfo> = fa.faces.iter().filter(|f| roundness(f) < SLIVER_RATIO).collect();
    thin.sort_by(|a, b| roundness(a).total_cmp(&roundness(b)));
    let mut sides: Vec<u32> = Vec::new();
    for f in thin {
        let mut long: Vec<u32> = f.segments.iter().copied().filter(|&s| !g.segments[s as usize].feature).collect();
        long.sort_by_key(|&s| std::cmp::Reverse(g.segments[s as usize].path.len()));
        for s in long.into_iter().take(2) {
            if !sides.contains(&s) {
                sides.push(s);
            }
        }
    }
    sides
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::primitives::quad_grid;

    /// Two curves across a 20 × 20 grid, one row apart, cut a 1 × 20 strip between two fat
    /// faces: the strip is the one sliver, and its long sides are the two curves.
    #[test]
    fn a_strip_between_two_close_curves_is_a_sliver() {
        let n = 20;
        let mesh = quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], n);
        let row = |j: u32| -> Vec<u32> { (0..=n).map(|i| j * (n + 1) + i).collect() };
        let mut g = CurveGraph::new(&mesh);
        g.add_path(&row(9), false);
        g.add_path(&row(10), false);
        let mut sides: Vec<Vec<u32>> = sliver_sides(&mesh, &g).iter().map(|&s| g.segments[s as usize].path.clone()).collect();
        sides.sort();
        assert_eq!(sides, vec![row(9), row(10)]);
        // Rows far apart make no sliver.
        let mut wide = CurveGraph::new(&mesh);
        wide.add_path(&row(5), false);
        wide.add_path(&row(15), false);
        assert!(sliver_sides(&mesh, &wide).is_empty());
    }
}
