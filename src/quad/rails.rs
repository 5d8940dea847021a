//! Rails: the tagged curves (and the boundary) as polylines on the surface, along which the
//! relaxation slides their samples ([`super::relax`]).
//!
//! Why: a tagged curve is a straight side of its charts, and extraction spaces its samples
//! evenly in the chart, not along the curve: where the harmonic map stretches one end of a
//! side and squeezes the other, the grid lines leave the curve at a slant, and the quads at
//! the curve are skewed however their inner corners move (at --quads 4000 on fandisk's
//! automatic layout, its corners on sharp edges deviated 9.0° from right on the mean, the
//! others 5.2°). A sample that slides along its curve keeps the edge loop the user asked for,
//! exactly on the curve, and lets the grid line meet it square.

use crate::geom::{add, dot, norm, scale, sub, Vec3};

/// A curve on the surface: its points in order and the arc length at each.
#[derive(Debug, Clone, Default)]
pub struct Polyline {
    points: Vec<Vec3>,
    at: Vec<f64>,
}

impl Polyline {
    pub fn new(points: Vec<Vec3>) -> Polyline {
        let mut at = Vec::with_capacity(points.len());
        let mut s = 0.0;
        for (k, p) in points.iter().enumerate() {
            if k > 0 {
                s += norm(sub(*p, points[k - 1]));
            }
            at.push(s);
        }
        Polyline { points, at }
    }

    pub fn length(&self) -> f64 {
        self.at.last().copied().unwrap_or(0.0)
    }

    /// The point at arc length `s` (clamped to the curve).
    pub fn point(&self, s: f64) -> Vec3 {
        let k = self.segment_at(s);
        self.on_segment(k, s)
    }

    /// The unit direction of the curve at arc length `s` (zero on a curve of no length).
    pub fn tangent(&self, s: f64) -> Vec3 {
        let k = self.segment_at(s);
        let d = sub(self.points[k + 1], self.points[k]);
        let l = norm(d);
        if l > 0.0 { scale(1.0 / l, d) } else { [0.0; 3] }
    }

    /// The point of the curve between arc lengths `lo` and `hi` nearest to `p`, and its arc
    /// length.
    pub fn nearest(&self, p: Vec3, lo: f64, hi: f64) -> (f64, Vec3) {
        let (first, last) = (self.segment_at(lo), self.segment_at(hi));
        let mut best = (f64::INFINITY, lo, self.point(lo));
        for k in first..=last {
            let (a, b) = (self.at[k].max(lo), self.at[k + 1].min(hi));
            let (pa, pb) = (self.on_segment(k, a), self.on_segment(k, b));
            let d = sub(pb, pa);
            let dd = dot(d, d);
            let t = if dd > 0.0 { (dot(sub(p, pa), d) / dd).clamp(0.0, 1.0) } else { 0.0 };
            let q = add(pa, scale(t, d));
            let dist = norm(sub(p, q));
            if dist < best.0 {
                best = (dist, a + t * (b - a), q);
            }
        }
        (best.1, best.2)
    }

    /// How far the curve between arc lengths `lo` and `hi` strays from the two chords from its
    /// point at `lo` to the one at `mid` and on to the one at `hi`: the quads' edges along it.
    pub fn chord_miss(&self, lo: f64, mid: f64, hi: f64) -> f64 {
        let (a, m, b) = (self.point(lo), self.point(mid), self.point(hi));
        let first = self.at.partition_point(|&x| x <= lo);
        let last = self.at.partition_point(|&x| x < hi);
        (first..last)
            .map(|k| {
                let (p, (x, y)) = (self.points[k], if self.at[k] <= mid { (a, m) } else { (m, b) });
                let d = sub(y, x);
                let dd = dot(d, d);
                let t = if dd > 0.0 { (dot(sub(p, x), d) / dd).clamp(0.0, 1.0) } else { 0.0 };
                norm(sub(p, add(x, scale(t, d))))
            })
            .fold(0.0, f64::max)
    }

    /// The segment (from point `k` to `k + 1`) holding arc length `s`.
    fn segment_at(&self, s: f64) -> usize {
        let segments = self.points.len().saturating_sub(1).max(1);
        self.at.partition_point(|&a| a <= s).saturating_sub(1).min(segments - 1)
    }

