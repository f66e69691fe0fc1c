//! The equality-constrained quadratic minimization of eq. (32)–(33),
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

use crate::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymmetricOrdering};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par, Side};

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
    /// Non-zeros of the factor L.
    pub factor_nonzeros: usize,
    /// The regularization δ used.
    pub delta: f64,
    /// Steps of iterative refinement taken.
    pub refinement_steps: usize,
    /// ‖r‖∞ / ‖rhs‖∞ of the unregularized system at the end.
    pub relative_residual: f64,
    /// Estimated 1-norm condition number ‖K‖₁‖K⁻¹‖₁ of the KKT matrix
    /// (Hager's estimator through the factorization, after scaling by the
    /// largest diagonal entry of H).
    pub condition: f64,
}

/// The solution x, the multipliers λ and how the solve went.
pub(crate) struct KktSolution {
    pub x: Vec<f64>,
    pub lambda: Vec<f64>,
    pub info: KktInfo,
}

/// Solves the KKT system for H (n × n, both triangles stored), the rows of
/// F over 0 … n−1, b and g.
pub(crate) fn solve_kkt(
    h: &SparseColMat<usize, f64>,
    rows: &[&[(usize, f64)]],
    b: &[f64],
    g: &[f64],
) -> Result<KktSolution> {
    let n = h.nrows();
    let m = rows.len();
    let size = n + m;
    let hscale = (0..n)
        .map(|j| diagonal(h, j).abs())
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let delta = DELTA * hscale;
    let mut triplets: Vec<Triplet<usize, usize, f64>> =
        Vec::with_capacity(h.compute_nnz() / 2 + n + 2 * m);
    for j in 0..n {
        for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
            if i >= j {
                triplets.push(Triplet::new(i, j, *v));
            }
        }
        triplets.push(Triplet::new(j, j, delta));
    }
    for (r, row) in rows.iter().enumerate() {
        for &(i, a) in row.iter() {
            triplets.push(Triplet::new(n + r, i, a));
        }
        triplets.push(Triplet::new(n + r, n + r, -delta));
    }
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(size, size, &triplets)
        .map_err(|e| too_large(size, &format!("{e:?}")))?;
    let symbolic = factorize_symbolic_cholesky(
        k.symbolic(),
        Side::Lower,
        SymmetricOrdering::Amd,
        Default::default(),
    )
    .map_err(|e| too_large(size, &format!("{e:?}")))?;
    let mut values = vec![0.0f64; symbolic.len_val()];
    let signs: Vec<i8> = (0..size).map(|i| if i < n { 1 } else { -1 }).collect();
    let par = Par::Seq;
    let mut mem = MemBuffer::new(
        symbolic
            .factorize_numeric_ldlt_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par)),
    );
    let ldlt = symbolic
        .factorize_numeric_ldlt(
            &mut values,
            k.as_ref(),
            Side::Lower,
            LdltRegularization {
                dynamic_regularization_signs: Some(&signs),
                dynamic_regularization_delta: delta,
                dynamic_regularization_epsilon: 1e-13 * hscale,
            },
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|e| Error::Singular {
            unknowns: n,
            condition: f64::INFINITY,
            hint: format!("the regularized KKT factorization failed ({e:?})"),
        })?;

    let solve = |v: &[f64], mem: &mut MemBuffer| {
        let mut col = Mat::<f64>::from_fn(size, 1, |i, _| v[i]);
        ldlt.solve_in_place_with_conj(Conj::No, col.as_mut(), par, MemStack::new(mem));
        (0..size).map(|i| col[(i, 0)]).collect::<Vec<f64>>()
    };
    let inverse_norm = hager(size, |v| solve(v, &mut mem));
    let condition = norm_1(h, rows) * inverse_norm;
    // Singular when δ would move the solution by more than 1% of itself.
    if inverse_norm.is_nan() || inverse_norm * delta > 0.01 {
        return Err(Error::Singular {
            unknowns: n,
            condition,
            hint: format!(
                "with the {m} independent constraint equations the KKT system is singular \
                 to working precision: either a direction of the {n} free coordinates costs \
                 nothing (fix more of the boundary, add constraints or stretch) or the \
                 continuity conditions are too many for the mesh (try relaxed or vertex-only \
                 continuity, or a higher degree)"
            ),
        });
    }
    let mut rhs = vec![0.0; size];
    for i in 0..n {
        rhs[i] = -b[i];
    }
    rhs[n..].copy_from_slice(g);
    let rhs_norm = rhs
        .iter()
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let mut z = vec![0.0; size];
    let mut residual = rhs.clone();
    let mut best = f64::INFINITY;
    let mut steps = 0;
    for step in 0..30 {
        let dz = solve(&residual, &mut mem);
        let trial: Vec<f64> = (0..size).map(|i| z[i] + dz[i]).collect();
        let r = kkt_residual(h, rows, &trial, &rhs);
        let norm = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if !norm.is_finite() || norm >= best {
            break;
        }
        steps = step;
        z = trial;
        residual = r;
        best = norm;
        if best <= 1e-15 * rhs_norm {
            break;
        }
    }
    let relative_residual = best / rhs_norm;
    if !relative_residual.is_finite() || relative_residual > 1e-6 {
        return Err(Error::Singular {
            unknowns: n,
            condition: f64::INFINITY,
            hint: format!(
                "the KKT system of {n} unknowns and {m} constraint equations does not determine \
                 the control points (relative residual {relative_residual:.2e} after refinement): \
                 fix more of the boundary or add an energy term that sees every free point"
            ),
        });
    }
    let lambda = z.split_off(n);
    Ok(KktSolution {
        x: z,
        lambda,
        info: KktInfo {
            size,
            factor_nonzeros: symbolic.len_val(),
            delta,
            refinement_steps: steps,
            relative_residual,
            condition,
        },
    })
}

