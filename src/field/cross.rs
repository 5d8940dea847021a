//! The smoothest 4-direction (cross) field: Knöppel, Crane, Pinkall, Schröder 2013,
//! *Globally Optimal Direction Fields* (method-notes §11).
//!
//! A cross at vertex `i` is the complex number `z_i = e^{4iθ_i}` in the vertex's tangent frame
//! ([`Frames`]), so the four directions of a cross are one value. Smoothness is the energy
//! `Σ_ij w_ij |z_j − r_ij z_i|²` with cotangent weights `w_ij` and the transport
//! `r_ij = e^{4iρ_ij}`: a Hermitian connection Laplacian `A`. With the lumped mass matrix `M`
//! and a guide `q` (principal curvature, [`super::curvature`]) the field solves
//! `(A + εM) z = εM q`; feature and boundary vertices are fixed to their line's direction
//! (Dirichlet rows moved to the right-hand side). Written over real and imaginary parts the
//! Hermitian system is real, symmetric positive definite, of size 2n: one sparse Cholesky
//! ([`SpdSolver`]). Where nothing guides or fixes the field (a sphere), the start is the
//! smoothest field, the lowest eigenvector of `(A, M)`, by inverse iteration.
//! A few rounds then solve again with the normalized field added to the guide, which makes the
//! field of unit crosses smooth where the guide is weak (Viertel and Osting 2019's
//! diffusion-and-normalize scheme).

use super::frames::Frames;
use super::Complex;
use crate::mesh::geometry::{cotangent_weights, vertex_areas};
use crate::mesh::{Mesh, NONE};
use crate::solve::{SolveError, SpdSolver};

/// Alignment length as a fraction of the bounding-box diagonal: the guide steers the field
/// over about this distance (`ε = 1 / (ALIGN_LENGTH · diagonal)²`).
const ALIGN_LENGTH: f64 = 0.08;
/// Inverse-iteration steps for an unguided field.
const EIGEN_STEPS: usize = 12;
/// Diffuse-and-normalize rounds after the first solve.
const ROUNDS: usize = 3;

/// The smallest positive cotangent weight used: negative weights (obtuse triangles) would
/// make the connection Laplacian indefinite.
pub(super) const MIN_WEIGHT: f64 = 1e-6;

