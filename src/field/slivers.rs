//! Faces that hold no quads well, and the traces to remove to merge them into a neighbour (the
//! issue's "drop traces that only make slivers"; `refine` in [`super::propose`]).
//!
//! Slivers: two traces that run side by side, close together, cut a long thin strip between
//! them. A strip of quads keeps its width from face to face (opposite sides have equal
//! counts), so a strip one quad wide here and seven wide where its traces part makes one of
//! the two places skewed and stretched whatever the counts; removing one of the strip's long
//! sides merges it into a neighbour. A face is a sliver by its proportions (about 1:8), or
//! where it is narrower than the quads it will be meshed with, whatever its proportions (on
//! the arms of CGAL's cactus, where strips ran thin in one face and wide in the next).
//!
//! Tiny faces: a face smaller than a 2 × 2 grid of the quads it will be meshed with. Traces
//! of the field's singularities that lie closer together than a quad (four valence-3 ones on a
//! hoof or a horn tip, a cluster on a scan's noise) end on each other in faces of a quad or
//! less, and every piece of their sides still takes a segment: the strips through them are
//! squeezed there and stretched where they run on (CGAL's cow at 4000 quads: 22 of its 103
//! faces held fewer than 4 quads, and 19 curves got less than half the segments their faces
//! asked for, the worst one where 6.4 were asked).

use super::faces::{analyze, FaceInfo};
use super::graph::CurveGraph;
use crate::mesh::Mesh;

/// A face whose isoperimetric ratio 16·area/perimeter² (1 for a square, about 4w/l for a
/// strip of width w and length l) is below this is a sliver: a strip of about 1:8.
const SLIVER_RATIO: f64 = 0.4;

/// A face of less area than this many squares of the quads' edge length is tiny: less than a
/// 2 × 2 grid of quads. Over 26 meshes (the shared ones and 19 of CGAL's) at 4000 quads,
/// with tiny faces merged first: mean angle deviation 8.50 -> 8.01°, geometric-mean Hausdorff
/// distance 1.48 -> 1.48 % (with 2: 8.17°, 1.56 %; with 8: 8.07°, 1.53 %).
const TINY_FACE_QUADS: f64 = 4.0;

/// 16·area/perimeter²: 1 for a square, small for a strip.
fn roundness(f: &FaceInfo) -> f64 {
    if f.perimeter > 0.0 { 16.0 * f.area / (f.perimeter * f.perimeter) } else { 1.0 }
}

/// 2·area/perimeter: about the width of a long strip, half the side of a square.
fn width(f: &FaceInfo) -> f64 {
    if f.perimeter > 0.0 { 2.0 * f.area / f.perimeter } else { 0.0 }
}

