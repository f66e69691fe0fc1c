//! The equality-constrained quadratic minimization of eq. (32)–(33),
//! and its special case without rows.
//!
//! ```text
//! minimize ½ xᵀH x + bᵀx  subject to  F x = g
//! ```
//!
//! through its KKT (saddle-point) system
//!
//! ```text
//! ⎡ H  Fᵀ ⎤ ⎡ x ⎤   ⎡ −b ⎤
//! ⎣ F  0  ⎦ ⎣ λ ⎦ = ⎣  g ⎦
//! ```
//!
//! factored as a quasi-definite matrix: +δ on the unknowns' diagonal, −δ on
//! the multipliers', so a sparse LDLᵀ without pivoting exists for any
//! symmetric ordering (Vanderbei 1995); faer's dynamic regularization
//! fixes any pivot of the wrong sign on the way. Iterative refinement
//! against the unregularized system then removes the δ error. (faer's
//! symmetric-indefinite LBLᵀ returned NaN on such systems, per the team's
//! measurements, so it is not used.) F must have full row rank (see the
//! reduction in `reduce.rs`).
//!
//! The quasi-definite factorization is only as stable as δ is large
//! against ‖K‖, and δ must be tiny for a singular system to show; with
//! many continuity rows it breaks down (measured: G1 at the vertices of
//! 10,000 cubic patches gave a non-finite inverse). Then the unregularized
//! system is factored by sparse LU with partial pivoting instead: stable,
//! about 3× slower (measured 5 s against 1.5 s at 10,000 patches), and
//! singular when its condition estimate exceeds 0.01/ε.
//!
//! Without rows, when no term couples the coordinates and every point is
//! free in all three or none, H = K ⊗ I₃: then K alone is factored by sparse
//! Cholesky and solves x, y and z as three right-hand sides (C0 surfaces:
//! 10,080 cubic patches 0.42 s against 0.72 s through the LDLᵀ of the
//! interleaved system, measured).

mod factor;
mod numerics;

use super::nullspace::NullSpace;
use crate::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::linalg::solvers::SolveCore;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LdltRef, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::solvers::Lu;
use faer::sparse::linalg::LuError;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par, Side};
use numerics::{diagonal, finish, norm_1, refine, same_bits, shared_block, singular, too_large};
pub(crate) use numerics::{hager, same_terms, shared_rows, sparse_llt, LltFailure};
use std::sync::{Arc, OnceLock};

/// δ relative to the largest diagonal entry of H. Small, so that the
/// regularized inverse still shows a singular direction as a norm of
/// about 1/δ (see [`KktInfo::condition`]); iterative refinement removes
/// its effect on the solution.
const DELTA: f64 = 1e-13;

/// What the KKT solve did and how well.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KktInfo {
    /// Unknowns plus multipliers.
    pub size: usize,
    /// Non-zeros of the factor L (LDLᵀ; faer does not expose the LU's).
    pub factor_nonzeros: Option<usize>,
    /// The regularization δ used.
    pub delta: f64,
    /// Steps of iterative refinement taken.
    pub refinement_steps: usize,
    /// ‖r‖∞ / ‖rhs‖∞ of the unregularized system at the end.
    pub relative_residual: f64,
    /// Estimated 1-norm condition number ‖K‖₁‖K⁻¹‖₁ of the KKT matrix
    /// (Hager's estimator through the factorization).
    pub condition: f64,
    /// Which factorization solved it.
    pub factorization: Factorization,
    /// Whether the system was one matrix for x, y and z: H = K ⊗ I₃ and
    /// F = F₁ ⊗ I₃ (no term or row couples the coordinates), factored at a
    /// third of the size with three right-hand sides. `size` and
    /// `factor_nonzeros` are then those of the one matrix.
    pub per_coordinate: bool,
    /// Whether the factorization reused the symbolic analysis (ordering,
    /// elimination tree) of an earlier one of the same pattern: only its
    /// numbers were redone (a weight changed; see [`crate::FactorCache`]).
    pub reused_symbolic: bool,
}

