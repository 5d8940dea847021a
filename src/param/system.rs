//! The global parameterization system (paper eq. 1–3, 11–12), in its symmetric form.
//!
//! Eq. 3 asks every free vertex to be the cotangent-weighted mean of its neighbours, each
//! brought into the vertex's chart by a transition. As written that matrix is not symmetric
//! (method-notes §4). We minimize instead the Dirichlet energy Σ_t ∫_t |∇u|², each triangle
//! evaluated in the chart of the face it lies in, its vertices from other charts brought in by
//! their transitions. Its minimizer satisfies eq. 3 wherever the transitions are rigid (then
//! both are the same harmonic map); where a transition scales, the energy stays a sum of
//! per-triangle convex terms, so the matrix is symmetric positive definite once the nodes are
//! fixed, and a sparse Cholesky factorization solves it (faer; `crate::solve`).
//!
//! Alignment (eq. 11): on the refined mesh (`cut`) every point of an aligned curve is a
//! vertex, so "lies on the straight chart side" is a constraint on one vertex. We eliminate it
//! exactly: such a vertex has one unknown `s`, its position `p + s (q − p)` on the side from
//! node p to node q. This replaces the mixed least-squares system of eq. 12 by an equivalent
//! smaller SPD system: the constraint holds exactly and the energy is minimal among all maps
//! that satisfy it — which is what eq. 12 computes, with the relaxed harmonic rows being
//! the vertices' energy gradients.
//!
//! A solve may also hold some curve vertices near given shares of their sides (`pins`, a
//! penalty on the diagonal, so the pattern stays): those a solve put out of order along them
//! (see `order`).
//!
//! Why this formulation and not eq. 3 as written: `docs/formulations.md` compares the two on
//! the known answers and the sample layouts (`cargo test --test param_formulations`).

use super::cut::CutMesh;
use super::frames::ChartFrames;
use super::order::nearest_in_order;
use super::transition::Affine;
use crate::geom::{cotangent, perp2};
use crate::clock::now;
use crate::culprits::Culprits;
use crate::mesh::NONE;
use crate::solve::{SolveError, SpdSolver};
use std::collections::HashMap;
use std::fmt;

/// How strongly a pinned curve vertex is held at its share of the side: this many times its
/// own diagonal of the system.
const PIN: f64 = 100.0;

/// The unknowns of one vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Var {
    /// Known: a node, or a vertex no triangle uses.
    Fixed,
    /// Free in its face's chart: unknowns `index`, `index + 1`.
    Free(u32),
    /// On an aligned curve: one unknown, the position along the chart side.
    OnSide(u32),
}

#[derive(Debug, Clone, PartialEq)]
pub enum ParamError {
    Solve(SolveError),
    /// The global system is not positive definite: its factorization met a pivot that is
    /// not strictly positive, at unknown `pivot`, which belongs to input mesh vertex
    /// `vertex` (for an unknown of a curve crossing: the nearest corner of the input
    /// triangle it lies in).
    NotPositiveDefinite { pivot: usize, vertex: u32 },
    /// A triangle touches a node that is not on its face (only on meshes too coarse for
    /// the layout).
    NodeNotOnFace { node: u32, face: u32 },
    /// A triangle has a vertex from a face that is not its neighbour across a curve.
    NotNeighbours { vertex: u32, face: u32 },
    /// A setting of [`super::ParamOptions`] is out of its range: `name` must be `must`.
    Option { name: &'static str, must: &'static str },
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamError::Solve(e) => write!(f, "the global system could not be solved: {e}"),
            ParamError::NotPositiveDefinite { pivot, vertex } => write!(
                f,
                "the global system could not be solved: sparse Cholesky: the matrix is not positive definite near vertex {vertex} (pivot {pivot})"
            ),
            ParamError::NodeNotOnFace { node, face } => {
                write!(f, "a triangle of face {face} touches node {node}, which is not on that face; the mesh is too coarse there")
            }
            ParamError::Option { name, must } => write!(f, "the option {name} must be {must}"),
            ParamError::NotNeighbours { vertex, face } => {
                write!(f, "a triangle of face {face} reaches vertex {vertex} of a face that is not its neighbour; the mesh is too coarse there")
            }
        }
    }
}

impl std::error::Error for ParamError {}

