//! The pieces the constrained solves share: sparse Cholesky with reuse of
//! its symbolic part, the K ⊗ I₃ and F₁ ⊗ I₃ pattern tests (one matrix for
//! x, y and z), iterative refinement against the unregularized system,
//! Hager's condition estimate, residuals and errors.

use super::*;

/// K (both triangles) when H (unknowns 3p + c) is K ⊗ I₃: no entry between
/// different coordinates and the three coordinates' blocks equal entry for
/// entry. `None` otherwise.
pub(super) fn shared_block(h: &SparseColMat<usize, f64>) -> Option<SparseColMat<usize, f64>> {
    let n = h.nrows();
    if n == 0 || n % 3 != 0 {
        return None;
    }
    let mut triplets = Vec::with_capacity(h.compute_nnz() / 6 + n);
    for q in 0..n / 3 {
        let first = h.row_idx_of_col_raw(3 * q);
        if first.iter().any(|&i| i % 3 != 0) {
            return None;
        }
        let values = h.val_of_col(3 * q);
        for d in 1..3 {
            let rows = h.row_idx_of_col_raw(3 * q + d);
            if rows.len() != first.len()
                || rows.iter().zip(first).any(|(&a, &b)| a != b + d)
                || !same_bits(h.val_of_col(3 * q + d), values)
            {
                return None;
            }
        }
        for (&i, &v) in first.iter().zip(values) {
            triplets.push(Triplet::new(i / 3, q, v));
        }
    }
    SparseColMat::try_new_from_triplets(n / 3, n / 3, &triplets).ok()
}

/// F₁ when the rows (3s + c over unknowns 3p + c) are F₁ ⊗ I₃: row 3s + c
/// has terms on coordinate c only, and rows 3s + 1, 3s + 2 are row 3s
/// shifted, coefficient for coefficient. `None` otherwise.
pub(crate) fn shared_rows(rows: &[&[(usize, f64)]]) -> Option<Vec<Vec<(usize, f64)>>> {
    if rows.len() % 3 != 0 {
        return None;
    }
    rows.chunks_exact(3)
        .map(|xyz| {
            let x = xyz[0];
            let shifted = |d: usize| {
                xyz[d].len() == x.len()
                    && xyz[d]
                        .iter()
                        .zip(x)
                        .all(|(a, b)| a.0 == b.0 + d && a.1.to_bits() == b.1.to_bits())
            };
            (x.iter().all(|&(i, _)| i % 3 == 0) && shifted(1) && shifted(2))
                .then(|| x.iter().map(|&(i, a)| (i / 3, a)).collect())
        })
        .collect()
}

/// Why [`sparse_llt`] failed.
pub(crate) enum LltFailure {
    /// The symbolic analysis (too large).
    Symbolic(String),
    /// A pivot was not positive.
    NotPositive,
}

/// The sparse Cholesky factorization (AMD ordering) of the SPD matrix whose
/// lower triangle is `lower`: symbolic part and values. With `reuse` (of
/// the same pattern) its symbolic part serves and only the numbers are
/// factored.
pub(crate) fn sparse_llt(
    lower: &SparseColMat<usize, f64>,
    reuse: Option<&Arc<SymbolicCholesky<usize>>>,
) -> std::result::Result<(Arc<SymbolicCholesky<usize>>, Vec<f64>), LltFailure> {
    let symbolic = match reuse {
        Some(s) => s.clone(),
        None => Arc::new(
            factorize_symbolic_cholesky(
                lower.symbolic(),
                Side::Lower,
                SymmetricOrdering::Amd,
                Default::default(),
            )
            .map_err(|e| LltFailure::Symbolic(format!("{e:?}")))?,
        ),
    };
    let mut values = vec![0.0f64; symbolic.len_val()];
    let par = Par::Seq;
    let mut mem =
        MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()));
    symbolic
        .factorize_numeric_llt(
            &mut values,
            lower.as_ref(),
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|_| LltFailure::NotPositive)?;
    Ok((symbolic, values))
}

/// Equal bit for bit.
pub(super) fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Sparse rows equal index for index and bit for bit.
pub(crate) fn same_terms(a: &[(usize, f64)], b: &[(usize, f64)]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.0 == y.0 && x.1.to_bits() == y.1.to_bits())
}

pub(super) fn singular(n: usize, m: usize, condition: f64) -> Error {
    Error::Singular {
        unknowns: n,
        condition,
        hint: format!(
            "with the {m} independent constraint equations the KKT system is singular \
             to working precision: either a direction of the {n} free coordinates costs \
             nothing (fix more of the boundary, add constraints or stretch) or the \
             continuity conditions are too many for the mesh (try relaxed or vertex-only \
             continuity, or a higher degree)"
        ),
    }
}

/// Iterative refinement against the unregularized system, keeping the best
/// iterate: (z, steps, ‖r‖∞/‖rhs‖∞).
pub(super) fn refine(
    h: &SparseColMat<usize, f64>,
    rows: &[&[(usize, f64)]],
    rhs: &[f64],
    mut solve: impl FnMut(&[f64]) -> Vec<f64>,
) -> (Vec<f64>, usize, f64) {
    let size = rhs.len();
    let rhs_norm = rhs
        .iter()
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let mut z = vec![0.0; size];
    let mut residual = rhs.to_vec();
    let mut best = f64::INFINITY;
    let mut steps = 0;
    for step in 0..30 {
        let dz = solve(&residual);
        let trial: Vec<f64> = (0..size).map(|i| z[i] + dz[i]).collect();
        let r = kkt_residual(h, rows, &trial, rhs);
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
    (z, steps, best / rhs_norm)
}

pub(super) fn finish(n: usize, mut z: Vec<f64>, info: KktInfo) -> Result<KktSolution> {
    let relative_residual = info.relative_residual;
    if !relative_residual.is_finite() || relative_residual > 1e-6 {
        return Err(Error::Singular {
            unknowns: n,
            condition: info.condition,
            hint: format!(
                "the KKT system of {n} unknowns and {} constraint equations does not determine \
                 the control points (relative residual {relative_residual:.2e} after refinement): \
                 fix more of the boundary or add an energy term that sees every free point",
                info.size - n
            ),
        });
    }
    let lambda = z.split_off(n);
    Ok(KktSolution { x: z, lambda, info })
}

/// Hager's (1984) estimate of ‖A⁻¹‖₁ for a symmetric A, given its solve.
pub(crate) fn hager(size: usize, mut solve: impl FnMut(&[f64]) -> Vec<f64>) -> f64 {
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
pub(super) fn norm_1(h: &SparseColMat<usize, f64>, rows: &[&[(usize, f64)]]) -> f64 {
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

pub(super) fn diagonal(h: &SparseColMat<usize, f64>, j: usize) -> f64 {
    h.row_idx_of_col(j)
        .zip(h.val_of_col(j))
        .filter(|(i, _)| *i == j)
        .map(|(_, v)| *v)
        .sum()
}

pub(super) fn too_large(size: usize, why: &str) -> Error {
    Error::Mismatch {
        what: "KKT system".into(),
        expected: "a size that fits in memory".into(),
        got: format!("{size} rows ({why})"),
    }
}
