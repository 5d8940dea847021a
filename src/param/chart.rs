//! Chart shapes and chart optimization (paper Section 3.1, eqs. 5–10; method-notes §2, §7).
//!
//! A chart is the quadrilateral a layout face is mapped to. Its corners are
//! `c0 = (0,0)`, `c1 = (a,0)`, `c2 = (d,e)`, `c3 = (b,c)` (counter-clockwise), so a general
//! quad has the five degrees of freedom `x = (a, b, c, d, e)`; a rectangle keeps `b = 0`,
//! `d = a`, `e = c` (two, `a` and `c`); a unit chart is a square of fixed side (none).
//!
//! Chart optimization picks the corners that make the parameterization of the face's patch
//! as isometric as possible. Every patch vertex keeps its bilinear coordinates `(s, t)`
//! w.r.t. the current corners, so its parameter position is linear in `x` (eq. 9):
//!
//! ```text
//! u(x) = s(1−t)·c1 + st·c2 + (1−s)t·c3
//! ```
//!
//! Each triangle's Jacobian `J = [u1−u0, u2−u0] P⁻¹` (eq. 8) is then linear in `x`, its
//! isometric distortion `‖JᵀJ − I‖²_F` (eq. 7) quartic, and the area-weighted sum over the
//! patch (eq. 10) is minimized by Newton's method ([`optimize`]).
//!
//! ```
//! use quadlay::param::chart::{optimize, Chart, ChartKind, ChartTriangle, OptimizeOptions};
//!
//! // A 2 × 1 rectangle in 3D, split into two triangles; (s, t) are its bilinear coordinates.
//! let p = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
//! let tris = [
//!     ChartTriangle::new([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [p[0], p[1], p[2]]),
//!     ChartTriangle::new([[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]], [p[0], p[2], p[3]]),
//! ];
//! let start = Chart::unit(1.5).with_kind(ChartKind::Rect);
//! let (chart, report) = optimize(&start, &tris, &OptimizeOptions::default());
//! assert!(report.energy_after < 1e-20);
//! assert!((chart.x[0] - 2.0).abs() < 1e-9 && (chart.x[2] - 1.0).abs() < 1e-9);
//! ```

use crate::geom::{
    add2, add_scaled, cross, cross2, det, dot, dot2, frob2, inner, inverse_with, mat_mul, norm2, scale2, sub, sub2,
    transpose, Mat2,
};

/// How many degrees of freedom a chart has (method-notes §2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChartKind {
    /// General quadrilateral: `x = (a, b, c, d, e)`, 5 degrees of freedom.
    Quad,
    /// Axis-aligned rectangle `a × c` (`b = 0`, `d = a`, `e = c`): 2 degrees of freedom.
    Rect,
    /// Square of a fixed side: nothing to optimize.
    Unit,
}

impl ChartKind {
    /// The number of free variables of this kind: 5, 2 or 0.
    pub fn dofs(self) -> usize {
        directions(self).len()
    }
}

/// Directions in `x = (a, b, c, d, e)` of the free variables `z` of a kind: `x = Σ zⱼ·Lⱼ`.
fn directions(kind: ChartKind) -> &'static [[f64; 5]] {
    const QUAD: [[f64; 5]; 5] = [
        [1.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 1.0],
    ];
    // Rect: z = (a, c) with d = a, e = c, b = 0.
    const RECT: [[f64; 5]; 2] = [[1.0, 0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 1.0, 0.0, 1.0]];
    match kind {
        ChartKind::Quad => &QUAD,
        ChartKind::Rect => &RECT,
        ChartKind::Unit => &[],
    }
}

/// A chart's corners `c0 = (0,0)`, `c1 = (a,0)`, `c2 = (d,e)`, `c3 = (b,c)` (method-notes §2;
/// paper eq. 9 weights: `s(1−t)` on c1, `st` on c2, `(1−s)t` on c3).
///
/// `x` always holds all five values `(a, b, c, d, e)`; for [`ChartKind::Rect`] and
/// [`ChartKind::Unit`] they satisfy that kind's constraints (build charts with the
/// constructors or [`Chart::with_kind`] to keep it so).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chart {
    /// Which constraints the corners obey, i.e. which variables [`optimize`] may change.
    pub kind: ChartKind,
    /// `(a, b, c, d, e)`.
    pub x: [f64; 5],
}

impl Chart {
    /// The square of side `side` (kind [`ChartKind::Unit`]). Method-notes §2: give all unit
    /// charts one common side in surface units, e.g. the mean layout edge length.
    pub fn unit(side: f64) -> Chart {
        Chart { kind: ChartKind::Unit, x: [side, 0.0, side, side, side] }
    }

    /// The rectangle `a × c` (kind [`ChartKind::Rect`]).
    pub fn rect(a: f64, c: f64) -> Chart {
        Chart { kind: ChartKind::Rect, x: [a, 0.0, c, a, c] }
    }

    /// The general quadrilateral with `x = (a, b, c, d, e)` (kind [`ChartKind::Quad`]).
    pub fn quad(x: [f64; 5]) -> Chart {
        Chart { kind: ChartKind::Quad, x }
    }

    /// The corners `[c0, c1, c2, c3]`, counter-clockwise for a valid chart.
    pub fn corners(&self) -> [[f64; 2]; 4] {
        let [a, b, c, d, e] = self.x;
        [[0.0, 0.0], [a, 0.0], [d, e], [b, c]]
    }

    /// The same chart seen as (or constrained to) another kind.
    ///
    /// - `Quad`: the corners unchanged, now all five free.
    /// - `Rect`: `b = 0`, `d = a`, `e = c` with `a` the mean of the bottom and top widths
    ///   (`a` and `d − b`) and `c` the mean of the left and right heights (`c` and `e`);
    ///   a rectangle is kept exactly.
    /// - `Unit`: the square whose side is the mean of the four edge lengths.
    pub fn with_kind(&self, kind: ChartKind) -> Chart {
        let [a, b, c, d, e] = self.x;
        match kind {
            ChartKind::Quad => Chart::quad(self.x),
            ChartKind::Rect => Chart::rect(0.5 * (a + (d - b)), 0.5 * (c + e)),
            ChartKind::Unit => {
                let k = self.corners();
                let side = (0..4).map(|i| norm2(sub2(k[(i + 1) % 4], k[i]))).sum::<f64>() / 4.0;
                Chart::unit(side)
            }
        }
    }

    /// The free variables of this chart's kind: `(a, b, c, d, e)` for `Quad`, `(a, c)` for
    /// `Rect` (from the same averages as [`Chart::with_kind`]), none for `Unit`.
    pub fn free_vars(&self) -> Vec<f64> {
        let [a, b, c, d, e] = self.x;
        match self.kind {
            ChartKind::Quad => self.x.to_vec(),
            ChartKind::Rect => vec![0.5 * (a + (d - b)), 0.5 * (c + e)],
            ChartKind::Unit => Vec::new(),
        }
    }

    /// The chart of the same kind with free variables `z` ([`Chart::free_vars`]), so
    /// `c.with_free_vars(&c.free_vars())` is `c.with_kind(c.kind)`. A `Unit` chart has none
    /// and is returned unchanged.
    ///
    /// # Panics
    /// If `z` is shorter than `self.kind.dofs()`.
    pub fn with_free_vars(&self, z: &[f64]) -> Chart {
        match self.kind {
            ChartKind::Quad => Chart::quad([z[0], z[1], z[2], z[3], z[4]]),
            ChartKind::Rect => Chart::rect(z[0], z[1]),
            ChartKind::Unit => *self,
        }
    }

    /// The point of the bilinear coordinates `st = (s, t)`: eq. 9,
    /// `u = s(1−t)·c1 + st·c2 + (1−s)t·c3` (with `c0 = 0`).
    pub fn point(&self, st: [f64; 2]) -> [f64; 2] {
        let [a, b, c, d, e] = self.x;
        let [s, t] = st;
        let (w1, w2, w3) = (s * (1.0 - t), s * t, (1.0 - s) * t);
        [w1 * a + w2 * d + w3 * b, w2 * e + w3 * c]
    }

