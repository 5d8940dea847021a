//! Quad mesh extraction (paper Section 4): sample counts per edge piece that agree on
//! opposite chart sides, a grid per chart, grid points mapped back to the surface.

pub mod closest;
pub mod quality;

pub mod counts;
pub mod cover;
pub mod density;
pub mod diagonals;
pub mod doublets;
pub mod locate;
pub mod rails;
pub mod rectify;
pub mod relax;

use crate::culprits::Culprits;
use crate::geom::{norm, sub};
use crate::layout::{CurveSource, SurfaceLayout};
use crate::mesh::{build_mesh, Mesh, MeshError, TriangleSoup, NONE};
use crate::param::frames::ChartFrames;
use crate::param::chart::ChartKind;
use crate::param::ParamSession;
use counts::{sample_counts, CountError};
use locate::{closest_on_segment, ChartIndex, Hit};
use std::fmt;

/// A pure quad mesh, welded: samples on layout edges and nodes are shared by the faces on
/// both sides.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct QuadMesh {
    pub positions: Vec<[f64; 3]>,
    /// Corners counter-clockwise seen from outside (the input's orientation).
    pub quads: Vec<[u32; 4]>,
    /// The layout node (corner or T-vertex) at each vertex, or [`NONE`].
    pub vertex_node: Vec<u32>,
}

impl QuadMesh {
    /// Vertices that are layout nodes (chart corners or T-vertices).
    pub fn node_vertices(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.vertex_node.len() as u32).filter(|&v| self.vertex_node[v as usize] != NONE)
    }
}

/// Settings of the extraction.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct QuadOptions {
    /// Target quad edge length in the mesh's units: the quad mesh gets about surface area /
    /// edge_length² quads ([`density`]). Default (via [`QuadOptions::for_mesh`]): 1/40 of the
    /// bounding-box diagonal.
    pub edge_length: f64,
    /// Rounds of relaxation on the surface ([`relax`]), one vertex at a time. Default:
    /// [`relax::ROUNDS`].
    pub relax_rounds: usize,
    /// Global steps toward rectangles before those rounds ([`rectify`]). Default:
    /// [`relax::STEPS`].
    pub rectify_steps: usize,
    /// Whether the samples of tagged curves slide along them in the rounds ([`rails`]).
    /// Default: true.
    pub slide_on_curves: bool,
    /// Whether the surface's points the quads miss most get a quad vertex on them after the
    /// rounds ([`cover`]). Default: true.
    pub cover_tips: bool,
}

impl QuadOptions {
    /// The default options for `mesh`.
    pub fn for_mesh(mesh: &Mesh) -> QuadOptions {
        QuadOptions::with_edge_length(default_edge_length(mesh))
    }
    pub fn with_edge_length(edge_length: f64) -> QuadOptions {
        QuadOptions { edge_length, relax_rounds: relax::ROUNDS, rectify_steps: relax::STEPS, slide_on_curves: true, cover_tips: true }
    }
}

/// 1/40 of the bounding-box diagonal of the mesh.
pub fn default_edge_length(mesh: &Mesh) -> f64 {
    let (lo, hi) = crate::mesh::geometry::bounding_box(mesh);
    norm(sub(hi, lo)) / 40.0
}

/// Peak memory per quad of a remesh's last stage (extraction, quality measures, report),
/// measured natively on mushroom-4: 516 MB for 0.82 M quads, 2030 MB for 3.3 M.
pub const BYTES_PER_QUAD: u64 = 650;

/// The memory one remesh may take for its quads: 2 GiB, what a browser tab can give the
/// page's wasm heap (wasm32 addresses 4 GiB at most; a growing heap is copied, and browsers
/// grant less on small machines). The command line keeps the same budget, so that both
/// make the same meshes and refuse the same edge lengths.
pub const MEMORY_BUDGET: u64 = 2 << 30;

/// The most quads one remesh makes: [`MEMORY_BUDGET`] over [`BYTES_PER_QUAD`] (3,303,820).
/// An edge length asking for more is refused before anything is allocated.
pub const MAX_QUADS: u64 = MEMORY_BUDGET / BYTES_PER_QUAD;

