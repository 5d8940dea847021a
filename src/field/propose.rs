//! An automatic coarse quad layout from the cross field (issue 22; method-notes §11).
//!
//! 1. The cross field and its singularities ([`compute_field`]); close valence-3/5 pairs
//!    cancel, and singularities on feature lines or the boundary are left to those lines.
//! 2. Feature lines and the boundary (with nodes at its corners, at least four per loop)
//!    are curves from the start.
//! 3. Separatrices leave every singular vertex (a cone of the field's seamless
//!    parameterization where one is near), and traces continue feature lines that end inside
//!    a smooth region (tagged and kept like the lines, and continued again should a repair
//!    take away what they ended on); they grow as a motorcycle graph of streamlines across
//!    triangles, each kept as the vertex path nearest it ([`Motorcycles`]). The whole
//!    proposal is made six times, the streamlines along the field, along the iso-lines of
//!    its two seamless parameterizations ([`super::seamless`]), along the smoothest field
//!    ([`compute_unguided_field`]) and along two fields in smoothed frames ([`SMOOTHINGS`]),
//!    all at once, and the layout whose quads come out best is kept ([`judge`], [`pick`]).
//! 4. Repairs until every face is what the layout reader accepts ([`analyze`]): a face that is
//!    not a disk (a ring round a limb, a handle, a sphere without singularities) gets a cross
//!    of traces from its deepest vertex, and where a few rounds of those miss, shortest arcs
//!    between its boundary loops or round its handles ([`super::arcs`]); a ring bounded by a
//!    closed feature line without corners (a hole's rim) first gets traces across the line
//!    from four nodes along it ([`loop_launches`]); dangling traces go;
//!    where a repair cut a trace at a node that another ended on, the two turn there and one
//!    of them is traced on through it ([`CurveGraph::bends`]); a face with no vertex inside
//!    loses a trace; a face with fewer than four nodes gets one more on its boundary; faces
//!    are split by more traces until there are about as many as asked for.
//! 5. The graph is written as a layout file (nodes on vertices, feature curves through all
//!    their vertices and tagged, traces through the few vertices that keep the geodesic on
//!    them, [`sparse_waypoints`], or through all where that lets curves meet) and checked
//!    with the layout reader ([`crate::layout::place`], once for both of the corners'
//!    placements) and the sample-count equations; every face gets a rectangle chart (see
//!    [`write`] for why not the paper's Section 5 general quads on feature faces), its
//!    corners where it turns most.
//! 6. A short solve measures each face's distortion; the faces far more distorted than the
//!    others get a cross of traces where it concentrates, and steps 4–5 run again, while the
//!    layout's distortion goes down; then a long side of a sliver face goes while the
//!    integer sample counts come nearer what the curves ask for (`refine`, [`merge_sides`]),
//!    faces smaller than a 2 × 2 grid of the quads judged first.
//! 7. The proposal kept gets versions with the corners of all faces chosen together, with
//!    fewer irregular vertices ([`super::corners`], [`with_corners_chosen`]); the judge keeps
//!    one where its quads are no worse.

use super::arcs::{arc_across, arc_round_handle, self_touching};
use super::cells::add_cell_borders;
use super::corners::{self, FaceTurns};
use super::faces::{analyze, FaceInfo, Faces};
use super::graph::CurveGraph;
use super::judge::{best, judge, Judged};
use super::seamless::iso_lines;
use super::separatrix::separatrix_directions;
use super::slivers::merge_sides;
use super::trace::{Motorcycles, TraceEnd, BLOCKED};
use super::waypoints::sparse_waypoints;
use super::features::Features;
use super::{compute_field, compute_smoothed_field, compute_unguided_field, diagonal, CrossField, DEFAULT_FEATURE_ANGLE};
use crate::layout::file::{EdgeSpec, PatchSpec};
use crate::layout::embedding::Directed;
use crate::layout::{curve, face_named_by, place, ChartType, CurveSource, Face, Layout, LayoutError, Location, MeshCounts, Numbering, Placement, SurfaceLayout, MAX_WAYPOINTS};
use crate::geom::{add, norm, sub, unit, Vec3};
use crate::mesh::geometry::corner_angle;
use crate::mesh::topology::topology;
use crate::mesh::{Mesh, NONE};
use crate::quad::counts::{sample_counts, CountError, Equation};
use crate::quad::default_edge_length;
use crate::quad::density::{edge_length_for_quads, face_areas, IncidenceCounts};
use crate::guidance::{face_distortion, nearest_vertex, FaceDistortion};
use crate::verdict::faces_above;
use crate::param::{ParamError, ParamOptions, ParamSession};
use crate::solve::SolveError;
use std::f64::consts::PI;
use std::fmt;

/// Options of [`propose_layout`] (cli.md, `quadlay layout`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct LayoutOptions {
    /// Sharp feature edges have a dihedral angle above this, in degrees. Default 35.
    pub feature_angle: f64,
    /// About how many faces the layout should have; `None`: as the field gives them.
    pub patches: Option<usize>,
    /// The quad edge length the layout will be remeshed at, where known (`quadlay remesh
    /// --layout auto`): the proposals are judged by their quads at it ([`judge`]);
    /// `None`: at [`JUDGE_SHARE`] of the default edge length.
    pub edge_length: Option<f64>,
}

impl Default for LayoutOptions {
    fn default() -> Self {
        LayoutOptions { feature_angle: DEFAULT_FEATURE_ANGLE, patches: None, edge_length: None }
    }
}

/// A proposed layout and the field it came from.
#[derive(Debug, Clone)]
pub struct Proposal {
    pub layout: Layout,
    pub field: CrossField,
    /// The layout as the reader places it on the mesh.
    pub surface: SurfaceLayout,
}

impl Proposal {
    /// Where the faces are more than [`PATCHES_SLACK`] times off the `patches` asked for (a
    /// wish that the field's singularities and the features bound), a sentence saying so.
    pub fn patches_note(&self, patches: Option<usize>) -> Option<String> {
        let n = patches?;
        let faces = self.surface.faces.len();
        let ratio = faces as f64 / n as f64;
        (!(1.0 / PATCHES_SLACK..=PATCHES_SLACK).contains(&ratio)).then(|| {
            format!("{faces} faces where about {n} were asked: the nearest the cross field's singularities and the features allowed")
        })
    }
}

/// Why no layout could be proposed.
#[derive(Debug, Clone, PartialEq)]
pub enum ProposeError {
    /// The field's linear system could not be solved (a degenerate mesh).
    Field(SolveError),
    /// The repairs did not reach a valid layout; says which rule still failed.
    NoValidLayout(String),
}

impl fmt::Display for ProposeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ProposeError::Field(e) => write!(f, "the cross field could not be computed: {e}"),
            ProposeError::NoValidLayout(why) => write!(f, "no valid layout could be made automatically: {why}"),
        }
    }
}

impl std::error::Error for ProposeError {}

/// Opposite singularities closer than this fraction of the diagonal cancel...
const CANCEL_DISTANCE: f64 = 0.03;
/// ... or, where `--patches` asks for fewer faces than that makes (more than this many times
/// fewer), twice as far apart, up to this many times.
const PATCHES_SLACK: f64 = 1.25;
const FEWER_PATCHES_TRIES: usize = 4;
/// Doublings of [`CANCEL_DISTANCE`] tried when the layout from the singularities fails.
const CANCEL_RETRIES: u32 = 1;
/// Traces along iso-lines that end on a curve within this fraction of the diagonal of where
/// one ended on it from the other side end there too ([`Motorcycles::snapping`]): two
/// iso-lines that meet a curve so close together stand for one grid line, and apart they
/// leave a piece of the curve that must take a segment however short it is. Over 26 meshes at
/// 4000 quads, geometric-mean Hausdorff distance 2.03 → 1.86 % of the diagonal, mean angle
/// deviation 11.20 → 11.11°, irregular vertices 2095 → 2179 (CGAL's knot1 0.65 → 0.29 % with
/// none, handle 5.7 → 2.4 %, lion-head 1.5 → 3.7 %); the shared meshes keep their layouts.
/// Snapping the field's own streamlines too (at 0.03 or 0.015) changed those: bunny_28k's
/// Hausdorff distance 1.27 → 0.85 %, but its irregular vertices 74 → 82 and elephant_44k's
/// 146 → 177, and on the 26 meshes the mean angle deviation rose.
const SNAP: f64 = 0.03;
/// Traces longer than this many diagonals stop (and are dropped as dangling).
const MAX_TRACE_LENGTH: f64 = 3.0;
/// A boundary vertex whose interior angle differs from π by more than this is a corner.
const BOUNDARY_CORNER: f64 = PI / 4.0;
/// Bound on the repair rounds.
const MAX_ROUNDS: usize = 400;
/// Rounds of [`repair`] after which it mends every empty face and every face short of nodes
/// at once rather than one a round: one at a time changes the layout least, but a mesh with
/// thin parts (CGAL's camel: 132 singularities, legs a few triangles across) holds hundreds
/// of them and did not converge in [`MAX_ROUNDS`]. The shared meshes converge before it.
const BATCH_AFTER: usize = 100;
/// Bound on the layouts written and refused (each costs a placement on the surface).
const MAX_REJECTIONS: usize = 40;
/// Bound on the rounds that add crosses of traces.
const MAX_SEED_ROUNDS: usize = 40;
/// Rounds of crosses of traces seeded in faces that are not disks before such faces are cut
/// with arcs ([`cut_rings`]): crosses follow the field, arcs do not. On CGAL's meshes, arcs
/// first (0) gave bull a layout 2.7 % of the diagonal off its surface instead of 18 %, but
/// blade 0.84 % instead of 0.29 % and head 2.9 % instead of 2.0 %.
const RING_SEEDS: usize = 3;
/// Bound on the rounds that split the faces a short solve finds distorted ([`refine`]).
const REFINES: usize = 3;
/// [`refine`] splits a face whose length error is above this multiple of the median face's...
const SPLIT_RATIO: f64 = 2.0;
/// ... and above this (a quarter of its area has lengths off by more than a quarter).
const SPLIT_FLOOR: f64 = 0.25;
/// [`missed_sides`]: curves whose count misses a face's wish by more than this many segments...
const MISS_SEGMENTS: f64 = 2.0;
/// ... the worst this many.
const MISSED_CURVES: usize = 3;
/// Bound on the removals of a sliver's side tried ([`refine`]; each writes the layout again).
/// 20 rather than 12 since coarse meshes are refined ([`crate::mesh::refine_coarse`]): over 26
/// meshes (the shared ones and 19 of CGAL's) the mean angle deviation went 8.79 → 8.49°, the
/// geometric-mean Hausdorff distance 1.64 → 1.54 % and the folded quads 93 → 90, for 2 % more
/// irregular vertices (elephant_44k 7.33 → 6.85°, 138 → 144; dino 4.4 → 5.8 %). Before the
/// refinement, CGAL's handle lost its layout to three faces at 20.
const MERGE_TRIES: usize = 20;
/// The most quads a proposal is judged by ([`judge`]): a remesh asked for millions would
/// otherwise remesh each proposal at once at that size, six times the memory of the one run.
const JUDGE_QUADS: f64 = 20_000.0;
/// A layout made without knowing its density (`quadlay layout`, the page's Suggest) is judged
/// at this share of the default edge length: about four times the default remesh's quads
/// (1300 on bunny_28k), nearer what users ask for (the 4000), and a layout's thin
/// strips and skewed faces show only at a finer density. Measured with the remesh at 4000
/// quads: bunny_28k's Hausdorff distance 1.44 % judged at the default, 1.21 % at half of it.
const JUDGE_SHARE: f64 = 0.5;

