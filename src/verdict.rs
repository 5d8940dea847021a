//! A verdict on every result: the warnings of the report (cli.md, "Report"), each saying in
//! words what a user should look at before trusting the quad mesh, with a point on the
//! surface and the layout entries it names. A clean result has none.
//!
//! The limits are stated against scales every result has, never tuned to a mesh:
//! - the quads miss the surface by more than [`MISSED_DIAGONAL`] of the bounding-box
//!   diagonal *and* more than [`MISSED_EDGES`] edge lengths: a quad mesh of edge length h
//!   cuts corners and creases by up to about h wherever no edge loop follows them, so only a
//!   miss beyond that says the layout or the density lost part of the shape;
//! - a face whose typical length error exceeds [`DISTORTED_RATIO`] times the area-weighted
//!   median face's and [`DISTORTED_FLOOR`] in absolute terms is "far more distorted than the
//!   others", if it holds at least [`DISTORTED_QUADS`] quads' area (a smaller face's
//!   distortion is not seen in its few quads);
//! - any flipped triangle of the final parameterization, any folded quad, and any curve whose
//!   desired count was below one half (rounding would give none) but got a segment;
//! - a curve whose segments are more than [`STRETCHED`] times longer than its faces ask for,
//!   and [`STRETCHED_SEGMENTS`] segments or more short: quads that many times longer than wide,
//!   which the equal counts of opposite sides forced through the faces and T-vertices round it.
//!   A stretched strip is where quads cut across the surface (eight's automatic layout: a curve
//!   asking for 19 segments got 2, and its quads missed the surface by 5 % of the diagonal), so
//!   the user learns which curves to look at, not only that the surface was missed. Squeezed
//!   quads (more segments than asked) stay on the surface and are not warned of.

use crate::guidance::FaceDistortion;
use crate::layout::{CurveSource, SurfaceLayout};
use crate::geom::Vec3;
use crate::param::chart::folded;
use crate::param::ParamSession;
use crate::quad::quality::Quality;
use crate::quad::QuadMesh;
use serde::Serialize;

/// A miss below this share of the bounding-box diagonal is no warning ("a few percent").
pub const MISSED_DIAGONAL: f64 = 0.05;
/// A miss below this many edge lengths is what the quads' size explains (see the module
/// documentation).
pub const MISSED_EDGES: f64 = 2.0;
/// A face is far more distorted than the others beyond this multiple of the median's length
/// error...
pub const DISTORTED_RATIO: f64 = 3.0;
/// ... and beyond this length error (half the face has lengths off by more than half).
pub const DISTORTED_FLOOR: f64 = 0.5;
/// ... in a face of at least this many quads' area (a 2 × 2 grid).
pub const DISTORTED_QUADS: f64 = 4.0;
/// A curve asking for fewer segments than this would round to none.
pub const RAISED_BELOW: f64 = 0.5;
/// A curve's segments this many times longer than its faces ask for...
pub const STRETCHED: f64 = 2.0;
/// ... and at least this many segments short (a curve asking for 2.9 segments and getting 1 is
/// a rounding, not a forced strip).
pub const STRETCHED_SEGMENTS: f64 = 2.0;
/// A quad count this far (as a share) from what the surface area asks for is a warning: the
/// area rule lands within 10 % on every sample layout (tests/quad_density.rs), and rounding
/// alone moves a coarse grid by up to 13 %.
pub const COUNT_OFF: f64 = 0.15;

/// One warning of the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Warning {
    /// `surface_missed`, `face_distorted`, `flipped_triangles`, `folded_quads`,
    /// `counts_raised`, `counts_stretched` or `quad_count_off`.
    pub kind: &'static str,
    /// What is wrong and what may help, for people.
    pub message: String,
    /// A point on the input surface to look at.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at: Option<Vec3>,
    /// The layout face it is about (the report's `faces` order).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub face: Option<usize>,
    /// Layout nodes it names (a face's corners).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub nodes: Vec<u32>,
    /// Entries of the layout's `edges` it names.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub edges: Vec<usize>,
    /// Mesh boundary loops whose pieces it names.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub boundary_loops: Vec<usize>,
    /// How many elements (triangles, quads) it counts, where it counts some.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub count: Option<usize>,
}