/// Why no quad mesh came out.
#[derive(Debug, Clone, PartialEq)]
pub enum QuadError {
    /// The edge length is not a positive finite number.
    EdgeLength(f64),
    /// The sample counts cannot be made consistent; `pieces` are the curves involved.
    Counts { error: CountError, pieces: Vec<CurveSource> },
    /// The edge length asks for more than [`MAX_QUADS`] quads (more memory than
    /// [`MEMORY_BUDGET`]): about `quads` (infinite when a curve's length over the edge length
    /// overflows).
    TooMany { quads: f64 },
    /// The quad mesh would not read back as a valid mesh (a quad folded over a neighbour,
    /// or with three corners on a line next to another such): `quad` is the first one the
    /// reader's check names, `at` its centre.
    Unreadable { quad: Option<u32>, at: [f64; 3], error: MeshError },
}

impl fmt::Display for QuadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            QuadError::EdgeLength(l) => write!(f, "the edge length must be a positive number, not {l}"),
            QuadError::Counts { error: CountError::Infeasible { .. }, pieces } => write!(
                f,
                "the layout does not make quads: opposite sides of its faces cannot get equal numbers of segments \
                 unless {} get fewer than one; move or remove a T-vertex there",
                pieces.iter().map(|p| p.to_string()).collect::<Vec<_>>().join(", ")
            ),
            QuadError::Counts { error, .. } => write!(f, "{error}"),
            QuadError::Unreadable { quad, at, error } => {
                let which = quad.map_or("a quad".to_string(), |q| format!("quad {q}"));
                write!(
                    f,
                    "the quad mesh would not read back: {which} (near {:.6}, {:.6}, {:.6}) folds over its neighbours or has \
                     three corners on a line ({error}); choose a shorter edge length, or tag the layout edges there for \
                     alignment",
                    at[0], at[1], at[2]
                )
            }
            QuadError::TooMany { quads } => {
                let gb = |quads: f64| quads * BYTES_PER_QUAD as f64 / 1e9;
                let about = if !quads.is_finite() {
                    "more quads than can be counted".to_string()
                } else if *quads < 1e15 {
                    format!("about {quads:.0} quads, which would take about {:.1} GB of memory", gb(*quads))
                } else {
                    format!("about {quads:.1e} quads, which would take about {:.1e} GB of memory", gb(*quads))
                };
                write!(
                    f,
                    "the edge length asks for {about} (the budget is {MAX_QUADS} quads, {:.1} GB); choose a longer edge length",
                    gb(MAX_QUADS as f64)
                )
            }
        }
    }
}

impl std::error::Error for QuadError {}

impl QuadError {
    /// A stable snake_case name of the error, for programs (the page).
    pub fn kind(&self) -> &'static str {
        match self {
            QuadError::EdgeLength(_) => "edge_length",
            QuadError::Counts { error: CountError::Infeasible { .. }, .. } => "counts_infeasible",
            QuadError::Counts { error: CountError::Fractional { .. }, .. } => "counts_fractional",
            QuadError::Counts { error: CountError::Solver(_), .. } => "counts_solver",
            QuadError::TooMany { .. } => "too_many_quads",
            QuadError::Unreadable { .. } => "quads_unreadable",
        }
    }

    /// The layout edges among the pieces whose counts cannot agree; where a quad folds.
    pub fn culprits(&self) -> Culprits {
        match self {
            QuadError::Counts { pieces, .. } => Culprits::edges(pieces.iter().filter_map(|p| p.edge())),
            QuadError::Unreadable { at, .. } => Culprits { point: Some(*at), ..Culprits::none() },
            _ => Culprits::none(),
        }
    }
}

/// The number of quads the face grids of `counts` make (side 0 times side 1 of every
/// face), in floating point so that no sum or product wraps; `counts[c]` is the number of
/// segments of curve `c`, or a wish for it (anything below one counts as one, as
/// [`sample_counts`] makes it). Opposite sides may still differ (desired counts): the
/// longer one counts. Infinite or NaN counts give an infinite total.
pub fn grid_quads(layout: &SurfaceLayout, counts: impl Fn(u32) -> f64) -> f64 {
    let side = |f: &crate::layout::Face, s: usize| -> f64 {
        let sum = |s: usize| f.side(s).iter().map(|d| counts(d.curve)).map(|c| if c.is_nan() { f64::INFINITY } else { c.max(1.0) }).sum::<f64>();
        sum(s).max(sum(s + 2))
    };
    layout.faces.iter().map(|f| side(f, 0) * side(f, 1)).sum()
}

