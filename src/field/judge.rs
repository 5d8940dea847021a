//! A proposed layout judged by its quads (issue 22): made as `quadlay remesh` makes them, at
//! the edge length they will be made at (the default one where that is not known), and
//! measured against the surface.
//!
//! The automatic layout is proposed six times: its traces along the cross field, along the
//! iso-lines of the field's seamless parameterization ([`super::seamless`]), along those of
//! the parameterization that asks for the scale its solve before took, along the smoothest
//! field (no curvature guide: [`super::compute_unguided_field`]), and along two fields in
//! frames whose normals are smoothed (`SMOOTHINGS` in [`super::propose`]). None wins
//! everywhere. Iso-lines give faces whose opposite sides agree, so the sample counts stretch
//! no strip of quads: eight's Hausdorff distance at 4000 quads falls from 5.3 to 1.3 % of the
//! diagonal, mushroom's from 0.97 to 0.62 %, bunny_1k8's from 2.6 to 1.3 %. But where the
//! parameterization shears or two cones' iso-lines run side by side, the field's traces make
//! the better layout (bunny_28k, nefertiti). The short solves that steer each proposal do not
//! tell them apart (their order disagreed with the quads' on four of twelve meshes); the
//! quads do.

use crate::layout::SurfaceLayout;
use crate::mesh::Mesh;
use crate::param::{ParamOptions, ParamSession};
use crate::quad::density::edge_length_for_quads;
use crate::quad::quality::measure;
use crate::quad::{check_reads_back, extract, QuadOptions};

/// A proposal's quads as the judge measures them.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Judged {
    /// Their Hausdorff distance to the surface, relative to the diagonal.
    pub hausdorff: f64,
    /// How far they are from what the issue asks (lower is better): the Hausdorff distance
    /// times their mean corner-angle deviation in degrees, times one more than the number of
    /// quads folded (a fold is a defect the user sees whatever the rest: the issue asks for
    /// none), times how many times too many quads it has ([`COUNT_SLACK`]).
    pub score: f64,
    /// How many of them are folded.
    #[serde(default)]
    pub folded: usize,
}

/// A proposal whose quads miss the surface by more than this many times the closest
/// proposal's is not kept, whatever its angles and folds: on camel (CGAL's data) a layout of
/// two faces, which cut off the legs and head (74 % of the diagonal), scored better than one
/// of 216 faces (5.4 %) that folds 21 quads.
const HAUSDORFF_SLACK: f64 = 2.0;

/// Rounds of relaxation of the quads judged, fewer than a remesh makes
/// ([`crate::quad::relax::ROUNDS`]): the first rounds mend folds and square most corners, and
/// the ranking needs no more. With 3 rounds every one of 26 meshes (the shared ones, CGAL's
/// and seven of ours) kept the layout it kept with 15, and `quadlay layout bunny_28k` took
/// 16 % less time; with none, three of them kept another, two of those missing the surface
/// by more.
const RELAX_ROUNDS: usize = 3;

/// Quads beyond this share more than the surface's area asks for (a layout whose curves and
/// T-vertices force a segment on every piece, however short) multiply the score by how many
/// times too many there are: a layout with twice the quads misses the surface by about half
/// as much, and is not what the user asked for.
const COUNT_SLACK: f64 = 0.15;

/// Global steps toward rectangles of the quads judged ([`crate::quad::rectify`]): none. Nor do
/// the samples of tagged curves slide, nor do the quads cover the tips ([`crate::quad::cover`]):
/// both mend a few vertices of any layout, and cost time the ranking does not need.
const RECTIFY_STEPS: usize = 0;

/// The quads of `layout` at `edge_length`, measured; `None` where the remesh fails (as
/// `remesh` would refuse it).
pub fn judge(mesh: &Mesh, layout: &SurfaceLayout, edge_length: f64) -> Option<Judged> {
    let options = ParamOptions::default();
    let mut param = ParamSession::new(mesh, layout, &options).ok()?;
    for _ in 0..options.iterations {
        param.step().ok()?;
    }
    param.finish().ok()?;
    let quad_options = QuadOptions { relax_rounds: RELAX_ROUNDS, rectify_steps: RECTIFY_STEPS, slide_on_curves: false, cover_tips: false, ..QuadOptions::with_edge_length(edge_length) };
    let (quads, _) = extract(layout, &param, &quad_options).ok()?;
    check_reads_back(&quads).ok()?;
    let q = measure(mesh, &quads);
    let asked = edge_length_for_quads(mesh, 1.0).powi(2) / (edge_length * edge_length);
    let over = (q.faces as f64 / ((1.0 + COUNT_SLACK) * asked)).max(1.0);
    let score = q.hausdorff * q.angle_deviation_mean_deg.max(1e-3) * (1.0 + q.flipped_quads as f64) * over;
    (score.is_finite() && q.hausdorff.is_finite()).then_some(Judged { hausdorff: q.hausdorff, score, folded: q.flipped_quads })
}

/// Scores this close to the best (relatively) are a tie: the remesh's noise, not the layout
/// (the sheared cube's three proposals score 2.08e-15 and 2.13e-15, its quads exact; the
/// tracings of a curved mesh differ 2 to 10 times).
const TIE: f64 = 0.05;

/// Which of the proposals judged to keep: the lowest score among those within
/// [`HAUSDORFF_SLACK`] of the closest to the surface, and of scores tied with it ([`TIE`])
/// the one of fewest curves (`curves[i]` of proposal `i`: less for the user to edit); `None`
/// if none could be judged.
pub fn best(judged: &[Option<Judged>], curves: &[usize]) -> Option<usize> {
    let closest = judged.iter().flatten().map(|j| j.hausdorff).fold(f64::INFINITY, f64::min);
    let near: Vec<(usize, f64)> =
        (0..judged.len()).filter_map(|i| judged[i].filter(|j| j.hausdorff <= HAUSDORFF_SLACK * closest).map(|j| (i, j.score))).collect();
    let lowest = near.iter().map(|n| n.1).fold(f64::INFINITY, f64::min);
    near.iter().filter(|n| n.1 <= lowest * (1.0 + TIE)).min_by_key(|n| (curves[n.0], n.0)).map(|n| n.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn judged(hausdorff: f64, score: f64) -> Option<Judged> {
        Some(Judged { hausdorff, score, folded: 0 })
    }

    /// The lowest score wins among the proposals near the surface; one far from it loses
    /// whatever its score, and one that could not be judged is never kept.
    #[test]
    fn the_best_score_near_the_surface_is_kept() {
        assert_eq!(best(&[judged(0.02, 3.0), judged(0.03, 2.0), None], &[10, 10, 10]), Some(1));
        assert_eq!(best(&[judged(0.054, 22.4), None, judged(0.74, 8.7)], &[10, 10, 10]), Some(0));
        assert_eq!(best(&[None, None], &[10, 10]), None);
    }

    /// Of scores within the tie, the proposal with fewest curves is kept.
    #[test]
    fn of_tied_scores_the_fewest_curves_are_kept() {
        assert_eq!(best(&[judged(0.01, 2.13), judged(0.01, 2.08), judged(0.01, 2.08)], &[12, 13, 13]), Some(0));
        assert_eq!(best(&[judged(0.01, 2.5), judged(0.01, 2.08)], &[12, 13]), Some(1));
    }
}
