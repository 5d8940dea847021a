//! The quadrangular global parameterization (paper Section 3).
//!
//! [`ParamSession`] runs the loop of Section 3.1: all layout edges aligned and unit charts,
//! an initial solve; then per iteration every chart optimized on its own ([`chart`]),
//! transitions rebuilt ([`transition`]) and the global system solved again ([`system`]);
//! finally the user's alignment tags restored and a last solve, mended where it folds
//! triangles (curve vertices put back in order along their sides, [`order`]; no negative edge
//! weight next to the layout). The browser runs one iteration per call; the command line runs
//! them all. The refined mesh ([`cut`]) has no chord, an edge inside a face between two
//! vertices on the layout, so no triangle has its three vertices on one straight side.
//!
//! # Where each equation of the paper lives
//!
//! | paper | what | code |
//! |---|---|---|
//! | eq. 1 | harmonic condition in one chart | [`system`]: the Dirichlet energy, whose minimizer is harmonic |
//! | eq. 2 | cotangent weights | [`crate::geom::cotangent`], summed per edge by `mesh::geometry::cotangent_weights`, per triangle by [`system::cotangent_halves`] |
//! | eq. 3 | harmonic condition across charts | [`system::System::solve`] (symmetric form; eq. 3 as written in `eq3.rs`, feature `eq3`, compared in `docs/formulations.md`) |
//! | eq. 4 | transition functions | [`transition::Affine::transition`], one per curve in [`frames::ChartFrames`] |
//! | eq. 5, 6 | Jacobian, singular values | [`chart::distortion`] (doc) |
//! | eq. 7 | isometric distortion ‖JᵀJ − I‖²_F | [`chart::distortion`] |
//! | eq. 8 | a triangle's Jacobian | [`chart::rest_frame`], [`chart::distortion`] |
//! | eq. 9 | bilinear coordinates in a chart | [`chart::Chart::point`], [`chart::Chart::bilinear_coords`] |
//! | eq. 10 | chart energy | [`chart::energy`], minimized by [`chart::optimize`] |
//! | Section 3.1 loop | optimize, rebuild transitions, solve | [`ParamSession::new`], [`ParamSession::step`], [`ParamSession::finish`] |
//! | eq. 11 | alignment of tagged curves | [`system::System`]: a tagged curve's vertices keep one unknown along their side |
//! | eq. 12 | mixed least squares | [`system::System`]: the equivalent elimination (module doc) |
//! | Section 3.3 | T-vertices | `FaceDomain::nodes` (a node at a fixed share of its side), a transition per curve piece |
//! | Section 4 | sample counts, grids, back-mapping | [`crate::quad::counts::sample_counts`], [`crate::quad::extract`] |

pub mod anderson;
pub mod chart;
pub mod cut;
pub mod frames;
#[cfg(feature = "eq3")]
pub mod eq3;
pub mod input_uv;
pub mod order;
pub mod system;
pub mod transition;

use crate::layout::{ChartType, SurfaceLayout};
use crate::mesh::{Mesh, NONE};
use chart::{optimize, rest_frame, Chart, ChartKind, ChartTriangle, OptimizeOptions};
use cut::{curve_sides, cut_mesh, CutMesh};
use crate::clock::now;
use std::collections::HashMap;
pub use system::StageTimes;
use frames::{ChartFrames, NodePositions};
use system::{Solution, System};
pub use system::ParamError;

