//! Dense symmetric positive definite solves, with the accuracy measured.
//!
//! Bernstein-basis energy systems are ill-conditioned (condition numbers of
//! 1e8–1e11 at modest degrees, Wu & Yang §3; Monterde & Ugail §3). The solve
//! therefore:
//! 1. equilibrates symmetrically, Â = S H S with S = diag(1/√H_ii), which
//!    removes the large spread of Bernstein Gram diagonals;
//! 2. factors Â = L Lᵀ (up to [`TINY`] unknowns by a plain loop, past that a
//!    blocked Cholesky on faer's kernels, stopping between panels once the
//!    work is cancelled, [`crate::budget`]);
//! 3. refines iteratively with residuals computed in twice-working precision
//!    (Ogita–Rump–Oishi compensated dot products), so the returned solution of
//!    the assembled system is accurate to about ε even when cond·ε is not small;
//! 4. estimates the 2-norm condition number of Â (Lanczos for λ_max of Â
//!    and of Â⁻¹, the latter by solves with the factor) and reports it.

use super::compensated::residual;
use super::jacobi::TensorBasis;
use crate::{Error, Result};
use faer::linalg::matmul::triangular::BlockStructure;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par};

/// Options for [`SpdFactor::new`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct SpdOptions {
    pub estimate_condition: bool,
    pub singular_condition: f64,
}

/// A solved SPD system with its accuracy.
pub(crate) struct SpdSolution {
    /// The solution, one column per right-hand side.
    pub x: Mat<f64>,
    /// Residual rhs − Hx per column, compensated.
    pub residual: Mat<f64>,
    /// Refinement steps taken.
    pub refinement_steps: usize,
}

/// The Cholesky factor of an equilibrated SPD matrix (in the better basis,
/// with a preconditioner), ready for any number of right-hand sides.
#[derive(Debug)]
pub(crate) struct SpdFactor {
    /// The equilibration S = diag(1/√H_ii).
    s: Vec<f64>,
    /// L of Â = L Lᵀ (lower triangle; the upper is not read).
    l: Mat<f64>,
    basis: Option<TensorBasis>,
    /// Estimated condition number of the equilibrated matrix (NaN if not estimated).
    pub condition: f64,
    /// Seconds spent factoring.
    pub factor_seconds: f64,
}

impl SpdFactor {
    /// Factors symmetric positive definite H (only H's diagonal and the
    /// factor are read here; H itself is passed again to [`SpdFactor::solve`]).
    ///
    /// With `precond = (Ĥ, Q)`, Ĥ ≈ Qᵀ H Q assembled in a better-conditioned
    /// basis is factored instead (in its own storage: no copy) and serves as
    /// the preconditioner of iterative refinement on H itself.
    pub(crate) fn new(
        h: &Mat<f64>,
        opts: SpdOptions,
        hint: &str,
        precond: Option<(Mat<f64>, TensorBasis)>,
    ) -> Result<Self> {
        let n = h.nrows();
        let not_pd = |pivot| Error::NotPositiveDefinite {
            unknowns: n,
            pivot,
            hint: hint.to_string(),
        };
        let (mut l, basis) = match precond {
            Some((m, q)) => (m, Some(q)),
            None => (h.clone(), None),
        };
        if let Some(i) = (0..n).find(|&i| !(l[(i, i)] > 0.0 && l[(i, i)].is_finite())) {
            return Err(not_pd(i));
        }
        let s: Vec<f64> = (0..n).map(|i| 1.0 / l[(i, i)].sqrt()).collect();
        // Â = S M S in the lower triangle, all the factorization reads.
        for j in 0..n {
            for (x, si) in l.col_as_slice_mut(j)[j..].iter_mut().zip(&s[j..]) {
                *x *= si * s[j];
            }
        }
        let t0 = std::time::Instant::now();
        cholesky_in_place(l.as_mut()).map_err(|e| match e {
            CholeskyStop::NotPositive(index) => not_pd(index),
            CholeskyStop::Cancelled => Error::Cancelled,
        })?;
        let factor_seconds = t0.elapsed().as_secs_f64();
        let condition = if opts.estimate_condition {
            condition_estimate(&l)
        } else {
            f64::NAN
        };
        if condition > opts.singular_condition {
            return Err(Error::Singular {
                unknowns: n,
                condition,
                hint: hint.to_string(),
            });
        }
        Ok(Self {
            s,
            l,
            basis,
            condition,
            factor_seconds,
        })
    }

