//! The KKT matrix factored: sparse Cholesky without rows; the rows
//! eliminated group by group (null space) when they are local; otherwise
//! regularized quasi-definite LDLᵀ, and sparse LU when that breaks down; per
//! coordinate when nothing couples x, y and z; refactored on the same
//! ordering when only the numbers change.

use super::*;

impl KktFactor {
    /// When H = K ⊗ I₃ and F = F₁ ⊗ I₃: the factorization of the one
    /// system (K, F₁), as [`try_kkt`] chooses it, and the solve of the
    /// whole system through it (refined against the whole). `None` when
    /// the system is not of that form or the one system's solve failed for
    /// its right-hand side (the whole system is then factored as it is);
    /// `Unfactorable` (with the whole system's counts) when the one system
    /// is singular — the whole matrix is three copies of it, rows and
    /// columns permuted, and is not tried (measured: 0.27 s of LU per
    /// attempt on exact G1 at 1,000 patches).
    pub(super) fn per_coordinate(
        h: &SparseColMat<usize, f64>,
        rows: &[&[(usize, f64)]],
        b: &[f64],
        g: &[f64],
    ) -> Option<KktOutcome> {
        let k = shared_block(h)?;
        let f1 = shared_rows(rows)?;
        let f1: Vec<&[(usize, f64)]> = f1.iter().map(Vec::as_slice).collect();
        let (one, first_choice) = if f1.is_empty() {
            (Box::new(Self::llt(&k, None).ok()?), true)
        } else {
            // The one system's right-hand sides do not matter to its
            // factorization; the x coordinates' serve.
            let bx: Vec<f64> = b.iter().step_by(3).copied().collect();
            let gx: Vec<f64> = g.iter().step_by(3).copied().collect();
            match try_kkt(&k, &f1, &bx, &gx) {
                KktOutcome::Solved {
                    factor,
                    first_choice,
                    ..
                } => (factor, first_choice),
                // The whole matrix is three copies of this one, rows and
                // columns permuted: singular with it (said with its counts).
                KktOutcome::Unfactorable(Error::Singular { condition, .. }) => {
                    return Some(KktOutcome::Unfactorable(singular(
                        h.nrows(),
                        rows.len(),
                        condition,
                    )))
                }
                _ => return None,
            }
        };
        let (delta, condition, entries) =
            (one.delta, one.condition, one.factor_entries.get().copied());
        let mut f = Self::new(
            h,
            rows,
            Inner::PerCoordinate(one),
            delta,
            entries.map(|e| 3 * e),
        );
        f.condition = condition;
        match f.solve(b, g) {
            Ok(solution) if solution.info.relative_residual <= 1e-12 => Some(KktOutcome::Solved {
                factor: Box::new(f),
                solution,
                first_choice,
            }),
            _ => None,
        }
    }

    /// The null-space elimination of local rows ([`NullSpace`]) and the
    /// solve through it; `None` when it does not apply or does not solve to
    /// 1e-12 (the KKT factorizations then take over).
    pub(super) fn null_space(
        h: &SparseColMat<usize, f64>,
        rows: &[&[(usize, f64)]],
        b: &[f64],
        g: &[f64],
    ) -> Option<KktOutcome> {
        if rows.is_empty() {
            return None;
        }
        let f = Self::with_null_space(h, rows, NullSpace::new(h, rows)?)?;
        match f.solve(b, g) {
            Ok(solution) if solution.info.relative_residual <= 1e-12 => Some(KktOutcome::Solved {
                factor: Box::new(f),
                solution,
                first_choice: true,
            }),
            _ => None,
        }
    }

    /// The factor through the null-space elimination `ns`, `None` when its
    /// condition estimate exceeds 0.01/ε.
    pub(super) fn with_null_space(
        h: &SparseColMat<usize, f64>,
        rows: &[&[(usize, f64)]],
        ns: NullSpace,
    ) -> Option<Self> {
        let entries = ns.factor_entries();
        let mut f = Self::new(h, rows, Inner::NullSpace(ns), 0.0, Some(entries));
        f.condition = norm_1(h, rows) * hager(f.size, |v| f.apply(v));
        if !f.condition.is_finite() || f.condition * f64::EPSILON > 0.01 {
            return None;
        }
        Some(f)
    }