/// Settings of a parameterization run: start from [`ParamOptions::DEFAULT`] and set what you
/// need (`let mut o = ParamOptions::DEFAULT; o.align = false;`).
///
/// The page's `startParam` takes the same settings as one JS object, by these names
/// (`chart` for [`default_chart`](Self::default_chart)); what it leaves out keeps its
/// default, and a key that is none of [`ParamOptions::KEYS`] is refused.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct ParamOptions {
    /// Chart-optimization iterations (paper Section 3.1) that `quadlay remesh` runs between
    /// [`ParamSession::new`] and [`ParamSession::finish`] (the page calls
    /// [`ParamSession::step`] itself). Default 3.
    pub iterations: usize,
    /// Honour the layout's alignment tags in the final solve; false (`--no-align`) aligns
    /// only the boundary pieces there. Default true.
    pub align: bool,
    /// The chart type of every face whose `patches` entry names none (`--chart`); `None`
    /// keeps the layout's `defaults.chart`. Default `None`.
    #[serde(rename = "chart")]
    pub default_chart: Option<ChartType>,
    /// Accelerate the chart-optimization loop (Anderson mixing, see [`anderson`]); false
    /// runs the paper's plain loop. Default true.
    pub accelerate: bool,
    /// How many earlier iterations Anderson mixing combines (0: none, the plain step).
    /// Default 5.
    pub anderson_depth: usize,
    /// An accelerated step is dropped for the plain one when it leaves the valid charts or
    /// its mean distortion exceeds this many times the previous iteration's: mixing need
    /// not lower the distortion every time, but a blow-up sends it back. Default 100.
    pub blow_up: f64,
    /// Shorten a chart step that flips triangles the previous solve did not (see
    /// `ParamSession::without_new_flips`). Default true; false runs the paper's loop as it
    /// is (the formulations are compared that way).
    pub guard_flips: bool,
    /// Shares of a chart step tried in turn when the full step flips triangles the previous
    /// solve did not (with [`guard_flips`](Self::guard_flips)). Each in (0, 1]. Default
    /// `[0.5, 0.25]`.
    pub step_shares: [f64; 2],
    /// Clean iterations in a row (a shortened step share kept, no new flips) before the
    /// share is doubled again: the share recovers when folds stop, and cannot shrink
    /// towards no step at all over many iterations. Default 2.
    pub grow_after: u32,
    /// Shares of each untagged curve's vertices, at each end, held on the chart side in the
    /// final solve's successive attempts when releasing the curves folds triangles (see
    /// [`ParamSession::finish`]); after them, every curve aligned. Each in [0, 1]. Default
    /// `[0.1, 0.25]`.
    pub final_anchors: [f64; 2],
    /// Which global system every solve uses (a comparison for tests, behind the `eq3`
    /// feature). Default [`Formulation::Symmetric`].
    #[cfg(feature = "eq3")]
    #[serde(skip)]
    pub formulation: Formulation,
}

impl ParamOptions {
    /// The defaults, each documented on its field.
    pub const DEFAULT: ParamOptions = ParamOptions {
        iterations: 3,
        align: true,
        default_chart: None,
        accelerate: true,
        anderson_depth: 5,
        blow_up: 100.0,
        guard_flips: true,
        step_shares: [0.5, 0.25],
        grow_after: 2,
        final_anchors: [0.1, 0.25],
        #[cfg(feature = "eq3")]
        formulation: Formulation::Symmetric,
    };

    /// The names the page may give (serde's names of the fields).
    pub const KEYS: [&'static str; 10] = [
        "iterations",
        "align",
        "chart",
        "accelerate",
        "anderson_depth",
        "blow_up",
        "guard_flips",
        "step_shares",
        "grow_after",
        "final_anchors",
    ];

    /// The first setting out of its range, with what it must be.
    ///
    /// # Errors
    /// [`ParamError::Option`] naming the field.
    pub fn check(&self) -> Result<(), ParamError> {
        let bad = |name: &'static str, must: &'static str| Err(ParamError::Option { name, must });
        if self.blow_up.is_nan() || self.blow_up < 1.0 {
            return bad("blow_up", "a number of at least 1");
        }
        if !self.step_shares.iter().all(|&s| s > 0.0 && s <= 1.0) {
            return bad("step_shares", "two numbers above 0 and at most 1");
        }
        if !self.final_anchors.iter().all(|&s| (0.0..=1.0).contains(&s)) {
            return bad("final_anchors", "two numbers from 0 to 1");
        }
        Ok(())
    }
}

impl Default for ParamOptions {
    fn default() -> Self {
        ParamOptions::DEFAULT
    }
}

/// The global system of eq. 3 (see [`system`] for why we chose the symmetric one).
#[cfg(feature = "eq3")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Formulation {
    /// Dirichlet energy with each triangle in its face's chart, sparse Cholesky ([`system`]).
    #[default]
    Symmetric,
    /// Eq. 3 as written, non-symmetric, sparse LU ([`eq3`]); for comparison.
    Eq3,
}

/// Distortion of one solve, over the triangles of the refined mesh.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Distortion {
    /// Area-weighted mean of ‖JᵀJ − I‖²_F (eq. 7).
    pub mean: f64,
    pub max: f64,
    /// Triangles whose chart image has non-positive area.
    pub flipped: usize,
}

/// One entry of the iteration history: 0 is the initial parameterization (unit charts).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct IterationStats {
    pub iteration: usize,
    pub distortion: Distortion,
    pub seconds: f64,
}

