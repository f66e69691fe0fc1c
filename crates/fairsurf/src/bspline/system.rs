//! The assembled free block of a B-spline problem and its unconstrained
//! solve: Cholesky (dense for small blocks, else sparse), refinement, the
//! check's corrections.

use crate::check;
use crate::solve::compensated::dot2_residual;
use crate::solve::dense::{SpdFactor, SpdOptions};
use crate::solve::kkt::KktInfo;
use crate::solve::kkt::{hager, sparse_llt, LltFailure};
use crate::{Error, Result, Vec3};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par};
use std::sync::Arc;
use std::time::Instant;

/// Free blocks of at most this many unknowns are factored dense: for the
/// small systems of a fill (16–40 free points, 48–120 unknowns coupled by
/// the normal field) faer's sparse Cholesky took 0.5 ms on 108 unknowns
/// (0.18 ms of it the symbolic analysis), its dense one a tenth of that.
pub(crate) const DENSE_UNKNOWNS: usize = 160;

/// Why a free block is not positive definite.
const HINT: &str =
    "the energy does not determine the free control points: add bend or stretch, or fix more points";

/// A B-spline system's Cholesky factor, kept between solves for the
/// editor's drags ([`crate::FactorCache::solve_bspline`]): the matrix it
/// factors, the factor, and the matrix's condition estimate.
#[derive(Debug)]
pub(crate) struct BSplineFactor {
    numbers: Numbers,
    condition: f64,
}

/// The matrix and its factor.
#[derive(Debug)]
enum Numbers {
    /// Sparse: the lower triangle, the symbolic analysis (AMD ordering,
    /// elimination tree) and the values.
    Sparse {
        lower: SparseColMat<usize, f64>,
        symbolic: Arc<SymbolicCholesky<usize>>,
        values: Vec<f64>,
    },
    /// Dense (at most [`DENSE_UNKNOWNS`] unknowns): the lower triangle
    /// (the upper zero) and its factor (equilibrated, on this thread:
    /// [`SpdFactor`]).
    Dense { lower: Mat<f64>, factor: SpdFactor },
}

/// A matrix to factor or factored, in the form its size asks for.
enum Matrix<'a> {
    Sparse(&'a SparseColMat<usize, f64>),
    Dense(&'a Mat<f64>),
}

/// [`Matrix`], owned.
enum Owned {
    Sparse(SparseColMat<usize, f64>),
    Dense(Mat<f64>),
}

impl Owned {
    fn as_matrix(&self) -> Matrix<'_> {
        match self {
            Owned::Sparse(m) => Matrix::Sparse(m),
            Owned::Dense(m) => Matrix::Dense(m),
        }
    }
}

impl BSplineFactor {
    /// Bytes held (matrix and factor).
    pub(crate) fn bytes(&self) -> usize {
        match &self.numbers {
            Numbers::Sparse { lower, values, .. } => {
                16 * (values.len() + lower.val().len()) + 8 * lower.ncols()
            }
            Numbers::Dense { lower, .. } => 16 * lower.nrows() * lower.ncols(),
        }
    }

    /// The factor's stored numbers.
    fn nonzeros(&self) -> usize {
        match &self.numbers {
            Numbers::Sparse { values, .. } => values.len(),
            Numbers::Dense { lower, .. } => lower.nrows() * (lower.nrows() + 1) / 2,
        }
    }