/// Refuses an edge length that asks for more than [`MAX_QUADS`] quads, from the layout's
/// curve lengths alone: callers may ask before anything is parameterized or allocated.
///
/// # Errors
/// [`QuadError::EdgeLength`] or [`QuadError::TooMany`].
pub fn check_edge_length(layout: &SurfaceLayout, edge_length: f64) -> Result<(), QuadError> {
    if !(edge_length.is_finite() && edge_length > 0.0) {
        return Err(QuadError::EdgeLength(edge_length));
    }
    within_cap(grid_quads(layout, |c| layout.curves[c as usize].curve.length / edge_length))
}

/// [`QuadError::TooMany`] for more than [`MAX_QUADS`] quads (never NaN: see [`grid_quads`]).
fn within_cap(quads: f64) -> Result<(), QuadError> {
    if quads > MAX_QUADS as f64 {
        return Err(QuadError::TooMany { quads });
    }
    Ok(())
}

/// Checks that `quads` reads back as every writer's reader takes it (each quad split along
/// its diagonal 0–2, as OBJ and PLY readers fan-triangulate and the glTF writers split):
/// what we write, `quadlay check` must accept.
///
/// # Errors
/// [`QuadError::Unreadable`] naming the first quad the reader's check names.
pub fn check_reads_back(quads: &QuadMesh) -> Result<(), QuadError> {
    let triangles: Vec<[u32; 3]> = quads.quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    let soup = TriangleSoup { positions: quads.positions.clone(), triangles, ..TriangleSoup::default() };
    let Err(error) = build_mesh(soup) else { return Ok(()) };
    let quad = error.face().map(|t| t / 2);
    let position = |v: u32| quads.positions.get(v as usize).copied().unwrap_or([f64::NAN; 3]);
    let centre = quad.and_then(|q| quads.quads.get(q as usize)).map(|q| {
        let p = q.map(position);
        [0, 1, 2].map(|k| p.iter().map(|c| c[k]).sum::<f64>() / 4.0)
    });
    // A vertex whose quads form more than one fan (a quad at it folded flat, its triangle
    // dropped as of zero area) names no quad: its own position, not NaN.
    let at = match (centre, &error) {
        (Some(at), _) => at,
        (None, MeshError::NonManifoldVertex { vertex }) => position(*vertex),
        (None, _) => [f64::NAN; 3],
    };
    Err(QuadError::Unreadable { quad, at, error })
}

/// Maps chart points of one face back to the surface.
struct BackMap<'a> {
    param: &'a ParamSession,
    index: Vec<ChartIndex>,
    frames: &'a ChartFrames,
    /// Grid points found in no triangle of their chart or its neighbours (moved onto the
    /// nearest triangle).
    outside: usize,
}

/// Relative tolerance of point location: points on a chart side count as inside.
const ON_SIDE: f64 = 1e-9;

impl BackMap<'_> {
    fn position(&self, hit: Hit) -> [f64; 3] {
        let cut = self.param.cut();
        let t = cut.triangles[hit.triangle as usize];
        let mut p = [0.0; 3];
        for k in 0..3 {
            let q = cut.positions[t[k] as usize];
            for i in 0..3 {
                p[i] += hit.bary[k] * q[i];
            }
        }
        p
    }

    /// The surface point at chart point `p` of `face`. Where the face's triangles do not
    /// cover `p` (next to a side that is not aligned, the side is straight in the chart but
    /// the curve is not) the point lies in a neighbour's triangles: `near` lists the face's
    /// pieces by distance from `p` (asked for only then), and we look across them through
    /// their transitions.
    fn surface_point(&mut self, face: u32, p: [f64; 2], near: impl FnOnce() -> Vec<u32>) -> [f64; 3] {
        if let Some(hit) = self.index[face as usize].locate(p, ON_SIDE) {
            return self.position(hit);
        }
        for c in near() {
            let Some((other, map)) = self.frames.across(c, face) else { continue };
            if let Some(hit) = self.index[other as usize].locate(map.apply(p), ON_SIDE) {
                return self.position(hit);
            }
        }
        self.outside += 1;
        match self.index[face as usize].nearest(p) {
            Some(hit) => self.position(hit),
            None => [f64::NAN; 3],
        }
    }
}