/// A face's nodes and how their chart positions follow from the chart's corners.
#[derive(Debug, Clone)]
struct FaceDomain {
    kind: ChartKind,
    /// (node, side s, τ): the node sits at c_s + τ (c_{s+1} − c_s); corners have τ = 0.
    nodes: Vec<(u32, usize, f64)>,
    /// Curve length on the surface of each of the four sides.
    side_lengths: [f64; 4],
}

/// Chart optimization may leave a chart's proportions at most this factor away from its
/// face's curves' ([`Chart::shape_deviation`]), or from the start's where that was further.
/// The bilinear model of Section 3.1 holds the parameterization fixed in each chart's (s, t)
/// coordinates; where a face's map is sheared (its s and t gradients nearly parallel, as on
/// a face that holds much curvature), the isometry energy is lowest with one side shrunk to
/// nothing, and the next solve collapses the face into a line: quads of zero width, the
/// surface there missed (eight and nefertiti's automatic layouts each had a chart collapse
/// to a side ratio of 1e9). The sound charts of the shared meshes' layouts stay within 10.
const SHAPE_BOUND: f64 = 16.0;

/// The final solve is mended this many times at most for curve vertices out of order
/// ([`ParamSession::mend`]).
const ORDER_ROUNDS: usize = 3;

/// The state of a parameterization: refined mesh, charts, factorizations, history.
pub struct ParamSession {
    cut: CutMesh,
    sides: Vec<[u32; 2]>,
    domains: Vec<FaceDomain>,
    charts: Vec<Chart>,
    /// Rest shape and area of every refined triangle (for distortion and eq. 10).
    rest: Vec<([[f64; 2]; 2], f64)>,
    /// Half cotangents of every refined triangle's corners, shared by both systems.
    weights: Vec<[f64; 3]>,
    /// The systems of the loop (every curve aligned) and of the final solve (the user's tags).
    all_aligned: System,
    user_aligned: System,
    options: ParamOptions,
    /// The curves aligned in the final solve.
    user_tags: Vec<bool>,
    history: Vec<IterationStats>,
    last: Solution,
    final_solution: Option<(Solution, Distortion)>,
    anderson: anderson::Anderson,
    /// The share of its chart step an iteration starts from: 1 until a step had to be
    /// shortened (see [`ParamSession::without_new_flips`]), then the share that was kept,
    /// doubled again after [`ParamOptions::grow_after`] clean iterations in a row.
    step_share: f64,
    /// Iterations in a row that kept the share and flipped no new triangles.
    kept_steps: u32,
    chart_seconds: f64,
}

/// The chart `share` of the way from `a` to `b` in the free variables of `kind`.
fn chart_between(a: &Chart, b: &Chart, kind: ChartKind, share: f64) -> Chart {
    let (x, y) = (a.with_kind(kind).free_vars(), b.with_kind(kind).free_vars());
    let z: Vec<f64> = x.iter().zip(&y).map(|(p, q)| p + share * (q - p)).collect();
    b.with_kind(kind).with_free_vars(&z)
}

fn chart_kind(c: ChartType) -> ChartKind {
    match c {
        ChartType::Quad => ChartKind::Quad,
        ChartType::Rect => ChartKind::Rect,
        ChartType::Unit => ChartKind::Unit,
    }
}

impl ParamSession {
    /// Refines the mesh along the layout, makes unit charts and solves the initial
    /// parameterization with every layout edge aligned (iteration 0).
    ///
    /// # Errors
    /// [`ParamError`] if the system cannot be solved or the mesh is too coarse.
    pub fn new(mesh: &Mesh, layout: &SurfaceLayout, options: &ParamOptions) -> Result<ParamSession, ParamError> {
        let t0 = now();
        let mut session = ParamSession::unsolved(mesh, layout, options)?;
        let sol = session.solve(None, &[], None)?;
        let distortion = session.distortion(&sol);
        session.last = sol;
        session.history.push(IterationStats { iteration: 0, distortion, seconds: now() - t0 });
        Ok(session)
    }

    /// Whether [`ParamSession::new`] gets as far as its factorization: the refined mesh, its
    /// charts and every triangle's vertices in its face's chart (the mesh is fine enough for
    /// the layout), without the factorization and the solve, three quarters of its time. The
    /// automatic layout checks each simplification it keeps this way.
    ///
    /// # Errors
    /// The [`ParamError`] that `new` would meet before its factorization.
    pub fn check(mesh: &Mesh, layout: &SurfaceLayout, options: &ParamOptions) -> Result<(), ParamError> {
        let session = ParamSession::unsolved(mesh, layout, options)?;
        session.all_aligned.check(&session.cut, &session.frames())
    }