impl ParamError {
    /// A stable snake_case name of the error, for programs (the page).
    pub fn kind(&self) -> &'static str {
        match self {
            ParamError::Solve(e) => e.kind(),
            ParamError::NotPositiveDefinite { .. } => "not_positive_definite",
            ParamError::NodeNotOnFace { .. } => "node_not_on_face",
            ParamError::NotNeighbours { .. } => "faces_not_neighbours",
            ParamError::Option { .. } => "bad_options",
        }
    }

    /// The node or mesh vertex the error names.
    pub fn culprits(&self) -> Culprits {
        match *self {
            ParamError::Solve(_) | ParamError::Option { .. } => Culprits::none(),
            ParamError::NotPositiveDefinite { vertex, .. } | ParamError::NotNeighbours { vertex, .. } => {
                Culprits::vertices([vertex])
            }
            ParamError::NodeNotOnFace { node, .. } => Culprits::nodes([node]),
        }
    }
}

impl From<SolveError> for ParamError {
    fn from(e: SolveError) -> Self {
        ParamError::Solve(e)
    }
}

/// A vertex's chart position as a linear function of the unknowns: `u = m z[vars] + b`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Expr {
    pub(super) var: Var,
    /// 2×2 (Free) or 2×1 in column 0 (OnSide).
    pub(super) m: [[f64; 2]; 2],
    pub(super) b: [f64; 2],
}

impl Expr {
    pub(super) fn fixed(b: [f64; 2]) -> Expr {
        Expr { var: Var::Fixed, m: [[0.0; 2]; 2], b }
    }
    pub(super) fn dims(&self) -> usize {
        match self.var {
            Var::Fixed => 0,
            Var::Free(_) => 2,
            Var::OnSide(_) => 1,
        }
    }
    pub(super) fn index(&self) -> u32 {
        match self.var {
            Var::Free(i) | Var::OnSide(i) => i,
            Var::Fixed => NONE,
        }
    }
    pub(super) fn transformed(&self, a: &Affine) -> Expr {
        let l = &a.m;
        let m = std::array::from_fn(|r| std::array::from_fn(|c| l[r][0] * self.m[0][c] + l[r][1] * self.m[1][c]));
        Expr { var: self.var, m, b: a.apply(self.b) }
    }
    pub(super) fn eval(&self, z: &[f64]) -> [f64; 2] {
        let zi = |k: usize| z[self.index() as usize + k];
        match self.var {
            Var::Fixed => self.b,
            Var::Free(_) => std::array::from_fn(|r| self.m[r][0] * zi(0) + self.m[r][1] * zi(1) + self.b[r]),
            Var::OnSide(_) => std::array::from_fn(|r| self.m[r][0] * zi(0) + self.b[r]),
        }
    }
}

/// The input mesh vertex of refined vertex `v`: itself, or for a curve crossing (numbered
/// after the input's vertices) the nearest corner of the input triangle it lies in.
fn input_vertex(cut: &CutMesh, v: u32) -> u32 {
    let Some(t) = cut.triangles.iter().position(|tri| tri.contains(&v)) else { return v };
    let origin = cut.triangle_origin[t];
    // The input triangle's corners are the three lowest vertex numbers among its pieces.
    let mut corners: Vec<u32> = (0..cut.triangles.len())
        .filter(|&k| cut.triangle_origin[k] == origin)
        .flat_map(|k| cut.triangles[k])
        .collect();
    corners.sort_unstable();
    corners.dedup();
    corners.truncate(3);
    if corners.contains(&v) {
        return v;
    }
    let at = cut.positions[v as usize];
    let d2 = |c: u32| (0..3).map(|k| (cut.positions[c as usize][k] - at[k]).powi(2)).sum::<f64>();
    corners.into_iter().min_by(|&a, &b| d2(a).total_cmp(&d2(b))).unwrap_or(v)
}

/// The vertices held on their chart side in a solve: every vertex of an aligned curve and,
/// with `anchor` > 0, that share of every other curve's vertices at each end.
pub fn held_on_side(cut: &CutMesh, aligned: &[bool], anchor: f64) -> Vec<bool> {
    let mut held = vec![false; cut.positions.len()];
    for (c, verts) in cut.curve_vertices.iter().enumerate() {
        let k = if aligned.get(c).copied().unwrap_or(false) {
            verts.len()
        } else {
            (verts.len() as f64 * anchor).ceil() as usize
        };
        for &v in verts.iter().take(k).chain(verts.iter().rev().take(k)) {
            held[v as usize] = true;
        }
    }
    held
}

