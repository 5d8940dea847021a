//! Point location among the triangles of one chart (method-notes §9): a uniform grid over
//! the triangles' parameter coordinates, so mapping a grid point back to the surface costs
//! a few barycentric tests instead of a scan of the chart.

/// Triangles of one chart, bucketed by their bounding boxes in parameter space.
pub struct ChartIndex {
    /// Per entry: the triangle's id (the caller's) and its three corners in the chart.
    triangles: Vec<(u32, [[f64; 2]; 3])>,
    origin: [f64; 2],
    cell: f64,
    size: [usize; 2],
    /// Per cell: positions in `triangles`.
    cells: Vec<Vec<u32>>,
}

/// A point inside (or on) a triangle: its id and barycentric coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub triangle: u32,
    pub bary: [f64; 3],
}

/// Barycentric coordinates of `p` in triangle `t`; `None` for a triangle without area.
fn barycentric(t: &[[f64; 2]; 3], p: [f64; 2]) -> Option<[f64; 3]> {
    let (a, b, c) = (t[0], t[1], t[2]);
    let det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let scale = (b[0] - a[0]).abs() + (b[1] - a[1]).abs() + (c[0] - a[0]).abs() + (c[1] - a[1]).abs();
    if det.abs() <= 1e-14 * scale * scale {
        return None;
    }
    let l1 = ((p[0] - a[0]) * (c[1] - a[1]) - (p[1] - a[1]) * (c[0] - a[0])) / det;
    let l2 = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / det;
    Some([1.0 - l1 - l2, l1, l2])
}

/// `bary` moved onto the triangle: negative weights (rounding, or a point just outside)
/// set to zero, so a point on a side stays on that side (mesh boundaries stay boundaries).
fn clamp(bary: [f64; 3]) -> [f64; 3] {
    let b = bary.map(|x| x.max(0.0));
    let s = b[0] + b[1] + b[2];
    if s > 0.0 {
        b.map(|x| x / s)
    } else {
        [1.0 / 3.0; 3]
    }
}

/// The point of the segment `a b` nearest to `p` in the plane.
pub fn closest_on_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let s = if len2 > 0.0 { (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0) } else { 0.0 };
    [a[0] + s * d[0], a[1] + s * d[1]]
}

/// The point of the triangle nearest to `p` in the plane (`p` itself inside).
fn closest(t: &[[f64; 2]; 3], p: [f64; 2]) -> [f64; 2] {
    if barycentric(t, p).is_some_and(|b| b.iter().all(|&x| x >= 0.0)) {
        return p;
    }
    let on_side = |k: usize| closest_on_segment(p, t[k], t[(k + 1) % 3]);
    let d2 = |q: [f64; 2]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
    (0..3).map(on_side).min_by(|a, b| d2(*a).total_cmp(&d2(*b))).unwrap_or(p)
}

/// At most this many cell entries per triangle (plus a constant) in a [`ChartIndex`]: on
/// ordinary charts, cells sized for two triangles each, a triangle covers two to four.
const FILINGS_PER_TRIANGLE: f64 = 16.0;

/// Cells of a grid of `cell`-sized squares over `extent`, at most 2048 along each axis.
fn grid_size(extent: [f64; 2], cell: f64) -> [usize; 2] {
    [((extent[0] / cell) as usize + 1).min(2048), ((extent[1] / cell) as usize + 1).min(2048)]
}

fn cell_of(p: [f64; 2], origin: [f64; 2], cell: f64, size: [usize; 2]) -> [usize; 2] {
    let c = |k: usize| (((p[k] - origin[k]) / cell).floor().max(0.0) as usize).min(size[k] - 1);
    [c(0), c(1)]
}

fn cell_range(t: &[[f64; 2]; 3], origin: [f64; 2], cell: f64, size: [usize; 2]) -> Option<([usize; 2], [usize; 2])> {
    if t.iter().flatten().any(|x| !x.is_finite()) {
        return None;
    }
    let lo = t.iter().fold([f64::INFINITY; 2], |m, p| [m[0].min(p[0]), m[1].min(p[1])]);
    let hi = t.iter().fold([f64::NEG_INFINITY; 2], |m, p| [m[0].max(p[0]), m[1].max(p[1])]);
    Some((cell_of(lo, origin, cell, size), cell_of(hi, origin, cell, size)))
}

/// How many cell entries filing `triangles` by their bounding boxes in cells of size `cell`
/// takes (counted, not made).
fn filings(triangles: &[(u32, [[f64; 2]; 3])], origin: [f64; 2], cell: f64, extent: [f64; 2]) -> f64 {
    let size = grid_size(extent, cell);
    triangles
        .iter()
        .filter_map(|(_, t)| cell_range(t, origin, cell, size))
        .map(|(a, b)| ((b[0] - a[0] + 1) * (b[1] - a[1] + 1)) as f64)
        .sum()
}

impl ChartIndex {
    /// Indexes `triangles` (id, corners in the chart). About two triangles per cell.
    pub fn new(triangles: Vec<(u32, [[f64; 2]; 3])>) -> ChartIndex {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for (_, t) in &triangles {
            for p in t {
                for k in 0..2 {
                    if p[k].is_finite() {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
            }
        }
        if lo[0] > hi[0] || lo[1] > hi[1] {
            return ChartIndex { triangles: Vec::new(), origin: [0.0; 2], cell: 1.0, size: [1, 1], cells: vec![Vec::new()] };
        }
        let extent = [(hi[0] - lo[0]).max(1e-300), (hi[1] - lo[1]).max(1e-300)];
        let target = (triangles.len() as f64 / 2.0).max(1.0);
        let mut cell = ((extent[0] * extent[1] / target).sqrt()).max(extent[0].max(extent[1]) / 2048.0);
        // A triangle is filed under every cell its bounding box covers. Long slivers (a fan
        // of them round one vertex) cover many cells each, so the filing would grow with the
        // square of the triangle count: coarser cells until the filing stays linear.
        let budget = FILINGS_PER_TRIANGLE * triangles.len() as f64 + 1024.0;
        while filings(&triangles, lo, cell, extent) > budget {
            cell *= 2.0;
        }
        let size = grid_size(extent, cell);
        let mut index = ChartIndex { triangles, origin: lo, cell, size, cells: vec![Vec::new(); size[0] * size[1]] };
        for (i, (_, t)) in index.triangles.iter().enumerate() {
            let Some((a, b)) = index.cell_range(t) else { continue };
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    index.cells[y * size[0] + x].push(i as u32);
                }
            }
        }
        index
    }

