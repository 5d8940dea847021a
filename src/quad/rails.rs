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

use super::closest::nearest_on_segment;
use crate::geom::{add, norm, scale, sub, Vec3};

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
            let (t, q) = nearest_on_segment(p, self.on_segment(k, a), self.on_segment(k, b));
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
                norm(sub(p, nearest_on_segment(p, x, y).1))
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
    fn in_order(&self) -> Vec<Vec<u32>> {
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

/// A vertex sliding on its curve moves at most this share of the way to its neighbour there
/// in one move...
const REACH: f64 = 0.5;
/// ... and comes no nearer to it than this share of the curve's mean spacing of samples: the
/// reach alone lets a vertex creep up on its neighbour move by move, and on CGAL's boeing two
/// samples met, leaving a quad of three corners on a line.
const GAP: f64 = 0.25;

/// The vertices on rails as the relaxation moves them: where each is along its curve, and
/// its neighbours there (it never passes them).
pub struct Slides<'a> {
    rails: &'a Rails,
    on: Vec<Option<(u32, f64)>>,
    beside: Vec<[Option<u32>; 2]>,
    /// Per curve, the least distance along it between its samples ([`GAP`]).
    gap: Vec<f64>,
}

impl<'a> Slides<'a> {
    /// The vertices of `rails` where they are, among `n` vertices.
    pub fn new(rails: &'a Rails, n: usize) -> Slides<'a> {
        let on: Vec<Option<(u32, f64)>> = (0..n).map(|v| rails.on.get(v).copied().flatten()).collect();
        let order = rails.in_order();
        let mut beside = vec![[None; 2]; n];
        for list in &order {
            for (k, &v) in list.iter().enumerate() {
                beside[v as usize] = [k.checked_sub(1).map(|j| list[j]), list.get(k + 1).copied()];
            }
        }
        let gap = rails.curves.iter().zip(&order).map(|(line, list)| GAP * line.length() / (list.len() + 1) as f64).collect();
        Slides { rails, on, beside, gap }
    }

    /// Whether vertex `v` slides on a curve.
    pub fn slides(&self, v: usize) -> bool {
        self.on[v].is_some()
    }

    /// Vertex `v`'s curve, where it is along it, and where its neighbours there are.
    fn span(&self, v: usize) -> Option<(&'a Polyline, u32, f64, f64, f64)> {
        let (c, s) = self.on[v]?;
        let line = &self.rails.curves[c as usize];
        let arc = |w: Option<u32>, end: f64| w.and_then(|w| self.on[w as usize]).map_or(end, |r| r.1);
        let [before, after] = self.beside[v];
        Some((line, c, s, arc(before, 0.0), arc(after, line.length())))
    }

    /// The direction of vertex `v`'s curve where it is.
    pub fn tangent(&self, v: usize) -> Option<Vec3> {
        self.span(v).map(|(line, _, s, _, _)| line.tangent(s))
    }

    /// Where a move of vertex `v` toward `target` lands on its curve, [`REACH`] and [`GAP`]
    /// from its neighbours there, and its arc length.
    pub fn land(&self, v: usize, target: Vec3) -> Option<(Vec3, f64)> {
        let (line, c, s, lo, hi) = self.span(v)?;
        let gap = self.gap[c as usize];
        let (lo, hi) = ((s - REACH * (s - lo)).max(lo + gap).min(s), (s + REACH * (hi - s)).min(hi - gap).max(s));
        let (arc, q) = line.nearest(target, lo, hi);
        Some((q, arc))
    }

    /// How far the curve strays from the chords to vertex `v`'s neighbours there with `v` at
    /// arc length `arc` ([`Polyline::chord_miss`]); 0 off rails.
    pub fn chord_miss(&self, v: usize, arc: f64) -> f64 {
        self.span(v).map_or(0.0, |(line, _, _, lo, hi)| line.chord_miss(lo, arc, hi))
    }

    /// Where vertex `v` is along its curve.
    pub fn arc(&self, v: usize) -> Option<f64> {
        self.on[v].map(|r| r.1)
    }

    /// Vertex `v` moved to arc length `arc` along its curve.
    pub fn moved(&mut self, v: usize, arc: f64) {
        if let Some(r) = &mut self.on[v] {
            r.1 = arc;
        }
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