/// The fields the proposal is traced along besides the surface's own: in frames whose normals
/// are diffused over these shares of the diagonal ([`compute_smoothed_field`]). The
/// proposals are chaotic (a field that moves a singularity a little changes the whole layout)
/// and the judge tells the good from the bad, so two more, whose singularities are where the
/// smoothed surface turns, mend layouts that the three others spoil. Measured, when they were
/// made only where none of the three others held the surface, at 4000 quads over 55 meshes (the
/// seven shared ones, 19 of CGAL's used while the proposal was tuned and 29 of CGAL's that
/// were not): geometric-mean Hausdorff distance 1.215 → 1.129 % of the diagonal, mean angle
/// deviation 7.70 → 7.70°, 4 % more irregular vertices, 151 folded quads where 143 were. On
/// the 29 untuned meshes 1.101 → 0.949 %, none farther from its surface (CGAL's pig 6.2 →
/// 1.8 %, three_peaks 3.4 → 1.1 %, ChineseDragon 5.4 → 3.0 %); on the 26 others 1.355 →
/// 1.371 % (bunny_1k8 2.10 → 1.54 %, 5.0 → 4.5°, 87 → 48 irregular vertices; camel 2.8 →
/// 1.6 %; elk 1.9 → 4.4 %, whose judge, at a coarser density, found the smoothed field's
/// layout nearer). With one field (1 %, always made) the 55 gave 1.166 %. They are made always
/// now ([`Tracings::propose`]).
const SMOOTHINGS: [f64; 2] = [0.01, 0.02];

/// Proposes a coarse quad layout for `mesh`; see the module documentation.
///
/// # Errors
/// [`ProposeError::Field`] if the field's solve fails; [`ProposeError::NoValidLayout`] if the
/// repairs cannot make a layout that the reader accepts and that has consistent sample counts.
pub fn propose_layout(mesh: &Mesh, options: &LayoutOptions) -> Result<Proposal, ProposeError> {
    Tracings::new(mesh, options)?.propose(mesh, options)
}

/// The cross field and what the proposals' traces follow: the field itself, the iso-lines
/// of its two seamless parameterizations (none where their factorization fails), the
/// smoothest field of the same constraints ([`compute_unguided_field`]), and the fields in
/// frames smoothed over each of [`SMOOTHINGS`] (none where a factorization fails); the
/// layout whose quads come out best is kept ([`judge`], [`pick`]).
pub struct Tracings {
    pub field: CrossField,
    /// The field and its two iso-line tracings, in that order; `None` where one could not be
    /// made.
    tracings: Vec<Option<CrossField>>,
    /// The smoothest field ([`UNGUIDED`]), made when a proposal along it is first asked for
    /// (the page's workers each make only some of the tracings); `None` where it could not be
    /// made.
    unguided: std::sync::OnceLock<Option<CrossField>>,
    /// The fields of [`SMOOTHINGS`], made when a proposal along one is first asked for (as the
    /// smoothest field); `None` where one could not be made.
    smoothed: [std::sync::OnceLock<Option<CrossField>>; SMOOTHINGS.len()],
}

/// The tracings of the surface's own field: its streamlines and its two iso-line tracings.
const OWN_TRACINGS: usize = 3;

/// The first of the other tracings ([`Tracings::candidate`] `OWN_TRACINGS`): streamlines
/// of the smoothest field, which has the surface's constraints but no curvature guide
/// ([`compute_unguided_field`]). Where the principal directions are noise at the scale of
/// the quads (a scan's bumps, the blends and fillets of a CAD part), the guided field bends
/// with them, its singularities come in pairs, and its layout skews its quads; the smoothest
/// field does not, but on a limb or a torus it is not the principal one and spirals. Neither
/// wins everywhere; the judge tells which. `quadlay layout`, then `remesh --quads 4000`, on
/// 29 of CGAL's meshes never used in tuning and 26 used (the seven shared ones among them):
/// - made with the smoothed fields' (only where the first three do not hold the surface):
///   mean angle deviation 7.46 → 7.33° and 7.35 → 7.16°, folded quads 80 → 62 and 50 → 49,
///   geometric-mean Hausdorff distance 0.876 → 0.887 % and 1.205 → 1.206 %; kept on 5 of the
///   55 (turbine 17.9 → 14.1° and 22 → 9 folded, lion-head 9.8 → 4.9°, pig's 4 folded quads
///   none, but 1.2 → 2.1 % of the diagonal off). Where it is made it costs time: paired
///   runs of `quadlay layout` took 1.10 times as long on bunny_1k8 and 1.70 times on
///   elephant_44k, whose smoothest field's proposal (333 faces, not kept) took 28 s where
///   the others took 11–16;
/// - always made, with the first three: 7.28° and 7.15°, 0.879 % and 1.185 % (bear 4.8 →
///   3.3°, fandisk 0.42 → 0.30 %), but `quadlay layout` on bunny_28k took 1.32 times as long
///   (paired runs) and the page's suggestion 1.3 times, for a layout it does not keep.
///
/// The smoothest field of every tracing instead (its iso-lines and smoothed frames too) is
/// worse on the whole (untuned 0.876 → 1.031 %, knot 0.55 → 3.76 %), though best on 9 of the
/// 29 (three_peaks 8.2 → 4.7°, triceratops 16.1 → 11.3°). Made always now, with all the
/// others ([`Tracings::propose`]).
const UNGUIDED: usize = OWN_TRACINGS;

/// One tracing's proposal, judged by its quads ([`Tracings::candidate`]).
pub struct Candidate {
    pub layout: Layout,
    pub surface: SurfaceLayout,
    /// Its quads as the judge measures them; `None` if they could not be made.
    pub judged: Option<Judged>,
}

impl Candidate {
    /// What [`pick`] compares: its judged quads and its curves (fewer: less for the user to
    /// edit).
    pub fn summary(&self) -> (Option<Judged>, usize) {
        (self.judged, self.layout.edges.len())
    }
}

impl Tracings {
    /// # Errors
    /// [`ProposeError::Field`] if the field's solve fails.
    pub fn new(mesh: &Mesh, options: &LayoutOptions) -> Result<Tracings, ProposeError> {
        let field = compute_field(mesh, options.feature_angle).map_err(ProposeError::Field)?;
        let isos: Vec<Option<CrossField>> = match iso_lines(mesh, &field) {
            Ok(isos) => isos.into_iter().map(|iso| Some(CrossField { iso, ..field.clone() })).collect(),
            Err(_) => vec![None, None],
        };
        let tracings = std::iter::once(Some(field.clone())).chain(isos).collect();
        Ok(Tracings { field, tracings, unguided: Default::default(), smoothed: Default::default() })
    }

    /// [`propose_layout`] with these tracings (made with `options`' feature angle): the
    /// proposals along all of them at once, the one [`pick`] keeps, its corners chosen
    /// ([`with_corners_chosen`]).
    ///
    /// All of them always. Until stop 55 the smoothest field's and the smoothed fields' were
    /// made only where none of the surface's own field's held the surface (its quads within an
    /// edge length of it, none folded), for time; but where one held, another was often better
    /// still: on nefertiti the field in frames smoothed over 2 % of the diagonal gives 4
    /// irregular vertices where the field's streamlines give 16 (the issue asks for at most
    /// 11), at 2.08° rather than 2.45°. `quadlay layout`, then `remesh --quads 4000`, on the
    /// 36 meshes (the shared ones and 29 of CGAL's): geometric-mean Hausdorff distance
    /// 1.311 → 1.281 %, mean angle deviation 6.63 → 6.42°, irregular vertices 2757 → 2733,
    /// folded quads 81 → 81; another layout kept on six (bear 0.85 → 0.51 % and 4.9 → 3.4°,
    /// handle 0.85 → 0.54 % but 4.6 → 6.7°). It costs time where the first three held:
    /// `quadlay layout bunny_28k` took 2.0 times as long in paired runs, for the layout it
    /// kept before; with the six made on as many threads as there are processors rather than
    /// on six ([`at_once`]), 0.87 times that again (13.5 s against 16.0 s), at 341 MiB
    /// rather than 762.
    ///
    /// # Errors
    /// [`ProposeError::NoValidLayout`] if no tracing gives a valid layout (the first one's
    /// reason).
    pub fn propose(&self, mesh: &Mesh, options: &LayoutOptions) -> Result<Proposal, ProposeError> {
        let candidates = at_once(&(0..self.count()).collect::<Vec<_>>(), |&k| self.candidate(mesh, k, options));
        let kept = pick(&candidates.iter().map(|c| c.as_ref().ok().map(Candidate::summary)).collect::<Vec<_>>());
        let mut error = None;
        let mut chosen = None;
        for (i, c) in candidates.into_iter().enumerate() {
            match c {
                Ok(c) if Some(i) == kept => chosen = Some(c),
                Err(e) => error = error.or(Some(e)),
                Ok(_) => {}
            }
        }
        let chosen = chosen.ok_or_else(|| error.unwrap_or_else(|| ProposeError::NoValidLayout("nothing was tried".into())));
        let c = self.conclude(mesh, chosen, options)?;
        Ok(Proposal { layout: c.layout, field: self.field.clone(), surface: c.surface })
    }

    /// The last step of a proposal, after [`pick`]: `kept` is the candidate it kept, or why
    /// no tracing made one. Where there is none, or its quads miss the surface by more than
    /// [`FAR_EDGES`] of their edge lengths, fold (the issue asks for none: on CGAL's man the
    /// one tracing that made a layout folded 65 quads at 4000, 21° mean angle deviation,
    /// where the cells' fold 9, 10°) or could not be made, the layout of Voronoi cells
    /// ([`Start::Cells`]) is made and judged too, and [`best`] decides; then the corners of
    /// the one kept are chosen ([`with_corners_chosen`]).
    ///
    /// # Errors
    /// `kept`'s error where the cells give no layout either.
    pub fn conclude(&self, mesh: &Mesh, kept: Result<Candidate, ProposeError>, options: &LayoutOptions) -> Result<Candidate, ProposeError> {
        let length = judged_length(mesh, options);
        let far = |c: &Candidate| c.judged.is_none_or(|j| j.hausdorff * diagonal(mesh) > FAR_EDGES * length || j.folded > 0);
        let kept = match kept {
            Ok(c) if !far(&c) => c,
            kept => match (kept, self.cells_candidate(mesh, options)) {
                (Ok(c), Some(cells)) => {
                    let curves = [c.layout.edges.len(), cells.layout.edges.len()];
                    if best(&[c.judged, cells.judged], &curves) == Some(1) {
                        cells
                    } else {
                        c
                    }
                }
                (Ok(c), None) => c,
                (Err(_), Some(cells)) => cells,
                (Err(e), None) => return Err(e),
            },
        };
        // Placed once more (the placement was not kept), for both versions.
        Ok(match place(mesh, &kept.layout, Numbering::of(mesh)) {
            Ok(placed) => with_corners_chosen(mesh, &self.field, &placed, kept, options),
            Err(_) => kept,
        })
    }

    /// The layout of Voronoi cells ([`Start::Cells`]) with the feature lines and without them,
    /// each judged, the better kept ([`best`]); `None` if neither can be made. Without: where
    /// sharp edges are noise they part the surface into pieces that no repair makes disks
    /// (CGAL's femur at 35°), or split it into slivers (CGAL's man: 20 % of the diagonal off
    /// with them, 5.7 % without).
    fn cells_candidate(&self, mesh: &Mesh, options: &LayoutOptions) -> Option<Candidate> {
        let plain = without_features(mesh, &self.field);
        let made: Vec<Candidate> = at_once(&[&self.field, &plain], |field| {
            let (layout, surface) = attempt(mesh, field, options, Start::Cells).ok()?;
            let judged = judge(mesh, &surface, judged_length(mesh, options));
            Some(Candidate { layout, surface, judged })
        })
        .into_iter()
        .flatten()
        .collect();
        let scores: Vec<Option<Judged>> = made.iter().map(|c| c.judged).collect();
        let curves: Vec<usize> = made.iter().map(|c| c.layout.edges.len()).collect();
        let kept = best(&scores, &curves).unwrap_or(0);
        made.into_iter().nth(kept)
    }

    /// How many proposals there are to make.
    pub fn count(&self) -> usize {
        UNGUIDED + 1 + SMOOTHINGS.len()
    }