    /// Bilinear coordinates `(s, t)` of the point `u` w.r.t. the current corners: the inverse
    /// of eq. 9 (method-notes §7).
    ///
    /// With `u = s·c1 + t·c3 + st·g`, `g = c2 − c1 − c3`, eliminating `s` leaves the quadratic
    /// `(g×c3)·t² + (c1×c3 + u×g)·t + u×c1 = 0`; `s` then follows by projection. Of the
    /// roots, the one nearest to `[0,1]²` is taken and polished by Newton steps on eq. 9, so
    /// inside a convex chart the result is the unique root in `[0,1]²` and `point` of it
    /// gives back `u` to rounding.
    ///
    /// Points slightly outside the chart get the extrapolated root (slightly outside
    /// `[0,1]²`, `point` still reproduces `u`), not a clamped one: chart optimization needs
    /// `uᵢ(x)` to reproduce the current parameterization exactly. Where no real root exists
    /// (outside the fold of a non-convex quad) the least-residual candidate is used. Never
    /// NaN: a chart collapsed to a point, or a non-finite `u`, gives the centre `(½, ½)`.
    pub fn bilinear_coords(&self, u: [f64; 2]) -> [f64; 2] {
        let [_, e, c2, f] = self.corners();
        let g = sub2(sub2(c2, e), f);
        let scale = self.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if !positive(scale) || !u[0].is_finite() || !u[1].is_finite() {
            return [0.5, 0.5];
        }
        if g == [0.0, 0.0] {
            // A parallelogram (every rect and unit chart): eq. 9 is linear, `u = s·c1 + t·c3`.
            let det = cross2(e, f);
            if det != 0.0 && det.is_finite() {
                return [cross2(u, f) / det, cross2(e, u) / det];
            }
        }
        let k2 = cross2(g, f);
        let k1 = cross2(e, f) + cross2(u, g);
        let k0 = cross2(u, e);

        // Candidate t values: both roots (stable formula; a clamped discriminant where
        // there is no real root), plus Newton from the centre as a safety net.
        let mut ts = [f64::NAN; 2];
        let sq = (k1 * k1 - 4.0 * k2 * k0).max(0.0).sqrt();
        let q = -0.5 * (k1 + sq.copysign(k1));
        if q != 0.0 {
            ts[0] = k0 / q;
            if k2 != 0.0 {
                ts[1] = q / k2;
            }
        } else if k2 != 0.0 {
            let r = (-k0 / k2).max(0.0).sqrt();
            ts = [r, -r];
        }

        let score = |st: [f64; 2]| -> f64 {
            let out = |v: f64| {
                if v < 0.0 {
                    -v
                } else if v > 1.0 {
                    v - 1.0
                } else {
                    0.0
                }
            };
            let d = (out(st[0]).powi(2) + out(st[1]).powi(2)).sqrt();
            d + norm2(sub2(self.point(st), u)) / scale
        };
        let mut best: Option<([f64; 2], f64)> = None;
        let consider = |best: &mut Option<([f64; 2], f64)>, st: [f64; 2]| {
            if !(st[0].is_finite() && st[1].is_finite()) {
                return;
            }
            let st = self.polish(st, u);
            let sc = score(st);
            if sc.is_finite() && best.is_none_or(|(_, b)| sc < b) {
                *best = Some((st, sc));
            }
        };
        for t in ts {
            if !t.is_finite() {
                continue;
            }
            let w = add2(e, scale2(t, g));
            let ww = dot2(w, w);
            if ww > 0.0 {
                consider(&mut best, [dot2(sub2(u, scale2(t, f)), w) / ww, t]);
            }
        }
        // The safety net is needed only when no root lands in the chart and reproduces `u`.
        if best.is_none_or(|(_, b)| b > 1e-12) {
            consider(&mut best, self.polish([0.5, 0.5], u));
        }
        match best {
            Some((st, _)) => st,
            None => [0.5, 0.5],
        }
    }

    /// Newton steps on `point(st) = u`, each kept only if it lowers the residual.
    fn polish(&self, mut st: [f64; 2], u: [f64; 2]) -> [f64; 2] {
        let [_, e, c2, f] = self.corners();
        let g = sub2(sub2(c2, e), f);
        let mut r = sub2(self.point(st), u);
        let mut rn = norm2(r);
        for _ in 0..8 {
            if rn == 0.0 {
                break;
            }
            let js = add2(e, scale2(st[1], g));
            let jt = add2(f, scale2(st[0], g));
            let det = cross2(js, jt);
            if det == 0.0 || !det.is_finite() {
                break;
            }
            let ds = cross2(r, jt) / det;
            let dt = cross2(js, r) / det;
            let next = [st[0] - ds, st[1] - dt];
            let rn_next = norm2(sub2(self.point(next), u));
            if rn_next.is_nan() || rn_next >= rn {
                break;
            }
            st = next;
            r = sub2(self.point(st), u);
            rn = rn_next;
        }
        st
    }

    /// Whether the corners form a strictly convex, counter-clockwise quadrilateral: every
    /// corner turns left. False for non-finite values.
    pub fn is_convex(&self) -> bool {
        let k = self.corners();
        (0..4).all(|i| {
            let turn = cross2(sub2(k[(i + 1) % 4], k[i]), sub2(k[(i + 2) % 4], k[(i + 1) % 4]));
            turn.is_finite() && turn > 0.0
        })
    }

    /// How far the chart's proportions are from the face's on the surface, given the curve
    /// lengths of its four sides: the largest factor by which the ratio of two of its side
    /// lengths differs from the ratio of those sides' curve lengths (1 when proportional;
    /// infinite for a side of length zero).
    pub fn shape_deviation(&self, curve_lengths: &[f64; 4]) -> f64 {
        let k = self.corners();
        let side: [f64; 4] = std::array::from_fn(|i| norm2(sub2(k[(i + 1) % 4], k[i])));
        let ratio: [f64; 4] = std::array::from_fn(|i| side[i] / curve_lengths[i]);
        let (low, high) = ratio.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &r| (l.min(r), h.max(r)));
        let deviation = high / low;
        if deviation.is_nan() { f64::INFINITY } else { deviation }
    }

    /// The chart's signed area (shoelace), positive for a counter-clockwise chart.
    pub fn area(&self) -> f64 {
        let k = self.corners();
        0.5 * (0..4).map(|i| cross2(k[i], k[(i + 1) % 4])).sum::<f64>()
    }

    /// Non-degenerate enough to optimize from: finite, `a > 0`, every edge longer than a
    /// tiny fraction of the longest, every corner angle at least ~1e-6 rad away from 0 and
    /// π (convex, hence positive area).
    fn is_well_shaped(&self) -> bool {
        if !self.x.iter().all(|v| v.is_finite()) || !positive(self.x[0]) {
            return false;
        }
        let k = self.corners();
        let edges: Vec<[f64; 2]> = (0..4).map(|i| sub2(k[(i + 1) % 4], k[i])).collect();
        let lengths: Vec<f64> = edges.iter().map(|&v| norm2(v)).collect();
        let longest = lengths.iter().fold(0.0f64, |m, &l| m.max(l));
        if !positive(longest) || lengths.iter().any(|&l| !positive(l - 1e-9 * longest)) {
            return false;
        }
        (0..4).all(|i| {
            let j = (i + 1) % 4;
            cross2(edges[i], edges[j]) >= 1e-6 * lengths[i] * lengths[j]
        })
    }
}

/// One triangle of a chart's patch: the bilinear coordinates of its three vertices and its
/// rest shape (eq. 8).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChartTriangle {
    /// Bilinear coordinates `(sᵢ, tᵢ)` of the vertices w.r.t. the chart (inverse of eq. 9).
    pub st: [[f64; 2]; 3],
    /// `P = [p1−p0, p2−p0]`: the triangle's 3D edges in a local orthonormal 2D frame of the
    /// triangle, as columns (row-major storage: `rest[row][col]`). See [`rest_frame`].
    pub rest: [[f64; 2]; 2],
    /// The surface triangle's area, the weight `A_{φ⁻¹(t)}` of eq. 10.
    pub area: f64,
}