/// Whether each vertex is known: a node, or a vertex no triangle uses.
fn fixed_vertices(cut: &CutMesh) -> Vec<bool> {
    let mut used = vec![false; cut.positions.len()];
    for t in &cut.triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    (0..cut.positions.len())
        .map(|v| cut.vertex_node[v] != NONE || !used[v] || cut.vertex_face[v] == NONE)
        .collect()
}

/// The unknowns of every vertex of the refined mesh and their count, as [`super::eq3`] uses
/// them: nodes fixed, vertices [`held_on_side`] one unknown along their chart side, every
/// other vertex two in its face's chart.
pub(super) fn unknowns(cut: &CutMesh, aligned: &[bool], anchor: f64) -> (Vec<Var>, usize) {
    let held = held_on_side(cut, aligned, anchor);
    let mut n = 0u32;
    let vars = fixed_vertices(cut)
        .iter()
        .zip(&held)
        .map(|(&fixed, &held)| {
            if fixed {
                Var::Fixed
            } else if held {
                n += 1;
                Var::OnSide(n - 1)
            } else {
                n += 2;
                Var::Free(n - 2)
            }
        })
        .collect();
    (vars, n as usize)
}

/// Every vertex with unknowns (`vars`) in the chart of its own face, as an expression: a
/// vertex off the curves by its own (u, v); a curve vertex by its coordinates along and
/// across its chart side from node p to node q, `p + s (q − p) + n (q − p)⊥`, with the n
/// column zero where it is held on the side (`held`, or an [`Var::OnSide`] vertex). `None`
/// for fixed vertices.
///
/// # Errors
/// [`ParamError::NodeNotOnFace`] if a curve's end node is not on the face left of it (a
/// mesh too coarse for the layout).
pub(super) fn own_exprs(cut: &CutMesh, vars: &[Var], frames: &ChartFrames, held: &[bool]) -> Result<Vec<Option<Expr>>, ParamError> {
    let ends: Vec<Option<([f64; 2], [f64; 2])>> =
        (0..cut.curve_vertices.len() as u32).map(|c| frames.curve_ends(cut, c)).collect();
    (0..cut.positions.len())
        .map(|vi| {
            let var = vars[vi];
            if var == Var::Fixed {
                return Ok(None);
            }
            let c = cut.vertex_curve[vi];
            if c == NONE {
                return Ok(Some(Expr { var, m: [[1.0, 0.0], [0.0, 1.0]], b: [0.0, 0.0] }));
            }
            let Some((p, q)) = ends[c as usize] else {
                let first = cut.curve_vertices[c as usize][0];
                return Err(ParamError::NodeNotOnFace { node: cut.vertex_node[first as usize], face: cut.vertex_face[vi] });
            };
            let d = [q[0] - p[0], q[1] - p[1]];
            let n = if held.get(vi) == Some(&true) || matches!(var, Var::OnSide(_)) { [0.0, 0.0] } else { perp2(d) };
            Ok(Some(Expr { var, m: [[d[0], n[0]], [d[1], n[1]]], b: p }))
        })
        .collect()
}

/// The expressions of triangle `t`'s corners in the chart of its face: their own
/// (`own`, as [`own_exprs`] gives them) or brought in from a neighbouring chart.
///
/// # Errors
/// [`ParamError::NodeNotOnFace`] or [`ParamError::NotNeighbours`] for a corner with no place in
/// that chart.
fn triangle_exprs(cut: &CutMesh, frames: &ChartFrames, own: &[Option<Expr>], t: usize) -> Result<[Expr; 3], ParamError> {
    let (tri, face) = (&cut.triangles[t], cut.triangle_face[t]);
    let e = |k: usize| frames.vertex_expr(cut, own, tri[k], face);
    Ok([e(0)?, e(1)?, e(2)?])
}

/// Half the cotangent of each triangle corner: the Dirichlet energy of a linear map on a
/// triangle is Σ_k w_k |u_{k+1} − u_{k+2}|² with w_k = cot θ_k / 2 (eq. 2's weights).
pub fn cotangent_halves(cut: &CutMesh) -> Vec<[f64; 3]> {
    cut.triangles
        .iter()
        .map(|t| {
            let p = t.map(|v| cut.positions[v as usize]);
            std::array::from_fn(|k| 0.5 * cotangent(p[k], p[(k + 1) % 3], p[(k + 2) % 3]))
        })
        .collect()
}