    /// x ≈ H⁻¹ r with the factor (no refinement).
    pub(crate) fn apply(&self, r: &Mat<f64>) -> Mat<f64> {
        let (n, s) = (self.s.len(), &self.s);
        let rq = self.basis.as_ref().map(|q| q.apply(r, true));
        let r = rq.as_ref().unwrap_or(r);
        let mut y = Mat::from_fn(n, r.ncols(), |i, c| s[i] * r[(i, c)]);
        llt_solve(&self.l, y.as_mut());
        let y = Mat::from_fn(n, r.ncols(), |i, c| s[i] * y[(i, c)]);
        match &self.basis {
            Some(q) => q.apply(&y, false),
            None => y,
        }
    }

    /// Solves H X = B for the factored H, refined iteratively against H
    /// itself with compensated residuals.
    pub(crate) fn solve(&self, h: &Mat<f64>, b: &Mat<f64>, max_steps: usize) -> SpdSolution {
        let (x, residual, refinement_steps) = refine(
            self.apply(b),
            |x| residual(h, x, b),
            |r| self.apply(r),
            max_steps,
        );
        SpdSolution {
            x,
            residual,
            refinement_steps,
        }
    }
}

/// Why [`cholesky_in_place`] stopped.
#[derive(Debug, PartialEq)]
pub(crate) enum CholeskyStop {
    /// The pivot of this row was not positive (or not finite).
    NotPositive(usize),
    /// The work was cancelled ([`crate::budget::checkpoint`]).
    Cancelled,
}

/// Columns per panel of [`cholesky_in_place`]: a panel of a 5,000-unknown
/// system takes a few tens of milliseconds, the longest a cancelled
/// factorization runs on.
const PANEL: usize = 256;

/// Below this many unknowns a factorization or a solve runs on one thread
/// and column by column: two threads and faer's blocked kernels cost more
/// than they save (this 2-core machine, Cholesky: 243 unknowns 0.16 ms alone,
/// 0.4 ms on two; 600: 1.6 / 2.5; 1083: 9.0 / 8.3).
const SMALL: usize = 1000;

/// A B, on this thread below about 4·10⁶ multiply-adds, else with faer's
/// global parallelism. faer's `*` always takes the global setting, which on
/// the editor's drags (a 121-point guide's H s, the rows' H x) woke the
/// pool for microseconds of work and left its threads spinning in
/// `sched_yield` (14–17% of the server's samples on 2 cores).
pub(crate) fn product(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let work = a.nrows() * a.ncols() * b.ncols();
    let par = if work < 4_000_000 {
        Par::Seq
    } else {
        faer::get_global_parallelism()
    };
    let mut out = Mat::<f64>::zeros(a.nrows(), b.ncols());
    faer::linalg::matmul::matmul(out.as_mut(), Accum::Replace, a, b, 1.0, par);
    out
}

