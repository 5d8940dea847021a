//! A small dense convex QP with lower bounds on linear forms and fixed variables, solved by
//! the dual active-set method of Goldfarb and Idnani ("A numerically stable dual method for
//! solving strictly convex quadratic programs", Math. Programming 27, 1983), the method of
//! R's `quadprog`:
//!
//! minimize ½ Σᵢ (aᵢ·z − dᵢ)²  subject to  aᵢ·z ≥ 1 for every row i, z_j = v_j when fixed.
//!
//! Why the dual method: it starts from the unconstrained minimum, needs no feasible point,
//! and proves infeasibility by itself (a violated constraint that no step can satisfy). Above
//! all, fixing one more variable is one more violated constraint, so the rounding in
//! [`super::bounded`] continues from the last solution instead of solving again.
//!
//! The state is the one of the paper: `J = L⁻ᵀ Q` and an upper triangular `R` with
//! `L⁻¹ N_A = Q [R; 0]`, where `H = L Lᵀ` is the objective's Hessian and `N_A` the normals of
//! the active constraints; adding or dropping a constraint is a few Givens rotations. Dense:
//! `z` has one entry per free piece of the layout (tens to a few hundred, about a thousand on
//! meshes with a hundred holes or handles), not one per piece.

use super::Row;

/// A constraint of the problem.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Constraint {
    /// `rows[i]·z ≥ 1`.
    Bound(usize),
    /// `sign · z_j ≥ sign · value`, held as an equality (never dropped); the sign makes the
    /// violated side the one added.
    Fix { j: usize, value: f64, sign: f64 },
}

/// A variable's fixing.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Fixing {
    Free,
    /// Fixed at this value, not (yet) among the active constraints: it holds without them or
    /// is violated and waits to be added.
    Pending(f64),
    /// Fixed at this value and active.
    Held(f64),
}

/// Violations below this are rounding noise (counts are tens, not millions).
const TOL: f64 = 1e-9;

/// The QP and the dual method's state; cloned for each pass of the rounding.
#[derive(Debug, Clone)]
pub(super) struct DualQp<'a> {
    /// Per piece, its count as a linear form in `z`.
    rows: &'a [Row],
    k: usize,
    /// `L⁻ᵀ Q`, `k × k`, column-major: column `c` at `j[c * k..]`. The method's hot loops
    /// run down columns: the Givens rotations of two columns, and the primal step (a sum of
    /// columns).
    j: Vec<f64>,
    /// `R`, row-major with rows `k` long: row `i` at `r[i * k..]`, column `c` (the `c`-th active
    /// constraint) at `r[i * k + c]`; rows `0..q` for `q` active constraints. Rows, because
    /// the back substitution and the rotations that drop a constraint run along them; entries
    /// below the first subdiagonal are never read.
    r: Vec<f64>,
    active: Vec<Constraint>,
    /// Lagrange multipliers of `active`.
    u: Vec<f64>,
    /// The current minimizer.
    pub z: Vec<f64>,
    fixed: Vec<Fixing>,
    /// Constraints added, so a degenerate problem cannot cycle forever.
    steps: usize,
}

/// Why the QP has no solution: the pieces whose bounds (with the fixed variables) conflict.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Conflict {
    pub pieces: Vec<u32>,
}