    /// The proposal along tracing `k` (below [`Tracings::count`]), judged: apart, the page
    /// makes them in workers of their own.
    ///
    /// # Errors
    /// [`ProposeError::NoValidLayout`] if the repairs cannot make a valid layout along it.
    pub fn candidate(&self, mesh: &Mesh, k: usize, options: &LayoutOptions) -> Result<Candidate, ProposeError> {
        let features = || self.field.features.clone();
        let field = if k < UNGUIDED {
            &self.tracings[k]
        } else if k == UNGUIDED {
            self.unguided.get_or_init(|| compute_unguided_field(mesh, features()).ok())
        } else {
            let j = k - UNGUIDED - 1;
            let Some(cell) = self.smoothed.get(j) else {
                return Err(ProposeError::NoValidLayout(format!("there are {} tracings, not {}", self.count(), k + 1)));
            };
            cell.get_or_init(|| compute_smoothed_field(mesh, features(), SMOOTHINGS[j]).ok())
        };
        let Some(field) = field else {
            return Err(ProposeError::NoValidLayout("this tracing's field or parameterization could not be solved".into()));
        };
        let (layout, surface) = propose_along(mesh, field, options)?;
        let judged = judge(mesh, &surface, judged_length(mesh, options));
        Ok(Candidate { layout, surface, judged })
    }
}

/// A proposal whose judged quads miss the surface by more than this many of their edge
/// lengths has lost a part of it (cut off, or folded over), and the Voronoi cells are tried
/// ([`Tracings::conclude`]): CGAL's man, whose field has 483 singularities, kept a layout of
/// 15 faces round one hand and one face for the rest of the body (51 % of the diagonal off),
/// and bull one 14 % off. A layout that holds the surface misses it by about an edge length
/// at most.
const FAR_EDGES: f64 = 4.0;

/// The quad edge length proposals are judged at: the one asked for, else [`JUDGE_SHARE`] of
/// the default, and at most [`JUDGE_QUADS`] quads (three remeshes run at once, and the
/// ranking needs no more).
fn judged_length(mesh: &Mesh, options: &LayoutOptions) -> f64 {
    options.edge_length.unwrap_or_else(|| JUDGE_SHARE * default_edge_length(mesh)).max(edge_length_for_quads(mesh, JUDGE_QUADS))
}

/// The kept proposal, or one of its versions with the corners of all faces chosen together
/// ([`corners::choose`], one per [`CORNER_BUDGETS`]) where the judge finds its quads no worse
/// ([`best`]; a tie keeps the larger budget's): fewer irregular vertices, but a face's
/// corners may move to where its boundary turns less and shear its quads. `field`: the
/// surface's ([`Tracings::field`]), whichever tracing made the proposal; `placed`: its layout
/// placed on `mesh` (each version changes only the corners).
pub fn with_corners_chosen(mesh: &Mesh, field: &CrossField, placed: &Placement, plain: Candidate, options: &LayoutOptions) -> Candidate {
    let length = judged_length(mesh, options);
    let mut versions: Vec<(Layout, SurfaceLayout)> = Vec::new();
    for budget in CORNER_BUDGETS {
        if let Some(v) = with_corners_together(mesh, field, placed, &plain.layout, budget) {
            if versions.iter().all(|w| w.0.patches != v.0.patches) {
                versions.push(v);
            }
        }
    }
    let judged = at_once(&versions, |v| judge(mesh, &v.1, length));
    let mut all: Vec<Candidate> = versions.into_iter().zip(judged).map(|((layout, surface), judged)| Candidate { layout, surface, judged }).collect();
    all.push(plain);
    let scores: Vec<Option<Judged>> = all.iter().map(|c| c.judged).collect();
    let kept = best(&scores, &vec![0; scores.len()]).unwrap_or(scores.len() - 1);
    all.swap_remove(kept)
}

/// Which of the candidates (one per tracing, in order; `None` where none was made, else its
/// judged quads and its curves) to keep: the best judged ([`best`]), else the first made
/// (none could be remeshed to judge it); `None` if none was made.
pub fn pick(candidates: &[Option<(Option<Judged>, usize)>]) -> Option<usize> {
    let judged: Vec<_> = candidates.iter().map(|c| c.and_then(|c| c.0)).collect();
    let curves: Vec<usize> = candidates.iter().map(|c| c.map_or(0, |c| c.1)).collect();
    best(&judged, &curves).or_else(|| candidates.iter().position(Option::is_some))
}

/// `f` of every item, in order: natively on as many threads as there are processors (this one
/// among them), each taking the next item left; in wasm one after the other. A thread that
/// cannot be started leaves its share to the others, and a panic in one is passed on.
///
/// No more threads than processors: each proposal holds its own parameterizations, and six at
/// once on two processors took more memory for no gain in time (bunny_28k: see
/// [`Tracings::propose`]).
fn at_once<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    #[cfg(not(target_arch = "wasm32"))]
    if items.len() > 1 {
        let next = std::sync::atomic::AtomicUsize::new(0);
        let work = || {
            let mut done = Vec::new();
            loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(x) = items.get(i) else { return done };
                done.push((i, f(x)));
            }
        };
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(items.len());
        let mut done: Vec<(usize, R)> = std::thread::scope(|scope| {
            let helpers: Vec<_> = (1..threads).filter_map(|_| std::thread::Builder::new().spawn_scoped(scope, work).ok()).collect();
            let mut all = work();
            for h in helpers {
                all.extend(h.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)));
            }
            all
        });
        done.sort_by_key(|d| d.0);
        return done.into_iter().map(|d| d.1).collect();
    }
    items.iter().map(f).collect()
}

/// The layout proposed with traces that follow `field` (its iso-lines where it has them).
fn propose_along(mesh: &Mesh, field: &CrossField, options: &LayoutOptions) -> Result<(Layout, SurfaceLayout), ProposeError> {
    // From the singularities first; should that fail, with the pairs of opposite ones twice
    // as far apart cancelled (fewer traces, fewer thin faces: on CGAL's camel, cow and dino
    // the first failed and the fallback below made a layout of two faces that cut off the
    // legs; a second doubling changed none of them), and last from crosses of traces alone
    // (the singularities are then where the traces meet).
    let first = attempt(mesh, field, options, Start::Singularities(CANCEL_DISTANCE));
    let (mut layout, mut surface) = match first {
        Ok(done) => done,
        Err(why) => (1..=CANCEL_RETRIES)
            .find_map(|k| attempt(mesh, field, options, Start::Singularities(CANCEL_DISTANCE * f64::from(1u32 << k))).ok())
            .map_or_else(|| attempt(mesh, field, options, Start::Crosses), Ok)
            .map_err(|_| ProposeError::NoValidLayout(why))?,
    };
    // Fewer faces asked for than the singularities make: cancel pairs farther apart, keeping
    // the layout whose face count is nearest (by ratio) to the one asked.
    if let Some(target) = options.patches {
        let off = |s: &SurfaceLayout| (s.faces.len() as f64 / target as f64).ln().abs();
        let mut distance = CANCEL_DISTANCE;
        for _ in 0..FEWER_PATCHES_TRIES {
            if surface.faces.len() as f64 <= PATCHES_SLACK * target as f64 {
                break;
            }
            distance *= 2.0;
            let Ok((l, s)) = attempt(mesh, field, options, Start::Singularities(distance)) else { continue };
            if off(&s) < off(&surface) {
                (layout, surface) = (l, s);
            }
        }
    }
    Ok((layout, surface))
}

/// What the curves of one construction of the layout start from.
#[derive(Debug, Clone, Copy)]
enum Start {
    /// Separatrices of the singularities, with opposite ones closer than this fraction of the
    /// diagonal cancelled.
    Singularities(f64),
    /// Crosses of traces alone (the singularities are then where the traces meet).
    Crosses,
    /// The borders of geodesic Voronoi cells ([`add_cell_borders`]): where the traces give no
    /// layout, or one far from the surface ([`Tracings::conclude`]).
    Cells,
}

/// Voronoi cells of the [`Start::Cells`] layout where `--patches` does not say: each cell
/// becomes a face or two, and the refinement splits the distorted ones.
const CELLS: usize = 40;

/// `field` without its feature lines ([`Tracings::cells_candidate`]).
fn without_features(mesh: &Mesh, field: &CrossField) -> CrossField {
    CrossField { features: Features::none(mesh), ..field.clone() }
}

/// One construction of the layout; the reason it failed otherwise.
fn attempt(mesh: &Mesh, field: &CrossField, options: &LayoutOptions, start: Start) -> Result<(Layout, SurfaceLayout), String> {
    let diag = diagonal(mesh);
    let mut g = CurveGraph::new(mesh);
    for &c in &field.features.corners {
        g.add_node(c, true);
    }
    for line in &field.features.lines {
        g.add_path(line, true);
    }
    boundary_nodes(mesh, &mut g);

    let mut launches: Vec<Launch> = Vec::new();
    if let Start::Cells = start {
        add_cell_borders(mesh, &mut g, options.patches.unwrap_or(CELLS));
        g.from_cells = true;
    }
    if let Start::Singularities(distance) = start {
        for (v, dirs) in singular_vertices(mesh, field, &g, distance * diag) {
            // Not pinned: a singularity left with two of its separatrices (the others
            // removed by repairs) is no corner but a bend, 90° on one side and 270° on the
            // other, where a chart corner folds the quads; the two curves join through it.
            g.add_node(v, false);
            launches.extend(dirs.into_iter().map(|d| (v, d, false)));
        }
    }
    for &c in &field.features.corners {
        if field.features.degree[c as usize] == 1 && !mesh.is_boundary_vertex(c) {
            if let Some(h) = mesh.outgoing(c).find(|&h| field.features.sharp[mesh.edge(h) as usize]) {
                launches.push((c, sub(mesh.position(c), mesh.position(mesh.to_vertex(h))), true));
            }
        }
    }
    grow(mesh, field, &mut g, diag, &launches);
    let mut seeds_left = MAX_SEED_ROUNDS;
    let first = finish(mesh, field, &mut g, options, diag, &mut seeds_left, Pass::Build)?;
    Ok(refine(mesh, field, options, diag, g, first, seeds_left))
}