    /// The point at arc length `s` on segment `k`.
    fn on_segment(&self, k: usize, s: f64) -> Vec3 {
        let Some(&b) = self.points.get(k + 1) else { return self.points.first().copied().unwrap_or([0.0; 3]) };
        let a = self.points[k];
        let span = self.at[k + 1] - self.at[k];
        let t = if span > 0.0 { ((s - self.at[k]) / span).clamp(0.0, 1.0) } else { 0.0 };
        add(a, scale(t, sub(b, a)))
    }
}

/// The rails of a quad mesh: per curve its polyline (empty where its samples do not slide),
/// per vertex the curve it slides on and its arc length there.
#[derive(Debug, Clone, Default)]
pub struct Rails {
    pub curves: Vec<Polyline>,
    pub on: Vec<Option<(u32, f64)>>,
}

/// A sample farther from its curve than this share of the curve's length does not slide (it
/// was put off the curve: a point the chart's triangles did not cover).
const OFF_CURVE: f64 = 1e-6;

impl Rails {
    /// Puts vertex `v` at `p` on curve `c`, if `p` is on it.
    pub fn place(&mut self, v: u32, c: u32, p: Vec3) {
        let line = &self.curves[c as usize];
        let (s, q) = line.nearest(p, 0.0, line.length());
        if norm(sub(q, p)) <= OFF_CURVE * line.length() {
            self.on[v as usize] = Some((c, s));
        }
    }

    /// Per curve, the vertices on it in order along it.
    pub fn in_order(&self) -> Vec<Vec<u32>> {
        let mut order = vec![Vec::new(); self.curves.len()];
        for (v, r) in self.on.iter().enumerate() {
            if let Some((c, _)) = r {
                order[*c as usize].push(v as u32);
            }
        }
        for list in &mut order {
            list.sort_by(|&a, &b| self.arc(a).total_cmp(&self.arc(b)));
        }
        order
    }

    fn arc(&self, v: u32) -> f64 {
        self.on[v as usize].map_or(0.0, |r| r.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn l_shape() -> Polyline {
        Polyline::new(vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0]])
    }

    #[test]
    fn points_and_tangents_follow_the_arc_length() {
        let l = l_shape();
        assert_eq!(l.length(), 3.0);
        assert_eq!(l.point(1.0), [1.0, 0.0, 0.0]);
        assert_eq!(l.point(2.5), [2.0, 0.5, 0.0]);
        assert_eq!(l.point(9.0), [2.0, 1.0, 0.0]);
        assert_eq!(l.tangent(0.5), [1.0, 0.0, 0.0]);
        assert_eq!(l.tangent(2.5), [0.0, 1.0, 0.0]);
    }

    #[test]
    fn the_nearest_point_stays_between_its_limits() {
        let l = l_shape();
        // Near the second leg, but held to the first.
        assert_eq!(l.nearest([3.0, 0.5, 0.0], 0.0, 1.5), (1.5, [1.5, 0.0, 0.0]));
        // Free to reach it.
        assert_eq!(l.nearest([3.0, 0.5, 0.0], 0.0, 3.0), (2.5, [2.0, 0.5, 0.0]));
        assert_eq!(l.nearest([0.5, 1.0, 0.0], 0.0, 3.0), (0.5, [0.5, 0.0, 0.0]));
    }

    #[test]
    fn the_chords_miss_the_bend_they_cut() {
        let l = l_shape();
        // Chords through the bend miss nothing; a chord across it misses its corner.
        assert_eq!(l.chord_miss(0.0, 2.0, 3.0), 0.0);
        // The corner (2, 0) from the chord (1.5, 0)–(2, 1).
        assert!((l.chord_miss(1.0, 1.5, 3.0) - 0.5 / 1.25f64.sqrt()).abs() < 1e-12, "{}", l.chord_miss(1.0, 1.5, 3.0));
    }

    #[test]
    fn only_points_on_a_curve_are_put_on_its_rail() {
        let mut rails = Rails { curves: vec![l_shape()], on: vec![None; 3] };
        rails.place(0, 0, [2.0, 0.75, 0.0]);
        rails.place(1, 0, [1.0, 0.5, 0.0]);
        rails.place(2, 0, [0.25, 0.0, 0.0]);
        assert_eq!(rails.on, vec![Some((0, 2.75)), None, Some((0, 0.25))]);
        assert_eq!(rails.in_order(), vec![vec![2, 0]]);
    }
}