    /// The session before its first solve: the refined mesh, unit charts and both systems.
    fn unsolved(mesh: &Mesh, layout: &SurfaceLayout, options: &ParamOptions) -> Result<ParamSession, ParamError> {
        options.check()?;
        let cut = cut_mesh(mesh, layout);
        let sides = curve_sides(layout);
        let curve_len: Vec<f64> = layout.curves.iter().map(|c| c.curve.length).collect();
        let mut domains = Vec::with_capacity(layout.faces.len());
        for f in &layout.faces {
            let mut nodes = Vec::with_capacity(f.nodes.len());
            let mut face_sides = [0.0; 4];
            for s in 0..4 {
                let pieces = f.side(s);
                let total: f64 = pieces.iter().map(|d| curve_len[d.curve as usize]).sum();
                face_sides[s] = total;
                let mut along = 0.0;
                for (k, d) in pieces.iter().enumerate() {
                    nodes.push((f.nodes[f.corners[s] + k], s, if total > 0.0 { along / total } else { 0.0 }));
                    along += curve_len[d.curve as usize];
                }
            }
            let kind = chart_kind(f.chart_with_default(options.default_chart));
            domains.push(FaceDomain { kind, nodes, side_lengths: face_sides });
        }
        // One common side for unit charts, so chart types compare by shape, not by units.
        let side = domains.iter().flat_map(|d| d.side_lengths).sum::<f64>() / (4 * domains.len()).max(1) as f64;
        let charts = domains.iter().map(|_| Chart::unit(side)).collect();
        let rest = cut
            .triangles
            .iter()
            .map(|t| {
                let p = t.map(|v| cut.positions[v as usize]);
                rest_frame(p[0], p[1], p[2])
            })
            .collect();
        let every = vec![true; layout.curves.len()];
        // Boundary pieces are always aligned (their `align` is set); `--no-align` drops the
        // user's tags only.
        let tags: Vec<bool> = layout
            .curves
            .iter()
            .zip(&sides)
            .map(|(c, s)| if options.align { c.align } else { s[1] == NONE })
            .collect();
        let general: Vec<bool> = domains.iter().map(|d| d.kind == ChartKind::Quad).collect();
        let all_aligned = System::new(&cut, general.clone(), &every);
        let user_aligned = System::new(&cut, general, &tags);
        let user_tags = tags;
        let weights = system::cotangent_halves(&cut);
        Ok(ParamSession {
            cut,
            sides,
            domains,
            charts,
            rest,
            weights,
            all_aligned,
            user_aligned,
            options: *options,
            user_tags,
            history: Vec::new(),
            last: Solution { corner_uv: Vec::new(), unknowns: Vec::new() },
            final_solution: None,
            anderson: anderson::Anderson::new(options.anderson_depth),
            step_share: 1.0,
            kept_steps: 0,
            chart_seconds: 0.0,
        })
    }

    /// The frames of the current charts: node positions in every chart, the faces beside
    /// every curve and the transitions across them (eq. 4).
    pub fn frames(&self) -> ChartFrames {
        let nodes: NodePositions = self
            .domains
            .iter()
            .zip(&self.charts)
            .map(|(d, chart)| {
                let c = chart.corners();
                d.nodes
                    .iter()
                    .map(|&(n, s, tau)| {
                        let (a, b) = (c[s], c[(s + 1) % 4]);
                        (n, [a[0] + tau * (b[0] - a[0]), a[1] + tau * (b[1] - a[1])])
                    })
                    .collect::<HashMap<u32, [f64; 2]>>()
            })
            .collect();
        ChartFrames::new(&self.cut, nodes, self.sides.clone())
    }

    /// A solve with every curve aligned (`None`, the loop's), or the final one with the
    /// user's tags and that share of every untagged curve's ends held on its side.
    /// `pins` hold some unknowns near given values ([`System::out_of_order`]); `weights`, if
    /// given, replace the cotangent weights (see [`ParamSession::mend`]).
    fn solve(&mut self, final_anchor: Option<f64>, pins: &[(u32, f64)], weights: Option<&[[f64; 3]]>) -> Result<Solution, ParamError> {
        let frames = self.frames();
        #[cfg(feature = "eq3")]
        if self.options.formulation == Formulation::Eq3 {
            let every;
            let aligned = if final_anchor.is_none() {
                every = vec![true; self.sides.len()];
                &every
            } else {
                &self.user_tags
            };
            return eq3::solve_eq3(&self.cut, aligned, &frames, &self.weights);
        }
        let held = self.held(final_anchor);
        let system = if final_anchor.is_some() { &mut self.user_aligned } else { &mut self.all_aligned };
        system.solve(&self.cut, &frames, weights.unwrap_or(&self.weights), &held, pins)
    }