/// Repairs `g` until it is valid, writes it, and simplifies where the reader or the counts
/// refuse it; the layout written, or why there is none.
fn finish(
    mesh: &Mesh,
    field: &CrossField,
    g: &mut CurveGraph,
    options: &LayoutOptions,
    diag: f64,
    seeds_left: &mut usize,
    pass: Pass,
) -> Result<Written, String> {
    let mut rejections = 0;
    let mut tried = Tried {
        seeds: Vec::new(),
        continue_bends: pass == Pass::Build,
        batch: false,
        ring_seeds: 0,
        on_arc: vec![false; mesh.n_vertices()],
        parted: Vec::new(),
        loop_length: LOOP_EDGES * judged_length(mesh, options),
    };
    // Segments whose sparse waypoints let their curve meet another: written with every vertex.
    let mut dense = vec![false; g.segments.len()];
    let mut solved = CountsSolved::default();
    for round in 0..MAX_ROUNDS {
        tried.batch = round >= BATCH_AFTER;
        if repair(mesh, field, g, options.patches, diag, seeds_left, &mut tried)? {
            continue;
        }
        dense.resize(g.segments.len(), false);
        let rejected = match write(mesh, field, g, &dense, pass == Pass::Build, &mut solved) {
            Ok(done) => return Ok(done),
            Err(e) => e,
        };
        // Simplify where the reader or the counts refused, and try again: first follow the
        // paths of sparse curves that meet or found no path more closely, then give up a trace.
        let live: Vec<u32> = g.live().collect();
        let sparse = |i: u32| live.get(i as usize).copied().filter(|&s| !dense[s as usize]);
        // A face whose curves, straightened between their waypoints, swept over every vertex
        // inside it: its curves (the edges between its nodes).
        let coarse: Vec<u32> = match &rejected {
            Rejected::Layout(LayoutError::TooCoarse { nodes }) if g.from_cells => {
                let vertex: Vec<u32> = (0..mesh.n_vertices() as u32).filter(|&v| g.node[v as usize]).collect();
                let at: Vec<u32> = nodes.iter().filter_map(|&n| vertex.get(n as usize).copied()).collect();
                let between = |s: u32| {
                    let p = &g.segments[s as usize].path;
                    at.contains(&p[0]) && at.contains(&p[p.len() - 1])
                };
                (0..live.len() as u32).filter(|&k| between(live[k as usize])).collect()
            }
            _ => Vec::new(),
        };
        let densify: Vec<u32> = match &rejected {
            Rejected::Layout(LayoutError::CurvesMeet { a, b, .. }) => [a, b].iter().filter_map(|c| c.edge().and_then(sparse)).collect(),
            Rejected::Layout(LayoutError::NoPath { edge, .. }) => sparse(*edge as u32).into_iter().collect(),
            Rejected::Layout(LayoutError::TooCoarse { .. }) if g.from_cells => coarse.iter().filter_map(|&k| sparse(k)).collect(),
            _ => Vec::new(),
        };
        for &s in &densify {
            dense[s as usize] = true;
        }
        let removed = !densify.is_empty()
            || match &rejected {
                Rejected::Layout(LayoutError::CurvesMeet { a: CurveSource::Edge(i), b: CurveSource::Edge(j), .. }) => {
                    remove_trace(g, None, &[*i as u32, *j as u32])
                }
                Rejected::Counts(CountError::Infeasible { pieces_at_one }, surface) => {
                    remove_trace(g, Some(surface), pieces_at_one)
                }
                Rejected::Counts(CountError::Fractional { piece }, surface) => remove_trace(g, Some(surface), &[*piece]),
                Rejected::Param(v, _) => remove_near(mesh, g, *v),
                Rejected::Layout(LayoutError::TooCoarse { .. }) if g.from_cells => remove_trace(g, None, &coarse),
                _ => false,
            };
        rejections += 1;
        if !removed || rejections > MAX_REJECTIONS {
            return Err(rejected.to_string());
        }
    }
    Err("the repairs did not converge".into())
}

/// Splits the faces a short solve finds far more distorted than the others (a face round an
/// ear's tip, or whose corners are not where it turns: no chart fits it) with a cross of traces
/// where their distortion concentrates, while that lowers the layout's distortion (the
/// area-weighted mean of the faces' length errors); the best layout written. The faces are
/// picked as the verdict picks them ([`faces_above`]), with a lower bar: the verdict warns of
/// what no chart optimization mends, this mends what it can. Measured at --quads 4000
/// (bench): Hausdorff distance on fandisk 8.2 → 3.0 % of the diagonal, elephant 3.6 → 2.3 %,
/// bunny_28k 2.9 → 2.3 %; nefertiti, eight and mushroom keep their first layout.
///
/// Then faces smaller than a 2 × 2 grid of the quads judged ([`merge_sides`]), and slivers: a
/// strip of quads keeps its width from face to face, so a strip one quad wide
/// in a sliver and seven where its traces part skews one of the two whatever the counts, and
/// the integer counts end far from what the curves ask for (bunny_28k: a 1 × 11 face whose
/// short sides asked for one segment got seven). A sliver's long side is removed where that
/// brings the counts nearer (`count_error`), at most [`MERGE_TRIES`] tries: fandisk 3.0 → 0.7 %,
/// bunny_28k's folded quads 5 → 0 and its angle deviation 16.4 → 14.5°. So is a side of the
/// faces whose counts miss most ([`missed_sides`]), where a face is no sliver but a strip of
/// quads still runs wide in one place and narrow in another: nefertiti's 6 faces become 4, at
/// --quads 2000 / 4000 / 8000 its mean angle deviation 25.5–26.5 → 11.5–12.1° and its
/// Hausdorff distance 1.70 / 1.51 / 1.38 → 1.91 / 1.06 / 0.83 %; mushroom's 5 become 4, 5.4 →
/// 2.9–3.3° and 2.05 / 0.85 / 0.67 → 1.61 / 0.97 / 0.63 %; the other shared meshes keep theirs.
fn refine(
    mesh: &Mesh,
    field: &CrossField,
    options: &LayoutOptions,
    diag: f64,
    g: CurveGraph,
    first: Written,
    seeds_left: usize,
) -> (Layout, SurfaceLayout) {
    let Written { layout, surface, param, count_error, curve_miss, count_freedom } = first;
    let Some(mut score) = param.and_then(|p| solved_distortion(p, &surface)) else { return (layout, surface) };
    let mut best = Kept { graph: g, layout, surface, count_error, curve_miss };
    let h = default_edge_length(mesh);
    let share = tries_share(count_freedom);
    for _ in 0..(REFINES as f64 * share) as usize {
        let surface = &best.surface;
        let mut bad = faces_above(&score.face_area, &score.measured, h, SPLIT_RATIO, SPLIT_FLOOR);
        let weight = |f: usize| score.face_area[f] * score.measured.length_error[f];
        bad.sort_by(|&a, &b| weight(b).total_cmp(&weight(a)));
        let seeds: Vec<u32> = bad
            .iter()
            .filter_map(|&f| score.measured.worst_at[f].and_then(|at| nearest_vertex(mesh, surface, f as u32, at)))
            .filter(|&v| !best.graph.taken(v))
            .collect();
        // All the distorted faces at once, else the worst alone: splitting one face moves the
        // traces of its neighbours, and may cost more there than it gains.
        let split = |seeds: &[u32]| {
            let mut trial = best.graph.clone();
            seed(mesh, field, &mut trial, seeds, diag);
            let mut left = seeds_left;
            let Written { layout, surface, param, count_error, curve_miss, .. } = finish(mesh, field, &mut trial, options, diag, &mut left, Pass::Build).ok()?;
            let s = solved_distortion(param?, &surface).filter(|s| s.mean < score.mean)?;
            Some((s, Kept { graph: trial, layout, surface, count_error, curve_miss }))
        };
        let tries: Vec<&[u32]> = match seeds.len() {
            0 => Vec::new(),
            1 => vec![&seeds],
            _ => vec![&seeds, &seeds[..1]],
        };
        let Some((s, better)) = first_some(&tries, |t| split(t)).0 else { break };
        score = s;
        best = better;
    }
    // Tiny faces and slivers: remove a side of one while the counts come nearer what the
    // curves ask for, tiny and narrow at the quads the proposal is judged by.
    let quad = judged_length(mesh, options);
    let mut tries = (MERGE_TRIES as f64 * share) as usize;
    while tries > 0 {
        // Then the sides of the faces whose counts miss most (after the slivers: tried first,
        // they took the budget from slivers that mattered more, chaotically).
        let mut candidates = merge_sides(mesh, &best.graph, quad);
        for s in missed_sides(&best.graph, &best.surface, &best.curve_miss) {
            if !candidates.contains(&s) {
                candidates.push(s);
            }
        }
        let merge = |&s: &u32| {
            let mut trial = best.graph.clone();
            trial.remove(s);
            let mut left = seeds_left;
            // The parameterization's checks of the refined mesh, only for a removal that helps.
            let w = finish(mesh, field, &mut trial, options, diag, &mut left, Pass::Merge).ok()?;
            let helps = w.count_error < best.count_error && ParamSession::check(mesh, &w.surface, &ParamOptions::default()).is_ok();
            helps.then_some(Kept { graph: trial, layout: w.layout, surface: w.surface, count_error: w.count_error, curve_miss: w.curve_miss })
        };
        let (merged, tried) = first_some(&candidates[..candidates.len().min(tries)], merge);
        tries -= tried;
        let Some(m) = merged else { break };
        best = m;
    }
    (best.layout, best.surface)
}

/// `layout` (as `placed`) with the corners of all its faces chosen together
/// ([`corners::choose`] within `budget`), if that moves any and the counts still hold.
fn with_corners_together(mesh: &Mesh, field: &CrossField, placed: &Placement, layout: &Layout, budget: f64) -> Option<(Layout, SurfaceLayout)> {
    let unpatched = Layout { patches: Vec::new(), ..layout.clone() };
    let w = write_patches(mesh, field, placed, unpatched, budget, false, &mut CountsSolved::default()).ok()?;
    (w.layout.patches != layout.patches).then_some((w.layout, w.surface))
}

/// Counts with more degrees of freedom than this cost [`refine`] fewer tries...
const TRIES_FREEDOM: f64 = 400.0;

/// ... in proportion to the cube of the freedom: what one try costs. Each try writes the
/// layout again, and the integer counts of a layout with many T-vertices are a dense
/// quadratic program as large as their freedom ([`crate::quad::counts`]). The shared meshes'
/// layouts and CGAL's have at most 330 (man, 483 singularities); CGAL's elephant-with-holes,
/// whose 106 holes get four nodes each, about 1000: each try took 2–6 s, and `quadlay
/// layout` had not ended after 18 minutes; with one merge and no split it takes 4 minutes
/// (the repairs' own writes, each of those solves).
fn tries_share(count_freedom: usize) -> f64 {
    (TRIES_FREEDOM / count_freedom.max(1) as f64).powi(3).min(1.0)
}

/// The first of `items` for which `f` gives something, and how many items that took (all of
/// them when none did): the tries of [`refine`], in their order, one after the other. Each
/// writes and solves a whole layout (about 0.1 s on bunny_28k). They ran two at a time on two
/// threads before, but the tracings' proposals already share the processors ([`at_once`]),
/// and a second try whose first succeeded was work thrown away: one at a time,
/// `quadlay layout` took 18 % less time on bunny_28k, 12 % on elephant_44k and 8 % on CGAL's
/// cow (paired runs, the same layouts).
fn first_some<T, R>(items: &[T], f: impl Fn(&T) -> Option<R>) -> (Option<R>, usize) {
    items.iter().enumerate().find_map(|(k, x)| f(x).map(|r| (Some(r), k + 1))).unwrap_or((None, items.len()))
}

/// The best layout [`refine`] has found so far, with the graph it was written from and its
/// counts' measures (as [`Written`] gives them).
struct Kept {
    graph: CurveGraph,
    layout: Layout,
    surface: SurfaceLayout,
    count_error: f64,
    curve_miss: Vec<f64>,
}

/// The traces bounding the faces of the curves whose counts miss their wish most (by more
/// than [`MISS_SEGMENTS`], the worst [`MISSED_CURVES`]): where a strip of quads is wide in
/// one place and narrow in another, one of these may be what holds it together.
fn missed_sides(g: &CurveGraph, surface: &SurfaceLayout, curve_miss: &[f64]) -> Vec<u32> {
    let live: Vec<u32> = g.live().collect();
    let mut worst: Vec<usize> = (0..curve_miss.len()).filter(|&c| curve_miss[c] > MISS_SEGMENTS).collect();
    worst.sort_by(|&a, &b| curve_miss[b].total_cmp(&curve_miss[a]));
    let mut out = Vec::new();
    for c in worst.into_iter().take(MISSED_CURVES) {
        for k in curves_round_faces_of(surface, &[c as u32]) {
            let CurveSource::Edge(i) = surface.curves[k as usize].source else { continue };
            let Some(&s) = live.get(i) else { continue };
            if !g.segments[s as usize].feature && !out.contains(&s) {
                out.push(s);
            }
        }
    }
    out
}

/// The curves round every face that has one of `curves` on its boundary, face by face.
fn curves_round_faces_of<'a>(surface: &'a SurfaceLayout, curves: &'a [u32]) -> impl Iterator<Item = u32> + 'a {
    surface
        .faces
        .iter()
        .filter(|f| f.pieces.iter().any(|d| curves.contains(&d.curve)))
        .flat_map(|f| f.pieces.iter().map(|d| d.curve))
}

/// A layout's distortion after the harmonic solve and one chart optimization (near what three
/// give, at a third of the time).
struct Solved {
    measured: FaceDistortion,
    face_area: Vec<f64>,
    /// The area-weighted mean of the faces' length errors.
    mean: f64,
}