/// `halves` ([`cotangent_halves`]) with the weight of every edge between two triangles that
/// touch the layout (a curve vertex or a node) made at least zero: where the two corners
/// facing such an edge add up to more than 180° (it is not Delaunay, as on slivers), its
/// negative half is raised until the sum is zero (both halves to zero if both are negative).
///
/// A negative edge weight lets the harmonic map push a vertex past its neighbours, and next
/// to a chart side past the side: on eight's automatic layout the three triangles still
/// flipped after the curves were put in order were round such an edge. With none, each vertex
/// is a convex combination of its neighbours (Tutte, Floater). Only the final solution is
/// solved with these (`ParamSession::mend`): raising every negative edge of the mesh for every
/// solve moved the charts and the quads (nefertiti's angle error 2.3 -> 3.0°). The triangles
/// that touch the layout are the ones a later solve assembles anew ([`Pattern::varying`]), so
/// no other term changes.
pub fn without_negative_edges(cut: &CutMesh, halves: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let touches: Vec<bool> = cut.triangles.iter().map(|t| t.iter().any(|&v| cut.on_layout(v))).collect();
    // Corner k of a triangle faces its edge from vertex k + 1 to k + 2.
    let mut facing: HashMap<(u32, u32), (usize, usize)> = HashMap::new();
    for (t, tri) in cut.triangles.iter().enumerate().filter(|&(t, _)| touches[t]) {
        for k in 0..3 {
            facing.insert((tri[(k + 1) % 3], tri[(k + 2) % 3]), (t, k));
        }
    }
    let mut out = halves.to_vec();
    for (&(a, b), &(t, k)) in &facing {
        let Some(&(u, j)) = facing.get(&(b, a)) else { continue };
        let (x, y) = (halves[t][k], halves[u][j]);
        if a < b && x + y < 0.0 {
            (out[t][k], out[u][j]) = if x < 0.0 && y < 0.0 { (0.0, 0.0) } else if x < 0.0 { (-y, y) } else { (x, -x) };
        }
    }
    out
}

/// Seconds spent in each stage of the solves so far, and how many numeric factorizations
/// they made (for benchmarks: each costs the most of any stage).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct StageTimes {
    pub assembly: f64,
    pub symbolic: f64,
    pub factor: f64,
    pub solve: f64,
    pub chart_optimization: f64,
    pub factorizations: u32,
}

/// The global system for one set of aligned curves: its unknowns, and one sparsity pattern
/// for all its solves, so the symbolic factorization is computed once (only values change).
///
/// A vertex inside a face has two unknowns, (u, v) in the face's chart. A vertex of a curve
/// has its coordinates along and across its chart side from node p to node q, at
/// `p + s (q − p) + n (q − p)⊥`: only s if the curve is aligned (eq. 11 held exactly), s and
/// n otherwise. Holding such a vertex on its side in one solve (anchoring, see
/// `ParamSession::finish`) is `n = 0`, an identity row in the same pattern.
///
/// Inside a chart u and v do not mix; they do through a curve vertex's side direction and
/// through transitions. Where no general quadrilateral chart is involved, chart sides are
/// parallel to the axes and transitions turn by multiples of 90°, so they still do not mix:
/// the pattern leaves out the entries that would couple them. An aligned side then touches
/// only u or only v, which splits the coupling graph further (bunny-ears' earlier box layout,
/// rect and unit charts with three general ones, every curve aligned: 2.5 M values in the
/// factor instead of 5.9 M).
pub struct System {
    /// Per vertex: `Free(i)` (unknowns i, i + 1), `OnSide(i)` or `Fixed`.
    vars: Vec<Var>,
    n_unknowns: usize,
    /// Per face: its chart is a general quadrilateral, whose sides may point anywhere.
    general: Vec<bool>,
    solver: Option<SpdSolver>,
    /// The pattern, fixed by the first solve (see [`Pattern`]).
    pattern: Pattern,
    pub times: StageTimes,
}

/// Where each triangle's terms go, fixed by the first solve. A triangle with only interior
/// vertices (no node, no curve vertex) adds the same values every time (its vertices are
/// their own unknowns, `m = I`, `b = 0`) and nothing to the right-hand side, so later solves
/// start from those sums and add only the triangles that touch a curve or a node (a tenth of
/// them on bunny-ears), straight into the matrix's stored values.
#[derive(Default)]
struct Pattern {
    /// Per candidate entry of the varying triangles, in assembly order: whether the pattern
    /// has it as an entry of its own (off the diagonal; a diagonal term of unknown i goes to
    /// `slot[i]`).
    keep: Vec<bool>,
    /// Per triangle (and one past the last): its first candidate, its first kept entry.
    candidate_start: Vec<u32>,
    value_start: Vec<u32>,
    /// The triangles whose values change between solves.
    varying: Vec<u32>,
    /// Per kept entry: its place among the matrix's stored values ([`SpdSolver::slots`]);
    /// the first entries are the unknowns' diagonals, in order.
    slot: Vec<u32>,
    /// The stored values summed over the constant triangles.
    constant: Vec<f64>,
}