/// A = L Lᵀ in place (the lower triangle becomes L; the strict upper
/// triangle is not read, and faer's kernels overwrite it within the
/// diagonal blocks). Up to [`TINY`] unknowns (column-major) by
/// [`cholesky_tiny`], a loop too short to need a cancellation check;
/// past that right-looking by panels of [`PANEL`]
/// columns on faer's kernels: the diagonal block by faer's Cholesky,
/// the panel below it by a triangular solve, the trailing lower triangle
/// by a symmetric rank-k update. Between panels it checks for
/// cancellation, so a cancelled solve stops within one panel's work
/// instead of running the whole O(n³/3) to its end.
pub(crate) fn cholesky_in_place(mut a: MatMut<'_, f64>) -> std::result::Result<(), CholeskyStop> {
    use faer::linalg::cholesky::llt::factor as llt;
    let n = a.nrows();
    if n <= TINY && a.row_stride() == 1 {
        return cholesky_tiny(a);
    }
    let par = if n < SMALL {
        Par::Seq
    } else {
        faer::get_global_parallelism()
    };
    let mut buffer = faer::dyn_stack::MemBuffer::new(llt::cholesky_in_place_scratch::<f64>(
        PANEL.min(n),
        par,
        Default::default(),
    ));
    let mut k = 0;
    while k < n {
        crate::budget::checkpoint().map_err(|_| CholeskyStop::Cancelled)?;
        let b = PANEL.min(n - k);
        let (_, _, _, rest) = a.rb_mut().split_at_mut(k, k);
        let (mut a11, _, mut a21, mut a22) = rest.split_at_mut(b, b);
        let stack = faer::dyn_stack::MemStack::new(&mut buffer);
        llt::cholesky_in_place(
            a11.rb_mut(),
            Default::default(),
            par,
            stack,
            Default::default(),
        )
        .map_err(|e| match e {
            llt::LltError::NonPositivePivot { index } => CholeskyStop::NotPositive(k + index),
        })?;
        if k + b < n {
            // A21 ← A21 L11⁻ᵀ, i.e. L11 A21ᵀ = A21ᵀ (old).
            solve_lower_triangular_in_place(a11.rb(), a21.rb_mut().transpose_mut(), par);
            // A22 ← A22 − A21 A21ᵀ, lower triangle only.
            faer::linalg::matmul::triangular::matmul(
                a22.rb_mut(),
                BlockStructure::TriangularLower,
                Accum::Add,
                a21.rb(),
                BlockStructure::Rectangular,
                a21.rb().transpose(),
                BlockStructure::Rectangular,
                -1.0,
                par,
            );
        }
        k += b;
    }
    Ok(())
}

/// Up to this many unknowns [`cholesky_in_place`] and [`gram`] run loops of
/// their own instead of faer's blocked kernels: faer's matrix product, on
/// its first call in a process, reads the CPU's cache sizes (about 100
/// sysfs files) and sizes its buffers by them — a 108-unknown Cholesky
/// took 1.6 ms in a fresh process against 0.05 ms warm, a whole
/// `fairsurf fill`'s library time on a four-sided hole.
const TINY: usize = 160;

/// [`cholesky_in_place`] column by column (left-looking: column j less
/// Σₖ₍ₖ₌₀…ⱼ₋₁₎ Lⱼₖ · column k, then divided by its pivot's root), for a
/// column-major A of at most [`TINY`] rows.
fn cholesky_tiny(mut a: MatMut<'_, f64>) -> std::result::Result<(), CholeskyStop> {
    let n = a.nrows();
    for j in 0..n {
        let (done, mut rest) = a.rb_mut().split_at_col_mut(j);
        let col = rest
            .rb_mut()
            .col_mut(0)
            .try_as_col_major_mut()
            .expect("column-major");
        let col = &mut col.as_slice_mut()[j..];
        for k in 0..j {
            let lk = done.rb().col(k).try_as_col_major().expect("column-major");
            let lk = &lk.as_slice()[j..];
            let ljk = lk[0];
            for (x, &l) in col.iter_mut().zip(lk) {
                *x -= ljk * l;
            }
        }
        let d = col[0];
        if !(d > 0.0 && d.is_finite()) {
            return Err(CholeskyStop::NotPositive(j));
        }
        let r = d.sqrt();
        col[0] = r;
        for x in &mut col[1..] {
            *x /= r;
        }
    }
    Ok(())
}

/// AᵀA (symmetric: its lower triangle by dot products of A's columns,
/// mirrored), by faer's product on this thread past [`TINY`] columns or
/// for a strided A.
pub(crate) fn gram(a: MatRef<'_, f64>) -> Mat<f64> {
    let n = a.ncols();
    let cols: Option<Vec<&[f64]>> = (0..n)
        .map(|j| a.col(j).try_as_col_major().map(|c| c.as_slice()))
        .collect();
    match cols {
        Some(cols) if n <= TINY => {
            let mut out = Mat::<f64>::zeros(n, n);
            for j in 0..n {
                for i in j..n {
                    let x = dot(cols[i], cols[j]);
                    out[(i, j)] = x;
                    out[(j, i)] = x;
                }
            }
            out
        }
        _ => {
            // On this thread, as the descent's per-span products always
            // ran (each a few ms at most: a thread pool's wake-up costs
            // more than it saves).
            let mut out = Mat::<f64>::zeros(n, n);
            faer::linalg::matmul::matmul(
                out.as_mut(),
                Accum::Replace,
                a.transpose(),
                a,
                1.0,
                Par::Seq,
            );
            out
        }
    }
}