impl<'a> DualQp<'a> {
    /// The unconstrained minimum of `½ Σᵢ (rows[i]·z − d[i])²` over `z ∈ ℝᵏ`. `None` when
    /// that Hessian is not positive definite (it is when the rows span `ℝᵏ`).
    pub fn new(rows: &'a [Row], k: usize, desired: &[f64]) -> Option<DualQp<'a>> {
        let mut h = vec![0.0; k * k];
        let mut g = vec![0.0; k];
        for (row, &d) in rows.iter().zip(desired) {
            for &(a, x) in row {
                g[a] += d * x;
                for &(b, y) in row {
                    h[a * k + b] += x * y;
                }
            }
        }
        let j = if k > BLOCKED_FROM { blocked(&h, k)? } else { unblocked(h, k)? };
        let z = minimizer(&j, &g, k);
        Some(DualQp { rows, k, j, r: Vec::new(), active: Vec::new(), u: Vec::new(), z, fixed: vec![Fixing::Free; k], steps: 0 })
    }

    /// Holds `z_j` at `value` from now on and solves again.
    ///
    /// # Errors
    /// [`Conflict`] if no `z` meets the bounds with the variables fixed so far; the state is
    /// then spoilt (callers rebuild it).
    pub fn fix(&mut self, j: usize, value: f64) -> Result<(), Conflict> {
        self.fixed[j] = Fixing::Pending(value);
        self.solve()
    }

    /// Holds `z_j` at `value` from now on if it is there already (within the solve's
    /// tolerance): a solved state stays solved, and nothing else changes (as [`DualQp::fix`]
    /// would leave it). Returns whether it did.
    pub fn fix_where_it_is(&mut self, j: usize, value: f64) -> bool {
        let held = (self.z[j] - value).abs() <= TOL;
        if held {
            self.fixed[j] = Fixing::Pending(value);
        }
        held
    }

    pub fn is_fixed(&self, j: usize) -> bool {
        self.fixed[j] != Fixing::Free
    }

    /// Pieces whose bound is active (held at one).
    pub fn pieces_at_one(&self) -> Vec<u32> {
        self.active_bounds(None)
    }

    /// The pieces of the active bounds, those whose entry in `involved` is nonzero if given.
    fn active_bounds(&self, involved: Option<&[f64]>) -> Vec<u32> {
        let mut pieces: Vec<u32> = self
            .active
            .iter()
            .enumerate()
            .filter(|&(m, _)| involved.is_none_or(|r| r[m].abs() > 1e-12))
            .filter_map(|(_, a)| match a {
                Constraint::Bound(i) => Some(*i as u32),
                Constraint::Fix { .. } => None,
            })
            .collect();
        pieces.sort_unstable();
        pieces
    }

    /// Adds violated constraints, the most violated first, until none is left.
    ///
    /// # Errors
    /// [`Conflict`] if the constraints cannot all hold, or (not seen) if the step count runs
    /// out on a degenerate problem.
    pub fn solve(&mut self) -> Result<(), Conflict> {
        loop {
            let mut worst: Option<(Constraint, f64)> = None;
            let mut consider = |c: Constraint, s: f64| {
                if s < -TOL && worst.is_none_or(|(_, w)| s < w) {
                    worst = Some((c, s));
                }
            };
            for (i, row) in self.rows.iter().enumerate() {
                consider(Constraint::Bound(i), dot(row, &self.z) - 1.0);
            }
            for (j, fixed) in self.fixed.iter().enumerate() {
                if let Fixing::Pending(value) = *fixed {
                    let off = self.z[j] - value;
                    let sign = if off < 0.0 { 1.0 } else { -1.0 };
                    consider(Constraint::Fix { j, value, sign }, -off.abs());
                }
            }
            let Some((c, _)) = worst else { return Ok(()) };
            self.steps += 1;
            if self.steps > 20 * (self.rows.len() + self.k) + 100 {
                return Err(self.conflict(c, None));
            }
            self.add(c)?;
        }
    }

    /// `normal(c)·z − rhs(c)`: negative when `c` is violated.
    fn slack(&self, c: Constraint) -> f64 {
        match c {
            Constraint::Bound(i) => dot(&self.rows[i], &self.z) - 1.0,
            Constraint::Fix { j, value, sign } => sign * (self.z[j] - value),
        }
    }

    /// `Jᵀ n` for the normal `n` of `c`.
    fn jt_normal(&self, c: Constraint) -> Vec<f64> {
        let fix;
        let normal: &[(usize, f64)] = match c {
            Constraint::Bound(i) => &self.rows[i],
            Constraint::Fix { j, sign, .. } => {
                fix = [(j, sign)];
                &fix
            }
        };
        self.j
            .chunks_exact(self.k)
            .map(|column| normal.iter().fold(0.0, |d, &(a, x)| d + x * column[a]))
            .collect()
    }

    /// The bounds in conflict when `c` cannot be added: `c` and the active bounds that
    /// `involved` says take part (all of them when it is `None`).
    fn conflict(&self, c: Constraint, involved: Option<&[f64]>) -> Conflict {
        let mut pieces = self.active_bounds(involved);
        if let Constraint::Bound(i) = c {
            pieces.push(i as u32);
        }
        pieces.sort_unstable();
        pieces.dedup();
        Conflict { pieces }
    }

    /// One step of the dual method: makes the violated `c` hold and active, dropping active
    /// bounds whose multipliers reach zero on the way (Goldfarb–Idnani, steps 2a–2c).
    fn add(&mut self, c: Constraint) -> Result<(), Conflict> {
        let k = self.k;
        let mut u_c = 0.0;
        loop {
            let q = self.active.len();
            let d = self.jt_normal(c);
            // Primal direction J₂ d₂ and dual direction R⁻¹ d₁.
            let d2_sq: f64 = d[q..].iter().map(|x| x * x).sum();
            let d_sq: f64 = d.iter().map(|x| x * x).sum();
            let independent = d2_sq > 1e-20 * d_sq;
            let mut back = vec![0.0; q];
            for i in (0..q).rev() {
                let row = &self.r[i * k..i * k + q];
                let s = d[i] - dense_dot(&row[i + 1..], &back[i + 1..]);
                back[i] = s / self.r[i * k + i];
            }
            // Partial step: the largest dual step keeping the bounds' multipliers ≥ 0.
            let mut partial: Option<(usize, f64)> = None;
            for (i, (&ri, &ui)) in back.iter().zip(&self.u).enumerate() {
                if matches!(self.active[i], Constraint::Bound(_)) && ri > 1e-12 {
                    let t = ui / ri;
                    if partial.is_none_or(|(_, best)| t < best) {
                        partial = Some((i, t));
                    }
                }
            }
            // Full step: the primal step making `c` hold.
            let full = independent.then(|| -self.slack(c) / d2_sq);
            let t = match (partial, full) {
                // `c`'s normal is a combination of the active ones (coefficients `back`)
                // that no step of theirs can make hold: those with a share are the culprits.
                (None, None) => return Err(self.conflict(c, Some(&back))),
                (Some((_, t1)), Some(t2)) => t1.min(t2),
                (Some((_, t1)), None) => t1,
                (None, Some(t2)) => t2,
            };
            if full.is_some() {
                // J₂ d₂, column by column (each entry summed in the order of m, from −0 as
                // `Sum` does).
                let mut step = vec![-0.0; k];
                for (column, &dm) in self.j.chunks_exact(k).zip(&d).skip(q) {
                    for (s, &jm) in step.iter_mut().zip(column) {
                        *s += jm * dm;
                    }
                }
                for (z, s) in self.z.iter_mut().zip(&step) {
                    *z += t * s;
                }
            }
            for (ui, ri) in self.u.iter_mut().zip(&back) {
                *ui -= t * ri;
            }
            u_c += t;
            match partial {
                Some((l, t1)) if full.is_none_or(|t2| t1 < t2) => self.drop_active(l),
                _ => {
                    self.push_active(c, u_c, d);
                    return Ok(());
                }
            }
        }
    }

    /// Rotates `d = Jᵀ n` (and `J`'s columns with it) so that only `d[..=q]` is nonzero, and
    /// appends it to `R` as the new active constraint's column.
    fn push_active(&mut self, c: Constraint, multiplier: f64, mut d: Vec<f64>) {
        let (k, q) = (self.k, self.active.len());
        for m in (q + 1..k).rev() {
            if d[m] == 0.0 {
                continue;
            }
            let h = d[m - 1].hypot(d[m]);
            let (cos, sin) = (d[m - 1] / h, d[m] / h);
            d[m - 1] = h;
            d[m] = 0.0;
            self.rotate_j(m - 1, cos, sin);
        }
        // Column q: d's entries 0..=q (those below are zero and below the subdiagonal).
        self.r.resize((q + 1) * k, 0.0);
        for (i, &di) in d.iter().enumerate().take(q + 1) {
            self.r[i * k + q] = di;
        }
        if let Constraint::Fix { j, value, .. } = c {
            self.fixed[j] = Fixing::Held(value);
        }
        self.active.push(c);
        self.u.push(multiplier);
    }

    /// Removes the `l`-th active constraint and makes `R` triangular again.
    fn drop_active(&mut self, l: usize) {
        let (k, q) = (self.k, self.active.len());
        for i in 0..q {
            self.r.copy_within(i * k + l + 1..i * k + q, i * k + l);
        }
        self.active.remove(l);
        self.u.remove(l);
        // Columns l.. now have one entry below the diagonal: rotate rows (m, m + 1) away.
        for m in l..q - 1 {
            let (a, b) = (self.r[m * k + m], self.r[(m + 1) * k + m]);
            if b == 0.0 {
                continue;
            }
            let h = a.hypot(b);
            let (cos, sin) = (a / h, b / h);
            let (upper, lower) = self.r[m * k..(m + 2) * k].split_at_mut(k);
            rotate(&mut upper[m..q - 1], &mut lower[m..q - 1], cos, sin);
            self.rotate_j(m, cos, sin);
        }
        self.r.truncate((q - 1) * k);
    }

    /// Columns `m` and `m + 1` of `J` ← their rotation by (cos, sin).
    fn rotate_j(&mut self, m: usize, cos: f64, sin: f64) {
        let k = self.k;
        let (left, right) = self.j[m * k..(m + 2) * k].split_at_mut(k);
        rotate(left, right, cos, sin);
    }
}

/// `(a, b) ← (cos a + sin b, −sin a + cos b)` entry by entry: a Givens rotation of two rows of
/// `R` or two columns of `J`, each stored along memory.
fn rotate(a: &mut [f64], b: &mut [f64], cos: f64, sin: f64) {
    for (x, y) in a.iter_mut().zip(b) {
        (*x, *y) = (cos * *x + sin * *y, -sin * *x + cos * *y);
    }
}

/// `a · b` in four interleaved partial sums: one running sum waits on every addition before
/// the next, and the back substitution of the dual method (`q²/2` products for `q` active
/// constraints, each time a constraint is added) spent most of the rounding's time waiting.
fn dense_dot(a: &[f64], b: &[f64]) -> f64 {
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = a4.remainder().iter().zip(b4.remainder()).map(|(x, y)| x * y).sum();
    let mut sums = [0.0; 4];
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            sums[k] += x[k] * y[k];
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

fn dot(row: &Row, z: &[f64]) -> f64 {
    row.iter().map(|&(a, x)| x * z[a]).sum()
}

/// `z = H⁻¹ g = J Jᵀ g` with `J = L⁻ᵀ` (column-major, `k × k`): the unconstrained minimum.
fn minimizer(j: &[f64], g: &[f64], k: usize) -> Vec<f64> {
    let jt_g: Vec<f64> = (0..k).map(|c| (0..k).map(|i| j[c * k + i] * g[i]).sum()).collect();
    (0..k).map(|i| (0..k).map(|c| j[c * k + i] * jt_g[c]).sum()).collect()
}

/// Sizes of `z` from which [`DualQp::new`] factors with faer's blocked kernels: above it, its
/// own loops took 40 % of `quadlay layout` on CGAL's cheese (genus 133, about 1000 free pieces
/// a layout, each factorization k³). Below it, they stay: the blocked sums round otherwise,
/// and that moves counts that sit near a half (over 26 meshes, 10 layouts changed, no better
/// and no worse in all).
const BLOCKED_FROM: usize = 400;

/// `J = L⁻ᵀ` (column-major) with `H = L Lᵀ` (`h` row-major, `k × k`), by plain loops; `None`
/// if `H` is not positive definite.
fn unblocked(mut h: Vec<f64>, k: usize) -> Option<Vec<f64>> {
    // H = L Lᵀ, L lower triangular, in place.
    for c in 0..k {
        let diag = h[c * k + c] - (0..c).map(|m| h[c * k + m] * h[c * k + m]).sum::<f64>();
        if diag.is_nan() || diag <= 0.0 {
            return None;
        }
        let diag = diag.sqrt();
        h[c * k + c] = diag;
        for i in c + 1..k {
            let s = h[i * k + c] - (0..c).map(|m| h[i * k + m] * h[c * k + m]).sum::<f64>();
            h[i * k + c] = s / diag;
        }
    }
    // J = L⁻ᵀ: column c of L⁻¹ is L⁻¹ e_c, i.e. row c of J.
    let mut j = vec![0.0; k * k];
    for c in 0..k {
        for i in c..k {
            let s = if i == c { 1.0 } else { 0.0 } - (c..i).map(|m| h[i * k + m] * j[c * k + m]).sum::<f64>();
            j[c * k + i] = s / h[i * k + i];
        }
    }
    // Row-major so far; stored column-major.
    Some((0..k * k).map(|x| j[(x % k) * k + x / k]).collect())
}

/// [`unblocked`] with faer's dense Cholesky and triangular solve.
fn blocked(h: &[f64], k: usize) -> Option<Vec<f64>> {
    let h = faer::Mat::<f64>::from_fn(k, k, |a, b| h[a * k + b]);
    let llt = h.llt(faer::Side::Lower).ok()?;
    let mut inverse = faer::Mat::<f64>::identity(k, k);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(llt.L(), inverse.as_mut(), faer::Par::Seq);
    // Column c of J = L⁻ᵀ is row c of L⁻¹.
    let j: Vec<f64> = (0..k * k).map(|x| inverse[(x / k, x % k)]).collect();
    j.iter().all(|x| x.is_finite()).then_some(j)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both factorizations give the same `J` (to rounding) on a positive definite `H` (a
    /// chain: 3 on the diagonal, −1 beside it), `J Jᵀ = H⁻¹`, and both refuse one that is not.
    #[test]
    fn blocked_and_unblocked_factor_alike() {
        let k: usize = 60;
        let h: Vec<f64> = (0..k * k).map(|x| match (x / k).abs_diff(x % k) { 0 => 3.0, 1 => -1.0, _ => 0.0 }).collect();
        let g: Vec<f64> = (0..k).map(|i| (i % 7) as f64 - 2.0).collect();
        let j1 = unblocked(h.clone(), k).unwrap();
        let j2 = blocked(&h, k).unwrap();
        assert!(j1.iter().zip(&j2).all(|(a, b)| (a - b).abs() < 1e-12));
        // z = J Jᵀ g solves H z = g, from either.
        let (z1, z2) = (minimizer(&j1, &g, k), minimizer(&j2, &g, k));
        assert!(z1.iter().zip(&z2).all(|(a, b)| (a - b).abs() < 1e-12));
        for i in 0..k {
            let hz: f64 = (0..k).map(|c| h[i * k + c] * z2[c]).sum();
            assert!((hz - g[i]).abs() < 1e-10, "row {i}: {hz} against {}", g[i]);
        }
        let singular: Vec<f64> = (0..k * k).map(|x| if x / k == x % k && x / k != 5 { 1.0 } else { 0.0 }).collect();
        assert!(unblocked(singular.clone(), k).is_none() && blocked(&singular, k).is_none());
    }

    /// A QP larger than [`BLOCKED_FROM`] (one piece per coordinate, and one piece of two)
    /// goes through the blocked factorization and solves as a small one does.
    #[test]
    fn a_large_qp_solves_through_the_blocked_factorization() {
        let k = BLOCKED_FROM + 50;
        let mut rows: Vec<Row> = (0..k).map(|i| vec![(i, 1.0)]).collect();
        rows.push(vec![(0, 1.0), (1, -1.0)]);
        let mut desired: Vec<f64> = (0..k).map(|i| 2.0 + (i % 5) as f64).collect();
        desired[0] = 5.0;
        desired[1] = 1.0;
        desired.push(-3.0);
        let mut qp = DualQp::new(&rows, k, &desired).unwrap();
        qp.solve().unwrap();
        // As in `bounds_hold_and_the_rest_moves_to_the_optimum`: z0 − z1 held at one.
        assert!((qp.z[0] - 3.5).abs() < 1e-9 && (qp.z[1] - 2.5).abs() < 1e-9, "{:?}", &qp.z[..2]);
        assert!((2..k).all(|i| (qp.z[i] - desired[i]).abs() < 1e-9));
        assert_eq!(qp.pieces_at_one(), vec![k as u32]);
    }

    #[test]
    fn bounds_hold_and_the_rest_moves_to_the_optimum() {
        // Pieces z0, z1 and z0 − z1, desired 5, 1 and −3: the last is held at one.
        let rows: Vec<Row> = vec![vec![(0, 1.0)], vec![(1, 1.0)], vec![(0, 1.0), (1, -1.0)]];
        let mut qp = DualQp::new(&rows, 2, &[5.0, 1.0, -3.0]).unwrap();
        qp.solve().unwrap();
        // On z0 − z1 = 1: minimize (z0 − 5)² + (z0 − 2)²: z0 = 3.5, z1 = 2.5.
        assert!((qp.z[0] - 3.5).abs() < 1e-12 && (qp.z[1] - 2.5).abs() < 1e-12, "{:?}", qp.z);
        assert_eq!(qp.pieces_at_one(), vec![2]);
        // Fixing z1 = 3 moves z0 to the best value with z0 ≥ 4.
        qp.fix(1, 3.0).unwrap();
        assert!((qp.z[0] - 4.0).abs() < 1e-12 && (qp.z[1] - 3.0).abs() < 1e-12, "{:?}", qp.z);
    }

    #[test]
    fn a_multiplier_reaching_zero_frees_the_bound() {
        // Pieces z0 (wants 0), z1 − z0 (wants 1), z1 (wants 3): the optimum holds z0 at one.
        let rows: Vec<Row> = vec![vec![(0, 1.0)], vec![(0, -1.0), (1, 1.0)], vec![(1, 1.0)]];
        let mut qp = DualQp::new(&rows, 2, &[0.0, 1.0, 3.0]).unwrap();
        qp.solve().unwrap();
        assert_eq!(qp.pieces_at_one(), vec![0]);
        assert!((qp.z[0] - 1.0).abs() < 1e-12 && (qp.z[1] - 2.5).abs() < 1e-12, "{:?}", qp.z);
        // Fixing z1 = 6 pulls z0 up to 2.5 (z0 − (5 − z0) = 0): its bound is let go.
        let mut pulled = qp.clone();
        pulled.fix(1, 6.0).unwrap();
        assert!(pulled.pieces_at_one().is_empty());
        assert!((pulled.z[0] - 2.5).abs() < 1e-12 && (pulled.z[1] - 6.0).abs() < 1e-12, "{:?}", pulled.z);
        // Fixing z1 = 1 would need z0 ≤ 0 (piece 1) and z0 ≥ 1 (piece 0).
        assert_eq!(qp.fix(1, 1.0).unwrap_err().pieces, vec![0, 1]);
    }

    #[test]
    fn fixing_a_variable_where_it_is_leaves_the_state_a_fix_would() {
        // z0 ≥ 1 is active (wants −2), z1 is free at 3: fixing z1 at 3 changes nothing else.
        let rows: Vec<Row> = vec![vec![(0, 1.0)], vec![(1, 1.0)], vec![(0, 1.0), (1, 1.0)]];
        let mut qp = DualQp::new(&rows, 2, &[-2.0, 3.0, 4.0]).unwrap();
        qp.solve().unwrap();
        let mut solved = qp.clone();
        let z1 = qp.z[1];
        assert!(!qp.fix_where_it_is(1, z1.round() + 1.0), "{z1} is not one more than its integer");
        solved.fix(1, z1).unwrap();
        assert!(qp.fix_where_it_is(1, z1));
        assert_eq!((&qp.z, &qp.fixed, &qp.active, &qp.u, qp.steps), (&solved.z, &solved.fixed, &solved.active, &solved.u, solved.steps));
    }

    #[test]
    fn the_dense_dot_product_is_the_sum_of_products() {
        for n in 0..11 {
            let a: Vec<f64> = (0..n).map(|i| 1.0 + i as f64 * 0.5).collect();
            let b: Vec<f64> = (0..n).map(|i| 2.0 - i as f64 * 0.25).collect();
            let plain: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            assert!((dense_dot(&a, &b) - plain).abs() <= 1e-12 * (1.0 + plain.abs()), "{n}");
        }
    }

    #[test]
    fn conflicting_bounds_are_infeasible() {
        // Piece 0 is z0, piece 1 is −z0: both ≥ 1 cannot hold.
        let rows: Vec<Row> = vec![vec![(0, 1.0)], vec![(0, -1.0)]];
        let mut qp = DualQp::new(&rows, 1, &[3.0, 3.0]).unwrap();
        assert_eq!(qp.solve().unwrap_err().pieces, vec![0, 1]);
    }
}
