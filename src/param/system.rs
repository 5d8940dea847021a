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
//! # Why symmetric: measured against eq. 3 as written
//!
//! [`super::eq3`] assembles eq. 3 itself on the same refined mesh and unknowns (normalized
//! cotangent rows, neighbours brought in by the transitions, the rows of aligned vertices
//! projected onto their side) and solves it by sparse LU; `ParamOptions::formulation` runs a
//! whole session with it. `cargo test --test param_formulations -- --nocapture` (default
//! options; mean of eq. 7 / flipped triangles; "loop": after the last chart iteration, every
//! edge aligned; "final": the user's tags, released curves without anchoring; seconds per
//! run, chart optimization included):
//!
//! | case          | it. | loop: symmetric | loop: eq. 3  | final: symmetric | final: eq. 3 | s, sym / eq. 3 |
//! |---------------|-----|-----------------|--------------|------------------|--------------|----------------|
//! | planar-quad   |  3  | 8.970e-2 / 0    | 8.970e-2 / 0 | 8.970e-2 / 0     | 8.970e-2 / 0 | 0.01 / 0.03    |
//! | planar-quad   | 30  | 2.6e-24 / 0     | 2.8e-24 / 0  | 2.6e-24 / 0      | 2.8e-24 / 0  | 0.05 / 0.15    |
//! | planar-2x2    |  3  | 3.604e-3 / 0    | 3.720e-3 / 0 | 3.764e-3 / 0     | 3.893e-3 / 0 | 0.01 / 0.02    |
//! | planar-2x2    | 30  | 9.1e-23 / 0     | 2.8e-19 / 0  | 9.1e-23 / 0      | 2.8e-19 / 0  | 0.07 / 0.17    |
//! | sheared-cube  |  3  | 2.661e-3 / 0    | 2.655e-3 / 0 | 2.608e-3 / 0     | 2.600e-3 / 0 | 0.01 / 0.05    |
//! | sheared-cube  | 30  | 1.1e-24 / 0     | 3.4e-25 / 0  | 1.1e-24 / 0      | 3.5e-25 / 0  | 0.11 / 0.35    |
//! | mushroom-4    |  3  | 1.158 / 0       | 1.158 / 0    | 1.158 / 0        | 1.158 / 0    | 0.10 / 0.35    |
//! | mushroom-grid |  3  | 0.8956 / 0      | 0.8957 / 0   | 0.8956 / 0       | 0.8957 / 0   | 0.11 / 0.38    |
//! | mushroom-t    |  3  | 0.6961 / 0      | 0.7031 / 4   | 0.7447 / 10      | 0.7217 / 8   | 0.11 / 0.44    |
//! | eight-rims    |  3  | 0.2125 / 1      | 0.2148 / 1   | 0.1824 / 2       | 0.1830 / 2   | 0.01 / 0.04    |
//! | fandisk-cube  |  3  | 0.3098 / 0      | 0.3239 / 7   | 0.3098 / 0       | 0.3239 / 7   | 0.44 / 1.15    |
//! | bunny-cube    |  3  | 0.5317 / 0      | 0.5288 / 0   | 0.4902 / 0       | 0.4899 / 3   | 1.77 / 7.87    |
//!
//! After 20 iterations the known answers are at 1.9e-8 (planar quad, both), 1.6e-13 / 5.2e-14
//! (2×2) and 8.0e-20 / 1.6e-18 (cube): both formulations reach the isometries, and below 1e-9
//! their ratio is rounding noise. We keep the symmetric system because
//! - where the transitions are rigid (one chart; unit charts without T-vertices) both are the
//!   same harmonic map: iteration 0 and the single-patch runs agree to the printed digits
//!   (down to rounding, 1e-24);
//! - where they scale, the chart loop ends within 1 % of eq. 3 on every case, equal or lower
//!   on five of the six samples (fandisk 4.4 %, eight-rims 1.1 %, mushroom-t 1.0 % lower),
//!   0.55 % higher on bunny-cube; and
//!   it flips no more triangles (eq. 3: 27 flipped on mushroom-t at iteration 0, whose
//!   T-vertex pieces scale even between unit charts, 7 on fandisk after the loop);
//! - solved once with the same charts the two differ by at most 1.2 % (fandisk 0.3098 vs
//!   0.3082, bunny 0.5317 vs 0.5285, eight-rims 0.2125 vs 0.2150): the formulation matters
//!   less than where the chart loop leads;
//! - it is symmetric positive definite: Cholesky with the symbolic factorization kept across
//!   solves, 2–5× faster per run than eq. 3's LU (symbolic analysis redone per solve).
//!
//! The exception is the final solve of mushroom-t, which releases its untagged curves: there
//! the symmetric map ends 3.2 % above eq. 3, and both fold triangles (10 against 8).