impl ChartTriangle {
    /// The triangle with bilinear coordinates `st` at 3D vertices `p` (rest shape and area
    /// from [`rest_frame`]).
    pub fn new(st: [[f64; 2]; 3], p: [[f64; 3]; 3]) -> ChartTriangle {
        let (rest, area) = rest_frame(p[0], p[1], p[2]);
        ChartTriangle { st, rest, area }
    }
}

/// The rest shape of a 3D triangle for eq. 8: `P = [p1−p0, p2−p0]` in the triangle's own
/// orthonormal 2D frame (first axis along `p1 − p0`, second axis in the triangle's plane
/// towards `p2`), so `P = [[|p1−p0|, (p2−p0)·x̂], [0, (p2−p0)·ŷ]]` has `det P = 2·area ≥ 0`.
/// Also returns the area.
///
/// A degenerate triangle (coincident or collinear vertices, non-finite input) gets area 0 and
/// a singular `P`; [`energy`] skips such triangles.
pub fn rest_frame(p0: [f64; 3], p1: [f64; 3], p2: [f64; 3]) -> ([[f64; 2]; 2], f64) {
    let e1 = sub(p1, p0);
    let e2 = sub(p2, p0);
    let l1 = dot(e1, e1).sqrt();
    let n = cross(e1, e2);
    let nn = dot(n, n).sqrt();
    if !positive(l1) || !positive(nn) {
        let l1 = if l1.is_finite() { l1 } else { 0.0 };
        return ([[l1, 0.0], [0.0, 0.0]], 0.0);
    }
    let x = [e1[0] / l1, e1[1] / l1, e1[2] / l1];
    // ŷ = n̂ × x̂: in the plane, with (p2−p0)·ŷ = |n| / |e1| > 0.
    let y = cross([n[0] / nn, n[1] / nn, n[2] / nn], x);
    ([[l1, dot(e2, x)], [0.0, dot(e2, y)]], 0.5 * nn)
}

/// `P⁻¹`, or `None` if `P` is not finite or numerically singular (`|det P| ≤ 1e-12·‖P‖²_F`).
fn rest_inverse(p: &Mat2) -> Option<Mat2> {
    let det = det(p);
    let f2 = frob2(p);
    if !det.is_finite() || !f2.is_finite() || det.abs() <= 1e-12 * f2 {
        return None;
    }
    Some(inverse_with(p, det))
}

/// Whether a triangle's image `u` is flipped or collapsed: its signed area is negative or, up
/// to rounding, zero (the sine of its angle at `u[0]` below 1e-12). A triangle whose three
/// vertices lie on one chart side (eight.obj has two, at a T-vertex) collapses exactly, and
/// the sign of its rounded area would otherwise be noise.
pub fn folded(u: [[f64; 2]; 3]) -> bool {
    let (a, b) = ([u[1][0] - u[0][0], u[1][1] - u[0][1]], [u[2][0] - u[0][0], u[2][1] - u[0][1]]);
    let signed = a[0] * b[1] - a[1] * b[0];
    signed <= 0.0 || signed * signed <= 1e-24 * (a[0] * a[0] + a[1] * a[1]) * (b[0] * b[0] + b[1] * b[1])
}

/// Isometric distortion of a triangle, eq. 7: `‖JᵀJ − I‖²_F` with `J = [u1−u0, u2−u0] P⁻¹`
/// (eq. 8), `u` the parameter positions of its vertices and `rest = P` its rest shape (see
/// [`ChartTriangle::rest`]). `J` is the linear part of the map near a point (eq. 5); with its
/// singular values σ₁, σ₂ (eq. 6) the distortion is (σ₁² − 1)² + (σ₂² − 1)², zero exactly
/// for isometries (rotations, with or without reflection); `2(σ²−1)²` for a uniform scale by σ.
///
/// Returns `f64::INFINITY` if `P` is singular (degenerate rest triangle): no Jacobian exists.
pub fn distortion(u: [[f64; 2]; 3], rest: [[f64; 2]; 2]) -> f64 {
    let Some(pinv) = rest_inverse(&rest) else {
        return f64::INFINITY;
    };
    let d = [[u[1][0] - u[0][0], u[2][0] - u[0][0]], [u[1][1] - u[0][1], u[2][1] - u[0][1]]];
    let j = mat_mul(&d, &pinv);
    let mut m = mat_mul(&transpose(&j), &j);
    m[0][0] -= 1.0;
    m[1][1] -= 1.0;
    frob2(&m)
}

/// The chart energy of eq. 10, `E(x) = Σ_t A_t · ‖J_tᵀJ_t − I‖²_F` with `u_i(x)` from eq. 9,
/// and its exact gradient and Hessian w.r.t. the free variables of `kind` (5 for `Quad`:
/// `a, b, c, d, e`; 2 for `Rect`: `a, c`; none for `Unit`).
///
/// `J = Σₖ xₖ Gₖ` is linear in the variables; with `M = JᵀJ − I` and `Sₖ = GₖᵀJ + JᵀGₖ`
/// (method-notes §7):
/// `∂E/∂xₖ = 2⟨M, Sₖ⟩`, `∂²E/∂xₖ∂xₗ = 2⟨Sₗ, Sₖ⟩ + 2⟨M, GₖᵀGₗ + GₗᵀGₖ⟩`, summed with the
/// area weights. The value is evaluated at `x` as given; for `Rect` the derivatives are
/// along `a` (moving `d` with it) and `c` (moving `e`), so `x` should satisfy the rectangle
/// constraints.
///
/// Triangles with a non-positive or non-finite area, a non-finite `st` or a singular rest
/// shape are skipped (they carry no area weight), so the result is finite for finite `x`
/// short of overflow. Returns `(E, gradient, Hessian)` with `gradient.len() == kind.dofs()`
/// and the Hessian `dofs × dofs`, symmetric.
pub fn energy(
    kind: ChartKind,
    x: &[f64; 5],
    tris: &[ChartTriangle],
) -> (f64, Vec<f64>, Vec<Vec<f64>>) {
    energy_of(x, &generators(kind, tris), directions(kind).len())
}

/// A usable triangle's part of eq. 10 that does not depend on the chart: its weight, the
/// generators `Gₖ` of its Jacobian (see [`triangle_generators`]) and their combinations
/// along the free directions of the chart's kind. [`optimize`] computes them once.
struct Generators {
    weight: f64,
    gx: [Mat2; 5],
    along: [Mat2; 5],
}

fn generators(kind: ChartKind, tris: &[ChartTriangle]) -> Vec<Generators> {
    let dirs = directions(kind);
    tris.iter()
        .filter_map(triangle_generators)
        .map(|(weight, gx)| {
            let mut along = [[[0.0; 2]; 2]; 5];
            for (g, dir) in along.iter_mut().zip(dirs) {
                for (dk, gk) in dir.iter().zip(&gx) {
                    if *dk != 0.0 {
                        *g = add_scaled(g, *dk, gk);
                    }
                }
            }
            Generators { weight, gx, along }
        })
        .collect()
}

/// [`energy`] from precomputed [`generators`], with `n` free variables.
fn energy_of(x: &[f64; 5], gens: &[Generators], n: usize) -> (f64, Vec<f64>, Vec<Vec<f64>>) {
    let mut value = 0.0;
    let mut grad = vec![0.0; n];
    let mut hess = vec![vec![0.0; n]; n];
    let mut sz = [[[0.0; 2]; 2]; 5];
    for Generators { weight: w, gx, along: gz } in gens {
        let w = *w;
        let (j, m) = strain(x, gx);
        value += w * frob2(&m);
        for k in 0..n {
            let gtj = mat_mul(&transpose(&gz[k]), &j);
            sz[k] = [
                [2.0 * gtj[0][0], gtj[0][1] + gtj[1][0]],
                [gtj[0][1] + gtj[1][0], 2.0 * gtj[1][1]],
            ];
            grad[k] += w * 2.0 * inner(&m, &sz[k]);
        }
        for k in 0..n {
            let gkt = transpose(&gz[k]);
            for l in 0..=k {
                // ⟨M, GₖᵀGₗ + GₗᵀGₖ⟩ = 2⟨M, GₖᵀGₗ⟩ since M is symmetric.
                let hkl = 2.0 * inner(&sz[l], &sz[k]) + 4.0 * inner(&m, &mat_mul(&gkt, &gz[l]));
                hess[k][l] += w * hkl;
            }
        }
    }
    for k in 1..n {
        let (upper, lower) = hess.split_at_mut(k);
        for (l, row) in upper.iter_mut().enumerate() {
            row[k] = lower[0][l];
        }
    }
    (value, grad, hess)
}