/// The point where line `a b` meets line `c d` (grid lines of a convex chart always meet).
fn intersect(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> [f64; 2] {
    let r = [b[0] - a[0], b[1] - a[1]];
    let s = [d[0] - c[0], d[1] - c[1]];
    let den = r[0] * s[1] - r[1] * s[0];
    if den.abs() < 1e-300 {
        return [(a[0] + b[0] + c[0] + d[0]) / 4.0, (a[1] + b[1] + c[1] + d[1]) / 4.0];
    }
    let t = ((c[0] - a[0]) * s[1] - (c[1] - a[1]) * s[0]) / den;
    [a[0] + t * r[0], a[1] + t * r[1]]
}

/// A sample on a face's side: its vertex and its chart position.
type Sample = (u32, [f64; 2]);

/// The statistics of an extraction.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Extraction {
    /// Segments per layout curve.
    pub counts: Vec<u32>,
    /// The desired (real) segments per layout curve: the mean of its faces' desires
    /// ([`density`]).
    pub desired: Vec<f64>,
    /// Grid points that fell outside every triangle of their chart and its neighbours and
    /// were moved onto the nearest one (a sign of flipped or folded triangles).
    pub outside_points: usize,
    /// Vertices moved by the relaxation on the surface ([`relax`]).
    pub relaxed_vertices: usize,
}

/// Sample counts at one edge length and the quads they make.
struct Counted {
    counts: Vec<u32>,
    desired: Vec<f64>,
    quads: f64,
}

/// Relative distance from the quads asked for within which the counts are taken as they are.
const QUAD_COUNT_TOLERANCE: f64 = 0.05;
/// Bound on the edge lengths tried to meet the quads asked for. Where many pieces are held at
/// one segment the quads fall slower than the edge length's square and each step closes in by
/// less: with 6, CGAL's camel and armadillo (automatic layouts) kept 4256 and 4541 quads for
/// 4000 asked; with 10, 4019 and 4377 (the other 24 meshes of the evaluation kept their quads).
/// Each step is one count solve.
const RESCALES: usize = 10;

/// The sample counts for edge length `h` that make about surface area / h² quads. Integer
/// counts that agree on opposite sides are not what the areas wished: every piece between
/// T-vertices takes at least one segment (a layout of many small faces gets more quads), and
/// faces whose opposite sides differ give up length to agree (fewer). Where the quads are
/// more than [`QUAD_COUNT_TOLERANCE`] off, the counts are made again at an edge length
/// scaled by the square root of the miss, and the nearest to what was asked is kept.
///
/// The counts can fail at a coarser edge length where they held at a finer one: with many
/// pieces held at one segment the rounding runs out of its budget (elephant's automatic
/// layout at 1.46 times the edge length asked, after 5435 quads at 1.25 for 4000 asked). A
/// step to or past an edge length that failed goes halfway there instead (geometrically), so
/// the search closes in on the coarsest that holds (there: 5269 quads at 1.35) rather than
/// stopping at the first failure. Where they fail at `h` itself, the search starts from the
/// nearest edge length where they hold ([`counts_near`]); where they fail at a step, the first
/// [`NEAR_RETRIES`] of those neighbours are tried before the step counts as failed.
fn counts_for_quads(layout: &SurfaceLayout, param: &ParamSession, h: f64) -> Result<Counted, QuadError> {
    let asked = density::face_areas(param.cut(), layout.faces.len()).iter().sum::<f64>() / (h * h);
    let (start, first) = counts_near(layout, param, h)?;
    Ok(nearest_count(asked, start, first, |x| counts_at(layout, param, x).ok()))
}