/// The traces whose removal merges a face that holds no quads well (at quads of edge length
/// `quad`) into a neighbour, in the order to try them: round each tiny face of `g` (the
/// smallest first, and of each its longest side first: merged across its longest side a face
/// grows most compactly), then the two longest sides of each sliver (the thinnest first, by
/// proportions); feature lines are never among them. Narrower than a quad, over the same 26
/// meshes: mean angle deviation 8.01 -> 7.91°, geometric-mean Hausdorff distance 1.476 ->
/// 1.470 %, three meshes changed (cactus 11.98 -> 8.87°).
pub fn merge_sides(mesh: &Mesh, g: &CurveGraph, quad: f64) -> Vec<u32> {
    let tiny_area = TINY_FACE_QUADS * quad * quad;
    let fa = analyze(mesh, g);
    let by_length_down = |f: &FaceInfo| {
        let mut sides: Vec<u32> = f.segments.iter().copied().filter(|&s| !g.segments[s as usize].feature).collect();
        sides.sort_by_key(|&s| std::cmp::Reverse(g.segments[s as usize].path.len()));
        sides
    };
    let mut tiny: Vec<&FaceInfo> = fa.faces.iter().filter(|f| f.area < tiny_area).collect();
    tiny.sort_by(|a, b| a.area.total_cmp(&b.area));
    let mut thin: Vec<&FaceInfo> = fa.faces.iter().filter(|f| roundness(f) < SLIVER_RATIO || width(f) < quad).collect();
    thin.sort_by(|a, b| roundness(a).total_cmp(&roundness(b)));
    let tiny_sides = tiny.into_iter().flat_map(by_length_down);
    let sliver_sides = thin.into_iter().flat_map(|f| by_length_down(f).into_iter().take(2));
    let mut sides: Vec<u32> = Vec::new();
    for s in tiny_sides.chain(sliver_sides) {
        if !sides.contains(&s) {
            sides.push(s);
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
        let mut sides: Vec<Vec<u32>> = merge_sides(&mesh, &g, 0.0).iter().map(|&s| g.segments[s as usize].path.clone()).collect();
        sides.sort();
        assert_eq!(sides, vec![row(9), row(10)]);
        // Rows far apart make no sliver.
        let mut wide = CurveGraph::new(&mesh);
        wide.add_path(&row(5), false);
        wide.add_path(&row(15), false);
        assert!(merge_sides(&mesh, &wide, 0.0).is_empty());
    }

    /// Two rows and two columns of a 20 × 20 grid, one row and one column apart, with nodes
    /// where they cross, cut a one-cell square there: tiny below a cell and a half of area, and then its sides come
    /// first, before the four strips' long sides; the fat corner faces are neither.
    #[test]
    fn a_face_smaller_than_asked_is_merged_first_across_its_longest_side() {
        let n = 20;
        let mesh = quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], n);
        let row = |j: u32| -> Vec<u32> { (0..=n).map(|i| j * (n + 1) + i).collect() };
        let column = |i: u32| -> Vec<u32> { (0..=n).map(|j| j * (n + 1) + i).collect() };
        let mut g = CurveGraph::new(&mesh);
        for (i, j) in [(9, 9), (10, 9), (9, 10), (10, 10)] {
            g.add_node(j * (n + 1) + i, false);
        }
        for path in [row(9), row(10), column(9), column(10)] {
            g.add_path(&path, false);
        }
        let cell = 1.0 / f64::from(n * n);
        let path = |s: u32| g.segments[s as usize].path.clone();
        let first_four = |area: f64| {
            let quad = (area / TINY_FACE_QUADS).sqrt();
            let mut four: Vec<Vec<u32>> = merge_sides(&mesh, &g, quad).into_iter().take(4).map(path).collect();
            four.sort();
            four
        };
        // The cell's four sides, each one grid edge long.
        let mut cell_sides: Vec<Vec<u32>> = vec![
            vec![9 * (n + 1) + 9, 9 * (n + 1) + 10],
            vec![10 * (n + 1) + 9, 10 * (n + 1) + 10],
            vec![9 * (n + 1) + 9, 10 * (n + 1) + 9],
            vec![9 * (n + 1) + 10, 10 * (n + 1) + 10],
        ];
        for side in &mut cell_sides {
            if !(0..g.segments.len() as u32).any(|s| path(s) == *side) {
                side.reverse();
            }
        }
        cell_sides.sort();
        assert_eq!(first_four(1.5 * cell), cell_sides);
        // Not tiny: the strips come first (the cell is no sliver).
        assert!(first_four(0.5 * cell).iter().all(|p| p.len() > 2));
    }

    /// A 4 × 1 face of grid cells is no sliver by its proportions, but it is one where the
    /// quads are wider than it, and then its long sides come first.
    #[test]
    fn a_face_narrower_than_a_quad_is_a_sliver() {
        let n = 20;
        let mesh = quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], n);
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut g = CurveGraph::new(&mesh);
        for path in [(8..=12).map(|i| at(i, 9)).collect::<Vec<u32>>(), (8..=12).map(|i| at(i, 10)).collect(), vec![at(8, 9), at(8, 10)], vec![at(12, 9), at(12, 10)]] {
            g.add_path(&path, false);
        }
        let cell = 1.0 / f64::from(n);
        assert!(merge_sides(&mesh, &g, 0.5 * cell).is_empty());
        // 0.9 of a cell: the face (0.8 of a cell wide) is not tiny (four cells, against 3.24).
        let mut long: Vec<Vec<u32>> = merge_sides(&mesh, &g, 0.9 * cell).iter().map(|&s| g.segments[s as usize].path.clone()).collect();
        long.sort();
        assert_eq!(long, vec![(8..=12).map(|i| at(i, 9)).collect::<Vec<u32>>(), (8..=12).map(|i| at(i, 10)).collect()]);
    }
}