fn solved_distortion(mut param: ParamSession, surface: &SurfaceLayout) -> Option<Solved> {
    param.step().ok()?;
    let faces = surface.faces.len();
    let measured = face_distortion(&param, faces);
    let face_area = face_areas(param.cut(), faces);
    let total: f64 = face_area.iter().sum();
    let mean = face_area.iter().zip(&measured.length_error).map(|(a, e)| a * e).sum::<f64>() / total;
    mean.is_finite().then_some(Solved { measured, face_area, mean })
}

/// Per vertex: [`BLOCKED`] where the graph or the boundary has it, else free.
fn owners(mesh: &Mesh, g: &CurveGraph) -> Vec<u32> {
    (0..mesh.n_vertices() as u32).map(|v| if g.taken(v) { BLOCKED } else { NONE }).collect()
}

/// A trace to grow: its start vertex, its heading there, and whether it continues a feature
/// line.
type Launch = (u32, Vec3, bool);

/// Grows traces from `launches` together (the motorcycle rule: the graph's vertices and
/// nodes are taken) and adds those that ended on something to the graph. A trace that
/// continues a feature line is kept and tagged like the line (a crease that fades out goes on
/// as an edge loop), so no repair leaves the line dangling for the pruning to take away.
fn grow(mesh: &Mesh, field: &CrossField, g: &mut CurveGraph, diag: f64, launches: &[Launch]) {
    // Iso-lines only: see SNAP.
    let snap = if field.iso.arms.is_empty() { 0.0 } else { SNAP * diag };
    let mut moto = Motorcycles::new(mesh, field, owners(mesh, g), MAX_TRACE_LENGTH * diag).snapping(snap).crossing(line_tangents(mesh, field, g));
    for &(v, heading, _) in launches {
        moto.launch(v, heading);
    }
    moto.run();
    // One trace per launch, in order, then their continuations across feature lines, each
    // tagged as the trace it continues.
    let mut feature: Vec<bool> = launches.iter().map(|l| l.2).collect();
    for t in &moto.traces[launches.len()..] {
        feature.push(feature.get(t.continues as usize).copied().unwrap_or(false));
    }
    for (t, &feature) in moto.traces.iter().zip(&feature) {
        if t.end == TraceEnd::Hit && t.path.len() >= 2 {
            g.add_path(&t.path, feature);
        }
    }
    g.prune(Some(mesh));
}

/// Per vertex inside a feature line (no node, not on the boundary): the line's direction
/// there, where traces that meet it go on across ([`Motorcycles::crossing`]); zero elsewhere.
/// A trace that ended on the line left a T-junction on each side, each where its own side's
/// trace met the line, and the piece of the line between them had to take a segment however
/// short, straining the counts round it (fandisk: 112 T-vertices, 8 curves whose counts
/// were stretched, where the hand-made `fandisk-features` has 18 T-vertices and its grid
/// lines cross the sharp edges). Measured with `quadlay layout`, then `remesh --quads 4000`,
/// on the 36 meshes (the shared ones and 29 of CGAL's): fandisk's mean angle deviation
/// 4.92 → 3.22° (0.33 → 0.49 % of the diagonal); geometric-mean Hausdorff distance 1.281 →
/// 1.264 %, mean angle deviation 6.42 → 6.25°, folded quads 81 → 68, irregular vertices
/// 2733 → 2721; only meshes with feature lines change (anchor 1.85 → 1.10 %, 11.1 → 8.3°,
/// spool 1.14 → 0.62 %, 5.3 → 4.0°; rotor 1.48 → 3.06 %).
fn line_tangents(mesh: &Mesh, field: &CrossField, g: &CurveGraph) -> Vec<Vec3> {
    let mut tangents = vec![[0.0; 3]; mesh.n_vertices()];
    for line in &field.features.lines {
        for w in line.windows(3) {
            if !g.node[w[1] as usize] && !mesh.is_boundary_vertex(w[1]) {
                tangents[w[1] as usize] = unit(sub(mesh.position(w[2]), mesh.position(w[0])));
            }
        }
    }
    tangents
}

/// Of the two directions that continue a bend's segments through it, the one whose trace
/// ends soonest (it changes the layout least).
/// `taken`: the graph's [`owners`].
fn shorter_continuation(mesh: &Mesh, field: &CrossField, taken: &[u32], diag: f64, v: u32, dirs: [Vec3; 2]) -> Vec3 {
    let length = |d: Vec3| {
        let mut moto = Motorcycles::new(mesh, field, taken.to_vec(), MAX_TRACE_LENGTH * diag);
        moto.launch(v, d);
        moto.run();
        let t = &moto.traces[0];
        if t.end == TraceEnd::Hit { t.path.len() } else { usize::MAX }
    };
    let [a, b] = dirs;
    if length(b) < length(a) { b } else { a }
}

/// Nodes on every boundary loop: its corners, and more (evenly by length) until it has four
/// (or as many as it has vertices).
fn boundary_nodes(mesh: &Mesh, g: &mut CurveGraph) {
    let interior_angle = |v: u32| -> f64 { mesh.outgoing(v).filter(|&h| mesh.face(h) != NONE).map(|h| corner_angle(mesh, h)).sum() };
    for lp in topology(mesh).boundary_loops {
        let verts: Vec<u32> = lp.iter().map(|&h| mesh.to_vertex(h)).collect();
        let chosen: Vec<usize> = (0..verts.len())
            .filter(|&k| g.node[verts[k] as usize] || (interior_angle(verts[k]) - PI).abs() > BOUNDARY_CORNER)
            .collect();
        for k in at_least_four(mesh, &verts, chosen) {
            g.add_node(verts[k], true);
        }
    }
}

/// `chosen` (positions in the closed loop `verts`) and more, each the vertex farthest along
/// the loop from every one chosen, until there are four (or as many as the loop has vertices).
fn at_least_four(mesh: &Mesh, verts: &[u32], mut chosen: Vec<usize>) -> Vec<usize> {
    let mut at = vec![0.0];
    for k in 1..verts.len() {
        at.push(at[k - 1] + norm(sub(mesh.position(verts[k]), mesh.position(verts[k - 1]))));
    }
    let total = at[verts.len() - 1] + norm(sub(mesh.position(verts[0]), mesh.position(verts[verts.len() - 1])));
    while chosen.len() < 4.min(verts.len()) {
        let gap = |k: usize| {
            chosen
                .iter()
                .map(|&c| {
                    let d = (at[k] - at[c]).abs();
                    d.min(total - d)
                })
                .fold(f64::INFINITY, f64::min)
        };
        let Some(k) = (0..verts.len()).max_by(|&a, &b| gap(a).total_cmp(&gap(b))) else { break };
        chosen.push(k);
    }
    chosen
}

/// A closed feature line at least this many judged quad edge lengths long (a hole's rim, a
/// fillet round a boss) is cut across where it bounds a face that is not a disk
/// ([`loop_launches`]).
const LOOP_EDGES: f64 = 4.0;

/// Traces across the closed feature lines (without corners, at least `length` long, with
/// fewer than four nodes) that bound a face of `not_disk`: nodes evenly along each until it
/// has four, and from every one a trace into each side of the line. Nothing else starts a
/// trace from such a line (no corner ends it, no singularity need lie near), so the band round
/// a hole in a plate, or a hole's wall between its two rims, stays a ring that the repairs cut
/// with shortest arcs, which hug the lines and leave empty faces that the next repair removes
/// again (CGAL's couplingdown: every proposal ran out of repair rounds). The field runs along
/// the line, so traces across it leave it square. Only where a ring needs it, so that no
/// other layout changes: at the start, on every such line, the 26 meshes of the bench's
/// comparisons came out the same but for CGAL's handle (0.59 → 0.73 % of the diagonal).
fn loop_launches(mesh: &Mesh, field: &CrossField, g: &mut CurveGraph, not_disk: &[&FaceInfo], length: f64) -> Vec<Launch> {
    let mut round = vec![false; mesh.n_vertices()];
    for f in not_disk {
        for &s in &f.segments {
            for &v in &g.segments[s as usize].path {
                round[v as usize] = true;
            }
        }
    }
    let mut launches = Vec::new();
    for line in &field.features.lines {
        let n = line.len().saturating_sub(1);
        let closed = n >= 4 && line[0] == line[n];
        if !closed || !line.iter().any(|&v| round[v as usize]) || line.iter().any(|&v| mesh.is_boundary_vertex(v)) {
            continue;
        }
        let long = line.windows(2).map(|w| norm(sub(mesh.position(w[1]), mesh.position(w[0])))).sum::<f64>() >= length;
        let verts = &line[..n];
        let chosen: Vec<usize> = (0..n).filter(|&k| g.node[verts[k] as usize]).collect();
        if !long || chosen.len() >= 4 {
            continue;
        }
        for k in at_least_four(mesh, verts, chosen) {
            let v = verts[k];
            g.add_node(v, true);
            let (prev, next) = (verts[(k + n - 1) % n], verts[(k + 1) % n]);
            launches.extend(headings_off_line(mesh, v, prev, next).into_iter().map(|d| (v, d, false)));
        }
    }
    launches
}

/// Headings from interior vertex `v` of a line (between its neighbours `prev` and `next` on
/// it) into each of the line's two sides: the mean direction to the ring vertices of the side.
fn headings_off_line(mesh: &Mesh, v: u32, prev: u32, next: u32) -> Vec<Vec3> {
    let ring: Vec<u32> = mesh.neighbors(v).collect();
    let (Some(i), Some(j)) = (ring.iter().position(|&u| u == prev), ring.iter().position(|&u| u == next)) else { return Vec::new() };
    let p = mesh.position(v);
    [(i, j), (j, i)]
        .into_iter()
        .map(|(a, b)| {
            let mut sum = [0.0; 3];
            let mut k = a;
            loop {
                sum = add(sum, unit(sub(mesh.position(ring[k]), p)));
                if k == b {
                    break;
                }
                k = (k + 1) % ring.len();
            }
            unit(sum)
        })
        .collect()
}