    /// The vertices a solve with `final_anchor` holds on their chart sides besides the
    /// aligned curves' (see [`ParamSession::solve`]).
    fn held(&self, final_anchor: Option<f64>) -> Vec<bool> {
        final_anchor.map_or_else(Vec::new, |anchor| system::held_on_side(&self.cut, &self.user_tags, anchor))
    }

    /// `sol` (solved with `final_anchor`, flipping `d.flipped` triangles) mended where it
    /// folds. First the curve vertices it put out of order along their sides are held at the
    /// nearest places in order and the system solved again (see `order`): at most
    /// [`ORDER_ROUNDS`] times while that flips fewer triangles, as a vertex freed of its
    /// neighbour's fold may leave the order next. If some still flip, once more with no
    /// negative edge weight next to the layout ([`system::without_negative_edges`]). Each
    /// step is kept only if it flips fewer. Only the final solution is mended: the charts and
    /// the sample counts come from the loop as before, so the quads move only round the mend.
    /// A mending solve that fails, or gives values that are not finite, ends the mending:
    /// `sol` was a result already.
    fn mend(&mut self, final_anchor: Option<f64>, sol: Solution, d: Distortion) -> (Solution, Distortion) {
        let mut pins: Vec<(u32, f64)> = Vec::new();
        let mut best = (sol, d);
        if best.0.unknowns.is_empty() {
            return best; // solved by no `System` (eq. 3, a comparison): nothing to hold
        }
        for _ in 0..ORDER_ROUNDS {
            if best.1.flipped == 0 {
                break;
            }
            let system = if final_anchor.is_some() { &self.user_aligned } else { &self.all_aligned };
            let out = system.out_of_order(&self.cut, &self.held(final_anchor), &best.0.unknowns);
            if out.is_empty() {
                break;
            }
            for (i, share) in out {
                match pins.iter_mut().find(|p| p.0 == i) {
                    Some(p) => p.1 = share,
                    None => pins.push((i, share)),
                }
            }
            let Some(sol) = self.mending_solve(final_anchor, &pins, None) else { break };
            let d = self.distortion(&sol);
            if d.flipped >= best.1.flipped {
                break;
            }
            best = (sol, d);
        }
        if best.1.flipped > 0 {
            let weights = system::without_negative_edges(&self.cut, &self.weights);
            if let Some(sol) = self.mending_solve(final_anchor, &pins, Some(&weights)) {
                let d = self.distortion(&sol);
                if d.flipped < best.1.flipped {
                    best = (sol, d);
                }
            }
        }
        best
    }

    /// A solve of [`ParamSession::mend`], if it succeeds with finite values.
    fn mending_solve(&mut self, final_anchor: Option<f64>, pins: &[(u32, f64)], weights: Option<&[[f64; 3]]>) -> Option<Solution> {
        self.solve(final_anchor, pins, weights).ok().filter(|sol| sol.unknowns.iter().all(|x| x.is_finite()))
    }

    fn distortion(&self, sol: &Solution) -> Distortion {
        let (mut sum, mut area_sum, mut max, mut flipped) = (0.0, 0.0, 0.0f64, 0);
        for (uv, &(rest, area)) in sol.corner_uv.iter().zip(&self.rest) {
            if chart::folded(*uv) {
                flipped += 1;
            }
            if area > 0.0 {
                let d = chart::distortion(*uv, rest);
                sum += area * d;
                area_sum += area;
                max = max.max(d);
            }
        }
        Distortion { mean: if area_sum > 0.0 { sum / area_sum } else { 0.0 }, max, flipped }
    }

