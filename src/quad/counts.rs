//! Sample counts per edge piece (paper Section 4; method-notes §8).
//!
//! Every layout curve (an edge piece between two nodes, T-vertices included) gets an
//! integer number of segments `n ≥ 1`. Per face, the pieces of opposite sides add up to
//! the same number, so the face's grid connects them: one linear equation `B n = 0` per
//! face and pair of opposite sides. We take the least-squares solution nearest the desired
//! counts under those equations (eq. 12 with A = I), then round as the paper does: Gaussian
//! elimination on `B` splits the pieces into free and dependent ones; the free ones are
//! rounded to the continuous solution and the dependent ones follow exactly.
//!
//! The paper goes on: when rounding makes a dependent piece fall below one segment, that
//! piece is fixed at one and everything is solved again. Here `bounded` takes over instead:
//! every sample layout rounds with no fix, and on the automatic layouts the fixes (13 to 25
//! a layout, an elimination each) all ended in a dead end.
//!
//! That fast path fails on layouts with many T-vertices that do have counts: the least
//! squares, blind to `n ≥ 1`, makes short pieces negative and the fixes cascade into a dead
//! end, or a pivot of two leaves a dependent count fractional. Then `bounded` solves the
//! problem with the bound from the start (a small QP over an integer basis of the solutions,
//! rounded one free piece at a time). The fast path's results are kept whenever it succeeds
//! without a fix, so every sample layout counts as before.
//!
//! When the equations cannot hold with every piece at one segment or more — a T-vertex
//! configuration that forces a piece to zero, say a side `a + b` opposite a side `c` while
//! another face forces `c = a` — there is no quad mesh of this layout:
//! [`CountError::Infeasible`] names pieces whose bounds conflict.

mod bounded;
mod dual_qp;

use crate::solve::SpdSolver;
use std::fmt;

/// One equation `Σ coefficient · n[curve] = 0`.
pub type Equation = Vec<(u32, i64)>;

/// Why no consistent sample counts exist.
#[derive(Debug, Clone, PartialEq)]
pub enum CountError {
    /// The equations admit no solution with each of these pieces at one segment or more:
    /// their bounds conflict, and none of them can be left out of the conflict (the dual
    /// certificate of the fallback's QP, see the module documentation). Should the rounding of a feasible problem run out of
    /// its budget instead (not seen), the pieces its continuous solution holds at one.
    Infeasible { pieces_at_one: Vec<u32> },
    /// The integer arithmetic on an equation of this piece overflowed, so its counts could not
    /// be made integers (not seen: the layouts' coefficients are ±1 and stay small).
    Fractional { piece: u32 },
    /// The sparse solver failed on the least-squares system (not seen: it is positive
    /// definite by construction).
    Solver(String),
}

impl fmt::Display for CountError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CountError::Infeasible { pieces_at_one } => write!(
                f,
                "opposite sides of the layout's faces cannot get equal numbers of segments with every edge piece \
                 getting at least one; pieces forced below one segment: {pieces_at_one:?}"
            ),
            CountError::Fractional { piece } => {
                write!(f, "the sample count of edge piece {piece} cannot be made an integer")
            }
            CountError::Solver(e) => write!(f, "the sample counts could not be computed: {e}"),
        }
    }
}

/// A sparse row: (column, coefficient), columns increasing, no exact zeros.
type Row = Vec<(usize, f64)>;

/// The counts' equations in reduced row echelon form: `n[pivot] + Σ r·n[free] = rhs`.
struct Echelon {
    /// Per independent equation: its pivot column, its coefficients, its right-hand side.
    rows: Vec<(usize, Row, f64)>,
    /// Columns without a pivot.
    free: Vec<usize>,
}

const EPS: f64 = 1e-9;

fn coefficient(row: &Row, col: usize) -> f64 {
    row.binary_search_by_key(&col, |e| e.0).map_or(0.0, |k| row[k].1)
}