    /// The factorization of another H with the pattern of this one's and
    /// the same rows, reusing this one's symbolic analysis (the ordering
    /// and elimination tree; for the null space also the elimination of the
    /// rows): only the numbers are factored again. `None` when the pattern
    /// differs, for an LU (faer keeps its symbolic part inside), or when
    /// the new matrix does not factor so (the caller then starts afresh).
    pub(crate) fn refactored(&self, h: &SparseColMat<usize, f64>) -> Option<Self> {
        if !self.same_pattern(h) {
            return None;
        }
        let rows: Vec<&[(usize, f64)]> = self.rows.iter().map(Vec::as_slice).collect();
        let mut f = match &self.inner {
            Inner::Llt { symbolic, .. } => Self::llt(h, Some(symbolic)).ok()?,
            Inner::Ldlt { symbolic, .. } => Self::ldlt(h, &rows, Some(symbolic)).ok()?,
            Inner::NullSpace(ns) => Self::with_null_space(h, &rows, ns.refactored(h)?)?,
            Inner::PerCoordinate(one) => {
                let one = one.refactored(&shared_block(h)?)?;
                let (delta, condition) = (one.delta, one.condition);
                let entries = one.factor_entries.get().copied();
                let inner = Inner::PerCoordinate(Box::new(one));
                let mut f = Self::new(h, &rows, inner, delta, entries.map(|e| 3 * e));
                f.condition = condition;
                f
            }
            Inner::Lu(_) => return None,
        };
        f.reused_symbolic = true;
        Some(f)
    }

    /// Whether H has the sparsity pattern of the H factored (its values
    /// may differ).
    pub(crate) fn same_pattern(&self, h: &SparseColMat<usize, f64>) -> bool {
        h.nrows() == self.h.nrows()
            && h.compute_nnz() == self.h.compute_nnz()
            && (0..h.ncols()).all(|j| h.row_idx_of_col_raw(j) == self.h.row_idx_of_col_raw(j))
    }

    /// Whether the rows are, coefficient for coefficient, those factored.
    pub(crate) fn rows_are(&self, rows: &[&[(usize, f64)]]) -> bool {
        rows.len() == self.rows.len() && rows.iter().zip(&self.rows).all(|(a, b)| same_terms(a, b))
    }

