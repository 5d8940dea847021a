//! The paper's eq. 3 as written, solved by sparse LU: the reference the symmetric
//! formulation of [`system`](super::system) is measured against (method-notes §4).
//!
//! Same refined mesh ([`CutMesh`]) and same unknowns as [`System`](super::system::System):
//! a free vertex has two unknowns in the chart of its own face, nodes are fixed at their
//! chart positions, and a vertex of an aligned curve has one unknown `s`, its position
//! `p + s (q − p)` on the straight chart side (eq. 11 held exactly).
//!
//! Row of free vertex i, in its own chart α (eq. 3 with the weights of eq. 2):
//!
//! Σ_j w̄_ij (φ_{β→α}(u_j) − u_i) = 0,  w̄_ij = w_ij / Σ_k w_ik,  w_ij = ½ (cot α_ij + cot β_ij),
//!
//! the cotangent weight summing the half cotangents ([`cotangent_halves`]) of the corners
//! opposite edge ij in both its triangles. A vertex on a curve has triangles in the faces on
//! both sides: each triangle's vertices are taken in the chart of the triangle's face (the
//! vertex's own, or through the curve's transition) and brought back into α by the inverse
//! transition, so every neighbour enters through the chart it was computed in. The
//! transition's translation and the nodes' positions go to the right-hand side.
//!
//! A vertex of an aligned curve has one unknown but eq. 3 gives it two rows. Eq. 12 would
//! keep the constraint rows exact and solve these harmonic rows in the least-squares sense;
//! we take the practical equivalent the elimination allows: the row projected onto the
//! side's direction (its tangential component), one equation for one unknown, so the system
//! stays square.
//!
//! The blocks coupling i to j and j to i are w̄_ij L and w̄_ji L⁻¹ (L the transition's linear
//! part): the matrix is not symmetric and needs a sparse LU ([`solve_lu`]).
//!
//! [`cotangent_halves`]: super::system::cotangent_halves

use super::cut::CutMesh;
use super::frames::ChartFrames;
use super::system::{own_exprs, unknowns, Expr, ParamError, Solution, Var};
use crate::mesh::NONE;
use crate::solve::{solve_lu, SolveError};