    /// Solves H x = b in place, one column per right-hand side.
    fn solve_in_place(&self, rhs: &mut Mat<f64>) {
        match &self.numbers {
            Numbers::Sparse {
                symbolic, values, ..
            } => {
                let par = Par::Seq;
                let mut mem =
                    MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), par));
                LltRef::new(symbolic.as_ref(), values).solve_in_place_with_conj(
                    Conj::No,
                    rhs.as_mut(),
                    par,
                    MemStack::new(&mut mem),
                );
            }
            Numbers::Dense { factor, .. } => *rhs = factor.apply(rhs),
        }
    }

    /// The matrix factored.
    fn matrix(&self) -> Matrix<'_> {
        match &self.numbers {
            Numbers::Sparse { lower, .. } => Matrix::Sparse(lower),
            Numbers::Dense { lower, .. } => Matrix::Dense(lower),
        }
    }

    /// Whether `m` has this matrix's nonzero pattern (dense: its size — so
    /// the cache's newest dense factor replaces a kept one of its size even
    /// for another free set of as many points: only speed is lost).
    fn same_pattern(&self, m: &Matrix) -> bool {
        match (self.matrix(), m) {
            (Matrix::Sparse(a), Matrix::Sparse(b)) => {
                let (a, b) = (a.symbolic(), b.symbolic());
                a.nrows() == b.nrows() && a.col_ptr() == b.col_ptr() && a.row_idx() == b.row_idx()
            }
            (Matrix::Dense(a), Matrix::Dense(b)) => a.nrows() == b.nrows(),
            _ => false,
        }
    }

    /// Whether `m` is this matrix, value for value.
    fn same_matrix(&self, m: &Matrix) -> bool {
        self.same_pattern(m)
            && match (self.matrix(), m) {
                (Matrix::Sparse(a), Matrix::Sparse(b)) => a.val() == b.val(),
                (Matrix::Dense(a), Matrix::Dense(b)) => a == *b,
                _ => false,
            }
    }

    /// Whether `other` factors a matrix of this one's pattern (a weight
    /// slider's steps: the newest replaces the others in the cache).
    pub(crate) fn same_pattern_as(&self, other: &BSplineFactor) -> bool {
        self.same_pattern(&other.matrix())
    }
}

/// How much of a kept factorization a solve used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Reuse {
    /// None: ordering and numbers computed.
    New,
    /// The ordering and elimination tree of one with the same pattern (a
    /// weight changed): only the numbers were computed.
    Symbolic,
    /// The whole factor of the same matrix (a fixed point moved): only the
    /// right-hand side was new.
    Numeric,
}

/// The assembled free block.
pub(super) struct System {
    pub(super) dim: usize,
    /// Lower triangle (duplicates are summed).
    pub(super) lower: Vec<Triplet<usize, usize, f64>>,
    /// Right-hand side, one column per coordinate or one.
    pub(super) b: Mat<f64>,
    /// ‖H‖∞ of the free block, the matrix solved (row sums of the entries'
    /// magnitudes as assembled: an upper bound when an entry arrives in
    /// parts). The fixed points' columns are in `b`, so ‖H‖∞‖x‖∞ + ‖b‖∞
    /// is the relative gradient's scale of this system; a Bézier solve,
    /// whose right-hand side is the linear term alone, takes its whole rows.
    pub(super) h_inf: f64,
    /// max H_ii of the free block.
    pub(super) h_diag: f64,
}

impl System {
    /// Row by row, the (column, value) pairs of the whole symmetric H.
    pub(super) fn rows(&self) -> Vec<Vec<(usize, f64)>> {
        let mut rows = vec![Vec::new(); self.dim];
        for t in &self.lower {
            rows[t.row].push((t.col, t.val));
            if t.row != t.col {
                rows[t.col].push((t.row, t.val));
            }
        }
        rows
    }

    /// b − H x with every row a compensated (Dot2) dot product: as if
    /// computed in twice the working precision, then rounded.
    pub(super) fn residual_dot2(&self, rows: &[Vec<(usize, f64)>], x: &Mat<f64>) -> Mat<f64> {
        let mut a = Vec::new();
        let mut xs = Vec::new();
        Mat::from_fn(self.dim, x.ncols(), |i, c| {
            a.clear();
            xs.clear();
            for &(j, v) in &rows[i] {
                a.push(v);
                xs.push(x[(j, c)]);
            }
            dot2_residual(self.b[(i, c)], &a, &xs)
        })
    }

