//! The one place that talks to the sparse solver: sparse Cholesky factorization of symmetric
//! positive definite (SPD) matrices with [faer](https://docs.rs/faer/0.24.4).
//!
//! The parameterization solves many systems $A x = b$ whose matrix keeps its sparsity pattern
//! while its values change (every Newton / chart-optimization iteration). Following faer, the
//! work is split in two:
//!
//! 1. [`SpdSolver::new`] takes the pattern once: it builds the compressed sparse column (CSC)
//!    structure of the lower triangle, a scatter map from the caller's entry order into it, a
//!    fill-reducing ordering $P$ (approximate minimum degree, AMD) and the symbolic
//!    factorization, i.e. the pattern of $L$ in $P A P^\top = L L^\top$.
//! 2. [`SpdSolver::factor`] computes the numeric values of $L$ for new values of $A$, reusing
//!    all of the above; [`SpdSolver::solve_in_place`] then solves
//!    $A x = b \iff L L^\top (P x) = P b$ as often as needed.
//!
//! Everything the caller's data decides is reported as a [`SolveError`]; nothing here panics
//! on bad input.
//!
//! # Example
//! ```
//! use quadlay::solve::SpdSolver;
//!
//! // A = [[4, 1], [1, 3]], given by its lower triangle (row, col).
//! let mut solver = SpdSolver::new(2, &[(0, 0), (1, 0), (1, 1)])?;
//! solver.factor(&[4.0, 1.0, 3.0])?;
//! let mut b = vec![1.0, 2.0];
//! solver.solve_in_place(&mut b)?; // x = A⁻¹ b = [1/11, 7/11]
//! assert!((b[0] - 1.0 / 11.0).abs() < 1e-14 && (b[1] - 7.0 / 11.0).abs() < 1e-14);
//!
//! // Same pattern, new values: only the numeric factorization is redone.
//! solver.factor(&[2.0, 0.0, 5.0])?;
//! let mut b = vec![2.0, 5.0];
//! solver.solve_in_place(&mut b)?;
//! assert!((b[0] - 1.0).abs() < 1e-14 && (b[1] - 1.0).abs() < 1e-14);
//! # Ok::<(), quadlay::solve::SolveError>(())
//! ```

use std::fmt;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{FaerError, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

/// The index type of the pattern, the ordering and the factor: four bytes rather than `usize`'s
/// eight natively (in wasm32 they are the same). The ordering walks index arrays, and halving
/// them halves the AMD ordering's and the symbolic factorization's time (docs/measurements.md).
/// A factor that would need more stored values than `u32` counts is reported as
/// [`SolveError::IndexOverflow`].
type Ix = u32;

/// Why a sparse SPD factorization or solve failed.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SolveError {
    /// The numeric factorization met a pivot that is not strictly positive (zero, negative or
    /// NaN): the matrix is not positive definite, or so badly conditioned that rounding made it
    /// look indefinite. The solver is left unfactored.
    NotPositiveDefinite {
        /// The row and column of that pivot in the caller's numbering (faer's index, taken
        /// back through the fill-reducing permutation).
        pivot: usize,
    },
    /// The pattern given to [`SpdSolver::new`] is unusable: an entry out of range, an entry in
    /// the strict upper triangle, or a column without a diagonal entry. The message names the
    /// offending entry or column.
    BadPattern(String),
    /// [`SpdSolver::factor`] got a different number of values than there are entries.
    ValueCountMismatch {
        /// Number of entries given to [`SpdSolver::new`].
        expected: usize,
        /// Number of values given.
        got: usize,
    },
    /// A value given to [`SpdSolver::factor`] is NaN or infinite.
    NonFiniteValue {
        /// Index of the offending value (and of its entry).
        entry: usize,
    },
    /// The numeric factorization produced non-finite values (overflow with huge entries).
    /// The solver is left unfactored.
    NumericalBreakdown,
    /// [`SpdSolver::solve_in_place`] got a right-hand side of the wrong length.
    RhsLengthMismatch {
        /// The matrix dimension `n`.
        expected: usize,
        /// Length of the right-hand side given.
        got: usize,
    },
    /// A right-hand side component is NaN or infinite.
    NonFiniteRhs {
        /// Index of the offending component.
        index: usize,
    },
    /// [`SpdSolver::solve_in_place`] was called before a successful [`SpdSolver::factor`]
    /// (or after a failed one).
    NotFactored,
    /// An allocation inside the solver failed.
    OutOfMemory,
    /// The factor has more nonzeros than the solver's index type can address.
    IndexOverflow,
    /// `solve_lu` (feature `eq3`): the square matrix is singular — structurally (no pivot at `column`) or
    /// numerically (a zero pivot made the solution non-finite; `column` is `None`).
    Singular {
        /// The elimination step at which no pivot was found, if known.
        column: Option<usize>,
    },
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SolveError::NotPositiveDefinite { pivot } => {
                write!(f, "sparse Cholesky: the matrix is not positive definite (pivot {pivot})")
            }
            SolveError::BadPattern(msg) => write!(f, "sparse Cholesky: bad pattern: {msg}"),
            SolveError::ValueCountMismatch { expected, got } => write!(
                f,
                "sparse Cholesky: {got} values given for {expected} entries"
            ),
            SolveError::NonFiniteValue { entry } => {
                write!(f, "sparse Cholesky: value of entry {entry} is not finite")
            }
            SolveError::NumericalBreakdown => write!(
                f,
                "sparse Cholesky: the factorization overflowed to non-finite values"
            ),
            SolveError::RhsLengthMismatch { expected, got } => write!(
                f,
                "sparse Cholesky: right-hand side has length {got}, the matrix is {expected}×{expected}"
            ),
            SolveError::NonFiniteRhs { index } => write!(
                f,
                "sparse Cholesky: right-hand side component {index} is not finite"
            ),
            SolveError::NotFactored => write!(
                f,
                "sparse Cholesky: solve called without a successful numeric factorization"
            ),
            SolveError::OutOfMemory => write!(f, "sparse Cholesky: out of memory"),
            SolveError::IndexOverflow => {
                write!(f, "sparse Cholesky: the factor is too large to index")
            }
            SolveError::Singular { column: Some(c) } => {
                write!(f, "sparse LU: the matrix is singular (no pivot at step {c})")
            }
            SolveError::Singular { column: None } => {
                write!(f, "sparse LU: the matrix is numerically singular")
            }
        }
    }
}