/// Assembles eq. 3 in the charts of `frames` (`aligned[c]` tells whether curve c is aligned)
/// and solves it by sparse LU. The inputs are those of
/// [`System::solve`](super::system::System::solve) plus the alignment tags the `System`
/// keeps; `weights` are the refined mesh's [`cotangent_halves`](super::system::cotangent_halves).
///
/// # Errors
/// [`ParamError::Solve`] with [`SolveError::Singular`] if the matrix is singular (or a
/// transition is), or [`ParamError::NodeNotOnFace`] / [`ParamError::NotNeighbours`] on a
/// mesh too coarse for the layout.
pub fn solve_eq3(cut: &CutMesh, aligned: &[bool], frames: &ChartFrames, weights: &[[f64; 3]]) -> Result<Solution, ParamError> {
    let (vars, n) = unknowns(cut, aligned, 0.0);
    let own = own_exprs(cut, &vars, frames, &[])?;
    let own_of = |v: u32| own[v as usize].unwrap_or(Expr::fixed([0.0, 0.0]));
    let mut exprs = Vec::with_capacity(cut.triangles.len());
    for (t, tri) in cut.triangles.iter().enumerate() {
        let face = cut.triangle_face[t];
        let e = |k: usize| frames.vertex_expr(cut, &own, tri[k], face);
        exprs.push([e(0)?, e(1)?, e(2)?]);
    }
    // Σ_j w_ij per vertex, for the normalization of eq. 2.
    let mut total = vec![0.0; cut.positions.len()];
    for (tri, w) in cut.triangles.iter().zip(weights) {
        for k in 0..3 {
            total[tri[k] as usize] += w[(k + 1) % 3] + w[(k + 2) % 3];
        }
    }
    let mut entries: Vec<(u32, u32)> = Vec::with_capacity(14 * n);
    let mut values: Vec<f64> = Vec::with_capacity(14 * n);
    let mut rhs = vec![0.0; n];
    for (t, tri) in cut.triangles.iter().enumerate() {
        let face = cut.triangle_face[t];
        for k in 0..3 {
            let i = tri[k];
            let var = vars[i as usize];
            if var == Var::Fixed {
                continue;
            }
            // From this triangle's chart back into i's own chart α.
            let back = match frames.to_face(cut, i, face)? {
                None => None,
                Some(phi) => Some(phi.inverse().ok_or(ParamError::Solve(SolveError::Singular { column: None }))?),
            };
            let own_face = cut.vertex_face[i as usize];
            let ui = own_of(i);
            // Row projections: both coordinates of a free vertex, the side direction of an
            // aligned one.
            let (rows, proj): (usize, [[f64; 2]; 2]) = match var {
                Var::OnSide(_) => {
                    let d = [ui.m[0][0], ui.m[1][0]];
                    let len = d[0].hypot(d[1]).max(f64::MIN_POSITIVE);
                    (1, [[d[0] / len, d[1] / len], [0.0, 0.0]])
                }
                _ => (2, [[1.0, 0.0], [0.0, 1.0]]),
            };
            let sum = total[i as usize];
            let scale = if sum.abs() > f64::MIN_POSITIVE { 1.0 / sum } else { 1.0 };
            for (jk, w) in [((k + 1) % 3, weights[t][(k + 2) % 3]), ((k + 2) % 3, weights[t][(k + 1) % 3])] {
                let j = tri[jk];
                let uj = match back {
                    None => exprs[t][jk],
                    Some(back) => {
                        let node = cut.vertex_node[j as usize];
                        if node != NONE && frames.nodes[own_face as usize].contains_key(&node) {
                            Expr::fixed(frames.node(node, own_face)?)
                        } else if node == NONE && cut.vertex_face[j as usize] == own_face {
                            own_of(j)
                        } else {
                            exprs[t][jk].transformed(&back)
                        }
                    }
                };
                let c = w * scale;
                // c (u_j − u_i), row by row.
                for (x, sx) in [(&uj, c), (&ui, -c)] {
                    for (r, p) in proj.iter().enumerate().take(rows) {
                        let row = ui.index() + r as u32;
                        rhs[row as usize] -= sx * (p[0] * x.b[0] + p[1] * x.b[1]);
                        for col in 0..x.dims() {
                            entries.push((row, x.index() + col as u32));
                            values.push(sx * (p[0] * x.m[0][col] + p[1] * x.m[1][col]));
                        }
                    }
                }
            }
        }
    }
    let mut z = rhs;
    solve_lu(n, &entries, &values, &mut z)?;
    let corner_uv = exprs.iter().map(|ex| ex.map(|e| e.eval(&z))).collect();
    Ok(Solution { corner_uv, unknowns: Vec::new() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{build_layout, parse_layout};
    use crate::param::transition::Affine;
    use crate::mesh::primitives::quad_grid;
    use crate::param::{Formulation, ParamOptions, ParamSession};

    const Q: [[f64; 2]; 4] = [[0.0, 0.0], [2.0, 0.0], [2.4, 1.3], [0.3, 1.1]];

    /// A planar general quadrilateral sampled n×n, cut into 2×2 faces by curves that run
    /// across triangles (tests/param_known_answers.rs), every chart `chart`.
    fn two_by_two(chart: &str, align: bool) -> (crate::mesh::Mesh, crate::layout::SurfaceLayout) {
        let m = 16;
        let mesh = quad_grid(Q, m);
        let id = |i: u32, j: u32| j * (m + 1) + i;
        let h = m / 2;
        let nodes = [id(0, 0), id(m, 0), id(m, m), id(0, m), id(h + 1, 0), id(m, h - 1), id(h - 1, m), id(0, h + 1), id(h, h)];
        let nodes: Vec<String> = nodes.iter().map(|v| format!("{{\"vertex\":{v}}}")).collect();
        let edges: Vec<String> =
            [[8, 4], [8, 5], [8, 6], [8, 7]].iter().map(|e| format!("{{\"nodes\":[{},{}],\"align\":{align}}}", e[0], e[1])).collect();
        let text = format!(
            "{{\"format\":\"quad-layout\",\"version\":1,\"defaults\":{{\"chart\":\"{chart}\"}},\"nodes\":[{}],\"edges\":[{}]}}",
            nodes.join(","),
            edges.join(",")
        );
        let layout = build_layout(&mesh, &parse_layout(&text).unwrap()).unwrap();
        (mesh, layout)
    }

    fn session(formulation: Formulation, align: bool) -> ParamSession {
        let (mesh, layout) = two_by_two("quad", align);
        let options = ParamOptions { formulation, align, ..ParamOptions::default() };
        ParamSession::new(&mesh, &layout, &options).unwrap()
    }

    fn max_difference(a: &Solution, b: &Solution) -> f64 {
        let mut d = 0.0f64;
        for (x, y) in a.corner_uv.iter().zip(&b.corner_uv) {
            for k in 0..3 {
                d = d.max((x[k][0] - y[k][0]).abs()).max((x[k][1] - y[k][1]).abs());
            }
        }
        d
    }

    /// With unit charts every transition is rigid (L⁻¹ = Lᵀ): the rows of eq. 3 are then the
    /// gradient of the Dirichlet energy scaled per vertex, and the two formulations agree,
    /// for free curve vertices and for aligned ones (the tangential row is the derivative
    /// along the side).
    #[test]
    fn rigid_transitions_give_the_symmetric_solution() {
        for align in [false, true] {
            let mut sym = session(Formulation::Symmetric, align);
            let mut eq3 = session(Formulation::Eq3, align);
            let d0 = max_difference(sym.solution(), eq3.solution());
            assert!(d0 < 1e-9, "align {align}: initial solves differ by {d0:e}");
            // The final solve releases the user's untagged curves: free curve vertices.
            sym.finish().unwrap();
            eq3.finish().unwrap();
            let d1 = max_difference(sym.solution(), eq3.solution());
            assert!(d1 < 1e-9, "align {align}: final solves differ by {d1:e}");
        }
    }

    /// After a chart optimization the transitions scale; eq. 3's solution then satisfies
    /// eq. 3, recomputed here vertex by vertex from the solution's triangles (every row,
    /// including the tangential rows of aligned vertices), and differs from the symmetric one.
    #[test]
    fn the_solution_satisfies_eq3_with_scaling_transitions() {
        let mut eq3 = session(Formulation::Eq3, false);
        let mut sym = session(Formulation::Symmetric, false);
        eq3.step().unwrap();
        sym.step().unwrap();
        eq3.finish().unwrap();
        let ChartFrames { nodes, transitions, .. } = eq3.frames();
        let cut = eq3.cut();
        let scales: Vec<f64> =
            transitions.iter().map(|a| (a.m[0][0] * a.m[1][1] - a.m[0][1] * a.m[1][0]).abs()).collect();
        assert!(scales.iter().any(|s| (s - 1.0).abs() > 1e-3), "no scaling transition: {scales:?}");
        let weights = crate::param::system::cotangent_halves(cut);
        let sides: Vec<[u32; 2]> = (0..cut.curve_vertices.len())
            .map(|c| {
                let mut s = [NONE, NONE];
                for (t, tri) in cut.triangles.iter().enumerate() {
                    for &v in tri {
                        if cut.vertex_curve[v as usize] == c as u32 && cut.triangle_face[t] != cut.vertex_face[v as usize] {
                            s = [cut.vertex_face[v as usize], cut.triangle_face[t]];
                        }
                    }
                }
                s
            })
            .collect();
        let mut residual = vec![[0.0f64; 2]; cut.positions.len()];
        let mut total = vec![0.0; cut.positions.len()];
        let mut own_uv = vec![None; cut.positions.len()];
        for (t, tri) in cut.triangles.iter().enumerate() {
            if tri.iter().any(|&v| cut.vertex_face[v as usize] == cut.triangle_face[t]) {
                for (k, &v) in tri.iter().enumerate() {
                    if cut.vertex_face[v as usize] == cut.triangle_face[t] {
                        own_uv[v as usize] = Some(eq3.solution().corner_uv[t][k]);
                    }
                }
            }
        }
        for (t, tri) in cut.triangles.iter().enumerate() {
            let f = cut.triangle_face[t];
            for k in 0..3 {
                let i = tri[k] as usize;
                if cut.vertex_node[i] != NONE {
                    continue;
                }
                let own = cut.vertex_face[i];
                let back = if own == f {
                    Affine::IDENTITY
                } else {
                    let c = cut.vertex_curve[i] as usize;
                    assert_eq!(sides[c], [own, f]);
                    transitions[c].inverse().unwrap()
                };
                let uv = &eq3.solution().corner_uv[t];
                let ui = back.apply(uv[k]);
                for (jk, w) in [((k + 1) % 3, weights[t][(k + 2) % 3]), ((k + 2) % 3, weights[t][(k + 1) % 3])] {
                    let uj = back.apply(uv[jk]);
                    residual[i][0] += w * (uj[0] - ui[0]);
                    residual[i][1] += w * (uj[1] - ui[1]);
                    total[i] += w;
                }
            }
        }
        let mut worst = 0.0f64;
        let mut checked = 0;
        for v in 0..cut.positions.len() {
            if cut.vertex_node[v] != NONE || total[v] == 0.0 || own_uv[v].is_none() {
                continue;
            }
            let r = [residual[v][0] / total[v], residual[v][1] / total[v]];
            let c = cut.vertex_curve[v];
            let r = if c != NONE && sides[c as usize][1] == NONE {
                // Boundary pieces are aligned: the tangential component only.
                let ends = &cut.curve_vertices[c as usize];
                let f = cut.vertex_face[v] as usize;
                let [p, q] = [ends[0], ends[ends.len() - 1]].map(|e| nodes[f][&cut.vertex_node[e as usize]]);
                let d = [q[0] - p[0], q[1] - p[1]];
                ((r[0] * d[0] + r[1] * d[1]) / d[0].hypot(d[1])).abs()
            } else {
                r[0].hypot(r[1])
            };
            worst = worst.max(r);
            checked += 1;
        }
        assert!(checked > 200, "{checked} vertices checked");
        assert!(worst < 1e-10, "eq. 3 residual {worst:e}");
        sym.finish().unwrap();
        let d = max_difference(sym.solution(), eq3.solution());
        assert!(d > 1e-8, "the formulations should differ once transitions scale ({d:e})");
    }
}