/// The search of [`counts_for_quads`] for the counts nearest `asked` quads, from those at edge
/// length `start` (`first`); `count` makes them at an edge length, `None` where they fail.
fn nearest_count(asked: f64, start: f64, first: Counted, mut count: impl FnMut(f64) -> Option<Counted>) -> Counted {
    let miss = |quads: f64| (quads / asked - 1.0).abs();
    // The latest edge length whose counts held and their quads; the nearest that failed.
    let (mut scale, mut quads) = (start, first.quads);
    let mut best = first;
    let mut failed: Option<f64> = None;
    for _ in 0..RESCALES {
        if miss(best.quads) <= QUAD_COUNT_TOLERANCE || !(quads > 0.0 && asked > 0.0) {
            break;
        }
        let wish = scale * (quads / asked).sqrt();
        let next = match failed {
            // `f` lies between `scale` and `wish`, or is `wish`.
            Some(f) if (f - scale) * (wish - f) >= 0.0 => (scale * f).sqrt(),
            _ => wish,
        };
        let near = RETRY_SCALES[..NEAR_RETRIES].iter().map(|&k| k * next);
        match std::iter::once(next).chain(near).find_map(|x| count(x).map(|c| (x, c))) {
            Some((next, trial)) => {
                (scale, quads) = (next, trial.quads);
                if miss(trial.quads) < miss(best.quads) {
                    best = trial;
                }
            }
            None => failed = Some(next),
        }
    }
    best
}

/// Edge lengths tried, as multiples of the one asked, where the counts fail at it: the
/// rounding of [`sample_counts`] can run out of its budget at one edge length and not at
/// another a few percent away, and not monotonically (an automatic layout of CGAL's homer
/// failed at 4000 and 5000 quads and held at 4500 and 6000).
const RETRY_SCALES: [f64; 14] = [0.98, 1.02, 0.96, 1.04, 0.94, 1.06, 0.92, 1.08, 0.9, 1.1, 0.85, 0.8, 0.7, 0.5];
/// Neighbours of a failed step of [`counts_for_quads`] tried ([`RETRY_SCALES`], 2 and 4 %
/// either side): failures are isolated edge lengths, not a bound. CGAL's camel with its
/// automatic layout at --quads 4000 failed at 1.28 times the edge length asked, and the search
/// closed in on 1.27 (5399 quads, 35 % over); past the failure the counts hold again (with 6
/// [`RESCALES`], 4256 quads at 4000 asked, 3523 at 3000 where there were 4235). A few count
/// solves more, only where a step fails.
const NEAR_RETRIES: usize = 4;

/// [`counts_at`] at `h`, or where that fails at the first of [`RETRY_SCALES`] where it holds
/// (and that edge length); the error at `h` where none does.
fn counts_near(layout: &SurfaceLayout, param: &ParamSession, h: f64) -> Result<(f64, Counted), QuadError> {
    let error = match counts_at(layout, param, h) {
        Ok(counted) => return Ok((h, counted)),
        Err(e @ QuadError::Counts { .. }) => e,
        Err(e) => return Err(e),
    };
    RETRY_SCALES.iter().find_map(|&k| counts_at(layout, param, k * h).ok().map(|c| (k * h, c))).ok_or(error)
}

/// The sample counts at edge length `h`: the desires of the faces' areas, solved and rounded.
fn counts_at(layout: &SurfaceLayout, param: &ParamSession, h: f64) -> Result<Counted, QuadError> {
    let desires = density::face_desires(layout, param, h);
    let problem = density::IncidenceCounts::new(layout, &desires);
    let counts = sample_counts(&problem.desired, &problem.equations).map_err(|error| {
        let incidences = match &error {
            CountError::Infeasible { pieces_at_one } => pieces_at_one.clone(),
            CountError::Fractional { piece } => vec![*piece],
            CountError::Solver(_) => Vec::new(),
        };
        let mut pieces: Vec<u32> = incidences.iter().map(|&i| problem.curve[i as usize]).collect();
        pieces.sort_unstable();
        pieces.dedup();
        let error = match error {
            CountError::Infeasible { .. } => CountError::Infeasible { pieces_at_one: pieces.clone() },
            CountError::Fractional { .. } => CountError::Fractional { piece: pieces[0] },
            other => other,
        };
        QuadError::Counts { error, pieces: pieces.iter().map(|&c| layout.curves[c as usize].source).collect() }
    })?;
    let counts = problem.per_curve(&counts, layout.curves.len());
    let desired = density::desired_counts(layout, &desires);
    // Rounding may add a little to the desired counts: count again, the counts now agree.
    let quads = grid_quads(layout, |c| counts[c as usize] as f64);
    within_cap(quads)?;
    Ok(Counted { counts, desired, quads })
}