impl std::error::Error for SolveError {}

impl From<FaerError> for SolveError {
    fn from(e: FaerError) -> Self {
        match e {
            FaerError::IndexOverflow => SolveError::IndexOverflow,
            // `FaerError` is non-exhaustive; anything else it may grow is an allocation-class
            // failure as far as callers are concerned.
            _ => SolveError::OutOfMemory,
        }
    }
}

impl SolveError {
    /// A stable snake_case name of the error, for programs (the page).
    pub fn kind(&self) -> &'static str {
        match self {
            SolveError::NotPositiveDefinite { .. } => "not_positive_definite",
            SolveError::BadPattern(_) => "bad_pattern",
            SolveError::ValueCountMismatch { .. } => "value_count_mismatch",
            SolveError::NonFiniteValue { .. } => "non_finite_value",
            SolveError::NumericalBreakdown => "numerical_breakdown",
            SolveError::RhsLengthMismatch { .. } => "rhs_length_mismatch",
            SolveError::NonFiniteRhs { .. } => "non_finite_rhs",
            SolveError::NotFactored => "not_factored",
            SolveError::OutOfMemory => "out_of_memory",
            SolveError::IndexOverflow => "index_overflow",
            SolveError::Singular { .. } => "singular",
        }
    }
}

/// A symmetric positive definite sparse matrix's pattern, factorized symbolically once; numeric
/// factorizations of matrices with that pattern reuse it (the parameterization re-solves with
/// new values every iteration).
///
/// Holds the CSC pattern of the lower triangle, the map from the caller's entry order into it,
/// the AMD ordering and symbolic Cholesky factor (simplicial or supernodal, as faer decides
/// from the flop count), and buffers for $A$'s values, $L$'s values and the factorization
/// workspace, so that [`SpdSolver::factor`] allocates nothing.
pub struct SpdSolver {
    n: usize,
    /// Lower triangle of `A`, CSC, rows sorted and unique within each column.
    pattern: SymbolicSparseColMat<Ix>,
    /// `scatter[k]` is the position of the caller's entry `k` in the CSC value array.
    scatter: Vec<Ix>,
    /// CSC values of `A`'s lower triangle, rebuilt by each `factor`.
    a_values: Vec<f64>,
    symbolic: SymbolicCholesky<Ix>,
    /// Values of `L`, laid out as `symbolic` says.
    l_values: Vec<f64>,
    /// Workspace of the numeric factorization, sized once.
    factor_mem: MemBuffer,
    /// Size of the workspace of one solve.
    solve_req: StackReq,
    factored: bool,
}

impl fmt::Debug for SpdSolver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SpdSolver")
            .field("n", &self.n)
            .field("entries", &self.scatter.len())
            .field("nnz_lower", &self.a_values.len())
            .field("nnz_factor", &self.l_values.len())
            .field("factored", &self.factored)
            .finish()
    }
}