/// The cross field, one unit complex number `e^{4iθ}` per vertex (zero for isolated vertices).
///
/// `fixed[v]`: a vertex whose cross is given (unit modulus).
///
/// # Errors
/// [`SolveError`] if the sparse factorization fails (a degenerate mesh).
pub fn cross_field(
    mesh: &Mesh,
    frames: &Frames,
    guide: &[Complex],
    fixed: &[Option<Complex>],
    diagonal: f64,
) -> Result<Vec<Complex>, SolveError> {
    let nv = mesh.n_vertices();
    let mut index = vec![NONE; nv];
    let mut n = 0usize;
    for v in 0..nv {
        if !mesh.is_isolated(v as u32) && fixed[v].is_none() {
            index[v] = n as u32;
            n += 1;
        }
    }
    let mass = vertex_areas(mesh);
    let weights = cotangent_weights(mesh);
    let eps = 1.0 / (ALIGN_LENGTH * diagonal).powi(2);

    // Entries of the lower triangle and the right-hand side of the fixed vertices.
    let mut entries: Vec<(u32, u32)> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    let mut diag = vec![0.0; n];
    let mut fixed_rhs = vec![0.0; 2 * n];
    for e in 0..mesh.n_edges() as u32 {
        let h = 2 * e;
        let (i, j) = (mesh.from_vertex(h), mesh.to_vertex(h));
        let w = weights[e as usize].max(MIN_WEIGHT);
        let r = Complex::polar(1.0, 4.0 * frames.transport(mesh, h));
        // Row j, column i of A: −w r (and its conjugate at row i, column j).
        let c = r * -w;
        let (ii, jj) = (index[i as usize], index[j as usize]);
        if ii != NONE {
            diag[ii as usize] += w;
        }
        if jj != NONE {
            diag[jj as usize] += w;
        }
        match (ii != NONE, jj != NONE) {
            (true, true) => {
                // Store the block of the larger row index.
                let (row, col, c) = if jj > ii { (jj, ii, c) } else { (ii, jj, c.conj()) };
                let (r0, c0) = (2 * row, 2 * col);
                entries.extend([(r0, c0), (r0, c0 + 1), (r0 + 1, c0), (r0 + 1, c0 + 1)]);
                values.extend([c.re, -c.im, c.im, c.re]);
            }
            (false, true) => {
                if let Some(zi) = fixed[i as usize] {
                    let t = c * zi;
                    fixed_rhs[2 * jj as usize] -= t.re;
                    fixed_rhs[2 * jj as usize + 1] -= t.im;
                }
            }
            (true, false) => {
                if let Some(zj) = fixed[j as usize] {
                    let t = c.conj() * zj;
                    fixed_rhs[2 * ii as usize] -= t.re;
                    fixed_rhs[2 * ii as usize + 1] -= t.im;
                }
            }
            (false, false) => {}
        }
    }
    let free: Vec<usize> = (0..nv).filter(|&v| index[v] != NONE).collect();
    let factor_with = |shift: f64| -> Result<SpdSolver, SolveError> {
        let mut ent = entries.clone();
        let mut val = values.clone();
        for (k, &v) in free.iter().enumerate() {
            let d = diag[k] + shift * mass[v];
            ent.extend([(2 * k as u32, 2 * k as u32), (2 * k as u32 + 1, 2 * k as u32 + 1)]);
            val.extend([d, d]);
        }
        let mut s = SpdSolver::new(2 * n, &ent)?;
        s.factor(&val)?;
        Ok(s)
    };

    let mut z: Vec<Complex> = (0..nv).map(|v| fixed[v].unwrap_or(Complex::ZERO)).collect();
    if n == 0 {
        return Ok(z);
    }
    let solver = factor_with(eps)?;
    let solve = |target: &dyn Fn(usize) -> Complex, z: &mut Vec<Complex>| -> Result<(), SolveError> {
        let mut b = fixed_rhs.clone();
        for (k, &v) in free.iter().enumerate() {
            let t = target(v) * (eps * mass[v]);
            b[2 * k] += t.re;
            b[2 * k + 1] += t.im;
        }
        solver.solve_in_place(&mut b)?;
        for (k, &v) in free.iter().enumerate() {
            z[v] = Complex { re: b[2 * k], im: b[2 * k + 1] };
        }
        Ok(())
    };

    let guided: f64 = free.iter().map(|&v| guide[v].abs() * mass[v]).sum();
    let total: f64 = free.iter().map(|&v| mass[v]).sum();
    let unguided = fixed.iter().all(Option::is_none) && guided < 1e-3 * total;
    if unguided {
        // Inverse iteration from a fixed pseudo-random start: the smoothest field.
        let eigen = factor_with(1e-4 * eps)?;
        let mut b = vec![0.0; 2 * n];
        for (k, x) in b.iter_mut().enumerate() {
            let s = (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(17) ^ 0xD1B5_4A32_D192_ED03;
            *x = (s % 10_000) as f64 / 5_000.0 - 1.0;
        }
        for _ in 0..EIGEN_STEPS {
            for (k, &v) in free.iter().enumerate() {
                b[2 * k] *= mass[v];
                b[2 * k + 1] *= mass[v];
            }
            eigen.solve_in_place(&mut b)?;
            let norm = b.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-300);
            b.iter_mut().for_each(|x| *x /= norm);
        }
        for (k, &v) in free.iter().enumerate() {
            z[v] = Complex { re: b[2 * k], im: b[2 * k + 1] };
        }
    } else {
        solve(&|v| guide[v], &mut z)?;
    }
    for _ in 0..ROUNDS {
        let prev: Vec<Complex> = z.iter().map(|c| c.unit()).collect();
        solve(&|v| guide[v] + prev[v], &mut z)?;
    }
    Ok(z.into_iter().map(Complex::unit).collect())
}