/// Eq. 10's value alone at `x`: a sum of non-negative terms, exact to rounding (the line
/// search compares values this close).
fn energy_value(x: &[f64; 5], gens: &[Generators]) -> f64 {
    let mut value = 0.0;
    for Generators { weight, gx, .. } in gens {
        value += weight * frob2(&strain(x, gx).1);
    }
    value
}

/// A triangle's Jacobian `J = Σₖ xₖ Gₖ` and its strain `M = JᵀJ − I` (eq. 7).
fn strain(x: &[f64; 5], gx: &[Mat2; 5]) -> (Mat2, Mat2) {
    let mut j = [[0.0; 2]; 2];
    for (xk, gk) in x.iter().zip(gx) {
        j = add_scaled(&j, *xk, gk);
    }
    let mut m = mat_mul(&transpose(&j), &j);
    m[0][0] -= 1.0;
    m[1][1] -= 1.0;
    (j, m)
}

/// Eq. 10 as a polynomial in the free variables `z`, for its gradient and Hessian without a
/// pass over the triangles. With `J = Σᵢ zᵢ Hᵢ` (`Hᵢ` the generators along the free
/// directions), `JᵀJ = Σ_{i≤j} zᵢzⱼ S_ij` with `S_ii = HᵢᵀHᵢ`, `S_ij = HᵢᵀHⱼ + HⱼᵀHᵢ`; so with
/// `c_a = zᵢzⱼ` for the pairs `a = (i, j)`,
/// `E = Σ_ab c_a c_b Q4_ab − 2 Σ_a c_a Q2_a + 2 Σ A_t`, where `Q4_ab = Σ_t A_t ⟨S_a, S_b⟩` and
/// `Q2_a = Σ_t A_t tr S_a` are summed once per [`optimize`]. Then with `D_ak = ∂c_a/∂z_k`
/// and `r = Q4 c − Q2`: `∇E = 2 Dᵀr` and `∇²E = 2 DᵀQ4 D + 2 Σ_a r_a ∂²c_a`. Its value
/// cancels large terms near an isometry, so the value comes from [`energy_value`].
struct Moments {
    n: usize,
    pairs: Vec<(usize, usize)>,
    q4: Vec<Vec<f64>>,
    q2: Vec<f64>,
}

impl Moments {
    fn new(gens: &[Generators], n: usize) -> Moments {
        let pairs: Vec<(usize, usize)> = (0..n).flat_map(|j| (0..=j).map(move |i| (i, j))).collect();
        let np = pairs.len();
        let mut q4 = vec![vec![0.0; np]; np];
        let mut q2 = vec![0.0; np];
        let mut sa = vec![[[0.0; 2]; 2]; np];
        for g in gens {
            for (s, &(i, j)) in sa.iter_mut().zip(&pairs) {
                let p = mat_mul(&transpose(&g.along[i]), &g.along[j]);
                *s = if i == j { p } else { add_scaled(&p, 1.0, &transpose(&p)) };
            }
            for a in 0..np {
                q2[a] += g.weight * (sa[a][0][0] + sa[a][1][1]);
                for b in 0..=a {
                    q4[a][b] += g.weight * inner(&sa[a], &sa[b]);
                }
            }
        }
        for a in 0..np {
            for b in 0..a {
                q4[b][a] = q4[a][b];
            }
        }
        Moments { n, pairs, q4, q2 }
    }

    /// The gradient and Hessian of eq. 10 at the free variables `z`.
    fn derivatives(&self, z: &[f64]) -> (Vec<f64>, Vec<Vec<f64>>) {
        let (n, np) = (self.n, self.pairs.len());
        let c: Vec<f64> = self.pairs.iter().map(|&(i, j)| z[i] * z[j]).collect();
        let r: Vec<f64> =
            (0..np).map(|a| self.q4[a].iter().zip(&c).map(|(q, cb)| q * cb).sum::<f64>() - self.q2[a]).collect();
        // D_ak = ∂c_a/∂z_k: z_j at k = i plus z_i at k = j.
        let mut d = vec![vec![0.0; n]; np];
        for (a, &(i, j)) in self.pairs.iter().enumerate() {
            d[a][i] += z[j];
            d[a][j] += z[i];
        }
        let mut grad = vec![0.0; n];
        let mut hess = vec![vec![0.0; n]; n];
        for a in 0..np {
            for k in 0..n {
                grad[k] += 2.0 * d[a][k] * r[a];
            }
            let (i, j) = self.pairs[a];
            // ∂²c_a/∂z_i∂z_j = 1, and 2 on the diagonal when i = j.
            hess[i][j] += 2.0 * r[a];
            hess[j][i] += 2.0 * r[a];
        }
        let qd: Vec<Vec<f64>> =
            (0..np).map(|a| (0..n).map(|l| (0..np).map(|b| self.q4[a][b] * d[b][l]).sum()).collect()).collect();
        for k in 0..n {
            for l in 0..n {
                hess[k][l] += 2.0 * (0..np).map(|a| d[a][k] * qd[a][l]).sum::<f64>();
            }
        }
        (grad, hess)
    }
}

/// For a usable triangle: its weight and `Gₖ = [B1ₖ − B0ₖ, B2ₖ − B0ₖ] P⁻¹` for the five chart
/// coordinates, where `Bᵢₖ` is column k of `∂uᵢ/∂x` (eq. 9), so that `J = Σₖ xₖ Gₖ`.
fn triangle_generators(tri: &ChartTriangle) -> Option<(f64, [Mat2; 5])> {
    if !positive(tri.area) {
        return None;
    }
    if !tri.st.iter().flatten().all(|v| v.is_finite()) {
        return None;
    }
    let pinv = rest_inverse(&tri.rest)?;
    // ∂u/∂x of eq. 9 at each vertex, as (x-row, y-row) columns for a, b, c, d, e.
    let b = tri.st.map(|[s, t]| {
        let (w1, w2, w3) = (s * (1.0 - t), s * t, (1.0 - s) * t);
        [[w1, 0.0], [w3, 0.0], [0.0, w3], [w2, 0.0], [0.0, w2]]
    });
    let mut gx = [[[0.0; 2]; 2]; 5];
    for (k, gk) in gx.iter_mut().enumerate() {
        let d = [
            [b[1][k][0] - b[0][k][0], b[2][k][0] - b[0][k][0]],
            [b[1][k][1] - b[0][k][1], b[2][k][1] - b[0][k][1]],
        ];
        *gk = mat_mul(&d, &pinv);
    }
    Some((tri.area, gx))
}

/// Settings of [`optimize`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OptimizeOptions {
    /// Maximum number of Newton iterations. Default 50.
    pub max_iterations: usize,
    /// Stop when the relative gradient norm `‖∇E‖·L / A` falls below this, with `L` the
    /// chart's largest coordinate and `A` the total area of the usable triangles (so the test
    /// does not depend on units). Default `1e-12`.
    pub tolerance: f64,
}

impl Default for OptimizeOptions {
    fn default() -> Self {
        OptimizeOptions { max_iterations: 50, tolerance: 1e-12 }
    }
}

/// Why [`optimize`] stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// The relative gradient norm fell below [`OptimizeOptions::tolerance`].
    Converged,
    /// [`OptimizeOptions::max_iterations`] Newton steps were taken.
    MaxIterations,
    /// No step along the search direction lowered the energy while keeping the chart
    /// well-shaped (typically the rounding floor near a minimum, or the optimum pushing the
    /// chart towards degeneracy). The best chart found is returned.
    LineSearchFailed,
    /// Nothing to do: a `Unit` chart, or no triangle with positive area and a regular rest
    /// shape. The chart is returned unchanged.
    NothingToOptimize,
    /// The start chart is degenerate (non-finite, `a ≤ 0`, not convex, or nearly so) or its
    /// energy is not finite. The chart is returned unchanged.
    InvalidStart,
}