fn singular_vertices(mesh: &Mesh, field: &CrossField, g: &CurveGraph, cancel: f64) -> Vec<(u32, Vec<[f64; 3]>)> {
    let centroid = |f: u32| {
        let p = mesh.triangles()[f as usize].map(|v| mesh.position(v));
        std::array::from_fn::<f64, 3, _>(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0)
    };
    let sing: Vec<_> = field
        .singularities
        .iter()
        .filter(|s| mesh.triangles()[s.triangle as usize].iter().all(|&v| !g.taken(v)))
        .collect();
    let mut gone = vec![false; sing.len()];
    let mut pairs = Vec::new();
    for i in 0..sing.len() {
        for j in i + 1..sing.len() {
            if sing[i].quarter_turns == -sing[j].quarter_turns {
                let d = norm(sub(centroid(sing[i].triangle), centroid(sing[j].triangle)));
                if d < cancel {
                    pairs.push((d, i, j));
                }
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (_, i, j) in pairs {
        if !gone[i] && !gone[j] {
            gone[i] = true;
            gone[j] = true;
        }
    }
    let mut used = vec![false; mesh.n_vertices()];
    let mut out = Vec::new();
    for (i, s) in sing.iter().enumerate() {
        if gone[i] {
            continue;
        }
        let c = centroid(s.triangle);
        // The triangle's corners, then their neighbours, nearest first: two singularities in
        // neighbouring triangles (they crowd where the surface curves most, an ear's tip) both
        // get a vertex, one ring apart, rather than the second being lost.
        let corners = mesh.triangles()[s.triangle as usize];
        let mut candidates: Vec<u32> = corners.iter().flat_map(|&v| std::iter::once(v).chain(mesh.neighbors(v))).collect();
        // Cones of the seamless parameterization first: its iso-lines part there.
        let cone = |v: u32| !field.iso.cone.get(v as usize).copied().unwrap_or(false);
        candidates.sort_by(|&a, &b| cone(a).cmp(&cone(b)).then(norm(sub(mesh.position(a), c)).total_cmp(&norm(sub(mesh.position(b), c)))));
        let free = |v: u32| !used[v as usize] && !g.taken(v) && mesh.neighbors(v).all(|u| !used[u as usize]);
        let Some(&v) = candidates.iter().find(|&&v| free(v)) else {
            continue;
        };
        let dirs = separatrix_directions(mesh, field, v);
        if dirs.is_empty() {
            continue;
        }
        used[v as usize] = true;
        out.push((v, dirs));
    }
    out
}

/// A repair that ran out of mesh vertices, with what the user can do: faces need vertices
/// inside and round them, and a mesh too coarse for the layout has too few. Splitting each
/// triangle into four (twice where once is not enough) let the layout of the coarse meshes of
/// `tests/hostile_input.rs` through: the 12-triangle cube, a 100:1 strip, a single triangle, an
/// 8 × 4 torus.
fn too_coarse(why: &str) -> String {
    format!("{why}; the mesh is too coarse there: split its triangles (each into four) and try again")
}

/// What [`finish`] is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Pass {
    /// A layout built or split: bends are traced on through, and [`write`] sets up the
    /// parameterization (and refuses what its checks refuse).
    Build,
    /// Two faces merged by removing a side: the curves at its ends join through the bends it
    /// leaves, and the parameterization is set up only for a merge that helps.
    Merge,
}

/// What a [`finish`] has tried, so as not to try it again, and may try.
struct Tried {
    /// The vertices faces that are not disks were seeded from, and bends continued from.
    seeds: Vec<u32>,
    continue_bends: bool,
    /// Past [`BATCH_AFTER`] rounds: mend all faces of a kind in one round.
    batch: bool,
    /// Rounds that seeded crosses in faces that are not disks.
    ring_seeds: usize,
    /// Per vertex: on an arc added ([`cut_rings`], [`part_arc_slits`]).
    on_arc: Vec<bool>,
    /// The arcs [`part_arc_slits`] added (their paths): one that a later round takes away
    /// again is not added again.
    parted: Vec<Vec<u32>>,
    /// The shortest closed feature line cut across ([`loop_launches`]).
    loop_length: f64,
}

impl Tried {
    /// Adds `arc` to `g` as a trace, its vertices marked as an arc's.
    fn add_arc(&mut self, g: &mut CurveGraph, arc: &[u32]) {
        for &v in arc {
            self.on_arc[v as usize] = true;
        }
        g.add_path(arc, false);
    }

    /// Whether segment `s` of `g` lies along arcs added (all its vertices are theirs).
    fn is_arc(&self, g: &CurveGraph, s: u32) -> bool {
        g.segments[s as usize].path.iter().all(|&v| self.on_arc[v as usize])
    }
}

/// One repair (see the module documentation); false when nothing needed repair.
fn repair(
    mesh: &Mesh,
    field: &CrossField,
    g: &mut CurveGraph,
    patches: Option<usize>,
    diag: f64,
    seeds_left: &mut usize,
    tried: &mut Tried,
) -> Result<bool, String> {
    g.prune(tried.continue_bends.then_some(mesh));
    let ends = g.dangling_feature_ends(mesh);
    if !ends.is_empty() && *seeds_left > 0 {
        // A repair took away what a feature line ended on: continue it again.
        *seeds_left -= 1;
        let launches: Vec<Launch> = ends.iter().map(|&(v, d)| (v, d, true)).collect();
        grow(mesh, field, g, diag, &launches);
        if g.dangling_feature_ends(mesh).len() < ends.len() {
            return Ok(true);
        }
    }
    // A repair cut a trace where another ended on it: continue one of the two on (once from
    // each node: a continuation that a later repair takes away again is not tried again).
    let bends: Vec<(u32, [Vec3; 2])> = g.bends(mesh).into_iter().filter(|(v, _)| !tried.seeds.contains(v)).collect();
    if !bends.is_empty() {
        let taken = owners(mesh, g);
        let launches: Vec<Launch> = bends.iter().map(|&(v, dirs)| (v, shorter_continuation(mesh, field, &taken, diag, v, dirs), false)).collect();
        tried.seeds.extend(bends.iter().map(|b| b.0));
        grow(mesh, field, g, diag, &launches);
        return Ok(true);
    }
    let fa = analyze(mesh, g);
    if part_arc_slits(mesh, g, &fa, tried) {
        return Ok(true);
    }
    let not_disk: Vec<&FaceInfo> = fa.faces.iter().filter(|f| f.euler != 1).collect();
    if !not_disk.is_empty() {
        // Before `loop_launches`, which may add nodes.
        let deepest = fa.deepest(mesh, g);
        let not_disk_deepest = || fa.faces.iter().zip(&deepest).filter(|(f, _)| f.euler != 1).filter_map(|(_, d)| *d);
        let launches = loop_launches(mesh, field, g, &not_disk, tried.loop_length);
        if !launches.is_empty() {
            grow(mesh, field, g, diag, &launches);
            return Ok(true);
        }
        // A seed whose traces all ended at once (the face is thin there) would only be tried
        // again: it is not.
        let seeds: Vec<u32> = not_disk_deepest().filter(|v| !tried.seeds.contains(v)).collect();
        let crosses_missed = seeds.is_empty() || *seeds_left == 0 || tried.ring_seeds >= RING_SEEDS;
        if crosses_missed && cut_rings(mesh, g, &fa, &deepest, tried) {
            return Ok(true);
        }
        if seeds.is_empty() {
            // A ring of curves with nothing inside, or too thin to cut: drop one of its traces
            // (not an arc: the arc that parts a slit would only be put back, round after
            // round, as on CGAL's femur).
            let s = not_disk.iter().flat_map(|f| f.segments.iter()).find(|&&s| !g.segments[s as usize].feature && !tried.is_arc(g, s));
            let Some(&s) = s else {
                return Err(too_coarse("a face is not a disk and has no vertex inside to cut it from"));
            };
            g.remove(s);
            return Ok(true);
        }
        if *seeds_left == 0 {
            // Arcs found nothing to cut (CGAL's femur, genus 2: a face whose boundary meets
            // itself in many slits).
            let at = not_disk_deepest().next().map(|v| mesh.position(v)).unwrap_or([f64::NAN; 3]);
            return Err(format!(
                "a face is still not a disk after arcs and {MAX_SEED_ROUNDS} rounds of crosses of traces cut it: it wraps round a \
                 handle or a part and its sides run into each other (near {:.6}, {:.6}, {:.6}); draw the layout there by hand",
                at[0], at[1], at[2]
            ));
        }
        *seeds_left -= 1;
        tried.ring_seeds += 1;
        tried.seeds.extend(&seeds);
        seed(mesh, field, g, &seeds, diag);
        return Ok(true);
    }
    if !fa.slits.is_empty() {
        for &s in &fa.slits {
            g.remove(s);
        }
        return Ok(true);
    }
    // One face a round, or all of them once the rounds pass [`BATCH_AFTER`].
    let at_once = if tried.batch { usize::MAX } else { 1 };
    let empty: Vec<&FaceInfo> = fa.faces.iter().filter(|f| f.inside == 0).take(at_once).collect();
    if !empty.is_empty() {
        for f in empty {
            // A side gone already merged this face with a neighbour.
            if f.segments.iter().any(|&s| g.segments[s as usize].path.is_empty()) {
                continue;
            }
            // A trace if there is one, else a feature line too short to hold quads.
            let s = f.segments.iter().copied().min_by_key(|&s| (g.segments[s as usize].feature, g.from_cells && !fa.merges_cleanly(g, s), g.segments[s as usize].path.len()));
            let Some(s) = s else {
                return Err(too_coarse("a face has no mesh vertex inside and no curve to remove"));
            };
            g.remove(s);
        }
        return Ok(true);
    }
    let few: Vec<&FaceInfo> = fa.faces.iter().filter(|f| f.nodes.len() < 4).take(at_once).collect();
    if !few.is_empty() {
        for f in few {
            let Some(v) = farthest_boundary_vertex(mesh, g, &fa.of_triangle, f, &fa.faces) else {
                return Err(too_coarse("a face has fewer than four nodes and no room for more"));
            };
            g.add_node(v, true);
        }
        return Ok(true);
    }
    if let Some(target) = patches {
        if fa.faces.len() < target {
            let deepest = fa.deepest(mesh, g);
            let mut order: Vec<(&FaceInfo, u32)> = fa.faces.iter().zip(&deepest).filter_map(|(f, d)| Some((f, (*d)?))).collect();
            order.sort_by(|a, b| b.0.area.total_cmp(&a.0.area));
            // A cross of traces splits a face into about four.
            let count = (target - fa.faces.len()).div_ceil(3).max(1);
            let seeds: Vec<u32> = order.iter().take(count).map(|&(_, v)| v).collect();
            if !seeds.is_empty() && *seeds_left > 0 {
                *seeds_left -= 1;
                let before = g.live().count();
                seed(mesh, field, g, &seeds, diag);
                return Ok(g.live().count() != before);
            }
        }
    }
    Ok(false)
}

/// Cuts every face that is not a disk with an arc between two loops of its boundary
/// ([`arc_across`]) or, where it has one loop, round a handle ([`arc_round_handle`]), or
/// else across the stretches of its boundary parted where it meets itself (a ring pinched at
/// a node, or joined by a slit: [`self_touching`]); false if no face has an arc (a closed
/// surface without curves yet: crosses of traces start it). The last was the Voronoi cells'
/// alone ([`CurveGraph::from_cells`]); for traces too, over 26 meshes (the shared ones and 19
/// of CGAL's, at 4000 quads, with [`part_arc_slits`] adding no arc twice and the cells tried
/// for folded proposals) the geometric-mean Hausdorff distance went 1.68 → 1.48 % of the
/// diagonal (CGAL's dino 5.8 → 2.1 %, diplodocus 5.9 → 1.2 %, couplingdown 5.2 → 2.8 %;
/// armadillo 1.9 → 3.3 %), the mean angle deviation 7.90 → 8.50°, irregular vertices
/// 1918 → 1751, folded quads 71 → 52.
fn cut_rings(mesh: &Mesh, g: &mut CurveGraph, fa: &Faces, deepest: &[Option<u32>], tried: &mut Tried) -> bool {
    let arcs: Vec<Vec<u32>> = (0..fa.faces.len() as u32)
        .filter(|&f| fa.faces[f as usize].euler != 1)
        .filter_map(|f| {
            arc_across(mesh, g, fa, deepest, f, &[])
                .or_else(|| arc_round_handle(mesh, g, fa, f))
                .or_else(|| arc_across(mesh, g, fa, deepest, f, &self_touching(mesh, fa, f)))
        })
        .collect();
    for arc in &arcs {
        tried.add_arc(g, arc);
    }
    !arcs.is_empty()
}

/// An arc of [`cut_rings`] has its face on both sides (a slit, which the reader refuses; a
/// ring cut once is so): parts the sides of the first such face's arcs with an arc between
/// two stretches of its boundary that they divide; false if there is none to part, or the
/// arc is one added before: the prune takes away an arc that ends on no curve, and adding it
/// again would go round in circles until the rounds run out (CGAL's couplingdown, whose
/// three proposals all failed so; the slit then goes as any other does).
fn part_arc_slits(mesh: &Mesh, g: &mut CurveGraph, fa: &Faces, tried: &mut Tried) -> bool {
    let ours = |s: &u32| tried.is_arc(g, *s);
    let Some(&s) = fa.slits.iter().find(|s| ours(s)) else { return false };
    let Some(face) = fa.faces.iter().position(|f| f.segments.contains(&s)) else { return false };
    let slits = fa.faces[face].segments.iter().filter(|s| fa.slits.contains(s) && ours(s));
    let sides: Vec<u32> = slits.flat_map(|&s| g.segments[s as usize].path.iter().copied()).collect();
    let Some(arc) = arc_across(mesh, g, fa, &fa.deepest(mesh, g), face as u32, &sides) else { return false };
    if tried.parted.contains(&arc) {
        return false;
    }
    tried.add_arc(g, &arc);
    tried.parted.push(arc);
    true
}

/// Launches a cross of traces (the field's four arms) from each seed vertex.
fn seed(mesh: &Mesh, field: &CrossField, g: &mut CurveGraph, seeds: &[u32], diag: f64) {
    for &s in seeds {
        g.add_node(s, false);
    }
    let launches: Vec<Launch> = seeds.iter().flat_map(|&s| field.arms(s).map(|arm| (s, arm, false))).collect();
    grow(mesh, field, g, diag, &launches);
}

/// A vertex on the boundary of face `f` (inside one of its segments, or on the mesh
/// boundary) as far as possible from the face's nodes.
fn farthest_boundary_vertex(mesh: &Mesh, g: &CurveGraph, of_triangle: &[u32], f: &FaceInfo, faces: &[FaceInfo]) -> Option<u32> {
    let fi = faces.iter().position(|x| std::ptr::eq(x, f))? as u32;
    let mut best: Option<(f64, u32)> = None;
    let mut consider = |v: u32| {
        if g.node[v as usize] {
            return;
        }
        let d = f.nodes.iter().map(|&n| norm(sub(mesh.position(n), mesh.position(v)))).fold(f64::INFINITY, f64::min);
        if best.is_none_or(|b| d > b.0) {
            best = Some((d, v));
        }
    };
    for &s in &f.segments {
        let p = &g.segments[s as usize].path;
        for &v in &p[1..p.len() - 1] {
            consider(v);
        }
    }
    for v in 0..mesh.n_vertices() as u32 {
        if g.is_boundary(v) && mesh.outgoing(v).any(|h| mesh.face(h) != NONE && of_triangle[mesh.face(h) as usize] == fi) {
            consider(v);
        }
    }
    best.map(|b| b.1)
}

/// Removes the shortest trace among the layout curves `curves` (edges are the live
/// segments in order; boundary pieces follow them), else among the curves of the faces
/// those curves bound; false if there is no trace to remove.
fn remove_trace(g: &mut CurveGraph, surface: Option<&SurfaceLayout>, curves: &[u32]) -> bool {
    let live: Vec<u32> = g.live().collect();
    let shortest = |g: &CurveGraph, cs: &mut dyn Iterator<Item = u32>| {
        cs.filter_map(|k| live.get(k as usize).copied())
            .filter(|&s| !g.segments[s as usize].feature)
            .min_by_key(|&s| g.segments[s as usize].path.len())
    };
    let mut s = shortest(g, &mut curves.iter().copied());
    if s.is_none() {
        if let Some(surface) = surface {
            s = shortest(g, &mut curves_round_faces_of(surface, curves));
        }
    }
    match s {
        Some(s) => {
            g.remove(s);
            true
        }
        None => false,
    }
}

/// Removes a trace at or next to vertex `v`; false if there is none.
fn remove_near(mesh: &Mesh, g: &mut CurveGraph, v: u32) -> bool {
    if v as usize >= mesh.n_vertices() {
        return false;
    }
    let touches = |g: &CurveGraph, s: u32| {
        let p = &g.segments[s as usize].path;
        p.contains(&v) || mesh.neighbors(v).any(|u| p.contains(&u))
    };
    let s = g
        .live()
        .filter(|&s| !g.segments[s as usize].feature && touches(g, s))
        .min_by_key(|&s| g.segments[s as usize].path.len());
    match s {
        Some(s) => {
            g.remove(s);
            true
        }
        None => false,
    }
}

/// Mesh steps along a curve to the point whose direction stands for the curve's at a node.
const CHORD_STEPS: usize = 4;

/// The most the turns at a layout's chart corners may grow, summed over a chain of faces
/// ([`corners::choose`]), to take away two irregular vertices: as much as one corner moved
/// from a turn of 112.5° to one of 157.5° (each a quarter of the way from the right angle to
/// the straight side), or half that. Each gives a version of the proposal, judged beside the
/// plain one. Measured over 26 meshes at --quads 4000 (the seven shared meshes, twelve of
/// CGAL's, seven of ours), either alone against none: with π/8 the mean angle deviation went
/// 10.29 -> 10.13°, the irregular vertices 1397 -> 1403 (bunny_28k 84 -> 74, camel 138 ->
/// 197); with π/4 10.29 -> 9.73° and 1397 -> 1345 (bunny_28k's version judged worse).
const CORNER_BUDGETS: [f64; 2] = [PI / 4.0, PI / 8.0];

/// The face's angle at each of its nodes, in the node's tangent plane, measured between
/// chords along its two curves (a trace zig-zags along mesh edges: its first edge says little).
fn turns_of(mesh: &Mesh, field: &CrossField, surface: &SurfaceLayout, f: &Face) -> Vec<f64> {
    let n = f.nodes.len();
    let chord = |d: &Directed, leaving: bool| -> [f64; 3] {
        let pts = &surface.curves[d.curve as usize].curve.points;
        // Leaving along d forwards starts at its first point; arriving, it ends at its last.
        let from_start = d.forward == leaving;
        let k = CHORD_STEPS.min((pts.len() - 1) / 2).max(1).min(pts.len() - 1);
        let (a, b) = if from_start { (&pts[0], &pts[k]) } else { (&pts[pts.len() - 1], &pts[pts.len() - 1 - k]) };
        sub(curve::position(mesh, b), curve::position(mesh, a))
    };
    (0..n)
        .map(|k| {
            let v = surface.node_vertex[f.nodes[k] as usize];
            let out = field.frames.angle(v, chord(&f.pieces[k], true));
            let back = field.frames.angle(v, chord(&f.pieces[(k + n - 1) % n], false));
            // Counter-clockwise from the leaving curve to the arriving one: the face's angle.
            (back - out).rem_euclid(2.0 * PI)
        })
        .collect()
}

/// Per node, whether quads should meet four at a time there: inside the surface, off the
/// feature lines, and away from the field's singularities (their triangles' corners and
/// those corners' neighbours, where [`singular_vertices`] puts them).
fn regular_nodes(mesh: &Mesh, field: &CrossField, surface: &SurfaceLayout) -> Vec<bool> {
    let mut singular = vec![false; mesh.n_vertices()];
    for s in &field.singularities {
        for &v in &mesh.triangles()[s.triangle as usize] {
            singular[v as usize] = true;
            for u in mesh.neighbors(v) {
                singular[u as usize] = true;
            }
        }
    }
    surface
        .node_vertex
        .iter()
        .map(|&v| !singular[v as usize] && !mesh.is_boundary_vertex(v) && field.features.degree[v as usize] == 0)
        .collect()
}

/// The sample counts [`write`] solved in one [`finish`], the latest few: its rounds write the
/// same layout again where a repair puts back what a refusal took away (on CGAL's
/// elephant-with-holes, 66 of the first 93 writes repeated one of two layouts, each count
/// solve 1.5 s).
#[derive(Default)]
struct CountsSolved(Vec<SolvedCounts>);

/// A count problem (the desired counts and the equations) and its solution.
struct SolvedCounts {
    desired: Vec<f64>,
    equations: Vec<Equation>,
    counts: Result<Vec<u32>, CountError>,
}

/// How many problems [`CountsSolved`] remembers.
const COUNTS_REMEMBERED: usize = 4;

impl CountsSolved {
    /// [`sample_counts`] of the problem, solved again only if it is none of the latest.
    fn counts(&mut self, desired: &[f64], equations: &[Equation]) -> Result<Vec<u32>, CountError> {
        if let Some(known) = self.0.iter().find(|s| s.desired == desired && s.equations == equations) {
            return known.counts.clone();
        }
        let counts = sample_counts(desired, equations);
        if self.0.len() == COUNTS_REMEMBERED {
            self.0.remove(0);
        }
        self.0.push(SolvedCounts { desired: desired.to_vec(), equations: equations.to_vec(), counts: counts.clone() });
        counts
    }
}

/// Why the layout reader or the sample counts refused a written layout.
#[derive(Debug)]
enum Rejected {
    Layout(LayoutError),
    Counts(CountError, Box<SurfaceLayout>),
    /// The parameterization cannot place the triangles at this vertex (curves too close for
    /// the mesh).
    Param(u32, ParamError),
    /// The layout would have this many waypoints, more than a layout file may have: the reader
    /// would refuse the file written.
    Waypoints(usize),
}

impl fmt::Display for Rejected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Rejected::Layout(e) => write!(f, "{e}"),
            Rejected::Counts(e, _) => write!(f, "sample counts: {e}"),
            Rejected::Param(_, e) => write!(f, "{e}"),
            Rejected::Waypoints(n) => write!(f, "the layout has {n} waypoints, more than a layout file may have ({MAX_WAYPOINTS})"),
        }
    }
}