/// The factorization of the KKT matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Factorization {
    /// Sparse Cholesky of H (no constraint rows).
    Llt,
    /// The rows eliminated group by group (each group's unknowns shared
    /// with no other), then sparse Cholesky of the reduced Hessian ZᵀHZ
    /// (`solve/nullspace.rs`).
    NullSpace,
    /// Regularized quasi-definite LDLᵀ (the first choice with rows).
    Ldlt,
    /// Sparse LU with partial pivoting of the unregularized matrix (when
    /// the LDLᵀ broke down).
    Lu,
}

impl Factorization {
    /// "LLT", "null space + LLT", "LDLT" or "LU".
    pub fn name(self) -> &'static str {
        match self {
            Factorization::Llt => "LLT",
            Factorization::NullSpace => "null space + LLT",
            Factorization::Ldlt => "LDLT",
            Factorization::Lu => "LU",
        }
    }
}

/// The solution x, the multipliers λ and how the solve went.
pub(crate) struct KktSolution {
    pub x: Vec<f64>,
    pub lambda: Vec<f64>,
    pub info: KktInfo,
}

/// Factors the KKT matrix of H (n × n, both triangles stored) and the rows
/// of F over 0 … n−1, and solves it for b and g: LDLᵀ first, LU when that
/// breaks down. The factorization is returned to solve for other b and g.
pub(crate) fn solve_kkt(
    h: &SparseColMat<usize, f64>,
    rows: &[&[(usize, f64)]],
    b: &[f64],
    g: &[f64],
) -> Result<(KktFactor, KktSolution)> {
    match try_kkt(h, rows, b, g) {
        KktOutcome::Solved {
            factor, solution, ..
        } => Ok((*factor, solution)),
        KktOutcome::Unfactorable(e) | KktOutcome::Failed(e) => Err(e),
    }
}

/// What a KKT solve came to.
pub(crate) enum KktOutcome {
    /// Solved by `factor`. `first_choice`: the factorization is the one a
    /// solve with any other right-hand side would choose too (the LDLᵀ, or
    /// the LU because no LDLᵀ of the matrix exists), so reusing it gives
    /// what a fresh solve gives.
    Solved {
        factor: Box<KktFactor>,
        solution: KktSolution,
        first_choice: bool,
    },
    /// Neither factorization of the matrix exists (to working precision),
    /// whatever the right-hand side.
    Unfactorable(Error),
    /// A factorization exists but the solve for this right-hand side was
    /// not accurate enough.
    Failed(Error),
}

/// [`solve_kkt`], saying why it failed or whether the factorization is the
/// first choice for any right-hand side.
pub(crate) fn try_kkt(
    h: &SparseColMat<usize, f64>,
    rows: &[&[(usize, f64)]],
    b: &[f64],
    g: &[f64],
) -> KktOutcome {
    if let Some(done) = KktFactor::per_coordinate(h, rows, b, g) {
        return done;
    }
    if let Some(done) = KktFactor::null_space(h, rows, b, g) {
        return done;
    }
    let ldlt = KktFactor::ldlt(h, rows, None);
    let ldlt_exists = ldlt.is_ok();
    let first = ldlt.and_then(|f| {
        let s = f.solve(b, g)?;
        Ok((f, s))
    });
    let first = match first {
        Ok((factor, solution)) if solution.info.relative_residual <= 1e-12 => {
            return KktOutcome::Solved {
                factor: Box::new(factor),
                solution,
                first_choice: true,
            }
        }
        other => other,
    };
    let lu = KktFactor::lu(h, rows);
    let lu_exists = lu.is_ok();
    let err = match lu.and_then(|f| {
        let s = f.solve(b, g)?;
        Ok((f, s))
    }) {
        Ok((factor, solution)) => {
            return KktOutcome::Solved {
                factor: Box::new(factor),
                solution,
                first_choice: !ldlt_exists,
            }
        }
        Err(e) => e,
    };
    // The LU's verdict stands unless the LDLᵀ had a usable answer.
    match first {
        Ok((factor, solution)) if solution.info.relative_residual <= 1e-6 => KktOutcome::Solved {
            factor: Box::new(factor),
            solution,
            first_choice: false,
        },
        _ if !ldlt_exists && !lu_exists => KktOutcome::Unfactorable(err),
        _ => KktOutcome::Failed(err),
    }
}