/// `row - factor · pivot`, dropping entries that cancel exactly; the columns it has that `row`
/// had not are pushed to `gained`.
fn subtract(row: &Row, factor: f64, pivot: &Row, gained: &mut Vec<usize>) -> Row {
    let mut out = Vec::with_capacity(row.len() + pivot.len());
    let (mut i, mut j) = (0, 0);
    loop {
        let (c, v) = match (row.get(i), pivot.get(j)) {
            (None, None) => return out,
            (Some(&(a, x)), Some(&(b, y))) if a == b => {
                (i, j) = (i + 1, j + 1);
                (a, x - factor * y)
            }
            (Some(&(a, x)), Some(&(b, _))) if a < b => {
                i += 1;
                (a, x)
            }
            (Some(&(a, x)), None) => {
                i += 1;
                (a, x)
            }
            (_, Some(&(b, y))) => {
                j += 1;
                let v = -factor * y;
                if v != 0.0 {
                    gained.push(b);
                }
                (b, v)
            }
        };
        if v != 0.0 {
            out.push((c, v));
        }
    }
}

/// Takes `factor · pivot` (row `r`, unit in column `col`) from each row of `targets` whose
/// coefficient in `col` exceeds `tolerance`, filing the columns a row gains in `by_col`; the
/// rows changed and their factors, for the caller's right-hand side.
fn eliminate(
    rows: &mut [Row],
    by_col: &mut [Vec<usize>],
    targets: Vec<usize>,
    r: usize,
    col: usize,
    pivot: &Row,
    tolerance: f64,
) -> Vec<(usize, f64)> {
    let mut changed = Vec::new();
    let mut gained = Vec::new();
    for s in targets {
        let factor = coefficient(&rows[s], col);
        if s == r || factor.abs() <= tolerance {
            continue;
        }
        gained.clear();
        let updated = subtract(&rows[s], factor, pivot, &mut gained);
        for &c in &gained {
            by_col[c].push(s);
        }
        rows[s] = updated;
        changed.push((s, factor));
    }
    changed
}

/// Reduces `rows · x = rhs` over the columns in `active` (the rows hold no others; the
/// known counts are already on the right-hand side), sparsely: each equation touches the
/// few pieces of two sides of a face, so a layout of ten thousand faces stays small. Pivots
/// on entries ±1 where there are any, so integer equations keep integer coefficients; among
/// equal candidates the first in the current row order, as dense elimination with row swaps
/// does. `None` when the equations contradict each other.
fn echelon(mut rows: Vec<Row>, mut rhs: Vec<f64>, active: &[usize], n: usize) -> Option<Echelon> {
    // Rows by column, and the row order (rows are swapped, not moved).
    let mut by_col: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (r, row) in rows.iter().enumerate() {
        for &(c, _) in row {
            by_col[c].push(r);
        }
    }
    let mut order: Vec<usize> = (0..rows.len()).collect();
    let mut position: Vec<usize> = (0..rows.len()).collect();
    let mut rows_done = 0;
    let mut pivots = Vec::new();
    let mut free = Vec::new();
    for &col in active {
        // Rows whose entry in `col` vanished by cancellation are dropped from the list here.
        by_col[col].retain(|&r| coefficient(&rows[r], col) != 0.0);
        let key = |r: usize| {
            let a = coefficient(&rows[r], col).abs();
            ((a - 1.0).abs() > EPS, -a)
        };
        let best = by_col[col]
            .iter()
            .copied()
            .filter(|&r| position[r] >= rows_done && coefficient(&rows[r], col).abs() > EPS)
            .min_by(|&r, &s| key(r).partial_cmp(&key(s)).unwrap_or(std::cmp::Ordering::Equal).then(position[r].cmp(&position[s])));
        let Some(r) = best else {
            free.push(col);
            continue;
        };
        let other = order[rows_done];
        order.swap(rows_done, position[r]);
        position.swap(r, other);
        let p = coefficient(&rows[r], col);
        for e in rows[r].iter_mut() {
            e.1 /= p;
        }
        rhs[r] /= p;
        let pivot = std::mem::take(&mut rows[r]);
        let targets = by_col[col].clone();
        for (s, factor) in eliminate(&mut rows, &mut by_col, targets, r, col, &pivot, EPS) {
            rhs[s] -= factor * rhs[r];
        }
        rows[r] = pivot;
        pivots.push(col);
        rows_done += 1;
    }
    if order[rows_done..].iter().any(|&r| rhs[r].abs() > 1e-7) {
        return None;
    }
    let rows = pivots.into_iter().enumerate().map(|(k, col)| (col, std::mem::take(&mut rows[order[k]]), rhs[order[k]])).collect();
    Some(Echelon { rows, free })
}