/// What one solve assembles: the refined mesh, every triangle's vertices as expressions in
/// its chart, the cotangent weights, the vertices held on their sides.
#[derive(Clone, Copy)]
struct Assembly<'a> {
    cut: &'a CutMesh,
    /// Per triangle in the first solve; per varying triangle ([`Pattern::varying`]) later.
    exprs: &'a [[Expr; 3]],
    weights: &'a [[f64; 3]],
    held: &'a [bool],
    /// Unknowns held near these values ([`System::out_of_order`]).
    pins: &'a [(u32, f64)],
}

/// Per-triangle chart coordinates of a solve, and the unknowns they came from.
#[derive(Debug, Clone)]
pub struct Solution {
    /// `corner_uv[t][k]`: vertex k of triangle t in the chart of the triangle's face.
    pub corner_uv: Vec<[[f64; 2]; 3]>,
    /// The system's unknowns (empty where no [`System`] solved it).
    pub unknowns: Vec<f64>,
}

/// Whether columns `x` and `y` of two expressions' matrices can give a nonzero product
/// when their components along the axes keep being zero or not (axis-parallel sides).
fn overlaps(x: [f64; 2], y: [f64; 2]) -> bool {
    let nonzero = |a: [f64; 2], k: usize| a[k] * a[k] > 1e-24 * (a[0] * a[0] + a[1] * a[1]);
    (nonzero(x, 0) && nonzero(y, 0)) || (nonzero(x, 1) && nonzero(y, 1))
}

/// Whether each vertex of triangle `t`, in the chart of the triangle's face, may turn
/// away from the axes: a curve vertex of a general chart, or one brought in through a
/// transition that touches a general chart. The others' matrices keep their zeros.
fn may_turn(cut: &CutMesh, general: &[bool], t: usize) -> [bool; 3] {
    let general = |f: u32| general.get(f as usize).copied().unwrap_or(true);
    let face = cut.triangle_face[t];
    cut.triangles[t].map(|v| {
        let home = cut.vertex_face[v as usize];
        if home == face {
            cut.vertex_curve[v as usize] != NONE && general(home)
        } else {
            general(home) || general(face)
        }
    })
}

/// The terms of triangle `t`'s Dirichlet energy Σ_k w_k |u_a − u_b|² (edge ab opposite
/// corner k, `u = M z + b`): adds its gradient's constant part to `rhs` and calls
/// `term(row, col, value, keep)` for every lower-triangle matrix entry, in a fixed order.
/// With `turns` (see [`may_turn`]) `keep` tells whether the entry belongs in the pattern.
fn triangle_terms(ex: &[Expr; 3], w: &[f64; 3], turns: Option<[bool; 3]>, rhs: &mut [f64], mut term: impl FnMut(u32, u32, f64, bool)) {
    for k in 0..3 {
        let (ia, ib) = ((k + 1) % 3, (k + 2) % 3);
        let (a, b) = (&ex[ia], &ex[ib]);
        let general = turns.is_some_and(|t| t[ia] || t[ib]);
        let d = [a.b[0] - b.b[0], a.b[1] - b.b[1]];
        // Term w |M_a z_a − M_b z_b + d|²: gradient rows M_aᵀ(...) and −M_bᵀ(...).
        for (x, sx) in [(a, 1.0), (b, -1.0)] {
            for i in 0..x.dims() {
                let row = x.index() + i as u32;
                let xi = [x.m[0][i], x.m[1][i]];
                rhs[row as usize] -= sx * w[k] * (xi[0] * d[0] + xi[1] * d[1]);
                for (y, sy) in [(a, 1.0), (b, -1.0)] {
                    for j in 0..y.dims() {
                        let col = y.index() + j as u32;
                        if col > row {
                            continue;
                        }
                        let yj = [y.m[0][j], y.m[1][j]];
                        // The pattern as if nothing were held: column 1 is column 0 turned by
                        // 90° (transitions are similarities).
                        let full = |e: &Expr, k: usize| if k == 0 { [e.m[0][0], e.m[1][0]] } else { perp2([e.m[0][0], e.m[1][0]]) };
                        let keep = turns.is_some() && (general || row == col || overlaps(full(x, i), full(y, j)));
                        term(row, col, sx * sy * w[k] * (xi[0] * yj[0] + xi[1] * yj[1]), keep);
                    }
                }
            }
        }
    }
}