/// A factored KKT matrix with the unregularized matrix it came from (for
/// iterative refinement, and to tell whether another system is this one):
/// it solves for any other b and g.
pub(crate) struct KktFactor {
    pub(crate) h: SparseColMat<usize, f64>,
    rows: Vec<Vec<(usize, f64)>>,
    inner: Inner,
    /// Entries of the factor: L's of the LDLᵀ; for the LU, the symbolic
    /// Cholesky factor's of the same pattern (faer does not expose the LU's
    /// own; L and U each hold at least that many).
    /// (For the LU, estimated when first asked: it costs an ordering.)
    factor_entries: OnceLock<usize>,
    /// What [`KktInfo`] says of the factorization.
    size: usize,
    delta: f64,
    condition: f64,
    /// Made by [`KktFactor::refactored`].
    reused_symbolic: bool,
}

enum Inner {
    /// The sparse Cholesky factor of H (no rows).
    Llt {
        symbolic: Arc<SymbolicCholesky<usize>>,
        values: Vec<f64>,
    },
    /// The factorization of [K F₁ᵀ; F₁ 0] when H = K ⊗ I₃ and F = F₁ ⊗ I₃
    /// (unknowns 3p + c, rows 3s + c): one system for the three coordinates.
    PerCoordinate(Box<KktFactor>),
    /// The rows eliminated, the reduced Hessian factored.
    NullSpace(NullSpace),
    /// The quasi-definite LDLᵀ of diag(I, D) K diag(I, D): its symbolic
    /// part and values, and the rows' scales D.
    Ldlt {
        symbolic: Arc<SymbolicCholesky<usize>>,
        values: Vec<f64>,
        row_scale: Vec<f64>,
    },
    Lu(Lu<usize, f64>),
}