/// The continuous counts nearest `desired` under the reduced equations, as values of the
/// free columns: minimize Σ_free (n − d)² + Σ_pivot (rhs − r·n_free − d_pivot)², through the
/// normal equations (I + RᵀR) n_free = d_free + Rᵀ (rhs − d_pivot), a sparse positive
/// definite system (each row of R couples the few free pieces of one equation).
///
/// # Errors
/// [`CountError::Solver`] if the sparse solver fails (it has no reason to: the matrix is
/// the identity plus a positive semidefinite one).
fn continuous_free(e: &Echelon, desired: &[f64], n: usize) -> Result<Vec<f64>, CountError> {
    let k = e.free.len();
    let mut index = vec![u32::MAX; n];
    for (i, &c) in e.free.iter().enumerate() {
        index[c] = i as u32;
    }
    let mut b: Vec<f64> = e.free.iter().map(|&c| desired[c]).collect();
    let mut entries: Vec<(u32, u32)> = (0..k as u32).map(|i| (i, i)).collect();
    let mut values = vec![1.0; k];
    for (pivot, coef, rhs) in &e.rows {
        let r: Vec<(u32, f64)> =
            coef.iter().filter(|&&(c, _)| index[c] != u32::MAX).map(|&(c, v)| (index[c], v)).collect();
        for &(i, ri) in &r {
            b[i as usize] += ri * (rhs - desired[*pivot]);
            for &(j, rj) in r.iter().filter(|&&(j, _)| j <= i) {
                entries.push((i, j));
                values.push(ri * rj);
            }
        }
    }
    let solver_error = |e: crate::solve::SolveError| CountError::Solver(e.to_string());
    let mut solver = SpdSolver::new(k, &entries).map_err(solver_error)?;
    solver.factor(&values).map_err(solver_error)?;
    solver.solve_in_place(&mut b).map_err(solver_error)?;
    Ok(b)
}

/// Integer sample counts, one per piece, each at least one, satisfying every equation,
/// near `desired` (paper Section 4). Desired counts below one (or not finite, which
/// callers refuse first: see [`super::check_edge_length`]) count as one.
///
/// # Errors
/// [`CountError`] when no such counts exist (see the module documentation).
pub fn sample_counts(desired: &[f64], equations: &[Equation]) -> Result<Vec<u32>, CountError> {
    let desired: Vec<f64> = desired.iter().map(|&d| if d.is_finite() { d.max(1.0) } else { 1.0 }).collect();
    let sparse = sparse_rows(equations);
    match rounded_least_squares(&desired, &sparse) {
        Err(CountError::Fractional { .. } | CountError::Infeasible { .. }) => {
            bounded::sample_counts(&desired, &sparse, equations)
        }
        result => result,
    }
}

/// Each equation as a sparse row, a piece named twice summed once.
fn sparse_rows(equations: &[Equation]) -> Vec<Row> {
    equations
        .iter()
        .map(|eq| {
            let mut row: Row = eq.iter().map(|&(c, k)| (c as usize, k as f64)).collect();
            crate::solve::sum_duplicates(&mut row);
            row.retain(|e| e.1 != 0.0);
            row
        })
        .collect()
}