impl SpdSolver {
    /// Analyzes the pattern of an `n`×`n` symmetric positive definite matrix: builds its CSC
    /// structure, computes the AMD fill-reducing ordering and the symbolic Cholesky
    /// factorization.
    ///
    /// `entries` are (row, col) positions of the LOWER triangle incl. diagonal (duplicates
    /// allowed, summed). Their order is the order of the values later given to
    /// [`SpdSolver::factor`]; any order is accepted.
    ///
    /// # Preconditions
    /// Every entry has `col <= row < n`, and every column has its diagonal entry (a positive
    /// definite matrix has a positive diagonal). `n == 0` is allowed (an empty system).
    ///
    /// # Errors
    /// - [`SolveError::BadPattern`] for an entry out of range, an entry above the diagonal, or
    ///   a column without a diagonal entry (the message names it);
    /// - [`SolveError::OutOfMemory`] / [`SolveError::IndexOverflow`] if the symbolic factor
    ///   cannot be allocated or indexed.
    pub fn new(n: usize, entries: &[(u32, u32)]) -> Result<SpdSolver, SolveError> {
        // faer orders in the signed counterpart of the index type.
        if n > Ix::MAX as usize / 2 {
            return Err(SolveError::BadPattern(format!("dimension {n} is too large")));
        }
        for (k, &(r, c)) in entries.iter().enumerate() {
            let (r, c) = (r as usize, c as usize);
            if r >= n || c >= n {
                return Err(SolveError::BadPattern(format!(
                    "entry {k} at ({r}, {c}) is out of range for a {n}×{n} matrix"
                )));
            }
            if r < c {
                return Err(SolveError::BadPattern(format!(
                    "entry {k} at ({r}, {c}) is above the diagonal; give the lower triangle"
                )));
            }
        }

        // Bucket the entries by column (counting sort), keeping each one's index k.
        let mut col_start = vec![0usize; n + 1];
        for &(_, c) in entries {
            col_start[c as usize + 1] += 1;
        }
        for j in 0..n {
            col_start[j + 1] += col_start[j];
        }
        let mut next = col_start.clone();
        let mut by_col: Vec<(u32, u32)> = vec![(0, 0); entries.len()]; // (row, k)
        for (k, &(r, c)) in entries.iter().enumerate() {
            let slot = &mut next[c as usize];
            by_col[*slot] = (r, k as u32);
            *slot += 1;
        }

        // Sort rows within each column, merge duplicates, record where each entry went.
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(entries.len());
        let mut scatter: Vec<Ix> = vec![0; entries.len()];
        col_ptr.push(0 as Ix);
        for j in 0..n {
            let bucket = &mut by_col[col_start[j]..col_start[j + 1]];
            bucket.sort_unstable();
            if bucket.first().map(|&(r, _)| r as usize) != Some(j) {
                return Err(SolveError::BadPattern(format!(
                    "column {j} has no diagonal entry"
                )));
            }
            let column_start = row_idx.len();
            for &(r, k) in bucket.iter() {
                if row_idx.len() == column_start || row_idx.last() != Some(&r) {
                    row_idx.push(r);
                }
                scatter[k as usize] = (row_idx.len() - 1) as Ix;
            }
            col_ptr.push(Ix::try_from(row_idx.len()).map_err(|_| SolveError::IndexOverflow)?);
        }
        drop(by_col);
        let nnz = row_idx.len();
        // Valid by construction: col_ptr is nondecreasing from 0 to nnz, rows are < n, sorted
        // and unique within each column.
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);

        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )?;

        let l_len = symbolic.len_val();
        let mut l_values = Vec::new();
        l_values
            .try_reserve_exact(l_len)
            .map_err(|_| SolveError::OutOfMemory)?;
        l_values.resize(l_len, 0.0);
        let factor_mem = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        )
        .map_err(|_| SolveError::OutOfMemory)?;
        let solve_req = symbolic.solve_in_place_scratch::<f64>(1, Par::Seq);

        Ok(SpdSolver {
            n,
            pattern,
            scatter,
            a_values: vec![0.0; nnz],
            symbolic,
            l_values,
            factor_mem,
            solve_req,
            factored: false,
        })
    }

    /// Numeric factorization with `values[k]` at `entries[k]` (same order as given to new;
    /// duplicates are summed).
    ///
    /// Computes $L$ with $P A P^\top = L L^\top$, reusing the ordering, the symbolic factor and
    /// all buffers from [`SpdSolver::new`]; the values are scattered through a precomputed
    /// index map (no sorting or hashing here). Replaces any earlier factorization.
    ///
    /// # Preconditions
    /// `values.len()` equals the number of entries given to [`SpdSolver::new`], and the matrix
    /// they describe is symmetric positive definite.
    ///
    /// # Errors
    /// - [`SolveError::ValueCountMismatch`] if `values` has the wrong length;
    /// - [`SolveError::NonFiniteValue`] for a NaN or infinite value (names the first one);
    /// - [`SolveError::NotPositiveDefinite`] if a pivot is not strictly positive;
    /// - [`SolveError::NumericalBreakdown`] if the factor overflowed;
    /// - [`SolveError::OutOfMemory`] / [`SolveError::IndexOverflow`] from the solver.
    ///
    /// The first two leave an earlier factorization usable; the others leave the solver
    /// unfactored until a later `factor` succeeds.
    pub fn factor(&mut self, values: &[f64]) -> Result<(), SolveError> {
        if values.len() != self.scatter.len() {
            return Err(SolveError::ValueCountMismatch {
                expected: self.scatter.len(),
                got: values.len(),
            });
        }
        if let Some(entry) = values.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFiniteValue { entry });
        }
        self.factored = false;
        self.a_values.fill(0.0);
        for (&pos, &v) in self.scatter.iter().zip(values) {
            self.a_values[pos as usize] += v;
        }
        self.factor_a_values()
    }

    /// Where each entry given to [`SpdSolver::new`] goes among the matrix's stored values
    /// (duplicates share one): callers that re-assemble often can sum into those values
    /// themselves and call [`SpdSolver::factor_summed`].
    pub fn slots(&self) -> &[u32] {
        &self.scatter
    }

    /// Numeric factorization from the matrix's stored values, summed as [`slots`](Self::slots)
    /// says (one per distinct position). Errors as [`SpdSolver::factor`], with
    /// [`SolveError::NonFiniteValue`] naming the stored value.
    pub fn factor_summed(&mut self, a_values: &[f64]) -> Result<(), SolveError> {
        if a_values.len() != self.a_values.len() {
            return Err(SolveError::ValueCountMismatch { expected: self.a_values.len(), got: a_values.len() });
        }
        if let Some(entry) = a_values.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFiniteValue { entry });
        }
        self.factored = false;
        self.a_values.copy_from_slice(a_values);
        self.factor_a_values()
    }

    /// The caller's row of faer's failed pivot `index`: faer counts it in the permuted
    /// order, one-based in a simplicial factorization (its `k + 1`), zero-based in a
    /// supernodal one.
    fn caller_index(&self, index: usize) -> usize {
        let k = match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
            SymbolicCholeskyRaw::Supernodal(_) => index,
        }
        .min(self.n - 1);
        self.symbolic.perm().map_or(k, |p| p.arrays().0[k] as usize)
    }

    /// Factors the matrix held in `a_values`.
    fn factor_a_values(&mut self) -> Result<(), SolveError> {
        if self.n == 0 {
            self.factored = true;
            return Ok(());
        }
        let a = SparseColMatRef::new(self.pattern.as_ref(), &self.a_values);
        let factored = self.symbolic.factorize_numeric_llt::<f64>(
            &mut self.l_values,
            a,
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut self.factor_mem),
            Default::default(),
        );
        if let Err(LltError::NonPositivePivot { index }) = factored {
            return Err(SolveError::NotPositiveDefinite { pivot: self.caller_index(index) });
        }
        // Pivots are checked to be > 0 but overflow can still slip in infinities.
        if self.l_values.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NumericalBreakdown);
        }
        self.factored = true;
        Ok(())
    }

    /// Solves A x = b in place (after factor): on return `b` holds $x = A^{-1} b$ for the
    /// values of the last successful [`SpdSolver::factor`].
    ///
    /// # Errors
    /// - [`SolveError::NotFactored`] without a successful factorization;
    /// - [`SolveError::RhsLengthMismatch`] if `b.len() != n`;
    /// - [`SolveError::NonFiniteRhs`] for a NaN or infinite component of `b`;
    /// - [`SolveError::OutOfMemory`] if the solve workspace cannot be allocated.
    ///
    /// On error `b` is left unchanged.
    pub fn solve_in_place(&self, b: &mut [f64]) -> Result<(), SolveError> {
        if !self.factored {
            return Err(SolveError::NotFactored);
        }
        if b.len() != self.n {
            return Err(SolveError::RhsLengthMismatch {
                expected: self.n,
                got: b.len(),
            });
        }
        if let Some(index) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFiniteRhs { index });
        }
        if self.n == 0 {
            return Ok(());
        }
        if let SymbolicCholeskyRaw::Supernodal(supernodal) = self.symbolic.raw() {
            solve_supernodal(supernodal, self.symbolic.perm(), &self.l_values, b);
            return Ok(());
        }
        // Small (O(n)) and needed because `self` is shared: allocate per solve.
        let mut mem = MemBuffer::try_new(self.solve_req).map_err(|_| SolveError::OutOfMemory)?;
        let llt = LltRef::<'_, Ix, f64>::new(&self.symbolic, &self.l_values);
        let n = self.n;
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, n, 1),
            Par::Seq,
            MemStack::new(&mut mem),
        );
        Ok(())
    }

    /// The dimension `n` of the matrix.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Number of stored values of the Cholesky factor $L$ (a measure of fill-in and memory).
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }

    /// Whether the last call to [`SpdSolver::factor`] succeeded, so that
    /// [`SpdSolver::solve_in_place`] can be used.
    pub fn is_factored(&self) -> bool {
        self.factored
    }
}