/// What [`optimize`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OptimizeReport {
    /// Energy (eq. 10) of the start chart (as constrained to its kind).
    pub energy_before: f64,
    /// Energy of the returned chart; never above `energy_before`.
    pub energy_after: f64,
    /// Newton steps accepted.
    pub iterations: usize,
    /// Relative gradient norm `‖∇E‖·L / A` at the returned chart (0 when there is nothing to
    /// optimize).
    pub gradient_norm: f64,
    /// Why it stopped.
    pub termination: Termination,
}

/// Chart optimization (paper Section 3.1): minimizes the energy of eq. 10 over the free
/// variables of `chart.kind` by Newton's method with a backtracking (Armijo) line search.
///
/// Where the Hessian is not positive definite it is shifted, `H + μI`, with μ grown until a
/// Cholesky factorization succeeds. Steps that make the chart non-finite, `a ≤ 0`,
/// non-convex or nearly degenerate (a corner angle within ~1e-6 rad of 0 or π) are rejected
/// like steps that raise the energy, so the returned chart is always well-shaped when the
/// start is. The start chart is first constrained to its kind ([`Chart::free_vars`]).
///
/// Never returns NaN: a `Unit` chart, a degenerate start or data without usable triangles
/// give the start chart back (see [`Termination`]); otherwise the result's energy is at most
/// the start's.
pub fn optimize(
    chart: &Chart,
    tris: &[ChartTriangle],
    opts: &OptimizeOptions,
) -> (Chart, OptimizeReport) {
    let kind = chart.kind;
    let start = chart.with_free_vars(&chart.free_vars());
    let gens = generators(kind, tris);
    let n = kind.dofs();
    let e0 = energy_value(&start.x, &gens);
    let unchanged = |termination| {
        let e = finite_or_inf(e0);
        let report = OptimizeReport {
            energy_before: e,
            energy_after: e,
            iterations: 0,
            gradient_norm: 0.0,
            termination,
        };
        (start, report)
    };
    if n == 0 {
        return unchanged(Termination::NothingToOptimize);
    }
    let total_area: f64 = gens.iter().map(|g| g.weight).sum();
    if total_area <= 0.0 {
        return unchanged(Termination::NothingToOptimize);
    }
    if !start.is_well_shaped() || !e0.is_finite() || !total_area.is_finite() {
        return unchanged(Termination::InvalidStart);
    }

    let moments = Moments::new(&gens, n);
    let mut z = start.free_vars();
    let mut current = start;
    let (mut g, mut h) = moments.derivatives(&z);
    let mut e = e0;
    let rel_grad = |c: &Chart, g: &[f64]| {
        let l = c.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        g.iter().map(|v| v * v).sum::<f64>().sqrt() * l / total_area
    };
    let mut iterations = 0;
    let termination = loop {
        let gn = rel_grad(&current, &g);
        if !gn.is_finite() {
            break Termination::LineSearchFailed;
        }
        if gn <= opts.tolerance {
            break Termination::Converged;
        }
        if iterations >= opts.max_iterations {
            break Termination::MaxIterations;
        }
        let mut p =
            shifted_newton_direction(&h, &g).unwrap_or_else(|| g.iter().map(|v| -v).collect());
        let mut slope: f64 = p.iter().zip(&g).map(|(a, b)| a * b).sum();
        if slope.is_nan() || slope >= 0.0 {
            p = g.iter().map(|v| -v).collect();
            slope = -g.iter().map(|v| v * v).sum::<f64>();
        }
        // Armijo decrease; or, once the decrease is below the rounding noise of E, a step
        // that keeps E within that noise and shrinks the gradient (Newton near a minimum
        // with E > 0, where the energy can no longer tell better from worse).
        let g_norm = g.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut accepted = None;
        let mut alpha = 1.0;
        for _ in 0..60 {
            let zc: Vec<f64> = z.iter().zip(&p).map(|(zi, pi)| zi + alpha * pi).collect();
            let cand = start.with_free_vars(&zc);
            if cand.is_well_shaped() {
                let ec = energy_value(&cand.x, &gens);
                let (gc, hc) = moments.derivatives(&zc);
                let gc_norm = gc.iter().map(|v| v * v).sum::<f64>().sqrt();
                let armijo = ec <= e + 1e-4 * alpha * slope && ec < e;
                let flat = ec <= e + ENERGY_NOISE * e && gc_norm < g_norm;
                if ec.is_finite() && (armijo || flat) {
                    accepted = Some((zc, cand, (ec, gc, hc)));
                    break;
                }
            }
            alpha *= 0.5;
        }
        let Some((zc, cand, eval)) = accepted else {
            break Termination::LineSearchFailed;
        };
        z = zc;
        current = cand;
        (e, g, h) = eval;
        iterations += 1;
    };
    if e.is_nan() || e > e0 {
        // Only the rounding-noise steps can get here: the start was already optimal.
        return unchanged(termination);
    }
    let report = OptimizeReport {
        energy_before: e0,
        energy_after: e,
        iterations,
        gradient_norm: finite_or_inf(rel_grad(&current, &g)),
        termination,
    };
    (current, report)
}

fn finite_or_inf(v: f64) -> f64 {
    if v.is_nan() {
        f64::INFINITY
    } else {
        v
    }
}

/// Relative rounding noise of an evaluation of [`energy`]: a sum of non-negative terms.
const ENERGY_NOISE: f64 = 1e-13;

/// Solves `(H + μI) p = −g` with the smallest μ ≥ 0 (grown from `1e-3·‖H‖_F`, doubling) for
/// which the Cholesky factorization succeeds (Nocedal & Wright, Alg. 3.3). `None` if `H`
/// is zero or non-finite.
fn shifted_newton_direction(h: &[Vec<f64>], g: &[f64]) -> Option<Vec<f64>> {
    let n = g.len();
    let norm = h.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
    if !positive(norm) {
        return None;
    }
    let beta = 1e-3 * norm;
    let min_diag = (0..n).map(|i| h[i][i]).fold(f64::INFINITY, f64::min);
    let mut mu = if min_diag > 0.0 { 0.0 } else { beta - min_diag };
    for _ in 0..100 {
        if let Some(l) = cholesky(h, mu) {
            // L y = −g, then Lᵀ p = y.
            let mut y = vec![0.0; n];
            for i in 0..n {
                let s: f64 = (0..i).map(|k| l[i][k] * y[k]).sum();
                y[i] = (-g[i] - s) / l[i][i];
            }
            let mut p = vec![0.0; n];
            for i in (0..n).rev() {
                let s: f64 = (i + 1..n).map(|k| l[k][i] * p[k]).sum();
                p[i] = (y[i] - s) / l[i][i];
            }
            return p.iter().all(|v| v.is_finite()).then_some(p);
        }
        mu = (2.0 * mu).max(beta);
    }
    None
}

/// Lower Cholesky factor of `H + μI`, or `None` if a pivot is not strictly positive.
fn cholesky(h: &[Vec<f64>], mu: f64) -> Option<Vec<Vec<f64>>> {
    let n = h.len();
    let mut l = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..=i {
            let s: f64 = (0..j).map(|k| l[i][k] * l[j][k]).sum();
            if i == j {
                let d = h[i][i] + mu - s;
                if !positive(d) {
                    return None;
                }
                l[i][i] = d.sqrt();
            } else {
                l[i][j] = (h[i][j] - s) / l[j][j];
            }
        }
    }
    Some(l)
}