    /// The first and last cell (x, y) of the bounding box of `t`; `None` for a triangle
    /// with a coordinate that is not finite.
    fn cell_range(&self, t: &[[f64; 2]; 3]) -> Option<([usize; 2], [usize; 2])> {
        cell_range(t, self.origin, self.cell, self.size)
    }

    fn cell_of(&self, p: [f64; 2]) -> [usize; 2] {
        cell_of(p, self.origin, self.cell, self.size)
    }

    /// The triangle containing `p`, allowing `tolerance` (relative to the triangle) outside
    /// its sides; the one `p` lies deepest in if several do.
    pub fn locate(&self, p: [f64; 2], tolerance: f64) -> Option<Hit> {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return None;
        }
        let c = self.cell_of(p);
        let mut best: Option<(f64, Hit)> = None;
        for &i in &self.cells[c[1] * self.size[0] + c[0]] {
            let (id, t) = &self.triangles[i as usize];
            let Some(bary) = barycentric(t, p) else { continue };
            let depth = bary[0].min(bary[1]).min(bary[2]);
            if depth >= -tolerance && best.is_none_or(|(d, _)| depth > d) {
                best = Some((depth, Hit { triangle: *id, bary: clamp(bary) }));
            }
        }
        best.map(|(_, hit)| hit)
    }

    /// The triangle nearest to `p` in the chart, `p` moved onto it; `None` for an empty chart.
    pub fn nearest(&self, p: [f64; 2]) -> Option<Hit> {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return None;
        }
        let d2 = |q: [f64; 2]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
        self.triangles
            .iter()
            .filter_map(|(id, t)| {
                let q = closest(t, p);
                barycentric(t, q).map(|b| (d2(q), Hit { triangle: *id, bary: clamp(b) }))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, hit)| hit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_triangle_of_points_of_a_grid() {
        // Two triangles per unit cell of a 10×10 grid.
        let mut tris = Vec::new();
        for y in 0..10 {
            for x in 0..10 {
                let (x, y) = (x as f64, y as f64);
                tris.push((tris.len() as u32, [[x, y], [x + 1.0, y], [x + 1.0, y + 1.0]]));
                tris.push((tris.len() as u32, [[x, y], [x + 1.0, y + 1.0], [x, y + 1.0]]));
            }
        }
        let index = ChartIndex::new(tris.clone());
        for p in [[0.3, 0.1], [9.9, 9.95], [5.5, 2.25], [0.0, 0.0], [10.0, 10.0], [10.0, 3.5]] {
            let hit = index.locate(p, 1e-9).unwrap();
            let t = tris[hit.triangle as usize].1;
            let q = [0, 1].map(|k| hit.bary[0] * t[0][k] + hit.bary[1] * t[1][k] + hit.bary[2] * t[2][k]);
            assert!((q[0] - p[0]).abs() < 1e-12 && (q[1] - p[1]).abs() < 1e-12, "{p:?} → {q:?}");
        }
        assert!(index.locate([10.5, 3.0], 1e-9).is_none());
        assert!(index.locate([f64::NAN, 3.0], 1e-9).is_none());
        let near = index.nearest([10.5, 3.0]).unwrap();
        let t = tris[near.triangle as usize].1;
        let q = [0, 1].map(|k| near.bary[0] * t[0][k] + near.bary[1] * t[1][k] + near.bary[2] * t[2][k]);
        assert!((q[0] - 10.0).abs() < 1e-12 && (q[1] - 3.0).abs() < 1e-12, "{q:?}");
    }

    #[test]
    fn a_fan_of_slivers_is_filed_in_linear_memory() {
        // 20,000 slivers round the origin: each one's bounding box spans a good part of the
        // chart, so filing by bounding boxes in cells sized for two triangles each would take
        // hundreds of entries per triangle.
        let n = 20_000u32;
        let corner = |k: u32| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            [a.cos(), a.sin()]
        };
        let tris: Vec<(u32, [[f64; 2]; 3])> = (0..n).map(|k| (k, [[0.0, 0.0], corner(k), corner(k + 1)])).collect();
        let index = ChartIndex::new(tris.clone());
        let entries: usize = index.cells.iter().map(Vec::len).sum();
        assert!(entries as f64 <= FILINGS_PER_TRIANGLE * n as f64 + 1024.0, "{entries} entries");
        for p in [[0.5, 0.01], [-0.3, -0.6], [0.001, 0.0005], [0.99, 0.0]] {
            let hit = index.locate(p, 1e-9).unwrap();
            let t = tris[hit.triangle as usize].1;
            let q = [0, 1].map(|k| hit.bary[0] * t[0][k] + hit.bary[1] * t[1][k] + hit.bary[2] * t[2][k]);
            assert!((q[0] - p[0]).abs() < 1e-12 && (q[1] - p[1]).abs() < 1e-12, "{p:?} → {q:?}");
        }
    }
}