/// X ← A⁻¹ X for A = L Lᵀ with L from [`cholesky_in_place`].
pub(crate) fn llt_solve(l: &Mat<f64>, mut x: MatMut<'_, f64>) {
    // One column, or a few of a small system: a pass over the factor per
    // column by hand (faer's blocked solve spends 1.5 ms setting up on its
    // first call in a process, a fresh command's every solve; past SMALL it
    // reads the factor once for all columns).
    if (x.ncols() == 1 || l.nrows() < SMALL) && x.ncols() <= 4 && x.row_stride() == 1 {
        for c in 0..x.ncols() {
            if let Some(col) = x.rb_mut().col_mut(c).try_as_col_major_mut() {
                factor_solve(l, col.as_slice_mut());
            }
        }
        return;
    }
    let par = faer::get_global_parallelism();
    solve_lower_triangular_in_place(l.as_ref(), x.rb_mut(), par);
    solve_upper_triangular_in_place(l.transpose(), x, par);
}

/// Iterative refinement from x: r = residual(x) (compensated), x += solve(r),
/// while ‖r‖₂ does not grow (ties allowed: an inconsistent least-squares
/// system keeps its residual) and the correction still changes x.
/// Returns (x, its residual, steps taken).
pub(crate) fn refine(
    mut x: Mat<f64>,
    residual: impl Fn(&Mat<f64>) -> Mat<f64>,
    solve: impl Fn(&Mat<f64>) -> Mat<f64>,
    max_steps: usize,
) -> (Mat<f64>, Mat<f64>, usize) {
    let mut r = residual(&x);
    let mut best = r.norm_l2();
    let mut steps = 0;
    while steps < max_steps && best > 0.0 {
        let dx = solve(&r);
        let x_new = &x + &dx;
        let r_new = residual(&x_new);
        let nr = r_new.norm_l2();
        if nr.is_nan() || nr > best * (1.0 + 1e-8) {
            break;
        }
        steps += 1;
        x = x_new;
        r = r_new;
        best = best.min(nr);
        // Stop once the correction no longer changes x in working precision.
        if norm_max(&dx) <= f64::EPSILON * norm_max(&x) {
            break;
        }
    }
    (x, r, steps)
}

/// λ_max(A) for symmetric positive semidefinite A given as `step` (x ↦ Ax),
/// from below: the largest Ritz value of the Lanczos process from a fixed
/// start (so the estimate is reproducible), at most 30 steps, fewer once a
/// step changes it by less than 1% — all the report and the singularity test
/// need. The Krylov space holds power iteration's iterates, so each step's
/// value is at least power iteration's Rayleigh quotient, and it settles in
/// fewer steps (14 → 9 on the degree-20 E1 inverse, whose eigenvalues crowd
/// at the top: each step is a pass over the factor).
pub(crate) fn largest_eigenvalue(n: usize, step: &dyn Fn(&Mat<f64>) -> Mat<f64>) -> f64 {
    let start: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i * 7919) % 101) as f64 / 101.0)
        .collect();
    let norm = dot(&start, &start).sqrt();
    let mut v = Mat::from_fn(n, 1, |i, _| start[i] / norm);
    let mut prev = vec![0.0; n];
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    let mut theta: f64 = 0.0;
    for k in 0..30 {
        let mut w = step(&v);
        let (vk, wk) = (v.col_as_slice(0), w.col_as_slice_mut(0));
        let alpha = dot(vk, wk);
        let beta_prev = betas.last().copied().unwrap_or(0.0);
        for ((x, &a), &p) in wk.iter_mut().zip(vk).zip(&prev) {
            *x -= alpha * a + beta_prev * p;
        }
        alphas.push(alpha);
        let next = tridiagonal_max(&alphas, &betas);
        let settled = k >= 2 && (next - theta).abs() <= 1e-2 * next.abs();
        theta = next;
        let beta = dot(wk, wk).sqrt();
        // An invariant subspace: its Ritz values are eigenvalues.
        if settled || beta.is_nan() || beta <= 1e-14 * next.abs() {
            break;
        }
        betas.push(beta);
        wk.iter_mut().for_each(|x| *x /= beta);
        prev.copy_from_slice(vk);
        v = w;
    }
    theta
}