    /// One iteration of Section 3.1: optimize every chart, rebuild the transitions, solve
    /// again with all edges aligned.
    ///
    /// # Errors
    /// [`ParamError`] from the solve.
    pub fn step(&mut self) -> Result<IterationStats, ParamError> {
        let t0 = now();
        let start = self.charts.clone();
        let mut tris: Vec<Vec<ChartTriangle>> = vec![Vec::new(); self.charts.len()];
        for (t, uv) in self.last.corner_uv.iter().enumerate() {
            let f = self.cut.triangle_face[t] as usize;
            if self.domains[f].kind == ChartKind::Unit {
                continue; // fixed: nothing to optimize
            }
            let chart = &self.charts[f];
            let st = uv.map(|u| chart.bilinear_coords(u));
            let (rest, area) = self.rest[t];
            tris[f].push(ChartTriangle { st, rest, area });
        }
        let t_charts = now();
        let fitted: Vec<Chart> = self
            .charts
            .iter()
            .enumerate()
            .map(|(f, chart)| {
                let kind = self.domains[f].kind;
                if kind == ChartKind::Unit {
                    return *chart;
                }
                optimize(&chart.with_kind(kind), &tris[f], &OptimizeOptions::default()).0
            })
            .collect();
        let fitted = self.within_shape_bound(&start, &fitted);
        self.chart_seconds += now() - t_charts;
        // The paper's step is `fitted`; Anderson mixing accelerates it (see `anderson`).
        let kinds: Vec<ChartKind> = self.domains.iter().map(|d| d.kind).collect();
        let flat = |charts: &[Chart]| -> Vec<f64> {
            charts.iter().zip(&kinds).flat_map(|(c, &k)| c.with_kind(k).free_vars()).collect()
        };
        let mixed = if self.options.accelerate {
            self.anderson.next(&flat(&self.charts), &flat(&fitted))
        } else {
            flat(&fitted)
        };
        let mut at = 0;
        let accelerated: Vec<Chart> = fitted
            .iter()
            .zip(&kinds)
            .map(|(fit, &k)| {
                if k == ChartKind::Unit {
                    return *fit;
                }
                let c = fit.with_kind(k).with_free_vars(&mixed[at..at + k.dofs()]);
                at += k.dofs();
                c
            })
            .collect();
        // Anderson steps need not lower the distortion every time; only a blow-up (or an
        // invalid chart) sends us back to the plain step.
        let previous = self.history.last().map_or(f64::INFINITY, |h| h.distortion.mean);
        let accelerated = self.within_shape_bound(&start, &accelerated);
        self.charts = self.between(&start, &accelerated, self.step_share);
        let valid = self.charts.iter().all(|c| c.is_convex() && c.x[0] > 0.0);
        let accepted = if valid { self.solve(None, &[], None).ok() } else { None }
            .map(|sol| {
                let d = self.distortion(&sol);
                (sol, d)
            })
            .filter(|(_, d)| d.mean <= self.options.blow_up * previous);
        let (sol, distortion) = match accepted {
            Some(result) => result,
            None => {
                // Fall back to the paper's plain step.
                self.anderson.reset();
                self.charts = self.between(&start, &fitted, self.step_share);
                let sol = self.solve(None, &[], None)?;
                let d = self.distortion(&sol);
                (sol, d)
            }
        };
        let (sol, distortion) = self.without_new_flips(&start, sol, distortion)?;
        self.last = sol;
        let stats = IterationStats { iteration: self.history.len(), distortion, seconds: now() - t0 };
        self.history.push(stats);
        self.final_solution = None;
        Ok(stats)
    }

    /// The charts `share` of the way from `start` to `end` (in each chart's free variables).
    fn between(&self, start: &[Chart], end: &[Chart], share: f64) -> Vec<Chart> {
        if share == 1.0 {
            return end.to_vec();
        }
        start.iter().zip(end).zip(&self.domains).map(|((a, b), dom)| chart_between(a, b, dom.kind, share)).collect()
    }

    /// Each chart of `end`, or where it leaves [`SHAPE_BOUND`], the furthest point towards it
    /// from `start` that does not (found by bisection: the bound is a test, not a formula).
    fn within_shape_bound(&self, start: &[Chart], end: &[Chart]) -> Vec<Chart> {
        start
            .iter()
            .zip(end)
            .zip(&self.domains)
            .map(|((a, b), dom)| {
                let sides = &dom.side_lengths;
                let limit = SHAPE_BOUND.max(a.with_kind(dom.kind).shape_deviation(sides));
                if b.shape_deviation(sides) <= limit {
                    return *b;
                }
                let (mut inside, mut outside) = (0.0, 1.0);
                for _ in 0..30 {
                    let mid = 0.5 * (inside + outside);
                    if chart_between(a, b, dom.kind, mid).shape_deviation(sides) <= limit {
                        inside = mid;
                    } else {
                        outside = mid;
                    }
                }
                chart_between(a, b, dom.kind, inside)
            })
            .collect()
    }