    /// b − H x, from the lower triangle.
    pub(super) fn residual(&self, x: &Mat<f64>) -> Mat<f64> {
        let mut r = self.b.clone();
        for t in &self.lower {
            for c in 0..x.ncols() {
                r[(t.row, c)] -= t.val * x[(t.col, c)];
                if t.row != t.col {
                    r[(t.col, c)] -= t.val * x[(t.row, c)];
                }
            }
        }
        r
    }
}

/// The free points solved and the report's figures that depend on how.
pub(super) struct Solved {
    /// The free points, in the order of the free list.
    pub(super) x: Vec<Vec3>,
    /// Σ x_i² over the free coordinates.
    pub(super) xx: f64,
    pub(super) gradient_norm: f64,
    pub(super) relative_gradient: f64,
    pub(super) residual: f64,
    /// E(x) − min E, before scaling.
    pub(super) excess: f64,
    pub(super) corrections: usize,
    pub(super) condition_estimate: f64,
    pub(super) factor_nonzeros: usize,
    pub(super) kkt: Option<KktInfo>,
    /// Seconds factoring and solving.
    pub(super) factor: f64,
    pub(super) solve: f64,
}

/// Cholesky of the free block (dense up to [`DENSE_UNKNOWNS`] unknowns,
/// else sparse with AMD ordering), one step of iterative refinement, then
/// the check's Newton corrections while the excess ½ gᵀH⁻¹g (g = b − Hx in
/// compensated products) falls.
/// With `kept` factorizations: the one of this very matrix is used as it is
/// (`Reuse::Numeric`), or the ordering of one with this pattern
/// (`Reuse::Symbolic`). Returns the factor used, to keep.
pub(super) fn unconstrained(
    sys: &System,
    coupled: bool,
    nf: usize,
    kept: &[Arc<BSplineFactor>],
) -> Result<(Solved, Arc<BSplineFactor>, Reuse)> {
    let t1 = Instant::now();
    let matrix = if sys.dim <= DENSE_UNKNOWNS {
        let mut full = Mat::<f64>::zeros(sys.dim, sys.dim);
        for t in &sys.lower {
            full[(t.row, t.col)] += t.val;
        }
        Owned::Dense(full)
    } else {
        Owned::Sparse(
            SparseColMat::try_new_from_triplets(sys.dim, sys.dim, &sys.lower)
                .expect("the triplets index the free block"),
        )
    };
    let same = kept.iter().find(|f| f.same_matrix(&matrix.as_matrix()));
    let pattern = kept
        .iter()
        .find(|f| f.same_pattern(&matrix.as_matrix()))
        .and_then(|f| match &f.numbers {
            Numbers::Sparse { symbolic, .. } => Some(symbolic),
            Numbers::Dense { .. } => None,
        });
    let not_positive = || Error::NotPositiveDefinite {
        unknowns: 3 * nf,
        pivot: 0,
        hint: HINT.into(),
    };
    let (factored, reuse) = match same {
        Some(f) => (f.clone(), Reuse::Numeric),
        None => {
            let (numbers, reuse) = match matrix {
                Owned::Dense(lower) => {
                    let options = SpdOptions {
                        estimate_condition: false,
                        singular_condition: f64::INFINITY,
                    };
                    // Named by free coordinates, as the sparse path does.
                    let factor =
                        SpdFactor::new(&lower, options, HINT, None).map_err(|e| match e {
                            Error::NotPositiveDefinite { .. } => not_positive(),
                            other => other,
                        })?;
                    (Numbers::Dense { lower, factor }, Reuse::New)
                }
                Owned::Sparse(lower) => {
                    let (symbolic, values) = sparse_llt(&lower, pattern).map_err(|e| match e {
                        LltFailure::NotPositive => not_positive(),
                        LltFailure::Symbolic(why) => Error::Mismatch {
                            what: "B-spline system".into(),
                            expected: "a size that fits in memory".into(),
                            got: format!("{nf} free points ({why})"),
                        },
                    })?;
                    let reuse = if pattern.is_some() {
                        Reuse::Symbolic
                    } else {
                        Reuse::New
                    };
                    let numbers = Numbers::Sparse {
                        lower,
                        symbolic,
                        values,
                    };
                    (numbers, reuse)
                }
            };
            let mut f = BSplineFactor {
                numbers,
                condition: f64::NAN,
            };
            // ‖H‖₁‖H⁻¹‖₁ (H symmetric: its 1-norm is its ∞-norm), Hager's
            // estimate through the factor.
            f.condition = sys.h_inf
                * hager(sys.dim, |v| {
                    let mut m = Mat::from_fn(sys.dim, 1, |i, _| v[i]);
                    f.solve_in_place(&mut m);
                    (0..sys.dim).map(|i| m[(i, 0)]).collect()
                });
            (Arc::new(f), reuse)
        }
    };
    let factor = t1.elapsed().as_secs_f64();

    let t2 = Instant::now();
    let mut solve = |rhs: &mut Mat<f64>| factored.solve_in_place(rhs);
    let mut x = sys.b.clone();
    solve(&mut x);
    // One step of iterative refinement: x += H⁻¹(b − Hx).
    let mut d = sys.residual(&x);
    solve(&mut d);
    x += &d;
    // The check's gradient, b − Hx with compensated products, and the
    // excess ½ gᵀH⁻¹g; Newton corrections while it falls.
    let rows = sys.rows();
    let excess_at = |x: &Mat<f64>, solve: &mut dyn FnMut(&mut Mat<f64>)| {
        let g = sys.residual_dot2(&rows, x);
        let mut d = g.clone();
        solve(&mut d);
        let e = 0.5 * dot(&g, &d);
        (e, g, d)
    };
    let (mut excess, mut r, mut d) = excess_at(&x, &mut solve);
    let mut corrections = 0;
    while corrections < check::MAX_CORRECTIONS && excess > 0.0 {
        let next = &x + &d;
        let (e2, r2, d2) = excess_at(&next, &mut solve);
        if e2.is_nan() || e2 >= excess {
            break;
        }
        (x, excess, r, d) = (next, e2, r2, d2);
        corrections += 1;
    }
    let condition_estimate = factored.condition;
    let solve_s = t2.elapsed().as_secs_f64();
    let x_free: Vec<Vec3> = (0..nf)
        .map(|row| {
            if coupled {
                [x[(3 * row, 0)], x[(3 * row + 1, 0)], x[(3 * row + 2, 0)]]
            } else {
                [x[(row, 0)], x[(row, 1)], x[(row, 2)]]
            }
        })
        .collect();
    let gradient_norm = inf(&r);
    let denom = sys.h_inf * inf(&x) + inf(&sys.b);
    let relative_gradient = if denom > 0.0 {
        gradient_norm / denom
    } else {
        gradient_norm
    };
    let residual = if inf(&sys.b) > 0.0 {
        gradient_norm / inf(&sys.b)
    } else {
        gradient_norm
    };
    let solved = Solved {
        x: x_free,
        xx: dot(&x, &x),
        gradient_norm,
        relative_gradient,
        residual,
        excess,
        corrections,
        condition_estimate,
        factor_nonzeros: factored.nonzeros(),
        kkt: None,
        factor,
        solve: solve_s,
    };
    Ok((solved, factored, reuse))
}

/// Σ a_ij b_ij.
fn dot(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    (0..a.ncols())
        .flat_map(|c| (0..a.nrows()).map(move |i| (i, c)))
        .map(|(i, c)| a[(i, c)] * b[(i, c)])
        .sum()
}

/// max |m_ij|.
fn inf(m: &Mat<f64>) -> f64 {
    (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |c| (i, c)))
        .fold(0.0f64, |a, (i, c)| a.max(m[(i, c)].abs()))
}