/// The paper's rounding (module documentation): least squares, free pieces rounded, the
/// dependent ones following.
///
/// # Errors
/// [`CountError::Infeasible`] when the equations contradict each other or a dependent piece
/// falls below one (the bounded solve takes over), [`CountError::Fractional`] at a non-unit
/// pivot, [`CountError::Solver`] (not seen).
fn rounded_least_squares(desired: &[f64], sparse: &[Row]) -> Result<Vec<u32>, CountError> {
    let n = desired.len();
    let active: Vec<usize> = (0..n).collect();
    let infeasible = |pieces_at_one: Vec<u32>| CountError::Infeasible { pieces_at_one };
    let e = echelon(sparse.to_vec(), vec![0.0; sparse.len()], &active, n).ok_or_else(|| infeasible(Vec::new()))?;
    let continuous = continuous_free(&e, desired, n)?;
    let mut counts = vec![1.0; n];
    for (&c, &x) in e.free.iter().zip(&continuous) {
        counts[c] = x.round().max(1.0);
    }
    let mut is_free = vec![false; n];
    for &c in &e.free {
        is_free[c] = true;
    }
    for (pivot, coef, rhs) in &e.rows {
        let v = rhs - coef.iter().filter(|&&(c, _)| is_free[c]).map(|&(c, r)| r * counts[c]).sum::<f64>();
        if (v - v.round()).abs() > 1e-6 {
            return Err(CountError::Fractional { piece: *pivot as u32 });
        }
        if v.round() < 1.0 {
            return Err(infeasible(vec![*pivot as u32]));
        }
        counts[*pivot] = v.round();
    }
    Ok(counts.iter().map(|&v| v as u32).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn holds(counts: &[u32], equations: &[Equation]) -> bool {
        equations.iter().all(|eq| eq.iter().map(|&(c, k)| k * counts[c as usize] as i64).sum::<i64>() == 0)
    }

    #[test]
    fn chords_get_the_rounded_mean_of_their_desires() {
        // A 1×2 strip of faces: pieces 0 = 1 = 2 (the three parallel edges), 3 = 4, 5 = 6.
        let eqs = vec![vec![(0, 1), (1, -1)], vec![(1, 1), (2, -1)], vec![(3, 1), (4, -1)], vec![(5, 1), (6, -1)]];
        let counts = sample_counts(&[4.2, 3.9, 4.4, 2.6, 2.8, 7.0, 7.0], &eqs).unwrap();
        assert_eq!(counts, vec![4, 4, 4, 3, 3, 7, 7]);
    }

    #[test]
    fn t_vertex_sides_sum_up() {
        // Side of pieces 0 + 1 opposite piece 2.
        let eqs = vec![vec![(0, 1), (1, 1), (2, -1)]];
        let counts = sample_counts(&[3.3, 5.4, 8.1], &eqs).unwrap();
        assert!(holds(&counts, &eqs), "{counts:?}");
        assert_eq!(counts[0] + counts[1], counts[2]);
        assert!((counts[2] as i64 - 9).abs() <= 1, "{counts:?}");
    }

    #[test]
    fn a_piece_below_one_is_raised() {
        // Pieces 0 + 1 = 2 with piece 1 wanting almost nothing: it still gets one segment.
        let eqs = vec![vec![(0, 1), (1, 1), (2, -1)]];
        let counts = sample_counts(&[5.0, 0.01, 5.0], &eqs).unwrap();
        assert!(holds(&counts, &eqs));
        assert!(counts.iter().all(|&c| c >= 1), "{counts:?}");
    }

    #[test]
    fn a_layout_forcing_a_piece_to_zero_is_infeasible() {
        // a + b = c on one face, c = a on another: b would need zero segments.
        let eqs = vec![vec![(0, 1), (1, 1), (2, -1)], vec![(2, 1), (0, -1)]];
        let err = sample_counts(&[4.0, 2.0, 6.0], &eqs).unwrap_err();
        assert_eq!(err, CountError::Infeasible { pieces_at_one: vec![1] });
        assert!(err.to_string().contains("at least one"));
    }

    #[test]
    fn random_layout_equations_always_hold() {
        // Sides made of one or two pieces in chains: every result satisfies B n = 0.
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 33) as f64 / (1u64 << 31) as f64
        };
        for _ in 0..50 {
            let n = 12;
            let mut eqs = Vec::new();
            for k in 0..4 {
                let (a, b, c) = (3 * k, 3 * k + 1, 3 * k + 2);
                eqs.push(vec![(a as u32, 1), (b as u32, 1), (c as u32, -1)]);
            }
            let desired: Vec<f64> = (0..n).map(|_| 1.0 + 9.0 * rnd()).collect();
            let counts = sample_counts(&desired, &eqs).unwrap();
            assert!(holds(&counts, &eqs), "{counts:?}");
            assert!(counts.iter().all(|&c| c >= 1));
        }
    }

    #[test]
    fn ten_thousand_faces_are_counted_sparsely() {
        // A 100 × 100-face grid: horizontal pieces h(i, j) (i < 100, j ≤ 100) and vertical
        // ones v(i, j) (i ≤ 100, j < 100); each face ties bottom to top and left to right, so
        // every column of h and every row of v is one chord of 101 pieces and gets the rounded
        // mean of their desires. Dense elimination holds 20,000 × 20,200 coefficients (3.2 GB).
        let f = 100usize;
        let h = |i: usize, j: usize| (j * f + i) as u32;
        let v = |i: usize, j: usize| (f * (f + 1) + j * (f + 1) + i) as u32;
        let mut eqs = Vec::new();
        for j in 0..f {
            for i in 0..f {
                eqs.push(vec![(h(i, j), 1), (h(i, j + 1), -1)]);
                eqs.push(vec![(v(i, j), 1), (v(i + 1, j), -1)]);
            }
        }
        let n = 2 * f * (f + 1);
        let desired: Vec<f64> = (0..n).map(|k| 3.0 + ((k * 7919) % 1000) as f64 / 250.0).collect();
        let counts = sample_counts(&desired, &eqs).unwrap();
        assert!(holds(&counts, &eqs));
        for i in 0..f {
            let chord: Vec<u32> = (0..=f).map(|j| h(i, j)).collect();
            let mean = chord.iter().map(|&c| desired[c as usize]).sum::<f64>() / chord.len() as f64;
            assert_eq!(counts[chord[0] as usize], mean.round() as u32, "column {i}");
        }
    }

    /// Problems dumped from automatic layouts where the fast path fails (`README.txt` there:
    /// whether the LP is feasible and the best integer counts' relative L1 deviation). Another
    /// folder of dumps in that format can be checked with `QUADLAY_COUNTS_CASES=folder`.
    #[test]
    fn dumped_layouts_get_counts_near_the_integer_optimum() {
        let dir = std::env::var("QUADLAY_COUNTS_CASES")
            .unwrap_or_else(|_| concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/counts").into());
        let readme = std::fs::read_to_string(format!("{dir}/README.txt")).unwrap();
        let mut checked = 0;
        for line in readme.lines().filter(|l| !l.starts_with('#') && !l.trim().is_empty()) {
            let name = line.split_whitespace().next().unwrap();
            let text = std::fs::read_to_string(format!("{dir}/{name}")).unwrap();
            let (desired, eqs): (Vec<f64>, Vec<Equation>) = serde_json::from_str(&text).unwrap();
            let start = std::time::Instant::now();
            let result = sample_counts(&desired, &eqs);
            let ms = start.elapsed().as_secs_f64() * 1e3;
            // The fast path fails on every dump, so the result is the fallback's: timed alone.
            let clamped: Vec<f64> = desired.iter().map(|d| d.max(1.0)).collect();
            let start = std::time::Instant::now();
            assert_eq!(bounded::sample_counts(&clamped, &sparse_rows(&eqs), &eqs), result, "{name}");
            let ms = format!("{ms:.1} ms ({:.1} ms in the fallback)", start.elapsed().as_secs_f64() * 1e3);
            if line.contains("INFEASIBLE") {
                let err = result.unwrap_err();
                let CountError::Infeasible { pieces_at_one } = &err else { panic!("{name}: {err:?}") };
                assert!(!pieces_at_one.is_empty(), "{name}");
                println!("{name}: {} pieces, infeasible as the LP ({} culprits), {ms}", desired.len(), pieces_at_one.len());
            } else {
                let optimum: f64 = line.rsplit([' ', ')']).find(|t| !t.is_empty()).unwrap().parse().unwrap();
                let counts = result.unwrap_or_else(|e| panic!("{name}: {e:?}"));
                assert!(holds(&counts, &eqs) && counts.iter().all(|&c| c >= 1), "{name}");
                // As the README's optimum: against the desired counts as given.
                let off: f64 = counts.iter().zip(&desired).map(|(&n, d)| (n as f64 - d).abs()).sum();
                let deviation = off / desired.iter().sum::<f64>();
                println!("{name}: {} pieces, deviation {deviation:.4}, integer optimum {optimum:.4}, {ms}", desired.len());
                // Least squares, not least deviations (see `bounded`): near, not at, the optimum.
                assert!(deviation <= optimum + 0.1, "{name}: {deviation} against {optimum}");
            }
            checked += 1;
        }
        assert!(checked > 0);
    }
}