    /// A chart step that flips triangles the previous solve did not is shortened: the charts
    /// move only part of the way from `start` ([`ParamOptions::step_shares`]). The isometry energy of
    /// Section 3.1 is measured on the current parameterization and knows nothing of the
    /// harmonic solve that follows, so a chart that fits its triangles best can still ask
    /// the solve to fold triangles near a corner whose chart angle moved far from its
    /// surface angle. The result with the fewest flips wins, the step's own on a tie.
    ///
    /// The share kept is where the next iteration starts: a layout whose full steps fold
    /// triangles keeps folding them (bunny-ears' full steps flipped 2, 8 and 16 triangles,
    /// every half step none), and each solve tried in vain costs a factorization. After
    /// [`ParamOptions::grow_after`] clean iterations in a row it doubles again (at most to 1).
    fn without_new_flips(
        &mut self,
        start: &[Chart],
        sol: Solution,
        d: Distortion,
    ) -> Result<(Solution, Distortion), ParamError> {
        let before = self.history.last().map_or(usize::MAX, |h| h.distortion.flipped);
        if !self.options.guard_flips || d.flipped <= before {
            self.kept_steps += 1;
            if self.kept_steps >= self.options.grow_after && self.step_share < 1.0 {
                self.step_share = (2.0 * self.step_share).min(1.0);
                self.kept_steps = 0;
            }
            return Ok((sol, d));
        }
        let full = self.charts.clone();
        let mut best = (sol, d, full.clone(), 1.0);
        for share in self.options.step_shares {
            self.charts = self.between(start, &full, share);
            let sol = self.solve(None, &[], None)?;
            let d = self.distortion(&sol);
            if d.flipped < best.1.flipped {
                best = (sol, d, self.charts.clone(), share);
            }
            if best.1.flipped <= before {
                break;
            }
        }
        self.charts = best.2;
        if best.3 < 1.0 {
            self.anderson.reset();
            self.step_share *= best.3;
        }
        // Not a clean iteration, whether a shorter step won or all folded as much: it does
        // not count towards growing the share again.
        self.kept_steps = 0;
        Ok((best.0, best.1))
    }

    /// The final solve with the user's alignment tags (paper 3.1, step 4).
    ///
    /// Releasing the untagged curves can fold triangles next to nodes: on coarse meshes a
    /// corner sector of a face may be one triangle wide, and the harmonic map alone does not
    /// keep the curves' order around a node whose chart angles differ much from its surface
    /// angles (mushroom-t folded 10 triangles, then 4 and 0 with anchors; eight-rims 2). When the released solve flips
    /// more triangles than the all-aligned one before it, the curves' ends are kept on their
    /// sides over a growing share of their vertices ([`ParamOptions::final_anchors`]) until it does not, or
    /// until a larger share stops lowering the count (then more will not help); the last
    /// resort aligns every curve, which is the all-aligned solve itself (reused). Either is
    /// then mended where it put curve vertices out of order along their sides
    /// ([`ParamSession::mend`]), and the loop's solve is compared mended: so the final
    /// solve never flips more than the optimization phase mended, and keeps the user's
    /// freedom wherever it can.
    ///
    /// # Errors
    /// [`ParamError`] from the solve.
    pub fn finish(&mut self) -> Result<Distortion, ParamError> {
        let (sol, d) = self.all_aligned_result();
        let aligned = self.mend(None, sol, d);
        if self.user_tags.iter().all(|&t| t) {
            // Every curve tagged: the final system is the one the last solve used, with the
            // same charts; its solution stands (no second factorization unless mended).
            let d = aligned.1;
            self.final_solution = Some(aligned);
            return Ok(d);
        }
        let before = aligned.1.flipped;
        // Eq. 3 (a comparison) is solved as the paper states it, without anchors.
        let final_anchors = self.options.final_anchors;
        #[cfg(feature = "eq3")]
        let anchors: &[f64] = if self.options.formulation == Formulation::Symmetric { &final_anchors } else { &[] };
        #[cfg(not(feature = "eq3"))]
        let anchors: &[f64] = &final_anchors;
        let mut used = 0.0;
        let mut sol = self.solve(Some(used), &[], None)?;
        let mut d = self.distortion(&sol);
        let mut fewest = usize::MAX;
        for &anchor in anchors {
            // Done when it flips no more than the loop; anchoring more is tried only while
            // anchoring helps (on bunny-ears it folds more: 492, then 711).
            if d.flipped <= before || d.flipped >= fewest {
                break;
            }
            fewest = d.flipped;
            used = anchor;
            sol = self.solve(Some(used), &[], None)?;
            d = self.distortion(&sol);
        }
        let chosen = if d.flipped > before && !anchors.is_empty() { aligned } else { self.mend(Some(used), sol, d) };
        let d = chosen.1;
        self.final_solution = Some(chosen);
        Ok(d)
    }