impl KktFactor {
    /// K⁻¹v through the factorization (of the regularized matrix for LDLᵀ).
    fn apply(&self, v: &[f64]) -> Vec<f64> {
        if let Inner::NullSpace(ns) = &self.inner {
            return ns.apply(v);
        }
        if let Inner::PerCoordinate(one) = &self.inner {
            let n = self.h.nrows();
            let (m, r) = (n / 3, self.rows.len() / 3);
            let mut out = vec![0.0; self.size];
            for c in 0..3 {
                let w: Vec<f64> = (0..m)
                    .map(|p| v[3 * p + c])
                    .chain((0..r).map(|s| v[n + 3 * s + c]))
                    .collect();
                let y = one.apply(&w);
                for p in 0..m {
                    out[3 * p + c] = y[p];
                }
                for s in 0..r {
                    out[n + 3 * s + c] = y[m + s];
                }
            }
            return out;
        }
        let mut col = Mat::<f64>::from_fn(self.size, 1, |i, _| v[i]);
        match &self.inner {
            Inner::Ldlt {
                symbolic,
                values,
                row_scale,
            } => {
                // K⁻¹ = diag(I, D) (diag(I, D) K diag(I, D))⁻¹ diag(I, D).
                let n = self.h.nrows();
                for (r, d) in row_scale.iter().enumerate() {
                    col[(n + r, 0)] *= d;
                }
                let par = Par::Seq;
                let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, par));
                LdltRef::new(symbolic.as_ref(), values).solve_in_place_with_conj(
                    Conj::No,
                    col.as_mut(),
                    par,
                    MemStack::new(&mut mem),
                );
                for (r, d) in row_scale.iter().enumerate() {
                    col[(n + r, 0)] *= d;
                }
            }
            Inner::Lu(lu) => lu.solve_in_place_with_conj(Conj::No, col.as_mut()),
            Inner::Llt { symbolic, values } => LltRef::new(symbolic.as_ref(), values)
                .solve_in_place_with_conj(
                    Conj::No,
                    col.as_mut(),
                    Par::Seq,
                    MemStack::new(&mut MemBuffer::new(
                        symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
                    )),
                ),
            Inner::PerCoordinate(_) | Inner::NullSpace(_) => unreachable!("solved above"),
        }
        (0..self.size).map(|i| col[(i, 0)]).collect()
    }

    /// Solves the system for b and g, refined against the unregularized
    /// matrix.
    pub(crate) fn solve(&self, b: &[f64], g: &[f64]) -> Result<KktSolution> {
        let n = self.h.nrows();
        let mut rhs: Vec<f64> = b.iter().map(|v| -v).collect();
        rhs.extend_from_slice(g);
        let rows: Vec<&[(usize, f64)]> = self.rows.iter().map(Vec::as_slice).collect();
        let (z, steps, relative_residual) = refine(&self.h, &rows, &rhs, |v| self.apply(v));
        let (one, per_coordinate) = match &self.inner {
            Inner::PerCoordinate(one) => (&**one, true),
            _ => (self, false),
        };
        let (factorization, factor_nonzeros) = match &one.inner {
            Inner::Llt { symbolic, .. } => (Factorization::Llt, Some(symbolic.len_val())),
            Inner::Ldlt { symbolic, .. } => (Factorization::Ldlt, Some(symbolic.len_val())),
            Inner::Lu(_) => (Factorization::Lu, None),
            Inner::NullSpace(ns) => (Factorization::NullSpace, Some(ns.factor_entries())),
            Inner::PerCoordinate(_) => unreachable!("one level"),
        };
        finish(
            n,
            z,
            KktInfo {
                size: one.size,
                factor_nonzeros,
                delta: self.delta,
                refinement_steps: steps,
                relative_residual,
                condition: self.condition,
                factorization,
                per_coordinate,
                reused_symbolic: self.reused_symbolic,
            },
        )
    }

    /// Whether H and F are, value for value, the matrix factored.
    pub(crate) fn is_for(&self, h: &SparseColMat<usize, f64>, rows: &[&[(usize, f64)]]) -> bool {
        self.h_is(h) && self.rows_are(rows)
    }

    /// How many rows F has.
    pub(crate) fn row_count(&self) -> usize {
        self.rows.len()
    }

    /// Whether H is, value for value, the one factored.
    pub(crate) fn h_is(&self, h: &SparseColMat<usize, f64>) -> bool {
        h.nrows() == self.h.nrows()
            && h.compute_nnz() == self.h.compute_nnz()
            && (0..h.ncols()).all(|j| {
                h.row_idx_of_col_raw(j) == self.h.row_idx_of_col_raw(j)
                    && same_bits(h.val_of_col(j), self.h.val_of_col(j))
            })
    }

    /// About how many bytes it holds.
    pub(crate) fn bytes(&self) -> usize {
        // A value and an index per entry, of H and F and of the factor.
        let entries = self.h.compute_nnz() + self.rows.iter().map(Vec::len).sum::<usize>();
        let factor = *self.factor_entries.get_or_init(|| self.lu_fill());
        16 * (entries + factor)
    }

    /// Twice the symbolic Cholesky fill of the KKT pattern (AMD order): L
    /// and U of the LU hold at least that many entries.
    fn lu_fill(&self) -> usize {
        let n = self.h.nrows();
        let mut t: Vec<Triplet<usize, usize, f64>> = Vec::new();
        for j in 0..n {
            t.extend(
                self.h
                    .row_idx_of_col(j)
                    .filter(|&i| i >= j)
                    .map(|i| Triplet::new(i, j, 1.0)),
            );
            t.push(Triplet::new(j, j, 1.0));
        }
        for (r, row) in self.rows.iter().enumerate() {
            t.extend(row.iter().map(|&(i, _)| Triplet::new(n + r, i, 1.0)));
            t.push(Triplet::new(n + r, n + r, 1.0));
        }
        SparseColMat::<usize, f64>::try_new_from_triplets(self.size, self.size, &t)
            .ok()
            .and_then(|k| {
                factorize_symbolic_cholesky(
                    k.symbolic(),
                    Side::Lower,
                    SymmetricOrdering::Amd,
                    Default::default(),
                )
                .ok()
            })
            .map_or(t.len(), |s| 2 * s.len_val())
    }
}
#[cfg(test)]
mod tests;