/// Solves $L L^\top y = b$ in place for a supernodal factor, with $b$ and $y$ in the original
/// order (`perm` maps them to the factor's).
///
/// faer's own solve does the same through its dense kernels, one triangular solve and one
/// matrix product per supernode; the supernodes of a surface mesh's factor are mostly a few
/// columns wide, and those calls cost more than the arithmetic (docs/measurements.md).
fn solve_supernodal(
    symbolic: &faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<Ix>,
    perm: Option<faer::perm::PermRef<'_, Ix>>,
    l_values: &[f64],
    b: &mut [f64],
) {
    let mut x: Vec<f64> = match perm {
        Some(p) => p.arrays().0.iter().map(|&i| b[i as usize]).collect(),
        None => b.to_vec(),
    };
    let val_start = symbolic.col_ptr_for_val();
    // Each supernode: columns start..start + w, stored column-major with the w rows of its
    // diagonal block first and then one row per entry of its pattern.
    let block = |s: usize| {
        let sn = symbolic.supernode(s);
        let w = (symbolic.supernode_end()[s] - symbolic.supernode_begin()[s]) as usize;
        let values = &l_values[val_start[s] as usize..val_start[s + 1] as usize];
        (sn.start(), w, sn.pattern(), values)
    };
    // Forward: L y = P b.
    for s in 0..symbolic.n_supernodes() {
        let (start, w, pattern, values) = block(s);
        let m = w + pattern.len();
        for j in 0..w {
            let column = &values[j * m..(j + 1) * m];
            let xj = x[start + j] / column[j];
            x[start + j] = xj;
            for i in j + 1..w {
                x[start + i] -= column[i] * xj;
            }
            for (&r, &l) in pattern.iter().zip(&column[w..]) {
                x[r as usize] -= l * xj;
            }
        }
    }
    // Backward: Lᵀ (P x) = y.
    for s in (0..symbolic.n_supernodes()).rev() {
        let (start, w, pattern, values) = block(s);
        let m = w + pattern.len();
        for j in (0..w).rev() {
            let column = &values[j * m..(j + 1) * m];
            let mut t = x[start + j];
            for i in j + 1..w {
                t -= column[i] * x[start + i];
            }
            for (&r, &l) in pattern.iter().zip(&column[w..]) {
                t -= l * x[r as usize];
            }
            x[start + j] = t / column[j];
        }
    }
    match perm {
        Some(p) => {
            for (&i, &xi) in p.arrays().0.iter().zip(&x) {
                b[i as usize] = xi;
            }
        }
        None => b.copy_from_slice(&x),
    }
}