impl Warning {
    fn new(kind: &'static str, message: String) -> Warning {
        Warning { kind, message, at: None, face: None, nodes: Vec::new(), edges: Vec::new(), boundary_loops: Vec::new(), count: None }
    }
}

/// Faces whose length error is far above the others' (see the module documentation), at
/// edge length `h`.
pub fn distorted_faces(face_area: &[f64], measured: &FaceDistortion, h: f64) -> Vec<usize> {
    faces_above(face_area, measured, h, DISTORTED_RATIO, DISTORTED_FLOOR)
}

/// Faces of at least [`DISTORTED_QUADS`] quads' area at edge length `h` whose length error is
/// above `ratio` times the area-weighted median face's and above `floor`.
pub fn faces_above(face_area: &[f64], measured: &FaceDistortion, h: f64, ratio: f64, floor: f64) -> Vec<usize> {
    let mut by_error: Vec<(f64, f64)> = measured.length_error.iter().copied().zip(face_area.iter().copied()).collect();
    by_error.sort_by(|a, b| a.0.total_cmp(&b.0));
    let half = 0.5 * face_area.iter().sum::<f64>();
    let mut below = 0.0;
    let median = by_error
        .iter()
        .find(|(_, a)| {
            below += a;
            below >= half
        })
        .map_or(0.0, |(e, _)| *e);
    (0..measured.length_error.len())
        .filter(|&f| {
            let e = measured.length_error[f];
            e > floor && e > ratio * median && face_area[f] >= DISTORTED_QUADS * h * h
        })
        .collect()
}

/// The curves whose `desired` counts are more than [`STRETCHED`] times their `counts` and
/// [`STRETCHED_SEGMENTS`] or more above, the most stretched first.
pub fn stretched_curves(desired: &[f64], counts: &[u32]) -> Vec<usize> {
    let stretch = |c: usize| desired[c] / counts[c].max(1) as f64;
    let mut out: Vec<usize> = (0..counts.len().min(desired.len()))
        .filter(|&c| stretch(c) > STRETCHED && desired[c] - counts[c] as f64 >= STRETCHED_SEGMENTS)
        .collect();
    out.sort_by(|&a, &b| stretch(b).total_cmp(&stretch(a)));
    out
}

/// Names the layout entries of `curves` in `w`: edges, and the boundary loops of boundary
/// pieces.
fn name_curves(w: &mut Warning, layout: &SurfaceLayout, curves: &[usize]) {
    for &c in curves {
        match layout.curves[c].source {
            CurveSource::Edge(i) => w.edges.push(i),
            CurveSource::Boundary { boundary_loop } if !w.boundary_loops.contains(&boundary_loop) => {
                w.boundary_loops.push(boundary_loop)
            }
            CurveSource::Boundary { .. } => {}
        }
    }
}

/// What went into a result, for [`warnings`].
pub struct Outcome<'a> {
    pub layout: &'a SurfaceLayout,
    pub param: &'a ParamSession,
    pub quads: &'a QuadMesh,
    pub quality: &'a Quality,
    /// Bounding-box diagonal of the input.
    pub diagonal: f64,
    /// The edge length asked for.
    pub edge_length: f64,
    /// The surface area the layout's faces cover (area / edge length² quads are asked for).
    pub surface_area: f64,
    /// Desired and final segments per curve.
    pub desired: &'a [f64],
    pub counts: &'a [u32],
    /// Faces far more distorted than the others ([`distorted_faces`]) and their errors.
    pub distorted: &'a [usize],
    pub measured: &'a FaceDistortion,
}