/// Strictly positive and finite (false for NaN).
fn positive(v: f64) -> bool {
    v > 0.0 && v.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift64*), uniform in [0, 1).
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
        }

        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }
    }

    /// Q's bilinear map with corners in eq. 9 order: `(1−s)(1−t)q0 + s(1−t)q1 + st q2 + (1−s)t q3`.
    fn bilinear(q: [[f64; 2]; 4], s: f64, t: f64) -> [f64; 2] {
        let w = [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
        let mut p = [0.0; 2];
        for (wi, qi) in w.iter().zip(&q) {
            p[0] += wi * qi[0];
            p[1] += wi * qi[1];
        }
        p
    }

    /// A rigid motion of the plane into 3D: rotate about an oblique axis, then translate.
    fn embed(p: [f64; 2]) -> [f64; 3] {
        let (axis, angle) = ([1.0f64, 2.0, -0.5], 0.9f64);
        let n = dot(axis, axis).sqrt();
        let k = [axis[0] / n, axis[1] / n, axis[2] / n];
        let v = [p[0], p[1], 0.0];
        let (s, c) = angle.sin_cos();
        let kv = cross(k, v);
        let kd = dot(k, v);
        let r: Vec<f64> = (0..3).map(|i| v[i] * c + kv[i] * s + k[i] * kd * (1.0 - c)).collect();
        [r[0] + 3.0, r[1] - 1.0, r[2] + 0.25]
    }

    /// An `n × n` grid in the bilinear domain mapped onto the planar quad `q` and placed in
    /// 3D: the surface is `q` itself, the bilinear coordinates the grid parameters.
    fn grid_patch(q: [[f64; 2]; 4], n: usize) -> Vec<ChartTriangle> {
        let st = |i: usize, j: usize| [i as f64 / n as f64, j as f64 / n as f64];
        let pos = |v: [f64; 2]| embed(bilinear(q, v[0], v[1]));
        let mut tris = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (st(i, j), st(i + 1, j), st(i + 1, j + 1), st(i, j + 1));
                for tri in [[a, b, c], [a, c, d]] {
                    tris.push(ChartTriangle::new(tri, tri.map(pos)));
                }
            }
        }
        tris
    }

    /// `q` moved so that q0 is at the origin and q1 on +x, as chart variables.
    fn canonical(q: [[f64; 2]; 4]) -> [f64; 5] {
        let e = sub2(q[1], q[0]);
        let (s, c) = (-e[1].atan2(e[0])).sin_cos();
        let place = |p: [f64; 2]| {
            let v = sub2(p, q[0]);
            [c * v[0] - s * v[1], s * v[0] + c * v[1]]
        };
        let [_, c1, c2, c3] = q.map(place);
        [c1[0], c3[0], c3[1], c2[0], c2[1]]
    }

    fn mean_edge(q: [[f64; 2]; 4]) -> f64 {
        (0..4).map(|i| norm2(sub2(q[(i + 1) % 4], q[i]))).sum::<f64>() / 4.0
    }

    fn random_triangles(rng: &mut Rng, count: usize) -> Vec<ChartTriangle> {
        (0..count)
            .map(|_| {
                let st = [0; 3].map(|_| [rng.range(0.0, 1.0), rng.range(0.0, 1.0)]);
                let p = [0; 3]
                    .map(|_| [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)]);
                ChartTriangle::new(st, p)
            })
            .collect()
    }

    fn assert_derivatives_match(chart: &Chart, tris: &[ChartTriangle]) {
        let kind = chart.kind;
        let z = chart.free_vars();
        let n = z.len();
        let (_, g, h) = energy(kind, &chart.x, tris);
        let at = |k: usize, d: f64| {
            let mut zz = z.clone();
            zz[k] += d;
            energy(kind, &chart.with_free_vars(&zz).x, tris)
        };
        let step = 1e-5;
        let mut g_err = 0.0f64;
        let mut h_err = 0.0f64;
        for k in 0..n {
            let (ep, gp, _) = at(k, step);
            let (em, gm, _) = at(k, -step);
            g_err = g_err.max(((ep - em) / (2.0 * step) - g[k]).abs());
            for l in 0..n {
                h_err = h_err.max(((gp[l] - gm[l]) / (2.0 * step) - h[k][l]).abs());
            }
        }
        let g_scale = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let h_scale = h.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(g_scale > 0.0 && h_scale > 0.0);
        assert!(g_err / g_scale < 1e-6, "{kind:?}: gradient rel. error {}", g_err / g_scale);
        assert!(h_err / h_scale < 1e-6, "{kind:?}: Hessian rel. error {}", h_err / h_scale);
        for (k, row) in h.iter().enumerate() {
            for (l, v) in row.iter().enumerate() {
                assert_eq!(*v, h[l][k]);
            }
        }
    }

    /// A convex general chart near the unit square's proportions.
    fn random_quad(rng: &mut Rng) -> Chart {
        Chart::quad([
            rng.range(0.5, 2.0),
            rng.range(-0.4, 0.4),
            rng.range(0.5, 2.0),
            rng.range(0.8, 2.5),
            rng.range(0.5, 2.0),
        ])
    }

    #[test]
    fn moments_give_the_derivatives_of_the_triangle_sums() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for _ in 0..20 {
            let tris = random_triangles(&mut rng, 15);
            let quad = random_quad(&mut rng);
            let rect = Chart::rect(rng.range(0.3, 2.0), rng.range(0.3, 2.0));
            for chart in [quad, rect] {
                let gens = generators(chart.kind, &tris);
                let n = chart.kind.dofs();
                let (e, g, h) = energy_of(&chart.x, &gens, n);
                let (gm, hm) = Moments::new(&gens, n).derivatives(&chart.free_vars());
                assert!((energy_value(&chart.x, &gens) - e).abs() <= 1e-14 * e);
                let scale = g.iter().chain(h.iter().flatten()).fold(0.0f64, |m, v| m.max(v.abs()));
                for (a, b) in g.iter().chain(h.iter().flatten()).zip(gm.iter().chain(hm.iter().flatten())) {
                    assert!((a - b).abs() <= 1e-12 * scale, "{:?}: {a} vs {b}", chart.kind);
                }
            }
        }
    }

    #[test]
    fn gradient_and_hessian_match_finite_differences() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..20 {
            let tris = random_triangles(&mut rng, 12);
            let quad = random_quad(&mut rng);
            assert_derivatives_match(&quad, &tris);
            let rect = Chart::rect(rng.range(0.3, 2.0), rng.range(0.3, 2.0));
            assert_derivatives_match(&rect, &tris);
        }
    }

    #[test]
    fn energy_of_unit_chart_has_no_derivatives() {
        let mut rng = Rng(7);
        let tris = random_triangles(&mut rng, 5);
        let (e, g, h) = energy(ChartKind::Unit, &Chart::unit(1.0).x, &tris);
        assert!(e > 0.0 && g.is_empty() && h.is_empty());
        assert_eq!(ChartKind::Quad.dofs(), 5);
        assert_eq!(ChartKind::Rect.dofs(), 2);
        assert_eq!(ChartKind::Unit.dofs(), 0);
    }

    #[test]
    fn energy_is_area_weighted_sum_of_distortions() {
        let mut rng = Rng(11);
        let tris = random_triangles(&mut rng, 6);
        let chart = Chart::quad([1.3, 0.2, 0.9, 1.6, 1.1]);
        let expected: f64 =
            tris.iter().map(|t| t.area * distortion(t.st.map(|st| chart.point(st)), t.rest)).sum();
        let (e, _, _) = energy(ChartKind::Quad, &chart.x, &tris);
        assert!((e - expected).abs() <= 1e-12 * expected, "{e} vs {expected}");
    }

    const GENERAL_Q: [[f64; 2]; 4] = [[0.0, 0.0], [2.0, 0.0], [2.4, 1.3], [0.3, 1.1]];

    /// Q in general position in the plane: rotated by 0.7 rad and moved.
    fn moved(q: [[f64; 2]; 4]) -> [[f64; 2]; 4] {
        let (s, c) = 0.7f64.sin_cos();
        q.map(|p| [c * p[0] - s * p[1] + 5.0, s * p[0] + c * p[1] - 3.0])
    }

    #[test]
    fn quad_optimization_recovers_a_planar_quad() {
        let q = moved(GENERAL_Q);
        let tris = grid_patch(q, 12);
        let start = Chart::unit(mean_edge(q)).with_kind(ChartKind::Quad);
        let (chart, report) = optimize(&start, &tris, &OptimizeOptions::default());
        assert!(report.energy_after < 1e-18, "{report:?}");
        assert!(report.energy_before > 1e-2, "{report:?}");
        let expected = canonical(q);
        for (got, want) in chart.x.iter().zip(&expected) {
            assert!((got - want).abs() < 1e-9, "{:?} vs {expected:?}", chart.x);
        }
        for (got, want) in expected.iter().zip(&[2.0, 0.3, 1.1, 2.4, 1.3]) {
            assert!((got - want).abs() < 1e-12);
        }
        assert_eq!(chart.kind, ChartKind::Quad);
    }

    #[test]
    fn rect_optimization_on_a_general_quad_stays_distorted() {
        let q = moved(GENERAL_Q);
        let tris = grid_patch(q, 12);
        let unit = Chart::unit(mean_edge(q));
        let unit_energy = energy(ChartKind::Unit, &unit.x, &tris).0;
        let (rect, report) =
            optimize(&unit.with_kind(ChartKind::Rect), &tris, &OptimizeOptions::default());
        let area: f64 = tris.iter().map(|t| t.area).sum();
        assert_eq!(report.termination, Termination::Converged, "{report:?}");
        assert!(report.energy_after > 0.05 * area, "{report:?} (area {area})");
        assert!(report.energy_after < 0.5 * unit_energy, "{report:?} vs unit {unit_energy}");
        assert_eq!(rect.kind, ChartKind::Rect);
        assert_eq!(rect, Chart::rect(rect.x[0], rect.x[2]));
    }

    #[test]
    fn rect_optimization_recovers_a_rectangle() {
        let q = moved([[0.0, 0.0], [3.0, 0.0], [3.0, 1.5], [0.0, 1.5]]);
        let tris = grid_patch(q, 8);
        let start = Chart::unit(mean_edge(q)).with_kind(ChartKind::Rect);
        let (chart, report) = optimize(&start, &tris, &OptimizeOptions::default());
        assert!(report.energy_after < 1e-18, "{report:?}");
        assert!((chart.x[0] - 3.0).abs() < 1e-9 && (chart.x[2] - 1.5).abs() < 1e-9, "{chart:?}");
    }

    #[test]
    fn unit_chart_is_returned_as_is() {
        let tris = grid_patch(moved(GENERAL_Q), 4);
        let unit = Chart::unit(1.7);
        let (chart, report) = optimize(&unit, &tris, &OptimizeOptions::default());
        assert_eq!(chart, unit);
        assert_eq!(report.termination, Termination::NothingToOptimize);
        assert_eq!(report.energy_before, report.energy_after);
        assert_eq!(report.iterations, 0);
    }

    fn test_quads() -> Vec<Chart> {
        vec![
            Chart::unit(1.0),
            Chart::rect(3.0, 0.5),
            Chart::quad(canonical(GENERAL_Q)),
            Chart::quad([2.0, 0.5, 1.0, 2.5, 1.0]), // parallelogram: linear in t
            Chart::quad([3.0, 1.0, 1.0, 2.0, 1.0]), // trapezoid
            Chart::quad([1.0, -0.3, 2.0, 1.2, 0.4]), // kite-like, strongly skewed
            Chart::quad([1e-3, 2e-4, 1.2e-3, 1.1e-3, 0.9e-3]),
            Chart::quad([1e3, -200.0, 700.0, 1.4e3, 900.0]),
        ]
    }

    #[test]
    fn bilinear_coords_invert_point() {
        for chart in test_quads() {
            assert!(chart.is_convex(), "{chart:?}");
            for i in 0..=10 {
                for j in 0..=10 {
                    let st = [i as f64 / 10.0, j as f64 / 10.0];
                    let back = chart.bilinear_coords(chart.point(st));
                    let err = (back[0] - st[0]).abs().max((back[1] - st[1]).abs());
                    assert!(err < 1e-12, "{chart:?} at {st:?}: {back:?}");
                }
            }
        }
    }

    #[test]
    fn point_inverts_bilinear_coords_inside() {
        let mut rng = Rng(3);
        for chart in test_quads() {
            let k = chart.corners();
            let scale = chart.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for _ in 0..200 {
                // A convex combination of the corners lies inside a convex chart.
                let w = [0; 4].map(|_| rng.next());
                let sum: f64 = w.iter().sum();
                let mut u = [0.0; 2];
                for (wi, ki) in w.iter().zip(&k) {
                    u = add2(u, scale2(wi / sum, *ki));
                }
                let st = chart.bilinear_coords(u);
                assert!(st.iter().all(|v| (-1e-12..=1.0 + 1e-12).contains(v)), "{chart:?}: {st:?}");
                let back = chart.point(st);
                assert!(
                    norm2(sub2(back, u)) < 1e-12 * scale,
                    "{chart:?}: {u:?} -> {st:?} -> {back:?}"
                );
            }
        }
    }

    #[test]
    fn bilinear_coords_extrapolate_slightly_outside_and_never_nan() {
        let chart = Chart::quad(canonical(GENERAL_Q));
        for st in [[-0.05, 0.5], [1.05, 0.3], [0.4, -0.02], [0.6, 1.1], [-0.05, -0.05]] {
            let got = chart.bilinear_coords(chart.point(st));
            assert!(
                (got[0] - st[0]).abs() < 1e-12 && (got[1] - st[1]).abs() < 1e-12,
                "{st:?}: {got:?}"
            );
        }
        // Mildly non-convex (c2 pushed inwards past the diagonal) and degenerate charts.
        let nonconvex = Chart::quad([2.0, 0.0, 2.0, 0.8, 0.8]);
        assert!(!nonconvex.is_convex());
        let degenerate = [Chart::quad([0.0; 5]), Chart::quad([1.0, 2.0, 0.0, 3.0, 0.0])];
        let mut rng = Rng(5);
        for chart in [nonconvex].iter().chain(&degenerate) {
            for _ in 0..500 {
                let u = [rng.range(-0.5, 2.5), rng.range(-0.5, 2.5)];
                let st = chart.bilinear_coords(u);
                assert!(st[0].is_finite() && st[1].is_finite(), "{chart:?} {u:?}");
            }
        }
        for i in 0..=10 {
            for j in 0..=10 {
                let st = [i as f64 / 10.0, j as f64 / 10.0];
                let u = nonconvex.point(st);
                let back = nonconvex.bilinear_coords(u);
                assert!(norm2(sub2(nonconvex.point(back), u)) < 1e-9, "{st:?} -> {back:?}");
            }
        }
    }

    #[test]
    fn distortion_vanishes_for_rotations_and_is_known_for_scales() {
        let mut rng = Rng(17);
        for _ in 0..50 {
            let p =
                [0; 3].map(|_| [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)]);
            let (rest, area) = rest_frame(p[0], p[1], p[2]);
            assert!(area > 0.0);
            let (s, c) = rng.range(-3.0, 3.0).sin_cos();
            let sigma = rng.range(0.2, 3.0);
            let u0 = [rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)];
            let place = |scale: f64| {
                let col = |k: usize| {
                    let v = [rest[0][k], rest[1][k]];
                    add2(u0, scale2(scale, [c * v[0] - s * v[1], s * v[0] + c * v[1]]))
                };
                [u0, col(0), col(1)]
            };
            assert!(distortion(place(1.0), rest) < 1e-24);
            let expected = 2.0 * (sigma * sigma - 1.0).powi(2);
            let got = distortion(place(sigma), rest);
            assert!((got - expected).abs() <= 1e-10 * expected.max(1e-3), "{got} vs {expected}");
        }
        assert_eq!(distortion([[0.0; 2]; 3], [[1.0, 2.0], [1.0, 2.0]]), f64::INFINITY);
    }

    #[test]
    fn rest_frame_keeps_lengths_angles_and_area() {
        let (p0, p1, p2) = ([1.0, 2.0, 3.0], [2.0, 2.5, 2.0], [0.5, 3.0, 4.0]);
        let (rest, area) = rest_frame(p0, p1, p2);
        let col = |k: usize| [rest[0][k], rest[1][k]];
        let (e1, e2) = (sub(p1, p0), sub(p2, p0));
        assert!((norm2(col(0)) - dot(e1, e1).sqrt()).abs() < 1e-14);
        assert!((norm2(col(1)) - dot(e2, e2).sqrt()).abs() < 1e-14);
        assert!((dot2(col(0), col(1)) - dot(e1, e2)).abs() < 1e-14);
        let n = cross(e1, e2);
        assert!((area - 0.5 * dot(n, n).sqrt()).abs() < 1e-14);
        assert!((cross2(col(0), col(1)) - 2.0 * area).abs() < 1e-14);
        assert_eq!(rest_frame(p0, p0, p2).1, 0.0);
        assert_eq!(rest_frame(p0, p1, [3.0, 3.0, 1.0]).1, 0.0); // collinear
    }

    #[test]
    fn shape_deviation_compares_side_ratios_with_the_curves() {
        // A 2 × 1 rectangle on curves 2, 1, 2, 1 long is proportional; on 1, 1, 1, 1 it is
        // twice too wide; collapsed, infinitely off.
        let r = Chart::rect(2.0, 1.0);
        assert!((r.shape_deviation(&[2.0, 1.0, 2.0, 1.0]) - 1.0).abs() < 1e-12);
        assert!((r.shape_deviation(&[1.0; 4]) - 2.0).abs() < 1e-12);
        assert!((Chart::rect(8.0, 1.0).shape_deviation(&[1.0, 2.0, 1.0, 2.0]) - 16.0).abs() < 1e-12);
        assert_eq!(Chart::rect(0.0, 1.0).shape_deviation(&[1.0; 4]), f64::INFINITY);
    }

    #[test]
    fn chart_kinds_convert() {
        let q = Chart::quad([2.0, 0.4, 1.0, 2.6, 1.4]);
        assert_eq!(q.with_kind(ChartKind::Rect), Chart::rect(2.1, 1.2));
        let r = Chart::rect(3.0, 1.0);
        assert_eq!(r.with_kind(ChartKind::Rect), r);
        assert_eq!(r.with_kind(ChartKind::Quad), Chart::quad(r.x));
        assert_eq!(r.with_kind(ChartKind::Unit), Chart::unit(2.0));
        assert_eq!(Chart::unit(2.0).corners(), [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]);
        assert_eq!(r.free_vars(), vec![3.0, 1.0]);
        assert_eq!(q.with_free_vars(&q.free_vars()), q);
        assert_eq!(r.with_free_vars(&[2.0, 5.0]), Chart::rect(2.0, 5.0));
        assert_eq!(Chart::unit(3.0).with_free_vars(&[]), Chart::unit(3.0));
        assert!((q.area() - 0.5 * (2.0 * 1.4 + (2.6 * 1.0 - 1.4 * 0.4))).abs() < 1e-14);
        assert!(Chart::quad([-1.0, 0.0, -1.0, -1.0, -1.0]).is_convex()); // turned by π
        assert!(!Chart::quad([1.0, 0.0, -1.0, 1.0, -1.0]).is_convex()); // clockwise
        assert!(!Chart::quad([1.0, 0.0, 1.0, 1.0, f64::NAN]).is_convex());
    }

    fn assert_sane(chart: &Chart, report: &OptimizeReport) {
        assert!(chart.x.iter().all(|v| v.is_finite()), "{chart:?}");
        assert!(chart.x[0] > 0.0 && chart.is_convex() && chart.area() > 0.0, "{chart:?}");
        assert!(!report.energy_before.is_nan() && !report.energy_after.is_nan(), "{report:?}");
        assert!(report.energy_after <= report.energy_before, "{report:?}");
    }

    #[test]
    fn optimize_survives_degenerate_triangles() {
        let p = [[1.0, 1.0, 1.0], [2.0, 2.0, 2.0], [3.0, 3.0, 3.0]]; // collinear
        let st = [[0.1, 0.1], [0.5, 0.2], [0.3, 0.9]];
        let mut tris = vec![ChartTriangle::new(st, p), ChartTriangle::new(st, [p[0]; 3])];
        tris.push(ChartTriangle { st, rest: [[1.0, 0.0], [0.0, 1.0]], area: 0.0 });
        tris.push(ChartTriangle { st, rest: [[f64::NAN, 0.0], [0.0, 1.0]], area: 1.0 });
        tris.push(ChartTriangle {
            st: [[f64::NAN; 2]; 3],
            rest: [[1.0, 0.0], [0.0, 1.0]],
            area: 1.0,
        });
        tris.push(ChartTriangle { st, rest: [[1.0, 0.0], [0.0, 1.0]], area: f64::INFINITY });
        for kind in [ChartKind::Quad, ChartKind::Rect] {
            let start = Chart::unit(1.0).with_kind(kind);
            let (chart, report) = optimize(&start, &tris, &OptimizeOptions::default());
            assert_eq!(chart, start);
            assert_eq!(report.termination, Termination::NothingToOptimize);
            assert_sane(&chart, &report);
        }
        let (chart, report) = optimize(
            &Chart::unit(1.0).with_kind(ChartKind::Quad),
            &[],
            &OptimizeOptions::default(),
        );
        assert_eq!(report.termination, Termination::NothingToOptimize);
        assert_sane(&chart, &report);
    }

    #[test]
    fn optimize_keeps_charts_valid_on_flipped_and_random_data() {
        let base = grid_patch(moved(GENERAL_Q), 6);
        // Mirrored parameters: the isometry would need a reflected chart, which is not allowed.
        let mirrored: Vec<ChartTriangle> = base
            .iter()
            .map(|t| ChartTriangle { st: t.st.map(|[s, t]| [1.0 - s, t]), ..*t })
            .collect();
        // Every other triangle flipped in the parameter domain.
        let half_flipped: Vec<ChartTriangle> = base
            .iter()
            .enumerate()
            .map(|(i, t)| {
                if i % 2 == 0 {
                    ChartTriangle { st: [t.st[0], t.st[2], t.st[1]], ..*t }
                } else {
                    *t
                }
            })
            .collect();
        let mut rng = Rng(23);
        let mut garbage = random_triangles(&mut rng, 40);
        for t in garbage.iter_mut() {
            t.st = t.st.map(|_| [rng.range(-3.0, 4.0), rng.range(-3.0, 4.0)]);
        }
        // Nearly flat rest triangles pull the chart's height towards zero.
        let flat: Vec<ChartTriangle> = base
            .iter()
            .map(|t| {
                let (rest, area) = (
                    [[t.rest[0][0], t.rest[0][1]], [t.rest[1][0] * 1e-5, t.rest[1][1] * 1e-5]],
                    t.area * 1e-5,
                );
                ChartTriangle { rest, area, ..*t }
            })
            .collect();
        for data in [&mirrored, &half_flipped, &garbage, &flat] {
            for kind in [ChartKind::Quad, ChartKind::Rect] {
                for side in [1e-3, 1.0, 1e3] {
                    let start = Chart::unit(side).with_kind(kind);
                    let (chart, report) = optimize(&start, data, &OptimizeOptions::default());
                    assert_sane(&chart, &report);
                    assert_eq!(chart.kind, kind);
                }
            }
        }
    }

    #[test]
    fn optimize_refuses_a_degenerate_start() {
        let tris = grid_patch(moved(GENERAL_Q), 4);
        for start in [
            Chart::quad([0.0, 0.0, 1.0, 0.0, 1.0]),
            Chart::quad([1.0, 0.0, 1.0, f64::NAN, 1.0]),
            Chart::quad([2.0, 0.0, 2.0, 0.8, 0.8]), // non-convex
            Chart::rect(1.0, -1.0),
        ] {
            let (chart, report) = optimize(&start, &tris, &OptimizeOptions::default());
            assert_eq!(report.termination, Termination::InvalidStart, "{start:?}");
            assert!(chart == start || chart.x.iter().any(|v| v.is_nan()));
            assert!(!report.energy_before.is_nan() && !report.energy_after.is_nan());
        }
    }
}
