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
//! When rounding makes a dependent piece fall below one segment, that piece is fixed at one
//! and everything is solved again (at most once per piece). When the equations cannot hold
//! with every piece at one segment or more — a T-vertex configuration that forces a piece to
//! zero, say a side `a + b` opposite a side `c` while another face forces `c = a` — there is no
//! quad mesh of this layout: [`CountError::Infeasible`] names the pieces that were fixed.

use std::fmt;

/// One equation `Σ coefficient · n[curve] = 0`.
pub type Equation = Vec<(u32, i64)>;

/// Why no consistent sample counts exist.
#[derive(Debug, Clone, PartialEq)]
pub enum CountError {
    /// The equations admit no solution with these pieces held at one segment.
    Infeasible { pieces_at_one: Vec<u32> },
    /// Elimination produced a fractional dependent count that rounding cannot repair
    /// (the layout's equations have a non-unit pivot; not seen on quad layouts).
    Fractional { piece: u32 },
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
        }
    }
}

/// The counts' equations in reduced row echelon form: `n[pivot] + Σ r·n[free] = rhs`.
struct Echelon {
    /// Per independent equation: its pivot column, its coefficients, its right-hand side.
    rows: Vec<(usize, Vec<f64>, f64)>,
    /// Columns without a pivot.
    free: Vec<usize>,
}

const EPS: f64 = 1e-9;

/// Reduces `a x = rhs` over the columns in `active` (the others are known and already on the
/// right-hand side). Pivots on entries ±1 where there are any, so integer equations keep
/// integer coefficients. `None` when the equations contradict each other.
fn echelon(mut a: Vec<Vec<f64>>, mut rhs: Vec<f64>, active: &[usize]) -> Option<Echelon> {
    let mut rows_done = 0;
    let mut pivots = Vec::new();
    let mut free = Vec::new();
    for &col in active {
        let candidates = (rows_done..a.len()).filter(|&r| a[r][col].abs() > EPS);
        let best = candidates.min_by(|&r, &s| {
            let key = |r: usize| ((a[r][col].abs() - 1.0).abs() > EPS, -a[r][col].abs());
            key(r).partial_cmp(&key(s)).unwrap_or(std::cmp::Ordering::Equal)
        });
        let Some(r) = best else {
            free.push(col);
            continue;
        };
        a.swap(rows_done, r);
        rhs.swap(rows_done, r);
        let p = a[rows_done][col];
        for x in a[rows_done].iter_mut() {
            *x /= p;
        }
        rhs[rows_done] /= p;
        for r in 0..a.len() {
            let factor = a[r][col];
            if r != rows_done && factor.abs() > EPS {
                for c in 0..a[r].len() {
                    a[r][c] -= factor * a[rows_done][c];
                }
                rhs[r] -= factor * rhs[rows_done];
            }
        }
        pivots.push(col);
        rows_done += 1;
    }
    if rhs[rows_done..].iter().any(|v| v.abs() > 1e-7) {
        return None;
    }
    let rows = pivots.into_iter().enumerate().map(|(r, col)| (col, std::mem::take(&mut a[r]), rhs[r])).collect();
    Some(Echelon { rows, free })
}

/// Solves the small symmetric positive definite system `m x = b` (Cholesky), in place in `b`.
fn solve_spd(mut m: Vec<Vec<f64>>, b: &mut [f64]) {
    let n = b.len();
    for j in 0..n {
        let d = (m[j][j] - (0..j).map(|k| m[j][k] * m[j][k]).sum::<f64>()).max(1e-300).sqrt();
        m[j][j] = d;
        for i in j + 1..n {
            m[i][j] = (m[i][j] - (0..j).map(|k| m[i][k] * m[j][k]).sum::<f64>()) / d;
        }
    }
    for i in 0..n {
        b[i] = (b[i] - (0..i).map(|k| m[i][k] * b[k]).sum::<f64>()) / m[i][i];
    }
    for i in (0..n).rev() {
        b[i] = (b[i] - (i + 1..n).map(|k| m[k][i] * b[k]).sum::<f64>()) / m[i][i];
    }
}

/// The continuous counts nearest `desired` under the reduced equations, as values of the
/// free columns: minimize Σ_free (n − d)² + Σ_pivot (rhs − r·n_free − d_pivot)².
fn continuous_free(e: &Echelon, desired: &[f64]) -> Vec<f64> {
    let k = e.free.len();
    // (I + RᵀR) n_free = d_free + Rᵀ (rhs − d_pivot)
    let mut m = vec![vec![0.0; k]; k];
    let mut b: Vec<f64> = e.free.iter().map(|&c| desired[c]).collect();
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for (pivot, coef, rhs) in &e.rows {
        let r: Vec<f64> = e.free.iter().map(|&c| coef[c]).collect();
        for i in 0..k {
            if r[i] == 0.0 {
                continue;
            }
            b[i] += r[i] * (rhs - desired[*pivot]);
            for j in 0..k {
                m[i][j] += r[i] * r[j];
            }
        }
    }
    solve_spd(m, &mut b);
    b
}

/// Integer sample counts, one per piece, each at least one, satisfying every equation,
/// near `desired` (paper Section 4).
///
/// # Errors
/// [`CountError`] when no such counts exist (see the module documentation).
pub fn sample_counts(desired: &[f64], equations: &[Equation]) -> Result<Vec<u32>, CountError> {
    let n = desired.len();
    let desired: Vec<f64> = desired.iter().map(|&d| if d.is_finite() { d.max(1.0) } else { 1.0 }).collect();
    let dense: Vec<Vec<f64>> = equations
        .iter()
        .map(|eq| {
            let mut row = vec![0.0; n];
            for &(c, k) in eq {
                row[c as usize] += k as f64;
            }
            row
        })
        .collect();
    let mut at_one: Vec<u32> = Vec::new();
    loop {
        let active: Vec<usize> = (0..n).filter(|c| !at_one.contains(&(*c as u32))).collect();
        let rhs: Vec<f64> =
            dense.iter().map(|row| -at_one.iter().map(|&c| row[c as usize]).sum::<f64>()).collect();
        let infeasible = || CountError::Infeasible { pieces_at_one: at_one.clone() };
        let e = echelon(dense.clone(), rhs, &active).ok_or_else(infeasible)?;
        let continuous = continuous_free(&e, &desired);
        let mut counts = vec![1.0; n];
        for (&c, &x) in e.free.iter().zip(&continuous) {
            counts[c] = x.round().max(1.0);
        }
        let mut below = None;
        for (pivot, coef, rhs) in &e.rows {
            let v = rhs - e.free.iter().map(|&c| coef[c] * counts[c]).sum::<f64>();
            if (v - v.round()).abs() > 1e-6 {
                return Err(CountError::Fractional { piece: *pivot as u32 });
            }
            counts[*pivot] = v.round();
            if v.round() < 1.0 && below.is_none() {
                below = Some(*pivot as u32);
            }
        }
        match below {
            None => return Ok(counts.iter().map(|&v| v as u32).collect()),
            Some(c) => at_one.push(c),
        }
    }
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
}