fn percent(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

/// The warnings of a result, in the order: surface, faces, flips, folds, counts, quad count.
pub fn warnings(o: &Outcome) -> Vec<Warning> {
    let mut out = Vec::new();
    let q = o.quality;
    let miss = q.hausdorff * o.diagonal;
    if q.hausdorff > MISSED_DIAGONAL && miss > MISSED_EDGES * o.edge_length {
        let mut w = Warning::new(
            "surface_missed",
            format!(
                "the quads miss the surface by up to {} of the bounding-box diagonal ({:.1} edge lengths) here: \
                 the layout's faces there hold more of the shape than their grid can follow; add a node there \
                 or ask for more quads",
                percent(q.hausdorff),
                miss / o.edge_length
            ),
        );
        w.at = Some(q.hausdorff_at);
        out.push(w);
    }
    for &f in o.distorted {
        let face = &o.layout.faces[f];
        let mut w = Warning::new(
            "face_distorted",
            format!(
                "face {f} (corners {:?}) is far more distorted than the others: its lengths are off by about {} \
                 in its chart; a node inside it, or corners where its surface angles are nearer 90°, would help",
                face.corner_nodes(),
                percent(o.measured.length_error[f])
            ),
        );
        w.face = Some(f);
        w.nodes = face.corner_nodes().to_vec();
        w.at = o.measured.worst_at[f];
        out.push(w);
    }
    let cut = o.param.cut();
    let flipped: Vec<usize> =
        (0..o.param.solution().corner_uv.len()).filter(|&t| folded(o.param.solution().corner_uv[t])).collect();
    if let Some(&first) = flipped.first() {
        let f = cut.triangle_face[first] as usize;
        let p = cut.triangles[first].map(|v| cut.positions[v as usize]);
        let mut w = Warning::new(
            "flipped_triangles",
            format!(
                "{} triangles are flipped in their charts (the first in face {f}): the quads there may fold or \
                 bunch up; more chart-optimization iterations, or layout curves that leave the nodes there at \
                 wider angles, may help",
                flipped.len()
            ),
        );
        w.at = Some(std::array::from_fn(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0));
        w.face = Some(f);
        w.count = Some(flipped.len());
        out.push(w);
    }
    if let Some(&first) = q.flipped.first() {
        let corners = o.quads.quads[first as usize];
        let mut w = Warning::new(
            "folded_quads",
            format!("{} quads face against the surface or are degenerate", q.flipped.len()),
        );
        let p: Vec<Vec3> = corners.iter().filter_map(|&v| o.quads.positions.get(v as usize).copied()).collect();
        if !p.is_empty() {
            w.at = Some(std::array::from_fn(|k| p.iter().map(|x| x[k]).sum::<f64>() / p.len() as f64));
        }
        w.count = Some(q.flipped.len());
        out.push(w);
    }
    let raised: Vec<usize> =
        (0..o.counts.len()).filter(|&c| o.desired[c] < RAISED_BELOW && o.counts[c] >= 1).collect();
    if let Some(&first) = raised.first() {
        let mut w = Warning::new(
            "counts_raised",
            format!(
                "{} layout curves are shorter than half an edge length but must get at least one segment: the \
                 quads there are smaller and squeezed; move those nodes apart or ask for more quads",
                raised.len()
            ),
        );
        name_curves(&mut w, o.layout, &raised);
        let points = &cut.curve_vertices[first];
        w.at = points.get(points.len() / 2).map(|&v| cut.positions[v as usize]);
        w.count = Some(raised.len());
        out.push(w);
    }
    let stretched = stretched_curves(o.desired, o.counts);
    if let Some(&worst) = stretched.first() {
        let (n, d) = (o.counts[worst], o.desired[worst]);
        let segments = if n == 1 { "segment" } else { "segments" };
        let curves = if stretched.len() == 1 { "layout curve" } else { "layout curves" };
        let which = match o.layout.curves[worst].source {
            CurveSource::Edge(i) => format!("layout edge {i}"),
            CurveSource::Boundary { boundary_loop } => format!("a piece of boundary loop {boundary_loop}"),
        };
        let mut w = Warning::new(
            "counts_stretched",
            format!(
                "{} {curves} got segments more than {STRETCHED} times longer than their faces ask for (the \
                 worst, {which}: {n} {segments} where about {d:.1} were asked, quads about {:.1} times longer along \
                 it than across): opposite sides of a face must get equal counts, and the faces and T-vertices \
                 round these curves force it; move or remove a T-vertex there, or make the faces nearer \
                 rectangles",
                stretched.len(),
                d / n.max(1) as f64
            ),
        );
        name_curves(&mut w, o.layout, &stretched);
        let points = &cut.curve_vertices[worst];
        w.at = points.get(points.len() / 2).map(|&v| cut.positions[v as usize]);
        w.count = Some(stretched.len());
        out.push(w);
    }
    let asked = o.surface_area / (o.edge_length * o.edge_length);
    let got = o.quads.quads.len() as f64;
    if asked.is_finite() && asked > 0.0 && (got - asked).abs() > COUNT_OFF * asked {
        let why = if got < asked {
            "fewer: no edge length gives counts nearer to it with opposite sides equal and every curve at least \
             one segment; faces nearer rectangles, with fewer T-vertices, get closer"
        } else {
            "more: every layout curve takes at least one segment and opposite sides must match; ask for more \
             quads or draw fewer faces"
        };
        let mut w = Warning::new(
            "quad_count_off",
            format!(
                "{} quads where the surface's area asks for about {asked:.0} ({} {why})",
                o.quads.quads.len(),
                percent((got - asked).abs() / asked)
            ),
        );
        w.count = Some(o.quads.quads.len());
        out.push(w);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn measured(length_error: Vec<f64>) -> FaceDistortion {
        let n = length_error.len();
        FaceDistortion { distortion: vec![0.0; n], length_error, length_error_all: 0.0, worst_at: vec![None; n] }
    }

    #[test]
    fn curves_far_from_their_counts_are_stretched_the_worst_first() {
        let desired = [10.0, 11.2, 9.0, 2.9, 0.3, 6.0, 7.5, 2.0];
        let counts = [10, 2, 4, 1, 1, 3, 3, 9];
        // 11.2 → 2 (5.6 times) before 7.5 → 3 (2.5) and 9 → 4 (2.25); 2.9 → 1 is a rounding
        // (fewer than two segments short), 6 → 3 exactly twice, 0.3 → 1 and 2 → 9 squeezed.
        assert_eq!(stretched_curves(&desired, &counts), vec![1, 6, 2]);
    }

    #[test]
    fn a_face_is_far_more_distorted_against_the_median_by_area() {
        // Four faces of area 10 with errors 10 %, 12 %, 15 %, 80 %: the last is far worse.
        let area = [10.0; 4];
        assert_eq!(distorted_faces(&area, &measured(vec![0.1, 0.12, 0.15, 0.8]), 1.0), vec![3]);
        // Not when it is below the absolute floor, nor when it is too small to see.
        assert_eq!(distorted_faces(&area, &measured(vec![0.1, 0.12, 0.15, 0.45]), 1.0), Vec::<usize>::new());
        assert_eq!(distorted_faces(&area, &measured(vec![0.1, 0.12, 0.15, 0.8]), 2.0), Vec::<usize>::new());
        // The median is by area: a big distorted face is the norm, not the exception.
        let area = [1.0, 1.0, 100.0];
        assert_eq!(distorted_faces(&area, &measured(vec![0.1, 0.1, 0.9]), 0.1), Vec::<usize>::new());
        // One face alone has no others to be worse than.
        assert_eq!(distorted_faces(&[5.0], &measured(vec![3.0]), 0.1), Vec::<usize>::new());
    }
}