impl System {
    /// The unknowns of the refined mesh with `aligned[c]` telling which curves are aligned;
    /// `general[f]` tells whether face f's chart is a general quadrilateral.
    pub fn new(cut: &CutMesh, general: Vec<bool>, aligned: &[bool]) -> System {
        let (vars, n) = unknowns(cut, aligned, 0.0);
        System { vars, n_unknowns: n, general, solver: None, pattern: Pattern::default(), times: StageTimes::default() }
    }

    pub fn n_unknowns(&self) -> usize {
        self.n_unknowns
    }

    /// Values in the Cholesky factor (0 before the first solve).
    pub fn factor_nnz(&self) -> usize {
        self.solver.as_ref().map_or(0, SpdSolver::factor_nnz)
    }

    /// The first solve's assembly: every candidate entry, the pattern kept, the symbolic
    /// and numeric factorization.
    fn first_solve(&mut self, a: &Assembly, rhs: &mut [f64], t0: f64) -> Result<(), ParamError> {
        let Assembly { cut, exprs, weights, held, pins } = *a;
        // Afresh: a first solve whose factorization failed left a partial pattern.
        self.pattern = Pattern::default();
        let p = &mut self.pattern;
        // At most 30 candidates per varying triangle (3 edges, 2 vertices, 2 unknowns each,
        // lower half), for a quarter of the triangles (a tenth on bunny-ears); reserved up
        // front, as growing these arrays costs as much as filling them.
        let n = exprs.len();
        p.keep.reserve(30 * n / 4);
        p.candidate_start.reserve(n + 1);
        p.value_start.reserve(n + 1);
        // The diagonal first, one entry per unknown (slot i is unknown i's diagonal), summed
        // here: two thirds of all terms are diagonal, and the solver's pattern analysis
        // sorts every entry it is given.
        let unknowns = self.n_unknowns as u32;
        let mut entries: Vec<(u32, u32)> = Vec::with_capacity(8 * n + unknowns as usize);
        entries.extend((0..unknowns).map(|i| (i, i)));
        let mut values = vec![0.0; unknowns as usize];
        values.reserve(8 * n);
        let mut constant_diagonal = vec![0.0; unknowns as usize];
        for (t, ex) in exprs.iter().enumerate() {
            p.candidate_start.push(p.keep.len() as u32);
            p.value_start.push(values.len() as u32);
            let interior = cut.triangles[t].iter().all(|&v| {
                let v = v as usize;
                matches!(self.vars[v], Var::Free(_)) && cut.vertex_curve[v] == NONE
            });
            if interior {
                // Every vertex its own unknowns (`m = I`, `b = 0`): each edge couples u with u
                // and v with v only and adds nothing to the right-hand side. Written out, nine
                // triangles in ten skip the general terms' products and pattern tests; later
                // solves never visit them, so they have no candidates.
                let index = ex.map(|e| e.index());
                for k in 0..3 {
                    let (a, b, w) = (index[(k + 1) % 3], index[(k + 2) % 3], weights[t][k]);
                    for c in 0..2 {
                        for d in [a + c, b + c] {
                            values[d as usize] += w;
                            constant_diagonal[d as usize] += w;
                        }
                        entries.push((a.max(b) + c, a.min(b) + c));
                        values.push(-w);
                    }
                }
                continue;
            }
            p.varying.push(t as u32);
            let turns = may_turn(cut, &self.general, t);
            triangle_terms(ex, &weights[t], Some(turns), rhs, |row, col, value, keep| {
                let diagonal = row == col;
                p.keep.push(keep && !diagonal);
                if diagonal {
                    values[row as usize] += value;
                } else if keep {
                    entries.push((row, col));
                    values.push(value);
                }
            });
        }
        p.candidate_start.push(p.keep.len() as u32);
        p.value_start.push(values.len() as u32);
        for (_, i) in self.released(cut) {
            entries.push((i, i));
        }
        values.extend(self.held_values(cut, held));
        // Slot i is unknown i's diagonal.
        for &(i, share) in pins {
            let w = PIN * values[i as usize];
            values[i as usize] += w;
            rhs[i as usize] += w * share;
        }
        let t1 = now();
        self.times.assembly += t1 - t0;
        let mut solver = SpdSolver::new(self.n_unknowns, &entries)?;
        let p = &mut self.pattern;
        p.slot = solver.slots().to_vec();
        p.constant = vec![0.0; p.slot.iter().map(|&s| s as usize + 1).max().unwrap_or(0)];
        for (i, &value) in constant_diagonal.iter().enumerate() {
            p.constant[p.slot[i] as usize] += value;
        }
        let mut varying = p.varying.iter().peekable();
        for t in 0..exprs.len() {
            if varying.next_if(|&&v| v as usize == t).is_some() {
                continue;
            }
            for k in p.value_start[t] as usize..p.value_start[t + 1] as usize {
                p.constant[p.slot[k] as usize] += values[k];
            }
        }
        let t2 = now();
        self.times.symbolic += t2 - t1;
        solver.factor(&values)?;
        self.solver = Some(solver);
        self.times.factor += now() - t2;
        self.times.factorizations += 1;
        Ok(())
    }