/// Hager's (1984) estimate of ‖A⁻¹‖₁ for a symmetric A, given its solve.
fn hager(size: usize, mut solve: impl FnMut(&[f64]) -> Vec<f64>) -> f64 {
    let mut x = vec![1.0 / size as f64; size];
    let mut estimate = 0.0;
    for _ in 0..5 {
        let y = solve(&x);
        if y.iter().any(|v| !v.is_finite()) {
            return f64::INFINITY;
        }
        estimate = y.iter().map(|v| v.abs()).sum::<f64>();
        let xi: Vec<f64> = y
            .iter()
            .map(|v| if *v >= 0.0 { 1.0 } else { -1.0 })
            .collect();
        let z = solve(&xi);
        let (j, zmax) = z.iter().enumerate().fold((0, 0.0f64), |(bj, bm), (j, v)| {
            if v.abs() > bm {
                (j, v.abs())
            } else {
                (bj, bm)
            }
        });
        let ztx: f64 = z.iter().zip(&x).map(|(a, b)| a * b).sum();
        if zmax <= ztx {
            break;
        }
        x = vec![0.0; size];
        x[j] = 1.0;
    }
    estimate
}

/// ‖K₀‖₁ of the unregularized KKT matrix (its largest column sum).
fn norm_1(h: &SparseColMat<usize, f64>, rows: &[&[(usize, f64)]]) -> f64 {
    let n = h.nrows();
    let mut col = vec![0.0f64; n + rows.len()];
    for j in 0..n {
        col[j] = h.val_of_col(j).iter().map(|v| v.abs()).sum();
    }
    for (k, row) in rows.iter().enumerate() {
        for &(i, a) in row.iter() {
            col[i] += a.abs();
            col[n + k] += a.abs();
        }
    }
    col.into_iter().fold(0.0, f64::max)
}

/// rhs − K₀ z for the unregularized KKT matrix K₀.
fn kkt_residual(
    h: &SparseColMat<usize, f64>,
    rows: &[&[(usize, f64)]],
    z: &[f64],
    rhs: &[f64],
) -> Vec<f64> {
    let n = h.nrows();
    let mut r = rhs.to_vec();
    for j in 0..n {
        for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
            r[i] -= v * z[j];
        }
    }
    for (k, row) in rows.iter().enumerate() {
        let lam = z[n + k];
        let mut fx = 0.0;
        for &(i, a) in row.iter() {
            r[i] -= a * lam;
            fx += a * z[i];
        }
        r[n + k] -= fx;
    }
    r
}

fn diagonal(h: &SparseColMat<usize, f64>, j: usize) -> f64 {
    h.row_idx_of_col(j)
        .zip(h.val_of_col(j))
        .filter(|(i, _)| *i == j)
        .map(|(_, v)| *v)
        .sum()
}

fn too_large(size: usize, why: &str) -> Error {
    Error::Mismatch {
        what: "KKT system".into(),
        expected: "a size that fits in memory".into(),
        got: format!("{size} rows ({why})"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equality_constrained_least_distance() {
        // min ½|x|² s.t. x0 + x1 + x2 = 3, x0 − x1 = 1: x = (1.5, 0.5, 1).
        let t: Vec<_> = (0..3).map(|i| Triplet::new(i, i, 1.0)).collect();
        let h = SparseColMat::try_new_from_triplets(3, 3, &t).unwrap();
        let r0 = [(0, 1.0), (1, 1.0), (2, 1.0)];
        let r1 = [(0, 1.0), (1, -1.0)];
        let s = solve_kkt(&h, &[&r0, &r1], &[0.0; 3], &[3.0, 1.0]).unwrap();
        for (got, want) in s.x.iter().zip([1.5, 0.5, 1.0]) {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
        // Stationarity: x + Fᵀλ = 0.
        assert!((s.x[2] + s.lambda[0]).abs() < 1e-14);
        assert!(s.info.relative_residual < 1e-15);
    }

    #[test]
    fn singular_hessian_made_definite_by_constraints() {
        // H = 0 on x1: only the constraint x1 = 2 determines it.
        let t = vec![Triplet::new(0, 0, 2.0), Triplet::new(1, 1, 0.0)];
        let h = SparseColMat::try_new_from_triplets(2, 2, &t).unwrap();
        let r = [(1, 1.0)];
        let s = solve_kkt(&h, &[&r], &[-2.0, 0.0], &[2.0]).unwrap();
        assert!((s.x[0] - 1.0).abs() < 1e-14 && (s.x[1] - 2.0).abs() < 1e-14);
    }

    #[test]
    fn an_undetermined_unknown_is_an_error() {
        let t = vec![Triplet::new(0, 0, 1.0), Triplet::new(1, 1, 0.0)];
        let h = SparseColMat::try_new_from_triplets(2, 2, &t).unwrap();
        let err = solve_kkt(&h, &[], &[0.0, 1.0], &[]).err().unwrap();
        assert!(matches!(err, Error::Singular { .. }), "{err}");
    }
}