    /// The loop's last solve (every curve aligned) and its distortion: already at hand.
    fn all_aligned_result(&self) -> (Solution, Distortion) {
        let d = self.history.last().map(|h| h.distortion).unwrap_or_else(|| self.distortion(&self.last));
        (self.last.clone(), d)
    }

    /// Every node's position in the chart of each face it is on: `[face][&node]`.
    pub fn node_positions(&self) -> NodePositions {
        self.frames().nodes
    }

    /// Seconds per stage over all solves and chart optimizations so far.
    pub fn stage_times(&self) -> StageTimes {
        let (a, b) = (self.all_aligned.times, self.user_aligned.times);
        StageTimes {
            assembly: a.assembly + b.assembly,
            symbolic: a.symbolic + b.symbolic,
            factor: a.factor + b.factor,
            solve: a.solve + b.solve,
            chart_optimization: self.chart_seconds,
            factorizations: a.factorizations + b.factorizations,
        }
    }

    /// ‖JᵀJ − I‖²_F (eq. 7) of every refined triangle in the latest [`solution`](Self::solution),
    /// in [`cut`](Self::cut)'s triangle order; 0 for triangles of zero area.
    pub fn triangle_distortion(&self) -> Vec<f64> {
        self.solution()
            .corner_uv
            .iter()
            .zip(&self.rest)
            .map(|(uv, &(rest, area))| if area > 0.0 { chart::distortion(*uv, rest) } else { 0.0 })
            .collect()
    }

    /// The distortion of the final solve, once [`finish`](Self::finish) ran.
    pub fn final_distortion(&self) -> Option<Distortion> {
        self.final_solution.as_ref().map(|(_, d)| *d)
    }
    pub fn history(&self) -> &[IterationStats] {
        &self.history
    }
    pub fn charts(&self) -> &[Chart] {
        &self.charts
    }
    pub fn cut(&self) -> &CutMesh {
        &self.cut
    }
    /// The latest solution: the final one after [`finish`](Self::finish), else the latest
    /// iteration's.
    pub fn solution(&self) -> &Solution {
        self.final_solution.as_ref().map_or(&self.last, |(s, _)| s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`ParamOptions::KEYS`] are exactly serde's names of the fields, every one read back,
    /// and a key that is none of them is refused.
    #[test]
    fn options_keys_are_the_serde_fields() {
        let json = serde_json::to_value(ParamOptions::DEFAULT).unwrap();
        let mut keys: Vec<&str> = json.as_object().unwrap().keys().map(String::as_str).collect();
        keys.sort_unstable();
        let mut known = ParamOptions::KEYS.to_vec();
        known.sort_unstable();
        assert_eq!(keys, known);
        let back: ParamOptions = serde_json::from_value(json).unwrap();
        assert_eq!(back, ParamOptions::DEFAULT);
        let some: ParamOptions = serde_json::from_str(r#"{"chart": "rect", "final_anchors": [0.2, 0.3]}"#).unwrap();
        assert_eq!((some.default_chart, some.final_anchors, some.align), (Some(ChartType::Rect), [0.2, 0.3], true));
        let e = serde_json::from_str::<ParamOptions>(r#"{"chart": "hex"}"#).unwrap_err().to_string();
        assert!(e.starts_with("unknown chart type 'hex' (quad, rect or unit)"), "{e}");
        assert!(serde_json::from_str::<ParamOptions>(r#"{"default_chart": "rect"}"#).is_err());
    }

    #[test]
    fn options_out_of_range_are_named() {
        assert_eq!(ParamOptions::DEFAULT.check(), Ok(()));
        let mut o = ParamOptions::DEFAULT;
        o.step_shares = [0.5, 0.0];
        assert_eq!(o.check(), Err(ParamError::Option { name: "step_shares", must: "two numbers above 0 and at most 1" }));
        o = ParamOptions::DEFAULT;
        o.blow_up = f64::NAN;
        assert!(matches!(o.check(), Err(ParamError::Option { name: "blow_up", .. })));
        o = ParamOptions::DEFAULT;
        o.final_anchors = [0.1, 1.5];
        assert!(matches!(o.check(), Err(ParamError::Option { name: "final_anchors", .. })));
    }
}