    /// A later solve's assembly: the constant sums plus the varying triangles, then the
    /// numeric factorization.
    fn later_solve(&mut self, a: &Assembly, rhs: &mut [f64], t0: f64) -> Result<(), ParamError> {
        let Assembly { cut, exprs, weights, held, pins } = *a;
        let p = &self.pattern;
        let mut stored = p.constant.clone();
        for (&t, ex) in p.varying.iter().zip(exprs) {
            let t = t as usize;
            let (mut candidate, mut at) = (p.candidate_start[t] as usize, p.value_start[t] as usize);
            triangle_terms(ex, &weights[t], None, rhs, |row, col, value, _| {
                if row == col {
                    stored[p.slot[row as usize] as usize] += value;
                } else if p.keep[candidate] {
                    stored[p.slot[at] as usize] += value;
                    at += 1;
                }
                candidate += 1;
            });
        }
        let first_held = *p.value_start.last().unwrap_or(&0) as usize;
        for (k, value) in self.held_values(cut, held).enumerate() {
            stored[p.slot[first_held + k] as usize] += value;
        }
        for &(i, share) in pins {
            let slot = p.slot[i as usize] as usize;
            let w = PIN * stored[slot];
            stored[slot] += w;
            rhs[i as usize] += w * share;
        }
        let t1 = now();
        self.times.assembly += t1 - t0;
        if let Some(solver) = self.solver.as_mut() {
            solver.factor_summed(&stored)?;
            self.times.factorizations += 1;
        }
        self.times.factor += now() - t1;
        Ok(())
    }

    /// A failed factorization's pivot named by the input mesh vertex whose unknown it is.
    fn pivot_vertex(&self, e: ParamError, cut: &CutMesh) -> ParamError {
        let ParamError::Solve(SolveError::NotPositiveDefinite { pivot }) = e else { return e };
        let owns = |var: &Var| match *var {
            Var::Free(i) => pivot == i as usize || pivot == i as usize + 1,
            Var::OnSide(i) => pivot == i as usize,
            Var::Fixed => false,
        };
        let vertex = self.vars.iter().position(owns).map_or(NONE, |v| input_vertex(cut, v as u32));
        ParamError::NotPositiveDefinite { pivot, vertex }
    }

    /// The curve vertices with an n unknown (those of released curves), with its index.
    fn released<'a>(&'a self, cut: &'a CutMesh) -> impl Iterator<Item = (usize, u32)> + 'a {
        self.vars.iter().enumerate().filter_map(|(v, var)| match var {
            Var::Free(i) if cut.vertex_curve[v] != NONE => Some((v, i + 1)),
            _ => None,
        })
    }