    /// The sparse Cholesky factorization of SPD H (no rows), with `reuse`'s
    /// symbolic analysis when given; singular when its condition estimate
    /// exceeds 0.01/ε.
    pub(super) fn llt(
        h: &SparseColMat<usize, f64>,
        reuse: Option<&Arc<SymbolicCholesky<usize>>>,
    ) -> Result<Self> {
        let n = h.nrows();
        let mut lower = Vec::with_capacity(h.compute_nnz() / 2 + n);
        for j in 0..n {
            for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
                if i >= j {
                    lower.push(Triplet::new(i, j, *v));
                }
            }
        }
        let lower = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &lower)
            .map_err(|e| too_large(n, &format!("{e:?}")))?;
        let (symbolic, values) = sparse_llt(&lower, reuse).map_err(|e| match e {
            LltFailure::Symbolic(why) => too_large(n, &why),
            LltFailure::NotPositive => singular(n, 0, f64::INFINITY),
        })?;
        let entries = symbolic.len_val();
        let mut f = Self::new(h, &[], Inner::Llt { symbolic, values }, 0.0, Some(entries));
        f.condition = norm_1(h, &[]) * hager(n, |v| f.apply(v));
        if !f.condition.is_finite() || f.condition * f64::EPSILON > 0.01 {
            return Err(singular(n, 0, f.condition));
        }
        Ok(f)
    }

    /// The regularized quasi-definite LDLᵀ, with `reuse`'s symbolic
    /// analysis when given; singular when δ would move the solution by more
    /// than 1% of itself.
    pub(super) fn ldlt(
        h: &SparseColMat<usize, f64>,
        rows: &[&[(usize, f64)]],
        reuse: Option<&Arc<SymbolicCholesky<usize>>>,
    ) -> Result<Self> {
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
        // Rows scaled to H's size: the factored matrix is
        // diag(I, D) K diag(I, D), whose quasi-definite LDLᵀ holds up where
        // rows of size 1 against H's diagonal of 1e3 broke it down.
        let row_scale: Vec<f64> = rows
            .iter()
            .map(|row| {
                let big = row.iter().fold(0.0f64, |m, &(_, a)| m.max(a.abs()));
                if big > 0.0 {
                    hscale / big
                } else {
                    1.0
                }
            })
            .collect();
        for (r, row) in rows.iter().enumerate() {
            for &(i, a) in row.iter() {
                triplets.push(Triplet::new(n + r, i, a * row_scale[r]));
            }
            triplets.push(Triplet::new(n + r, n + r, -delta));
        }
        let k = SparseColMat::<usize, f64>::try_new_from_triplets(size, size, &triplets)
            .map_err(|e| too_large(size, &format!("{e:?}")))?;
        let symbolic = match reuse {
            Some(s) => s.clone(),
            None => Arc::new(
                factorize_symbolic_cholesky(
                    k.symbolic(),
                    Side::Lower,
                    SymmetricOrdering::Amd,
                    Default::default(),
                )
                .map_err(|e| too_large(size, &format!("{e:?}")))?,
            ),
        };
        let mut values = vec![0.0f64; symbolic.len_val()];
        let signs: Vec<i8> = (0..size).map(|i| if i < n { 1 } else { -1 }).collect();
        let par = Par::Seq;
        let mut mem =
            MemBuffer::new(symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()));
        symbolic
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
        let entries = symbolic.len_val();
        let mut f = Self::new(
            h,
            rows,
            Inner::Ldlt {
                symbolic,
                values,
                row_scale,
            },
            delta,
            Some(entries),
        );
        let inverse_norm = hager(size, |v| f.apply(v));
        f.condition = norm_1(h, rows) * inverse_norm;
        if inverse_norm.is_nan() || inverse_norm * delta > 0.01 {
            return Err(singular(n, m, f.condition));
        }
        Ok(f)
    }

    /// Sparse LU with partial pivoting of the unregularized matrix;
    /// singular when its condition estimate exceeds 0.01/ε.
    pub(super) fn lu(h: &SparseColMat<usize, f64>, rows: &[&[(usize, f64)]]) -> Result<Self> {
        let n = h.nrows();
        let m = rows.len();
        let size = n + m;
        let mut triplets: Vec<Triplet<usize, usize, f64>> =
            Vec::with_capacity(h.compute_nnz() + 2 * rows.iter().map(|r| r.len()).sum::<usize>());
        for j in 0..n {
            for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
                triplets.push(Triplet::new(i, j, *v));
            }
        }
        for (r, row) in rows.iter().enumerate() {
            for &(i, a) in row.iter() {
                triplets.push(Triplet::new(n + r, i, a));
                triplets.push(Triplet::new(i, n + r, a));
            }
        }
        let k = SparseColMat::<usize, f64>::try_new_from_triplets(size, size, &triplets)
            .map_err(|e| too_large(size, &format!("{e:?}")))?;
        let lu = k.as_ref().sp_lu().map_err(|e| match e {
            LuError::SymbolicSingular { .. } => singular(n, m, f64::INFINITY),
            LuError::Generic(e) => too_large(size, &format!("{e:?}")),
        })?;
        let mut f = Self::new(h, rows, Inner::Lu(lu), 0.0, None);
        f.condition = norm_1(h, rows) * hager(size, |v| f.apply(v));
        if !f.condition.is_finite() || f.condition * f64::EPSILON > 0.01 {
            return Err(singular(n, m, f.condition));
        }
        Ok(f)
    }

    pub(super) fn new(
        h: &SparseColMat<usize, f64>,
        rows: &[&[(usize, f64)]],
        inner: Inner,
        delta: f64,
        factor_entries: Option<usize>,
    ) -> Self {
        let known = OnceLock::new();
        if let Some(e) = factor_entries {
            let _ = known.set(e);
        }
        Self {
            factor_entries: known,
            h: h.clone(),
            rows: rows.iter().map(|r| r.to_vec()).collect(),
            size: h.nrows() + rows.len(),
            inner,
            delta,
            condition: f64::NAN,
            reused_symbolic: false,
        }
    }
}