use super::cut::CutMesh;
use super::transition::Affine;
use crate::mesh::geometry::{cross, dot, norm, sub};
use crate::clock::now;
use crate::mesh::NONE;
use crate::solve::{SolveError, SpdSolver};
use std::collections::HashMap;
use std::fmt;

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

/// Positions of the nodes in each face's chart (corners and T-vertices).
pub type NodePositions = Vec<HashMap<u32, [f64; 2]>>;

#[derive(Debug, Clone, PartialEq)]
pub enum ParamError {
    Solve(SolveError),
    /// A triangle touches a node that is not on its face (only on meshes too coarse for
    /// the layout).
    NodeNotOnFace { node: u32, face: u32 },
    /// A triangle has a vertex from a face that is not its neighbour across a curve.
    NotNeighbours { vertex: u32, face: u32 },
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamError::Solve(e) => write!(f, "the global system could not be solved: {e}"),
            ParamError::NodeNotOnFace { node, face } => {
                write!(f, "a triangle of face {face} touches node {node}, which is not on that face; the mesh is too coarse there")
            }
            ParamError::NotNeighbours { vertex, face } => {
                write!(f, "a triangle of face {face} reaches vertex {vertex} of a face that is not its neighbour; the mesh is too coarse there")
            }
        }
    }
}

impl std::error::Error for ParamError {}

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