    /// The diagonal of each [`released`](Self::released) vertex's n unknown: 1 for a vertex
    /// held on its side (an identity row keeps n = 0), 0 otherwise.
    fn held_values<'a>(&'a self, cut: &'a CutMesh, held: &'a [bool]) -> impl Iterator<Item = f64> + 'a {
        self.released(cut).map(move |(v, _)| if held.get(v) == Some(&true) { 1.0 } else { 0.0 })
    }

    /// The unknowns of the curve vertices that `z` puts out of order along their chart side
    /// (at or behind an earlier one, or past an end, short of the least gap), each with the
    /// nearest share in order ([`nearest_in_order`]). Only curves whose vertices all lie on
    /// their side (aligned, or held as `held` tells) count.
    pub fn out_of_order(&self, cut: &CutMesh, held: &[bool], z: &[f64]) -> Vec<(u32, f64)> {
        let along = |v: u32| match self.vars[v as usize] {
            Var::OnSide(i) => Some(i),
            Var::Free(i) if held.get(v as usize) == Some(&true) => Some(i),
            _ => None,
        };
        let mut pins = Vec::new();
        for verts in &cut.curve_vertices {
            if verts.len() < 3 {
                continue;
            }
            let inner = &verts[1..verts.len() - 1];
            let Some(unknowns) = inner.iter().map(|&v| along(v)).collect::<Option<Vec<u32>>>() else { continue };
            let mut length: Vec<f64> = verts
                .windows(2)
                .map(|w| crate::geom::norm(crate::geom::sub(cut.positions[w[1] as usize], cut.positions[w[0] as usize])))
                .collect();
            let total: f64 = length.iter().sum();
            if total <= 0.0 {
                continue;
            }
            length.iter_mut().for_each(|l| *l /= total);
            let s: Vec<f64> = unknowns.iter().map(|&i| z[i as usize]).collect();
            if s.iter().any(|x| !x.is_finite()) {
                continue; // a failed solve: nothing to put in order
            }
            if let Some(fixed) = nearest_in_order(&s, &length) {
                pins.extend(unknowns.iter().zip(s.iter().zip(fixed)).filter(|(_, (a, b))| (*a - b).abs() > 1e-12).map(|(&i, (_, b))| (i, b)));
            }
        }
        pins
    }

    /// What a first [`System::solve`] meets before its factorization: the error of the first
    /// vertex that has no place in its triangle's chart (a mesh too coarse for the layout).
    ///
    /// # Errors
    /// [`ParamError::NodeNotOnFace`] or [`ParamError::NotNeighbours`], as the solve gives them.
    pub fn check(&self, cut: &CutMesh, frames: &ChartFrames) -> Result<(), ParamError> {
        let own = own_exprs(cut, &self.vars, frames, &[])?;
        (0..cut.triangles.len()).try_for_each(|t| triangle_exprs(cut, frames, &own, t).map(|_| ()))
    }

    /// Assembles and solves the system in the charts of `frames` (node positions and
    /// transitions), with the refined mesh's [`cotangent_halves`] as `weights`, holding the
    /// vertices `held` on their chart sides (see [`held_on_side`]; aligned curves' always
    /// are, and an empty `held` holds no others), and `pins` near their values.
    ///
    /// # Errors
    /// [`ParamError`]: a failed factorization, or a mesh too coarse for the layout.
    pub fn solve(&mut self, cut: &CutMesh, frames: &ChartFrames, weights: &[[f64; 3]], held: &[bool], pins: &[(u32, f64)]) -> Result<Solution, ParamError> {
        let t0 = now();
        let own = own_exprs(cut, &self.vars, frames, held)?;
        let exprs_of = |t: usize| triangle_exprs(cut, frames, &own, t);
        let first = self.solver.is_none();
        // Later solves need only the varying triangles' expressions: the others' vertices
        // are their own unknowns.
        let exprs = if first {
            (0..cut.triangles.len()).map(exprs_of).collect::<Result<Vec<_>, _>>()?
        } else {
            self.pattern.varying.iter().map(|&t| exprs_of(t as usize)).collect::<Result<Vec<_>, _>>()?
        };
        let mut rhs = vec![0.0; self.n_unknowns];
        let assembly = Assembly { cut, exprs: &exprs, weights, held, pins };
        let factored = if first {
            self.first_solve(&assembly, &mut rhs, t0)
        } else {
            self.later_solve(&assembly, &mut rhs, t0)
        };
        factored.map_err(|e| self.pivot_vertex(e, cut))?;
        let t3 = now();
        let mut z = rhs;
        if let Some(solver) = self.solver.as_ref() {
            solver.solve_in_place(&mut z)?;
        }
        self.times.solve += now() - t3;
        if first {
            return Ok(Solution { corner_uv: exprs.iter().map(|ex| ex.map(|e| e.eval(&z))).collect(), unknowns: z });
        }
        let mut varying = self.pattern.varying.iter().zip(&exprs).peekable();
        let corner_uv = cut
            .triangles
            .iter()
            .enumerate()
            .map(|(t, tri)| match varying.next_if(|(&v, _)| v as usize == t) {
                Some((_, ex)) => ex.map(|e| e.eval(&z)),
                None => tri.map(|v| own[v as usize].map_or([0.0, 0.0], |e| e.eval(&z))),
            })
            .collect();
        Ok(Solution { corner_uv, unknowns: z })
    }
}