/// The largest eigenvalue of the symmetric tridiagonal matrix with
/// diagonal `a` and off-diagonal `b` (`b.len() + 1 == a.len()`), by
/// bisection on Sturm counts between Gershgorin's bounds.
fn tridiagonal_max(a: &[f64], b: &[f64]) -> f64 {
    let radius =
        |i: usize| (if i > 0 { b[i - 1].abs() } else { 0.0 }) + b.get(i).map_or(0.0, |x| x.abs());
    let mut lo = (0..a.len())
        .map(|i| a[i] - radius(i))
        .fold(f64::INFINITY, f64::min);
    let mut hi = (0..a.len())
        .map(|i| a[i] + radius(i))
        .fold(f64::NEG_INFINITY, f64::max);
    // How many eigenvalues are below x: the negative pivots of T − xI.
    let below = |x: f64| {
        let mut d = 1.0;
        let mut count = 0;
        for i in 0..a.len() {
            let off = if i > 0 { b[i - 1] * b[i - 1] } else { 0.0 };
            d = a[i] - x - off / d;
            if d == 0.0 {
                d = f64::MIN_POSITIVE;
            }
            if d < 0.0 {
                count += 1;
            }
        }
        count
    };
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if below(mid) == a.len() {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// max |entry|.
pub(crate) fn norm_max(m: &Mat<f64>) -> f64 {
    let mut v: f64 = 0.0;
    for c in 0..m.ncols() {
        for &e in m.col_as_slice(c) {
            v = v.max(e.abs());
        }
    }
    v
}

/// λ_max(Â)/λ_min(Â) for SPD Â with its Cholesky factor L (the lower
/// triangle of `l`): λ_max of Â = L Lᵀ and of Â⁻¹ by [`largest_eigenvalue`],
/// each from a fixed start, so the estimate is reproducible. It is a lower
/// bound: the stopping rule leaves each λ a few percent low on crowded
/// spectra (the tests: 3–8%).
fn condition_estimate(l: &Mat<f64>) -> f64 {
    let n = l.nrows();
    let largest = || largest_eigenvalue(n, &|v| factor_product(l, v));
    let inverse = || {
        largest_eigenvalue(n, &|v| {
            let mut w = v.clone();
            factor_solve(l, w.col_as_slice_mut(0));
            w
        })
    };
    // The two iterations are independent: side by side on two threads
    // when they are worth a thread (from 400 unknowns).
    let (lmax, inv) = if n >= 400 {
        crate::budget::join(largest, inverse)
    } else {
        (largest(), inverse())
    };
    lmax * inv
}

/// Σ xᵢ yᵢ in four interleaved sums (independent chains: they pipeline
/// and vectorize, where one running sum waits on each add).
pub(crate) fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail: f64 = xc
        .remainder()
        .iter()
        .zip(yc.remainder())
        .map(|(p, q)| p * q)
        .sum();
    for (a, b) in xc.zip(yc) {
        for k in 0..4 {
            acc[k] += a[k] * b[k];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// x ← (L Lᵀ)⁻¹ x for the lower triangle L of `l`: column by column, an
/// update below the diagonal forward, a dot product backward (for one
/// vector as fast as faer's blocked solve, without its first call's
/// 1.5 ms of setup).
fn factor_solve(l: &Mat<f64>, x: &mut [f64]) {
    let n = x.len();
    for j in 0..n {
        let col = l.col_as_slice(j);
        x[j] /= col[j];
        let xj = x[j];
        for (xi, &lij) in x[j + 1..].iter_mut().zip(&col[j + 1..]) {
            *xi -= lij * xj;
        }
    }
    for j in (0..n).rev() {
        let col = l.col_as_slice(j);
        x[j] = (x[j] - dot(&col[j + 1..], &x[j + 1..])) / col[j];
    }
}

/// L Lᵀ v for the lower triangle L of `l`: Â v from Â's Cholesky factor,
/// two passes over the factor's columns (a dot product, then an update).
fn factor_product(l: &Mat<f64>, v: &Mat<f64>) -> Mat<f64> {
    let n = l.nrows();
    let v = v.col_as_slice(0);
    let y: Vec<f64> = (0..n)
        .map(|j| dot(&l.col_as_slice(j)[j..], &v[j..]))
        .collect();
    let mut z = Mat::<f64>::zeros(n, 1);
    let z_col = z.col_as_slice_mut(0);
    for (j, &yj) in y.iter().enumerate() {
        for (zi, &lij) in z_col[j..].iter_mut().zip(&l.col_as_slice(j)[j..]) {
            *zi += lij * yj;
        }
    }
    z
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts() -> SpdOptions {
        SpdOptions {
            estimate_condition: true,
            singular_condition: 1e15,
        }
    }

    /// The Hilbert matrix (cond ≈ 1.6e13 at n = 10, after scaling less) is
    /// solved to a small residual and its condition number is estimated
    /// within a factor of 10 of the value from the literature.
    #[test]
    fn hilbert_matrix_solve_is_refined() {
        let n = 8;
        let h = Mat::from_fn(n, n, |i, j| 1.0 / (i + j + 1) as f64);
        let x_true = Mat::from_fn(n, 1, |i, _| (i + 1) as f64);
        let b = &h * &x_true;
        let f = SpdFactor::new(&h, opts(), "test", None).unwrap();
        let sol = f.solve(&h, &b, 10);
        let r = norm_max(&residual(&h, &sol.x, &b));
        assert!(r <= 1e-15 * norm_max(&b), "residual {r}");
        // cond₂ of the 8×8 Hilbert matrix is 1.5258e10; equilibration lowers it a little.
        assert!(f.condition > 1e8 && f.condition < 2e10, "{}", f.condition);
    }

    /// The small loop's factor is faer's (the one past [`TINY`]) to
    /// rounding, on the lower triangle, and both name the same row when a
    /// pivot is not positive; L Lᵀ is A.
    #[test]
    fn tiny_cholesky_is_faers_factor() {
        let n = 40;
        let a = Mat::from_fn(n, n, |i, j| {
            let d = (i as f64 - j as f64).abs();
            if i == j {
                4.0 + i as f64 / n as f64
            } else {
                1.0 / (1.0 + d * d)
            }
        });
        let mut ours = a.clone();
        cholesky_in_place(ours.as_mut()).unwrap();
        let lf = a.llt(faer::Side::Lower).unwrap().L().to_owned();
        let l = Mat::from_fn(n, n, |i, j| if i >= j { ours[(i, j)] } else { 0.0 });
        assert!(norm_max(&(&l - &lf)) <= 1e-14, "{}", norm_max(&(&l - &lf)));
        assert!(norm_max(&(&l * l.transpose() - &a)) <= 1e-14 * 5.0);
        // Not positive at row 23: both stop there.
        let mut b = a.clone();
        b[(23, 23)] = -1.0;
        assert!(matches!(
            b.llt(faer::Side::Lower),
            Err(faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index: 23 })
        ));
        assert_eq!(
            cholesky_in_place(b.as_mut()),
            Err(CholeskyStop::NotPositive(23))
        );
        // A NaN pivot too.
        let mut c = a.clone();
        c[(7, 7)] = f64::NAN;
        assert_eq!(
            cholesky_in_place(c.as_mut()),
            Err(CholeskyStop::NotPositive(7))
        );
        let mut big = Mat::from_fn(TINY + 1, TINY + 1, |i, j| {
            if i == j {
                if i == 23 {
                    -1.0
                } else {
                    2.0
                }
            } else {
                0.0
            }
        });
        assert_eq!(
            cholesky_in_place(big.as_mut()),
            Err(CholeskyStop::NotPositive(23))
        );
    }

    /// AᵀA by dot products equals faer's product to rounding, symmetric to
    /// the bit; a strided A (a row-major view) takes faer's product.
    #[test]
    fn gram_is_the_product() {
        let a = Mat::from_fn(57, 9, |i, j| {
            ((i * 7 + j * 3) % 11) as f64 - 5.0 + 0.1 * j as f64
        });
        let g = gram(a.as_ref());
        let want = a.transpose() * &a;
        assert!(
            norm_max(&(&g - &want)) <= 1e-12,
            "{}",
            norm_max(&(&g - &want))
        );
        assert_eq!(g, g.transpose().to_owned());
        let t = a.transpose().to_owned();
        let strided = gram(t.as_ref().transpose());
        assert!(norm_max(&(&strided - &want)) <= 1e-12);
    }

    #[test]
    fn indefinite_and_singular_systems_are_errors() {
        let mut h = Mat::<f64>::identity(3, 3);
        h[(2, 2)] = -1.0;
        assert!(matches!(
            SpdFactor::new(&h, opts(), "x", None),
            Err(Error::NotPositiveDefinite { pivot: 2, .. })
        ));
        // Rank one: [[1,1],[1,1]] passes the diagonal test, fails as singular.
        let h = Mat::from_fn(2, 2, |_, _| 1.0);
        assert!(matches!(
            SpdFactor::new(&h, opts(), "x", None),
            Err(Error::NotPositiveDefinite { .. } | Error::Singular { .. })
        ));
    }

    /// A symmetric positive definite matrix spanning several panels, with
    /// a spread of scales.
    fn spd(n: usize) -> Mat<f64> {
        let g = Mat::from_fn(n, n, |i, j| (((i * 31 + j * 17) % 23) as f64 - 11.0) / 7.0);
        let mut a = &g * g.transpose();
        for i in 0..n {
            a[(i, i)] += 1.0 + i as f64;
        }
        a
    }

    /// The blocked factor is a Cholesky factor: L Lᵀ reproduces A to
    /// rounding, and it agrees with faer's unblocked one.
    #[test]
    fn blocked_cholesky_factors_across_panels() {
        let n = 2 * PANEL + 37;
        let a = spd(n);
        let mut l = a.clone();
        cholesky_in_place(l.as_mut()).unwrap();
        let l = Mat::from_fn(n, n, |i, j| if i >= j { l[(i, j)] } else { 0.0 });
        let back = &l * l.transpose();
        let err = norm_max(&(&back - &a));
        assert!(err <= 1e-13 * norm_max(&a), "‖LLᵀ − A‖ = {err}");
        let faer_l = a.llt(faer::Side::Lower).unwrap().L().to_owned();
        assert!(norm_max(&(&l - &faer_l)) <= 1e-12 * norm_max(&faer_l));
        // And the solve with it.
        let x = Mat::from_fn(n, 2, |i, c| (i + c) as f64);
        let mut y = &a * &x;
        llt_solve(&l, y.as_mut());
        assert!(norm_max(&(&y - &x)) <= 1e-9 * norm_max(&x));
    }

    /// Power iteration's Rayleigh quotient with the same start and the same
    /// stopping rule (what the estimate was before Lanczos).
    fn power_iteration(n: usize, step: &dyn Fn(&Mat<f64>) -> Mat<f64>) -> f64 {
        let mut v = Mat::from_fn(n, 1, |i, _| 1.0 + ((i * 7919) % 101) as f64 / 101.0);
        let mut lambda: f64 = 0.0;
        for k in 0..30 {
            v *= faer::Scale(1.0 / v.norm_l2());
            let w = step(&v);
            let next = (v.transpose() * &w)[(0, 0)];
            let settled = k >= 2 && (next - lambda).abs() <= 1e-2 * next.abs();
            (lambda, v) = (next, w);
            if settled {
                break;
            }
        }
        lambda
    }

    /// Lanczos' largest Ritz value approaches λ_max from below and is at
    /// least power iteration's estimate: on the path graph's Laplacian
    /// (eigenvalues 2 − 2 cos(kπ/(n+1)), crowded at the top: 8% low when
    /// the 1% rule stops it) and a diagonal matrix with a crowded top (3%
    /// low), and exact for the identity (its Krylov space is one vector).
    #[test]
    fn lanczos_estimates_the_largest_eigenvalue_from_below() {
        let n = 300;
        let laplacian = |v: &Mat<f64>| {
            Mat::from_fn(n, 1, |i, _| {
                let left = if i > 0 { v[(i - 1, 0)] } else { 0.0 };
                let right = if i + 1 < n { v[(i + 1, 0)] } else { 0.0 };
                2.0 * v[(i, 0)] - left - right
            })
        };
        let d: Vec<f64> = (0..n)
            .map(|i| 1.0 + 10.0 * (i as f64 / n as f64).sqrt())
            .collect();
        let diagonal = |v: &Mat<f64>| Mat::from_fn(n, 1, |i, _| d[i] * v[(i, 0)]);
        let path = 2.0 - 2.0 * (n as f64 * std::f64::consts::PI / (n + 1) as f64).cos();
        type Step<'a> = &'a dyn Fn(&Mat<f64>) -> Mat<f64>;
        let cases: [(Step, f64, f64); 2] = [(&laplacian, path, 0.9), (&diagonal, d[n - 1], 0.95)];
        for (step, want, within) in cases {
            let got = largest_eigenvalue(n, step);
            let power = power_iteration(n, step);
            assert!(
                got <= want * (1.0 + 1e-12) && got >= within * want,
                "{got} vs {want}"
            );
            assert!(
                got >= power * (1.0 - 1e-12),
                "{got} below power iteration's {power}"
            );
        }
        let got = largest_eigenvalue(n, &|v| v.clone());
        assert!((got - 1.0).abs() <= 1e-14, "{got}");
    }

    /// Bisection on Sturm counts finds a tridiagonal matrix's largest
    /// eigenvalue: the path Laplacian's closed form, and faer's symmetric
    /// eigenvalues of an irregular one.
    #[test]
    fn tridiagonal_max_is_the_largest_eigenvalue() {
        let n = 12;
        let want = 2.0 - 2.0 * (n as f64 * std::f64::consts::PI / (n + 1) as f64).cos();
        let got = tridiagonal_max(&vec![2.0; n], &vec![-1.0; n - 1]);
        assert!((got - want).abs() <= 1e-13, "{got} vs {want}");
        let a: Vec<f64> = (0..n).map(|i| ((i * 7) % 5) as f64 - 1.3).collect();
        let b: Vec<f64> = (0..n - 1).map(|i| 0.4 + ((i * 3) % 4) as f64).collect();
        let t = Mat::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => a[i],
            1 => b[i.min(j)],
            _ => 0.0,
        });
        let eig = t.self_adjoint_eigenvalues(faer::Side::Lower).unwrap();
        let want = eig.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let got = tridiagonal_max(&a, &b);
        assert!((got - want).abs() <= 1e-12 * want.abs(), "{got} vs {want}");
        assert_eq!(tridiagonal_max(&[3.5], &[]), 3.5);
    }

    /// L Lᵀ v from the factor is A v, and the solve by columns undoes it.
    #[test]
    fn factor_product_and_solve_are_the_matrix_and_its_inverse() {
        let n = PANEL + 41;
        let a = spd(n);
        let mut l = a.clone();
        cholesky_in_place(l.as_mut()).unwrap();
        let v = Mat::from_fn(n, 1, |i, _| ((i * 13) % 7) as f64 - 3.0);
        let av = &a * &v;
        let got = factor_product(&l, &v);
        assert!(norm_max(&(&got - &av)) <= 1e-12 * norm_max(&av));
        let mut back = av.clone();
        factor_solve(&l, back.col_as_slice_mut(0));
        assert!(norm_max(&(&back - &v)) <= 1e-9 * norm_max(&v));
    }

    /// A pivot that fails in a later panel is named by its row in the whole
    /// matrix; a cancelled factorization stops.
    #[test]
    fn blocked_cholesky_names_the_failing_row_and_stops_when_cancelled() {
        let n = PANEL + 50;
        let mut a = spd(n);
        let bad = PANEL + 20;
        a[(bad, bad)] = -1e6;
        assert_eq!(
            cholesky_in_place(a.as_mut()),
            Err(CholeskyStop::NotPositive(bad))
        );
        let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
        let budget = crate::budget::Budget {
            cancel: Some(flag),
            ..Default::default()
        };
        let mut a = spd(n);
        let r = crate::budget::with_budget(budget, || cholesky_in_place(a.as_mut()));
        assert_eq!(r, Err(CholeskyStop::Cancelled));
    }

    /// Timing against faer's own Cholesky (run by hand: `cargo test
    /// --release -p fairsurf blocked_cholesky_speed -- --ignored --nocapture`).
    #[test]
    #[ignore]
    fn blocked_cholesky_speed() {
        for n in [243, 600, 1083, 1323, 2883, 5043] {
            let a = spd(n);
            let mut best = [f64::INFINITY; 2];
            for _ in 0..5 {
                let t = std::time::Instant::now();
                let _ = a.llt(faer::Side::Lower).unwrap();
                best[0] = best[0].min(t.elapsed().as_secs_f64());
                let t = std::time::Instant::now();
                let mut l = a.clone();
                cholesky_in_place(l.as_mut()).unwrap();
                best[1] = best[1].min(t.elapsed().as_secs_f64());
            }
            println!("n {n}: faer {:.4} s, blocked {:.4} s", best[0], best[1]);
        }
    }
}