#[cfg(feature = "eq3")]
/// Solves the square, generally non-symmetric system $A x = b$ by sparse LU with partial
/// (row) pivoting and a COLAMD column ordering (faer's `SparseColMat::sp_lu`), in place: on
/// return `b` holds $x$. `A` is given as `(row, col)` entries with `values`; duplicated
/// entries are summed. Nothing is kept between calls (the symbolic analysis is redone), so
/// this serves comparisons and one-off solves; the SPD systems of the parameterization use
/// [`SpdSolver`].
///
/// # Errors
/// - [`SolveError::BadPattern`] for an entry out of range;
/// - [`SolveError::ValueCountMismatch`], [`SolveError::RhsLengthMismatch`];
/// - [`SolveError::NonFiniteValue`], [`SolveError::NonFiniteRhs`];
/// - [`SolveError::Singular`] if the matrix is structurally or numerically singular;
/// - [`SolveError::OutOfMemory`] / [`SolveError::IndexOverflow`] from faer.
///
/// On error `b` is left unchanged.
pub fn solve_lu(n: usize, entries: &[(u32, u32)], values: &[f64], b: &mut [f64]) -> Result<(), SolveError> {
    use faer::linalg::solvers::Solve;
    use faer::sparse::linalg::LuError;
    use faer::sparse::{SparseColMat, Triplet};
    if values.len() != entries.len() {
        return Err(SolveError::ValueCountMismatch { expected: entries.len(), got: values.len() });
    }
    if b.len() != n {
        return Err(SolveError::RhsLengthMismatch { expected: n, got: b.len() });
    }
    if let Some(entry) = values.iter().position(|v| !v.is_finite()) {
        return Err(SolveError::NonFiniteValue { entry });
    }
    if let Some(index) = b.iter().position(|v| !v.is_finite()) {
        return Err(SolveError::NonFiniteRhs { index });
    }
    if let Some(&(r, c)) = entries.iter().find(|&&(r, c)| r as usize >= n || c as usize >= n) {
        return Err(SolveError::BadPattern(format!("entry ({r}, {c}) is outside the {n}×{n} matrix")));
    }
    if n == 0 {
        return Ok(());
    }
    let triplets: Vec<Triplet<usize, usize, f64>> =
        entries.iter().zip(values).map(|(&(r, c), &val)| Triplet::new(r as usize, c as usize, val)).collect();
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets).map_err(|e| match e {
        faer::sparse::CreationError::Generic(e) => SolveError::from(e),
        faer::sparse::CreationError::OutOfBounds { row, col } => {
            SolveError::BadPattern(format!("entry ({row}, {col}) is outside the {n}×{n} matrix"))
        }
    })?;
    let lu = a.sp_lu().map_err(|e| match e {
        LuError::SymbolicSingular { index } => SolveError::Singular { column: Some(index) },
        LuError::Generic(e) => SolveError::from(e),
    })?;
    let mut x = b.to_vec();
    lu.solve_in_place(MatMut::from_column_major_slice_mut(&mut x, n, 1));
    if x.iter().any(|v| !v.is_finite()) {
        return Err(SolveError::Singular { column: None });
    }
    b.copy_from_slice(&x);
    Ok(())
}