/// Extracts the quad mesh of a finished parameterization (paper Section 4).
///
/// Every curve gets a sample count ([`counts`]) near its desired count, which follows the
/// faces' surface areas ([`density`]: about surface area / h² quads); each face's grid joins the samples of
/// opposite sides; grid points are mapped back to the surface through the triangles
/// parameterized in the face's chart, or in a neighbour's across the nearest side. Samples
/// on curves and nodes have one vertex each, shared by both faces: the mesh is welded by
/// construction. Last, the vertices off tagged curves are relaxed on the surface ([`relax`]):
/// at --quads 4000 on the automatic layouts of the seven shared meshes the mean angle
/// deviation falls by 0.8–15.3° (bunny_28k 13.7 → 7.4°) and the folded quads from 50 to 16
/// in all; the Hausdorff distances stay within 0.25 % (fandisk 0.35 → 0.39 %, eight 5.10 →
/// 5.31 %). Then the points of the surface the quads miss most, tips that fall between grid
/// lines, get the nearest free corner moved onto them ([`cover`]).
///
/// # Errors
/// [`QuadError`] for a bad edge length, a layout whose counts cannot agree, or a mesh of
/// more than [`MAX_QUADS`] quads.
pub fn extract(layout: &SurfaceLayout, param: &ParamSession, options: &QuadOptions) -> Result<(QuadMesh, Extraction), QuadError> {
    let h = options.edge_length;
    check_edge_length(layout, h)?;
    let Counted { counts, desired, .. } = counts_for_quads(layout, param, h)?;

    let cut = param.cut();
    let solution = param.solution();
    let frames = param.frames();
    let mut per_face: Vec<Vec<(u32, [[f64; 2]; 3])>> = vec![Vec::new(); layout.faces.len()];
    for (t, uv) in solution.corner_uv.iter().enumerate() {
        per_face[cut.triangle_face[t] as usize].push((t as u32, *uv));
    }
    let mut map = BackMap {
        param,
        index: per_face.into_iter().map(ChartIndex::new).collect(),
        frames: &frames,
        outside: 0,
    };
    let node_at = |f: usize, n: u32| frames.nodes[f].get(&n).copied().unwrap_or([f64::NAN; 2]);
    let pieces_by_distance = |f: usize, p: [f64; 2]| -> Vec<u32> {
        let distance = |a, b| {
            let q = closest_on_segment(p, a, b);
            (q[0] - p[0]).hypot(q[1] - p[1])
        };
        let face = &layout.faces[f];
        let mut by: Vec<(f64, u32)> = face
            .pieces
            .iter()
            .enumerate()
            .map(|(k, d)| {
                let (a, b) = (node_at(f, face.nodes[k]), node_at(f, face.nodes[(k + 1) % face.nodes.len()]));
                (distance(a, b), d.curve)
            })
            .collect();
        by.sort_by(|x, y| x.0.total_cmp(&y.0));
        by.into_iter().map(|(_, c)| c).collect()
    };

    let mut mesh = QuadMesh::default();
    let mut quad_face = Vec::new();
    // Nodes: their own mesh vertex.
    let node_vertex: Vec<u32> = layout
        .node_vertex
        .iter()
        .enumerate()
        .map(|(n, &v)| {
            mesh.positions.push(cut.positions[v as usize]);
            mesh.vertex_node.push(n as u32);
            (mesh.positions.len() - 1) as u32
        })
        .collect();
    // Curve samples, placed in the chart of the face on the curve's left.
    let mut first_sample = Vec::with_capacity(layout.curves.len());
    for (c, lc) in layout.curves.iter().enumerate() {
        first_sample.push(mesh.positions.len() as u32);
        let f = frames.sides[c][0] as usize;
        let (a, b) = (node_at(f, lc.nodes[0]), node_at(f, lc.nodes[1]));
        let k = counts[c];
        for j in 1..k {
            let s = j as f64 / k as f64;
            let p = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
            mesh.positions.push(map.surface_point(f as u32, p, || pieces_by_distance(f, p)));
            mesh.vertex_node.push(NONE);
        }
    }
    let curve_sample = |c: usize, j: u32| -> u32 {
        let lc = &layout.curves[c];
        if j == 0 {
            node_vertex[lc.nodes[0] as usize]
        } else if j == counts[c] {
            node_vertex[lc.nodes[1] as usize]
        } else {
            first_sample[c] + j - 1
        }
    };

    for (f, face) in layout.faces.iter().enumerate() {
        // The samples of each side, from corner s to corner s + 1.
        let sides: Vec<Vec<Sample>> = (0..4)
            .map(|s| {
                let mut out: Vec<Sample> = Vec::new();
                let first = face.corners[s];
                for (k, d) in face.side(s).iter().enumerate() {
                    let (a, b) = (node_at(f, face.nodes[first + k]), node_at(f, face.nodes[(first + k + 1) % face.nodes.len()]));
                    let n = counts[d.curve as usize];
                    for j in usize::from(k > 0) as u32..=n {
                        let along = if d.forward { j } else { n - j };
                        let t = j as f64 / n as f64;
                        out.push((curve_sample(d.curve as usize, along), [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]));
                    }
                }
                out
            })
            .collect();
        let (n, m) = (sides[0].len() - 1, sides[1].len() - 1);
        debug_assert_eq!((n, m), (sides[2].len() - 1, sides[3].len() - 1));
        // Interior grid points: where the line between opposite samples of sides 0 and 2
        // meets the line between those of sides 1 and 3.
        let interior = mesh.positions.len() as u32;
        for j in 1..m {
            for i in 1..n {
                let p = intersect(sides[0][i].1, sides[2][n - i].1, sides[3][m - j].1, sides[1][j].1);
                mesh.positions.push(map.surface_point(f as u32, p, || pieces_by_distance(f, p)));
                mesh.vertex_node.push(NONE);
            }
        }
        let id = |i: usize, j: usize| -> u32 {
            if j == 0 {
                sides[0][i].0
            } else if i == n {
                sides[1][j].0
            } else if j == m {
                sides[2][n - i].0
            } else if i == 0 {
                sides[3][m - j].0
            } else {
                interior + ((j - 1) * (n - 1) + (i - 1)) as u32
            }
        };
        for j in 0..m {
            for i in 0..n {
                mesh.quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                quad_face.push(f as u32);
            }
        }
    }
    // The samples of tagged curves (and the boundary) stay on them: they are the edge loops
    // asked for. The nodes stay where they are; the others may slide along their curve.
    let mut pinned = vec![false; mesh.positions.len()];
    let mut rails = rails::Rails { curves: vec![rails::Polyline::default(); layout.curves.len()], on: vec![None; mesh.positions.len()] };
    for (c, lc) in layout.curves.iter().enumerate() {
        if lc.align {
            for j in 0..=counts[c] {
                pinned[curve_sample(c, j) as usize] = true;
            }
            if options.slide_on_curves {
                rails.curves[c] = rails::Polyline::new(cut.curve_vertices[c].iter().map(|&v| cut.positions[v as usize]).collect());
                for j in 1..counts[c] {
                    let v = curve_sample(c, j);
                    rails.place(v, c as u32, mesh.positions[v as usize]);
                }
            }
        }
    }
    // A general quadrilateral chart asks for quads of its own angles, not right ones: the
    // vertices of its quads are not squared (the sheared cube's faces stay congruent
    // parallelograms).
    let mut squared = vec![true; mesh.positions.len()];
    for (q, &f) in mesh.quads.iter().zip(&quad_face) {
        if param.charts()[f as usize].kind == ChartKind::Quad {
            q.iter().for_each(|&v| squared[v as usize] = false);
        }
    }
    let dropped = doublets::dissolve(&mut mesh, &mut quad_face);
    doublets::remove_marked(&mut pinned, &dropped);
    doublets::remove_marked(&mut squared, &dropped);
    doublets::remove_marked(&mut rails.on, &dropped);
    let surface = relax::Surface::new(&cut.positions, cut.triangles.clone());
    // Two nodes one quad apart across a diagonal: merged where that leaves fewer irregular
    // vertices (over 26 meshes' automatic layouts at --quads 4000, 2208 -> 2127).
    let merged = diagonals::collapse(&mut mesh, &mut quad_face, &pinned, &surface);
    doublets::remove_marked(&mut pinned, &merged);
    doublets::remove_marked(&mut squared, &merged);
    doublets::remove_marked(&mut rails.on, &merged);
    let relaxed_vertices = relax::relax(&mut mesh, &surface, &pinned, &rails, &squared, options.rectify_steps, options.relax_rounds);
    if options.cover_tips {
        cover::cover(&mut mesh, &surface, &pinned);
    }
    Ok((mesh, Extraction { counts, desired, outside_points: map.outside, relaxed_vertices }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The counts at edge length `x` (1: the one asked) of a layout like CGAL's camel with its
    /// automatic layout at 4000 quads: many pieces held at one segment, so the quads fall
    /// slower than 1 / x² towards a floor; the rounding fails between 1.27 and 1.29.
    fn camel_like(x: f64) -> Option<Counted> {
        let quads = (2600.0 + 3948.0 / x.powf(1.5)).round();
        (!(1.27..1.29).contains(&x)).then(|| Counted { counts: Vec::new(), desired: Vec::new(), quads })
    }

    /// A step of the search where the counts fail is retried a little either side, and the
    /// search goes on past it: without, it closes in on the failure from below and keeps 5360
    /// quads for 4000 asked (34 % over; camel itself 5399).
    #[test]
    fn the_search_for_the_quads_asked_steps_past_an_edge_length_where_counts_fail() {
        let first = camel_like(1.0).unwrap();
        let kept = nearest_count(4000.0, 1.0, first, camel_like);
        assert!((kept.quads / 4000.0 - 1.0).abs() < 0.1, "{}", kept.quads);
        // Counts that hold everywhere are searched as before: within the tolerance at once.
        let smooth = |x: f64| Some(Counted { counts: Vec::new(), desired: Vec::new(), quads: (6548.0 / (x * x)).round() });
        let kept = nearest_count(4000.0, 1.0, smooth(1.0).unwrap(), smooth);
        assert!((kept.quads / 4000.0 - 1.0).abs() <= QUAD_COUNT_TOLERANCE, "{}", kept.quads);
    }

    #[test]
    fn a_folded_quad_mesh_is_refused_naming_the_quad() {
        // Two unit squares side by side read back; fold the second over the first (it
        // runs along their shared edge the same way) and they do not.
        let positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0]];
        let good = QuadMesh { positions: positions.clone(), quads: vec![[0, 1, 2, 3], [1, 4, 5, 2]], vertex_node: vec![NONE; 6] };
        assert_eq!(check_reads_back(&good), Ok(()));
        let folded = QuadMesh { quads: vec![[0, 1, 2, 3], [1, 2, 5, 4]], ..good };
        let err = check_reads_back(&folded).unwrap_err();
        let QuadError::Unreadable { quad, at, .. } = &err else { panic!("{err}") };
        assert_eq!(*quad, Some(1));
        assert_eq!(*at, [1.5, 0.5, 0.0]);
        assert!(err.to_string().starts_with("the quad mesh would not read back: quad 1 (near 1.500000, 0.500000, 0.000000)"), "{err}");
    }

    #[test]
    fn quads_meeting_at_a_vertex_only_are_refused_naming_where() {
        // Two unit squares touching at a corner (2): more than one fan round it, no quad
        // named, so the place is the vertex's (it was NaN).
        let positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [2.0, 1.0, 0.0], [2.0, 2.0, 0.0], [1.0, 2.0, 0.0]];
        let bowtie = QuadMesh { positions, quads: vec![[0, 1, 2, 3], [2, 4, 5, 6]], vertex_node: vec![NONE; 7] };
        let err = check_reads_back(&bowtie).unwrap_err();
        let QuadError::Unreadable { quad: None, at, .. } = &err else { panic!("{err}") };
        assert_eq!(*at, [1.0, 1.0, 0.0]);
        assert!(err.to_string().contains("(near 1.000000, 1.000000, 0.000000)"), "{err}");
    }
}