/// A layout written: the file, as the reader places it, and the parameterization set up on it
/// where asked (its checks passed; [`refine`] solves it).
struct Written {
    layout: Layout,
    surface: SurfaceLayout,
    param: Option<ParamSession>,
    /// How far the integer sample counts are from what the curves' lengths ask for: the sum of
    /// the differences over the sum of the wishes (each at least one segment).
    count_error: f64,
    /// Per layout curve: the most its count differs from a face's wish for it, in segments.
    curve_miss: Vec<f64>,
    /// The counts' degrees of freedom: their unknowns less their equations.
    count_freedom: usize,
}

/// The layout file of the graph, checked by the layout reader and the sample-count equations.
fn write(mesh: &Mesh, field: &CrossField, g: &CurveGraph, dense: &[bool], set_up: bool, solved: &mut CountsSolved) -> Result<Written, Rejected> {
    let nodes: Vec<u32> = (0..mesh.n_vertices() as u32).filter(|&v| g.node[v as usize]).collect();
    let mut index = vec![NONE; mesh.n_vertices()];
    for (i, &v) in nodes.iter().enumerate() {
        index[v as usize] = i as u32;
    }
    let edges: Vec<EdgeSpec> = g
        .live()
        .map(|s| {
            let seg = &g.segments[s as usize];
            let p = &seg.path;
            // Feature lines run along mesh edges: they keep every vertex.
            let via = if seg.feature || dense[s as usize] { p[1..p.len() - 1].to_vec() } else { sparse_waypoints(mesh, p) };
            EdgeSpec {
                nodes: [index[p[0] as usize], index[p[p.len() - 1] as usize]],
                align: seg.feature,
                via: via.into_iter().map(|v| Location::Vertex(v as u64)).collect(),
            }
        })
        .collect();
    // `build_layout` takes the layout as data and does not count them; the reader does.
    let waypoints = edges.iter().map(|e| e.via.len()).sum();
    if waypoints > MAX_WAYPOINTS {
        return Err(Rejected::Waypoints(waypoints));
    }
    let layout = Layout {
        nodes: nodes.iter().map(|&v| Location::Vertex(v as u64)).collect(),
        edges,
        default_chart: ChartType::Rect,
        // The identity of the mesh it was made for (layout-format.md, `mesh`).
        mesh: Some(MeshCounts::of(mesh)),
        ..Default::default()
    };
    // Placed once: the patches change only the corners.
    let placed = place(mesh, &layout, Numbering::of(mesh)).map_err(Rejected::Layout)?;
    write_patches(mesh, field, &placed, layout, 0.0, set_up, solved)
}