/// The unknowns of every vertex of the refined mesh and their count: nodes fixed, vertices
/// of aligned curves (and, with `anchor` > 0, that share of every other curve's vertices at
/// each end) one unknown along their chart side, every other vertex two in its face's chart.
pub(super) fn unknowns(cut: &CutMesh, aligned: &[bool], anchor: f64) -> (Vec<Var>, usize) {
    let mut anchored = vec![false; cut.positions.len()];
    for verts in &cut.curve_vertices {
        let k = (verts.len() as f64 * anchor).ceil() as usize;
        for &v in verts.iter().take(k).chain(verts.iter().rev().take(k)) {
            anchored[v as usize] = true;
        }
    }
    let mut used = vec![false; cut.positions.len()];
    for t in &cut.triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    let mut n = 0u32;
    let vars = (0..cut.positions.len())
        .map(|v| {
            if cut.vertex_node[v] != NONE || !used[v] || cut.vertex_face[v] == NONE {
                return Var::Fixed;
            }
            let c = cut.vertex_curve[v];
            if c != NONE && (aligned.get(c as usize).copied().unwrap_or(false) || anchored[v]) {
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

/// Half the cotangent of each triangle corner: the Dirichlet energy of a linear map on a
/// triangle is Σ_k w_k |u_{k+1} − u_{k+2}|² with w_k = cot θ_k / 2 (eq. 2's weights).
pub fn cotangent_halves(cut: &CutMesh) -> Vec<[f64; 3]> {
    cut.triangles
        .iter()
        .map(|t| {
            let p = t.map(|v| cut.positions[v as usize]);
            std::array::from_fn(|k| {
                let (u, w) = (sub(p[(k + 1) % 3], p[k]), sub(p[(k + 2) % 3], p[k]));
                0.5 * dot(u, w) / norm(cross(u, w)).max(f64::MIN_POSITIVE)
            })
        })
        .collect()
}

/// Seconds spent in each stage of the solves so far (for benchmarks).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct StageTimes {
    pub assembly: f64,
    pub symbolic: f64,
    pub factor: f64,
    pub solve: f64,
    pub chart_optimization: f64,
}

/// The system for one set of aligned curves: its unknowns and a factorization whose
/// symbolic part is kept across solves (only the charts, hence the values, change).
pub struct System {
    vars: Vec<Var>,
    n_unknowns: usize,
    solver: Option<SpdSolver>,
    /// Lower-triangle entries in assembly order (fixed by the unknowns and the triangles).
    entries: Vec<(u32, u32)>,
    pub times: StageTimes,
}

/// Per-triangle chart coordinates of a solve, and per-vertex coordinates in their own chart.
#[derive(Debug, Clone)]
pub struct Solution {
    /// `corner_uv[t][k]`: vertex k of triangle t in the chart of the triangle's face.
    pub corner_uv: Vec<[[f64; 2]; 3]>,
}

impl System {
    /// Unknowns for the refined mesh with `aligned[c]` telling which curves are aligned.
    ///
    /// `anchor` (0 to 1/2) keeps that share of the vertices at each end of a curve that is
    /// not aligned on the chart side, so the curve leaves its node in the side's direction
    /// (see `ParamSession::finish`: released curves can fold thin corner sectors).
    pub fn new(cut: &CutMesh, aligned: &[bool], anchor: f64) -> System {
        let (vars, n) = unknowns(cut, aligned, anchor);
        System {
            vars,
            n_unknowns: n,
            solver: None,
            entries: Vec::new(),
            times: StageTimes::default(),
        }
    }

    /// For every unknown, a number for its vertex: the fill-reducing ordering is computed
    /// on the graph of vertices (see [`SpdSolver::with_groups`]).
    fn vertex_groups(&self) -> Vec<u32> {
        let mut group = vec![0u32; self.n_unknowns];
        let mut next = 0u32;
        for var in &self.vars {
            let (first, dims) = match *var {
                Var::Fixed => continue,
                Var::Free(i) => (i as usize, 2),
                Var::OnSide(i) => (i as usize, 1),
            };
            for g in &mut group[first..first + dims] {
                *g = next;
            }
            next += 1;
        }
        group
    }

    pub fn n_unknowns(&self) -> usize {
        self.n_unknowns
    }

    /// The chart position of vertex `v` of a triangle in face `face`, as an expression.
    fn expr(
        &self,
        cut: &CutMesh,
        v: u32,
        face: u32,
        nodes: &NodePositions,
        sides: &[[u32; 2]],
        transitions: &[Affine],
    ) -> Result<Expr, ParamError> {
        let vi = v as usize;
        let node = cut.vertex_node[vi];
        if node != NONE {
            let p = nodes[face as usize].get(&node).ok_or(ParamError::NodeNotOnFace { node, face })?;
            return Ok(Expr { var: Var::Fixed, m: [[0.0; 2]; 2], b: *p });
        }
        let own = cut.vertex_face[vi];
        let var = self.vars[vi];
        let base = match var {
            Var::OnSide(_) => {
                let c = cut.vertex_curve[vi] as usize;
                let ends = [cut.curve_vertices[c][0], *cut.curve_vertices[c].last().unwrap_or(&v)];
                let [p, q] = ends.map(|e| nodes[own as usize].get(&cut.vertex_node[e as usize]).copied());
                let (Some(p), Some(q)) = (p, q) else {
                    return Err(ParamError::NodeNotOnFace { node: cut.vertex_node[ends[0] as usize], face: own });
                };
                Expr { var, m: [[q[0] - p[0], 0.0], [q[1] - p[1], 0.0]], b: p }
            }
            _ => Expr { var, m: [[1.0, 0.0], [0.0, 1.0]], b: [0.0, 0.0] },
        };
        if own == face {
            return Ok(base);
        }
        let c = cut.vertex_curve[vi];
        if c != NONE && sides[c as usize] == [own, face] {
            return Ok(base.transformed(&transitions[c as usize]));
        }
        Err(ParamError::NotNeighbours { vertex: v, face })
    }

    /// Assembles and solves the system for the given node positions and transitions
    /// (`transitions[c]` maps the chart left of curve c to the chart on its right), with the
    /// refined mesh's [`cotangent_halves`] as `weights`.
    ///
    /// # Errors
    /// [`ParamError`]: a failed factorization, or a mesh too coarse for the layout.
    pub fn solve(
        &mut self,
        cut: &CutMesh,
        nodes: &NodePositions,
        sides: &[[u32; 2]],
        transitions: &[Affine],
        weights: &[[f64; 3]],
    ) -> Result<Solution, ParamError> {
        let t0 = now();
        let mut exprs = Vec::with_capacity(cut.triangles.len());
        for (t, tri) in cut.triangles.iter().enumerate() {
            let face = cut.triangle_face[t];
            let e: Result<Vec<Expr>, ParamError> =
                tri.iter().map(|&v| self.expr(cut, v, face, nodes, sides, transitions)).collect();
            let e = e?;
            exprs.push([e[0], e[1], e[2]]);
        }
        let record_pattern = self.solver.is_none();
        let mut entries: Vec<(u32, u32)> = Vec::new();
        let mut values: Vec<f64> = Vec::with_capacity(self.entries.len());
        let mut rhs = vec![0.0; self.n_unknowns];
        for (t, ex) in exprs.iter().enumerate() {
            for k in 0..3 {
                // Edge between corners a and b, opposite corner k.
                let (a, b) = (&ex[(k + 1) % 3], &ex[(k + 2) % 3]);
                let w = weights[t][k];
                let d = [a.b[0] - b.b[0], a.b[1] - b.b[1]];
                // Term w |M_a z_a − M_b z_b + d|²: gradient rows M_aᵀ(...) and −M_bᵀ(...).
                for (x, sx) in [(a, 1.0), (b, -1.0)] {
                    for i in 0..x.dims() {
                        let row = x.index() + i as u32;
                        let mt_d = x.m[0][i] * d[0] + x.m[1][i] * d[1];
                        rhs[row as usize] -= sx * w * mt_d;
                        for (y, sy) in [(a, 1.0), (b, -1.0)] {
                            for j in 0..y.dims() {
                                let col = y.index() + j as u32;
                                if col > row {
                                    continue;
                                }
                                let v = sx * sy * w * (x.m[0][i] * y.m[0][j] + x.m[1][i] * y.m[1][j]);
                                if record_pattern {
                                    entries.push((row, col));
                                }
                                values.push(v);
                            }
                        }
                    }
                }
            }
        }
        let t1 = now();
        self.times.assembly += t1 - t0;
        if record_pattern && self.n_unknowns > 0 {
            self.solver = Some(SpdSolver::with_groups(self.n_unknowns, &entries, &self.vertex_groups())?);
            self.entries = entries;
        }
        let t2 = now();
        self.times.symbolic += t2 - t1;
        let mut z = rhs;
        if self.n_unknowns > 0 {
            let solver = self.solver.as_mut().ok_or(ParamError::Solve(SolveError::NotPositiveDefinite))?;
            solver.factor(&values)?;
            let t3 = now();
            self.times.factor += t3 - t2;
            solver.solve_in_place(&mut z)?;
            self.times.solve += now() - t3;
        }
        let corner_uv = exprs.iter().map(|ex| ex.map(|e| e.eval(&z))).collect();
        Ok(Solution { corner_uv })
    }
}