/// A sparse row of (column, coefficient) in column order, each column once: the coefficients
/// of a column named more than once summed.
pub fn sum_duplicates(row: &mut Vec<(usize, f64)>) {
    row.sort_by_key(|e| e.0);
    row.dedup_by(|later, kept| {
        let same = later.0 == kept.0;
        if same {
            kept.1 += later.1;
        }
        same
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Instant;

    /// Lower-triangle entries of the 5-point Laplacian on a `w`×`h` grid plus `shift` on the
    /// diagonal (Dirichlet-like: the diagonal is always 4).
    fn grid_laplacian(w: usize, h: usize, shift: f64) -> (usize, Vec<(u32, u32)>, Vec<f64>) {
        let n = w * h;
        let id = |x: usize, y: usize| (y * w + x) as u32;
        let mut entries = Vec::with_capacity(3 * n);
        let mut values = Vec::with_capacity(3 * n);
        for y in 0..h {
            for x in 0..w {
                entries.push((id(x, y), id(x, y)));
                values.push(4.0 + shift);
                if x + 1 < w {
                    entries.push((id(x + 1, y), id(x, y)));
                    values.push(-1.0);
                }
                if y + 1 < h {
                    entries.push((id(x, y + 1), id(x, y)));
                    values.push(-1.0);
                }
            }
        }
        (n, entries, values)
    }

    /// The 7-point Laplacian of a w×w×w grid plus the identity, as lower-triangle entries.
    fn cube_laplacian(w: usize) -> (usize, Vec<(u32, u32)>, Vec<f64>) {
        let n = w * w * w;
        let id = |x: usize, y: usize, z: usize| ((z * w + y) * w + x) as u32;
        let (mut entries, mut values) = (Vec::new(), Vec::new());
        for z in 0..w {
            for y in 0..w {
                for x in 0..w {
                    entries.push((id(x, y, z), id(x, y, z)));
                    values.push(7.0);
                    for (dx, dy, dz) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                        if x + dx < w && y + dy < w && z + dz < w {
                            entries.push((id(x + dx, y + dy, z + dz), id(x, y, z)));
                            values.push(-1.0);
                        }
                    }
                }
            }
        }
        (n, entries, values)
    }

    /// y = A x for the symmetric matrix given by lower-triangle entries (duplicates summed).
    fn sym_matvec(n: usize, entries: &[(u32, u32)], values: &[f64], x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; n];
        for (&(r, c), &v) in entries.iter().zip(values) {
            let (r, c) = (r as usize, c as usize);
            y[r] += v * x[c];
            if r != c {
                y[c] += v * x[r];
            }
        }
        y
    }

    fn norm(v: &[f64]) -> f64 {
        v.iter().map(|a| a * a).sum::<f64>().sqrt()
    }

    fn rel_residual(n: usize, e: &[(u32, u32)], v: &[f64], x: &[f64], b: &[f64]) -> f64 {
        let ax = sym_matvec(n, e, v, x);
        let r: Vec<f64> = ax.iter().zip(b).map(|(a, b)| a - b).collect();
        norm(&r) / norm(b)
    }

    fn known_solution(n: usize) -> Vec<f64> {
        (0..n).map(|i| (0.37 * i as f64).sin() + 0.001 * i as f64).collect()
    }

    /// Deterministic permutation (xorshift Fisher–Yates) to feed entries in a scrambled order.
    fn shuffle<T>(v: &mut [T], mut seed: u64) {
        for i in (1..v.len()).rev() {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            v.swap(i, (seed % (i as u64 + 1)) as usize);
        }
    }

    #[test]
    fn solve_grid_laplacian_10k_against_known_solution() {
        let (n, entries, values) = grid_laplacian(100, 100, 0.1);
        assert_eq!(n, 10_000);
        let x_true = known_solution(n);
        let b = sym_matvec(n, &entries, &values, &x_true);

        let mut solver = SpdSolver::new(n, &entries).unwrap();
        solver.factor(&values).unwrap();
        let mut x = b.clone();
        solver.solve_in_place(&mut x).unwrap();

        let res = rel_residual(n, &entries, &values, &x, &b);
        assert!(res < 1e-10, "relative residual {res}");
        let err: Vec<f64> = x.iter().zip(&x_true).map(|(a, b)| a - b).collect();
        assert!(norm(&err) / norm(&x_true) < 1e-10);
        // AMD keeps the fill far below the dense n²/2.
        assert!(solver.factor_nnz() < 40 * n, "fill {}", solver.factor_nnz());
    }

    /// Our triangular solves on a supernodal factor against faer's own on the same factor.
    #[test]
    fn supernodal_solve_matches_faers() {
        // Large enough for faer to choose the supernodal factorization.
        let (n, entries, values) = grid_laplacian(200, 150, 0.1);
        let mut solver = SpdSolver::new(n, &entries).unwrap();
        solver.factor(&values).unwrap();
        assert!(matches!(solver.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_)));
        let b: Vec<f64> = (0..n).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
        let mut ours = b.clone();
        solver.solve_in_place(&mut ours).unwrap();
        let mut faers = b;
        let llt = LltRef::<'_, Ix, f64>::new(&solver.symbolic, &solver.l_values);
        let mut mem = MemBuffer::new(solver.solve_req);
        llt.solve_in_place_with_conj(Conj::No, MatMut::from_column_major_slice_mut(&mut faers, n, 1), Par::Seq, MemStack::new(&mut mem));
        let scale = faers.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let diff = ours.iter().zip(&faers).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff <= 1e-12 * scale, "largest difference {diff:e} against {scale:e}");
    }

    #[test]
    fn scrambled_entry_order_gives_same_solution() {
        let (n, entries, values) = grid_laplacian(30, 20, 0.5);
        let mut pairs: Vec<((u32, u32), f64)> =
            entries.iter().copied().zip(values.iter().copied()).collect();
        shuffle(&mut pairs, 0x9e37_79b9_7f4a_7c15);
        let (e2, v2): (Vec<_>, Vec<_>) = pairs.into_iter().unzip();
        let x_true = known_solution(n);
        let b = sym_matvec(n, &entries, &values, &x_true);
        let mut solver = SpdSolver::new(n, &e2).unwrap();
        solver.factor(&v2).unwrap();
        let mut x = b.clone();
        solver.solve_in_place(&mut x).unwrap();
        assert!(rel_residual(n, &entries, &values, &x, &b) < 1e-12);
    }

    #[test]
    fn values_summed_by_slot_factor_like_entries() {
        let (n, entries, values) = grid_laplacian(30, 20, 0.1);
        // Every entry given twice, halved: duplicates share a slot.
        let twice: Vec<(u32, u32)> = entries.iter().chain(&entries).copied().collect();
        let halves: Vec<f64> = values.iter().chain(&values).map(|v| 0.5 * v).collect();
        let mut solver = SpdSolver::new(n, &twice).unwrap();
        let mut summed = vec![0.0; solver.slots().iter().max().map_or(0, |&m| m as usize + 1)];
        for (&slot, &v) in solver.slots().iter().zip(&halves) {
            summed[slot as usize] += v;
        }
        solver.factor_summed(&summed).unwrap();
        let b = sym_matvec(n, &entries, &values, &known_solution(n));
        let mut x = b.clone();
        solver.solve_in_place(&mut x).unwrap();
        assert!(rel_residual(n, &entries, &values, &x, &b) < 1e-12);
        assert!(matches!(solver.factor_summed(&summed[1..]), Err(SolveError::ValueCountMismatch { .. })));
        summed[3] = f64::NAN;
        assert_eq!(solver.factor_summed(&summed), Err(SolveError::NonFiniteValue { entry: 3 }));
    }

    #[test]
    fn refactor_with_new_values_reuses_symbolic_and_is_right() {
        let (n, entries, values) = grid_laplacian(100, 100, 0.1);
        let mut solver = SpdSolver::new(n, &entries).unwrap();
        let perm_ptr = solver.symbolic.perm().map(|p| p.arrays().0.as_ptr());
        let l_ptr = solver.l_values.as_ptr();
        solver.factor(&values).unwrap();

        for round in 1..4 {
            // Different weights per edge (still diagonally dominant → SPD) and a new shift.
            let values2: Vec<f64> = entries
                .iter()
                .enumerate()
                .map(|(k, &(r, c))| {
                    if r == c {
                        4.0 * (1.0 + 0.3 * round as f64) + 0.01 * round as f64
                    } else {
                        -(1.0 + 0.3 * round as f64) * (0.5 + 0.5 * ((k % 7) as f64 / 7.0))
                    }
                })
                .collect();
            solver.factor(&values2).unwrap();
            let x_true = known_solution(n);
            let b = sym_matvec(n, &entries, &values2, &x_true);
            let mut x = b.clone();
            solver.solve_in_place(&mut x).unwrap();
            let res = rel_residual(n, &entries, &values2, &x, &b);
            assert!(res < 1e-10, "round {round}: relative residual {res}");
        }
        // Same ordering and factor storage as after `new`: nothing symbolic was redone.
        assert_eq!(solver.symbolic.perm().map(|p| p.arrays().0.as_ptr()), perm_ptr);
        assert_eq!(solver.l_values.as_ptr(), l_ptr);
    }

    #[test]
    fn not_positive_definite_names_the_pivot_in_the_callers_numbering() {
        // One negative diagonal entry: the pivots eliminated before it belong to an SPD
        // principal submatrix, so the factorization fails exactly there, whatever the
        // ordering. Plane grids factor simplicially, a cube's (more fill) supernodally.
        let mut paths = [false; 2];
        let cases = [(grid_laplacian(4, 4, 0.0), 5), (grid_laplacian(100, 100, 0.0), 4321), (cube_laplacian(16), 2345), (cube_laplacian(16), 4095)];
        for ((n, entries, mut values), k) in cases {
            let diagonal = entries.iter().position(|&e| e == (k as u32, k as u32)).unwrap();
            values[diagonal] = -1e3;
            let mut s = SpdSolver::new(n, &entries).unwrap();
            assert_eq!(s.factor(&values), Err(SolveError::NotPositiveDefinite { pivot: k }), "n = {n}");
            paths[matches!(s.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_)) as usize] = true;
        }
        assert_eq!(paths, [true, true], "both factorizations (simplicial, supernodal) tried");
    }

    #[test]
    fn not_positive_definite_is_an_error_not_a_panic() {
        // [[1, 2], [2, 1]] has eigenvalues 3 and -1.
        let mut s = SpdSolver::new(2, &[(0, 0), (1, 0), (1, 1)]).unwrap();
        assert!(matches!(s.factor(&[1.0, 2.0, 1.0]), Err(SolveError::NotPositiveDefinite { .. })));
        assert!(!s.is_factored());
        assert_eq!(s.solve_in_place(&mut [1.0, 1.0]), Err(SolveError::NotFactored));
        // Negative definite diagonal.
        assert!(matches!(s.factor(&[-1.0, 0.0, -1.0]), Err(SolveError::NotPositiveDefinite { .. })));
        // Singular (zero pivot).
        assert!(matches!(s.factor(&[1.0, 1.0, 1.0]), Err(SolveError::NotPositiveDefinite { .. })));
        // Recovers with valid values.
        s.factor(&[2.0, 1.0, 2.0]).unwrap();
        let mut b = [3.0, 3.0];
        s.solve_in_place(&mut b).unwrap();
        assert!((b[0] - 1.0).abs() < 1e-14 && (b[1] - 1.0).abs() < 1e-14);

        // A large indefinite grid matrix (shift pushes the diagonal below the spectrum's top):
        // exercises whatever path (simplicial/supernodal) faer picked for it.
        let (n, entries, values) = grid_laplacian(100, 100, -1.0);
        let mut s = SpdSolver::new(n, &entries).unwrap();
        assert!(matches!(s.factor(&values), Err(SolveError::NotPositiveDefinite { .. })));
        let (_, _, values) = grid_laplacian(100, 100, 0.0);
        s.factor(&values).unwrap();
    }

    #[test]
    fn duplicated_entries_are_summed() {
        // A = [[4, 1, 0], [1, 5, 2], [0, 2, 6]], with entries split into pieces, scrambled.
        let entries = [(1, 1), (0, 0), (2, 1), (1, 0), (0, 0), (2, 2), (1, 1), (2, 1), (1, 0)];
        let values = [2.0, 1.5, 0.5, 0.25, 2.5, 6.0, 3.0, 1.5, 0.75];
        let mut s = SpdSolver::new(3, &entries).unwrap();
        assert_eq!(s.a_values.len(), 5, "duplicates merged into one CSC slot each");
        s.factor(&values).unwrap();
        let x_true = [1.0, -2.0, 3.0];
        let mut b = [4.0 * 1.0 + 1.0 * -2.0, 1.0 + 5.0 * -2.0 + 2.0 * 3.0, 2.0 * -2.0 + 6.0 * 3.0];
        s.solve_in_place(&mut b).unwrap();
        for (x, t) in b.iter().zip(&x_true) {
            assert!((x - t).abs() < 1e-13, "{b:?}");
        }

        // Grid with every entry given twice with half the value.
        let (n, entries, values) = grid_laplacian(20, 15, 0.2);
        let mut e2 = entries.clone();
        e2.extend_from_slice(&entries);
        let v2: Vec<f64> = values.iter().chain(&values).map(|v| v / 2.0).collect();
        let mut s = SpdSolver::new(n, &e2).unwrap();
        s.factor(&v2).unwrap();
        let x_true = known_solution(n);
        let b = sym_matvec(n, &entries, &values, &x_true);
        let mut x = b.clone();
        s.solve_in_place(&mut x).unwrap();
        assert!(rel_residual(n, &entries, &values, &x, &b) < 1e-12);
    }

    #[test]
    fn bad_input_gives_errors() {
        // Out of range.
        assert!(matches!(
            SpdSolver::new(2, &[(0, 0), (1, 1), (2, 0)]),
            Err(SolveError::BadPattern(_))
        ));
        assert!(matches!(
            SpdSolver::new(2, &[(0, 0), (1, 1), (1, 7)]),
            Err(SolveError::BadPattern(_))
        ));
        // Upper triangle.
        assert!(matches!(
            SpdSolver::new(2, &[(0, 0), (0, 1), (1, 1)]),
            Err(SolveError::BadPattern(_))
        ));
        // Missing diagonal.
        let e = SpdSolver::new(3, &[(0, 0), (2, 1), (2, 2)]).unwrap_err();
        assert_eq!(e, SolveError::BadPattern("column 1 has no diagonal entry".into()));
        assert!(e.to_string().contains("column 1"));

        let mut s = SpdSolver::new(2, &[(0, 0), (1, 0), (1, 1)]).unwrap();
        // Values length mismatch.
        assert_eq!(
            s.factor(&[1.0, 2.0]),
            Err(SolveError::ValueCountMismatch { expected: 3, got: 2 })
        );
        // Non-finite values.
        assert_eq!(s.factor(&[1.0, f64::NAN, 1.0]), Err(SolveError::NonFiniteValue { entry: 1 }));
        assert_eq!(
            s.factor(&[f64::INFINITY, 0.0, 1.0]),
            Err(SolveError::NonFiniteValue { entry: 0 })
        );
        // Solve before factor.
        assert_eq!(s.solve_in_place(&mut [1.0, 1.0]), Err(SolveError::NotFactored));
        s.factor(&[2.0, 0.0, 2.0]).unwrap();
        // Rejected values keep the earlier factorization.
        assert!(s.factor(&[f64::NAN, 0.0, 1.0]).is_err());
        assert!(s.is_factored());
        // Right-hand side of wrong length / non-finite.
        assert_eq!(
            s.solve_in_place(&mut [1.0]),
            Err(SolveError::RhsLengthMismatch { expected: 2, got: 1 })
        );
        let mut b = [1.0, f64::NAN];
        assert_eq!(s.solve_in_place(&mut b), Err(SolveError::NonFiniteRhs { index: 1 }));
        let mut b = [2.0, 4.0];
        s.solve_in_place(&mut b).unwrap();
        assert!((b[0] - 1.0).abs() < 1e-15 && (b[1] - 2.0).abs() < 1e-15, "{b:?}");
        // Overflow inside the factorization.
        let mut s = SpdSolver::new(2, &[(0, 0), (1, 0), (1, 1)]).unwrap();
        let r = s.factor(&[1e-300, 1e300, 1e300]);
        assert!(r.is_err(), "{r:?}");
        assert!(!s.is_factored());
    }

    #[test]
    fn empty_and_diagonal_systems() {
        let mut s = SpdSolver::new(0, &[]).unwrap();
        s.factor(&[]).unwrap();
        s.solve_in_place(&mut []).unwrap();

        let mut s = SpdSolver::new(3, &[(0, 0), (1, 1), (2, 2)]).unwrap();
        s.factor(&[2.0, 4.0, 8.0]).unwrap();
        let mut b = [2.0, 2.0, 2.0];
        s.solve_in_place(&mut b).unwrap();
        for (x, t) in b.iter().zip([1.0, 0.5, 0.25]) {
            assert!((x - t).abs() < 1e-15, "{b:?}");
        }
    }

    /// Timing at n = 10⁵; run with `cargo test --lib solve -- --nocapture` to see it.
    #[test]
    fn timing_grid_laplacian_100k() {
        let (n, entries, values) = grid_laplacian(400, 250, 0.0);
        assert_eq!(n, 100_000);
        let x_true = known_solution(n);
        let b = sym_matvec(n, &entries, &values, &x_true);

        let t0 = Instant::now();
        let mut solver = SpdSolver::new(n, &entries).unwrap();
        let t_symbolic = t0.elapsed();
        let t1 = Instant::now();
        solver.factor(&values).unwrap();
        let t_factor = t1.elapsed();
        let mut x = b.clone();
        let t2 = Instant::now();
        solver.solve_in_place(&mut x).unwrap();
        let t_solve = t2.elapsed();
        let t3 = Instant::now();
        solver.factor(&values).unwrap();
        let mut x2 = b.clone();
        solver.solve_in_place(&mut x2).unwrap();
        let t_refactor = t3.elapsed();

        let res = rel_residual(n, &entries, &values, &x, &b);
        let kind = match solver.symbolic.raw() {
            faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Simplicial(_) => "simplicial",
            faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(_) => "supernodal",
        };
        println!(
            "solve timing, 400×250 grid Laplacian (n = {n}, nnz(L) = {}, {kind}): \
             symbolic {:.1} ms, factor {:.1} ms, solve {:.1} ms, factor + solve {:.1} ms, \
             refactor + solve {:.1} ms, relative residual {res:.2e}",
            solver.factor_nnz(),
            t_symbolic.as_secs_f64() * 1e3,
            t_factor.as_secs_f64() * 1e3,
            t_solve.as_secs_f64() * 1e3,
            (t_factor + t_solve).as_secs_f64() * 1e3,
            t_refactor.as_secs_f64() * 1e3,
        );
        assert!(res < 1e-10, "relative residual {res}");
    }
    #[cfg(feature = "eq3")]
    #[test]
    fn lu_solves_a_non_symmetric_system_and_reports_singularity() {
        // A = [[2, 1, 0], [0, 3, 1], [1, 0, 4]], with the (0, 0) entry split in two.
        let entries = [(0, 0), (0, 1), (1, 1), (1, 2), (2, 0), (2, 2), (0, 0)];
        let values = [1.5, 1.0, 3.0, 1.0, 1.0, 4.0, 0.5];
        let x_true = [1.0, -2.0, 0.5];
        let mut b = [2.0 * 1.0 - 2.0, 3.0 * -2.0 + 0.5, 1.0 + 4.0 * 0.5];
        solve_lu(3, &entries, &values, &mut b).unwrap();
        for (x, t) in b.iter().zip(&x_true) {
            assert!((x - t).abs() < 1e-14, "{b:?}");
        }
        // Structurally singular: column 1 is empty.
        let mut b = [1.0, 1.0];
        let e = solve_lu(2, &[(0, 0), (1, 0)], &[1.0, 1.0], &mut b).unwrap_err();
        assert!(matches!(e, SolveError::Singular { .. }), "{e:?}");
        assert_eq!(b, [1.0, 1.0]);
        // Numerically singular: [[1, 1], [1, 1]].
        let e = solve_lu(2, &[(0, 0), (0, 1), (1, 0), (1, 1)], &[1.0; 4], &mut b).unwrap_err();
        assert!(matches!(e, SolveError::Singular { .. }), "{e:?}");
        assert!(matches!(solve_lu(2, &[(2, 0)], &[1.0], &mut b), Err(SolveError::BadPattern(_))));
        solve_lu(0, &[], &[], &mut []).unwrap();
    }
}