/// `layout` (without patches, as `placed`) with a rectangle chart on every face and the corners
/// [`corners::choose`] picks within `corner_budget`, checked by the layout reader and the
/// sample-count equations (and the parameterization's set-up where asked).
fn write_patches(
    mesh: &Mesh,
    field: &CrossField,
    placed: &Placement,
    mut layout: Layout,
    corner_budget: f64,
    set_up: bool,
    solved: &mut CountsSolved,
) -> Result<Written, Rejected> {
    let surface = placed.with_patches(mesh, &layout).map_err(Rejected::Layout)?;
    // Corners where the face turns most, measured along the curves rather than on their
    // first mesh edge (a trace zig-zags along edges). Every face gets a rectangle: the
    // paper's Section 5 gives faces bounded by features general quadrilaterals, but those
    // charts shear where the face's corners on the surface are far from right angles, and
    // their quads with them. Measured at --quads 4000 (bench; the faces with a feature or
    // boundary side general, then rectangles): bunny_1k8 Hausdorff 3.99 -> 2.58 %, angle
    // deviation 21.6 -> 16.4°, folded quads 12 -> 1; fandisk 0.69 -> 0.35 %, 9.4 -> 9.2°,
    // 3 -> 1; mushroom 1.06 -> 0.85 %, 6.7 -> 5.4°; eight 9.3 -> 9.5 %, 28.8 -> 29.4°,
    // 17 -> 13; nefertiti 0.81 -> 2.37 %, 28.0 -> 23.9°. The user re-charts a face at will.
    let turns: Vec<FaceTurns> =
        surface.faces.iter().map(|f| FaceTurns { nodes: f.nodes.clone(), turns: turns_of(mesh, field, &surface, f) }).collect();
    let chosen = corners::choose(&turns, &regular_nodes(mesh, field, &surface), corner_budget);
    let specs: Vec<PatchSpec> = surface
        .faces
        .iter()
        .zip(&chosen)
        .map(|(f, c)| PatchSpec { corners: c.map(|k| f.nodes[k]), chart: Some(ChartType::Rect) })
        .collect();
    // A patches entry names the first face with its four corners counter-clockwise round it;
    // where that is another face (a torus cut into two rings of faces: both have all four),
    // the face keeps the reader's corners and the default chart.
    for (fi, p) in specs.iter().enumerate() {
        if face_named_by(surface.faces.iter().map(|f| &f.nodes[..]), &p.corners).0 == Some(fi) {
            layout.patches.push(p.clone());
        }
    }
    let surface = placed.with_patches(mesh, &layout).map_err(Rejected::Layout)?;
    let h = default_edge_length(mesh);
    // The counts of Section 4 as extraction poses them (one unknown per face and piece),
    // wished from the curves' lengths; the error names curves.
    let desires: Vec<Vec<f64>> = surface
        .faces
        .iter()
        .map(|f| f.pieces.iter().map(|d| surface.curves[d.curve as usize].curve.length / h).collect())
        .collect();
    let problem = IncidenceCounts::new(&surface, &desires);
    let n = match solved.counts(&problem.desired, &problem.equations) {
        Ok(n) => n,
        Err(e) => {
            let curve = |i: u32| problem.curve.get(i as usize).copied().unwrap_or(NONE);
            let e = match e {
                CountError::Infeasible { pieces_at_one } => {
                    CountError::Infeasible { pieces_at_one: pieces_at_one.into_iter().map(curve).collect() }
                }
                CountError::Fractional { piece } => CountError::Fractional { piece: curve(piece) },
                other => other,
            };
            return Err(Rejected::Counts(e, Box::new(surface)));
        }
    };
    let count_freedom = problem.desired.len().saturating_sub(problem.equations.len());
    let wished: Vec<f64> = problem.desired.iter().map(|d| d.max(1.0)).collect();
    let count_error = n.iter().zip(&wished).map(|(&n, d)| (n as f64 - d).abs()).sum::<f64>() / wished.iter().sum::<f64>();
    let mut curve_miss = vec![0.0f64; surface.curves.len()];
    for ((&n, d), &c) in n.iter().zip(&wished).zip(&problem.curve) {
        curve_miss[c as usize] = curve_miss[c as usize].max((n as f64 - d).abs());
    }
    if !set_up {
        return Ok(Written { layout, surface, param: None, count_error, curve_miss, count_freedom });
    }
    // The parameterization's own checks of the cut mesh.
    match ParamSession::new(mesh, &surface, &ParamOptions::default()) {
        Ok(param) => Ok(Written { layout, surface, param: Some(param), count_error, curve_miss, count_freedom }),
        Err(e) => {
            let v = match e {
                ParamError::NotNeighbours { vertex, .. } => vertex,
                ParamError::NodeNotOnFace { node, .. } => surface.node_vertex.get(node as usize).copied().unwrap_or(NONE),
                _ => NONE,
            };
            Err(Rejected::Param(v, e))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::curve::tests::load;

    /// A problem met again gets the counts (or the refusal) it got, from the latest few.
    #[test]
    fn counts_solved_again_are_the_ones_solved() {
        // Pieces 0 + 1 = 2 (a side of two pieces opposite one), desired 1.4, 2.6, d.
        let equations: Vec<Equation> = vec![vec![(0, 1), (1, 1), (2, -1)]];
        let problem = |d: f64| vec![1.4, 2.6, d];
        let mut solved = CountsSolved::default();
        for d in [4.0, 3.0, 4.0, 5.0, 6.0, 7.0, 4.0] {
            assert_eq!(solved.counts(&problem(d), &equations), sample_counts(&problem(d), &equations), "{d}");
            assert!(solved.0.len() <= COUNTS_REMEMBERED);
        }
        // An infeasible one too: piece 0 = piece 0 + piece 1 leaves piece 1 at zero.
        let infeasible: Vec<Equation> = vec![vec![(0, 1), (0, -1), (1, -1)]];
        let first = solved.counts(&[2.0, 2.0], &infeasible);
        assert!(first.is_err());
        assert_eq!(solved.counts(&[2.0, 2.0], &infeasible), first);
    }

    /// The layout kept is the best of the six tracings' candidates by their quads
    /// ([`pick`]).
    #[test]
    fn the_tracing_whose_quads_are_best_is_kept() {
        let mesh = load("eight.obj");
        let options = LayoutOptions::default();
        let tracings = Tracings::new(&mesh, &options).unwrap();
        assert_eq!(tracings.count(), 6);
        let mut made: Vec<Candidate> = (0..tracings.count()).map(|k| tracings.candidate(&mesh, k, &options).unwrap()).collect();
        let kept = propose_layout(&mesh, &options).unwrap();
        let i = pick(&made.iter().map(|c| Some(c.summary())).collect::<Vec<_>>()).unwrap();
        let placed = place(&mesh, &made[i].layout, Numbering::of(&mesh)).unwrap();
        let chosen = with_corners_chosen(&mesh, &tracings.field, &placed, made.swap_remove(i), &options);
        assert_eq!(kept.layout, chosen.layout);
    }

    /// More items than processors: each is done once, and the answers come in the items'
    /// order whichever thread took them.
    #[test]
    fn at_once_answers_in_order() {
        let items: Vec<u64> = (0..40).collect();
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let out = at_once(&items, |&x| {
            calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            // Uneven work, so that the threads take the items out of order.
            std::thread::sleep(std::time::Duration::from_micros((x % 7) * 200));
            x * x
        });
        assert_eq!(out, items.iter().map(|x| x * x).collect::<Vec<_>>());
        assert_eq!(calls.into_inner(), items.len());
    }

    /// The best judged of all the tracings' proposals is kept, whichever tracing made it; where
    /// none could be judged, the first made.
    #[test]
    fn the_best_judged_proposal_of_all_tracings_is_kept() {
        let judged = |hausdorff: f64, score: f64| Some((Some(Judged { hausdorff, score, folded: 0 }), 10));
        assert_eq!(pick(&[judged(0.010, 3.0), judged(0.012, 4.0), None, judged(0.009, 1.0)]), Some(3));
        assert_eq!(pick(&[judged(0.010, 3.0), judged(0.012, 2.0), None, judged(0.030, 1.0)]), Some(1));
        assert_eq!(pick(&[None, Some((None, 10)), Some((None, 8))]), Some(1));
        assert_eq!(pick(&[None, None]), None);
    }

    /// Where no tracing made a layout, the last step makes one of Voronoi cells: on eight
    /// (genus 2) every cell is a disk, the layout reads back, and its quads can be made.
    #[test]
    fn without_a_tracing_s_layout_the_cells_give_one() {
        let mesh = load("eight.obj");
        let options = LayoutOptions::default();
        let tracings = Tracings::new(&mesh, &options).unwrap();
        let none = Err(ProposeError::NoValidLayout("none".into()));
        let c = tracings.conclude(&mesh, none, &options).unwrap();
        assert!(c.surface.faces.len() >= 8, "{} faces", c.surface.faces.len());
        let judged = c.judged.expect("its quads judged");
        assert!(judged.hausdorff < 0.1, "{judged:?}");
        place(&mesh, &c.layout, Numbering::of(&mesh)).unwrap().with_patches(&mesh, &c.layout).unwrap();
        // And a tracing's layout near the surface is kept as it is, up to its corners.
        let made = tracings.candidate(&mesh, 0, &options).unwrap();
        let edges = made.layout.edges.clone();
        assert_eq!(tracings.conclude(&mesh, Ok(made), &options).unwrap().layout.edges, edges);
    }

    /// Nodes where the quads of `surface` meet other than four at a time (once per face a node
    /// is a corner of, twice per face it lies on a side of), off the boundary.
    fn irregular_nodes(mesh: &Mesh, surface: &SurfaceLayout) -> usize {
        let mut valence = vec![0; surface.node_vertex.len()];
        for f in &surface.faces {
            for (k, &node) in f.nodes.iter().enumerate() {
                valence[node as usize] += if f.corners.contains(&k) { 1 } else { 2 };
            }
        }
        (0..valence.len()).filter(|&i| valence[i] != 4 && !mesh.is_boundary_vertex(surface.node_vertex[i])).count()
    }

    /// On a real mesh the corners chosen together leave fewer irregular nodes than each face's
    /// sharpest four, and the layout written reads back with them.
    #[test]
    fn corners_chosen_together_leave_fewer_irregular_nodes() {
        let mesh = load("bunny_1k8.obj");
        let options = LayoutOptions::default();
        let tracings = Tracings::new(&mesh, &options).unwrap();
        let field = tracings.tracings[0].as_ref().expect("the surface's field");
        let (layout, surface) = propose_along(&mesh, field, &options).unwrap();
        let placed = place(&mesh, &layout, Numbering::of(&mesh)).unwrap();
        let (together, surface_together) = with_corners_together(&mesh, field, &placed, &layout, CORNER_BUDGETS[0]).unwrap();
        assert_eq!(together.edges, layout.edges);
        let (before, after) = (irregular_nodes(&mesh, &surface), irregular_nodes(&mesh, &surface_together));
        assert!(after + 2 <= before, "{before} -> {after}");
        let read = place(&mesh, &together, Numbering::of(&mesh)).unwrap().with_patches(&mesh, &together).unwrap();
        let corners = |s: &SurfaceLayout| s.faces.iter().map(|f| f.corners.map(|k| f.nodes[k])).collect::<Vec<_>>();
        assert_eq!(corners(&read), corners(&surface_together));
    }

    /// Layouts whose counts have the freedom of the shared meshes' and CGAL's (up to 330) get
    /// every try; one with 1000 (a scan with 106 holes) one merge and no split: a try there
    /// costs (1000 / 400)³ ≈ 16 times one at 400.
    #[test]
    fn large_counts_cost_refine_its_tries() {
        for freedom in [0, 1, 90, 330, 400] {
            assert_eq!(tries_share(freedom), 1.0, "{freedom}");
        }
        let share = tries_share(1000);
        assert!((share - 0.064).abs() < 1e-12, "{share}");
        assert_eq!(((MERGE_TRIES as f64 * share) as usize, (REFINES as f64 * share) as usize), (1, 0));
        assert!(tries_share(2000) < tries_share(1000));
    }

    /// The tries give the first that helps, and how many tries that took.
    #[test]
    fn first_some_is_the_first_in_order_with_the_tries_counted_one_by_one() {
        let even = |&x: &u32| (x % 2 == 0).then_some(10 * x);
        assert_eq!(first_some(&[1, 3, 4, 6, 7], even), (Some(40), 3));
        assert_eq!(first_some(&[1, 2, 4], even), (Some(20), 2));
        assert_eq!(first_some(&[2, 4], even), (Some(20), 1));
        assert_eq!(first_some(&[1, 3, 5], even), (None, 3));
        assert_eq!(first_some(&[] as &[u32], even), (None, 0));
    }
}
