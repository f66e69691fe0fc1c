//! Harmonic (Theorem 1, Prop. 1) and biharmonic (Theorem 2, Prop. 2) Bézier
//! surfaces: the free control points solve "every Bernstein coefficient of
//! Δx (or Δ²x) vanishes", a consistent overdetermined linear system when the
//! construction exists.

use super::operator::{check_degree, max_abs, operator_matrix, relative_residual, Operator};
use super::{Construction, ConstructionReport, Method, Override, EXACT_TOLERANCE};
use crate::analysis::measures;
use crate::solve::lstsq::solve_lstsq;
use crate::solve::Timings;
use crate::{Error, Result, TensorPatch};
use faer::Mat;
use std::time::Instant;

/// Options for the constructions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstructOptions {
    /// When no surface of the kind has the given boundary (the system is
    /// inconsistent), return the least-squares net with `exact: false` and
    /// its residual instead of an error (default false).
    pub least_squares: bool,
    /// Compute area, functionals and curvature of the result (default true).
    pub analyse: bool,
}

impl Default for ConstructOptions {
    fn default() -> Self {
        Self {
            least_squares: false,
            analyse: true,
        }
    }
}

/// The harmonic Bézier surface with the first and last rows of `net`
/// (P_0j and P_nj): Monterde & Ugail, Theorem 1 and Prop. 1. The inner rows
/// of `net` are ignored. When the degree in u is even the corner P_nm is
/// determined by the other boundary-row points (Prop. 1(2)); if the given
/// value differs it is replaced and listed in `report.overridden`.
///
/// ```
/// use fairsurf::{harmonic::{harmonic, relative_residual, Operator}, TensorPatch};
/// // Rows of x = (u, v, u² − v²)-like data at degree 3.
/// let net = TensorPatch::from_fn(3, 3, |i, j| [i as f64, j as f64, (i * j) as f64 * 0.1]);
/// let h = harmonic(&net).unwrap();
/// assert!(h.report.exact && h.report.residual < 1e-12);
/// assert!(relative_residual(Operator::Laplacian, &h.patch) < 1e-12);
/// ```
pub fn harmonic(net: &TensorPatch) -> Result<Construction> {
    harmonic_with(net, &ConstructOptions::default())
}

/// [`harmonic`] with options.
pub fn harmonic_with(net: &TensorPatch, opts: &ConstructOptions) -> Result<Construction> {
    let (n, m) = net.degree();
    check_degree("harmonic surface", (n, m), 2)?;
    let inner = |i: usize, _j: usize| i > 0 && i < n;
    let full = operator_matrix(Operator::Laplacian, (n, m));
    let first = identity_solve(Operator::Laplacian, &full, net, &inner, "harmonic surface")?;
    if first.report.exact {
        return finish(first, opts);
    }
    // Prop. 1(2): the corner P_nm may be determined by the rest.
    let corner = |i: usize, j: usize| inner(i, j) || (i, j) == (n, m);
    let second = identity_solve(Operator::Laplacian, &full, net, &corner, "harmonic surface")?;
    if second.report.exact {
        let mut c = second;
        let (given, determined) = (net.point(n, m), c.patch.point(n, m));
        // Rounding alone moves it by ~ε·|net|: list real changes only.
        let moved =
            (0..3).any(|k| (given[k] - determined[k]).abs() > 1e-10 * max_abs(net).max(1e-300));
        if moved {
            c.report.overridden.push(Override {
                index: (n, m),
                given,
                determined,
            });
        }
        return finish(c, opts);
    }
    inconsistent(
        first,
        opts,
        format!(
            "no harmonic Bézier surface of degree ({n}, {m}) has these first and last rows \
             (the corner P_{n}{m} was freed too)"
        ),
    )
}

/// The biharmonic Bézier surface with the boundary ring of `net` (Monterde &
/// Ugail, Theorem 2 and Prop. 2). Exists for every boundary when n = m; for
/// some n ≠ m (e.g. 4×6, 3×9) the system is inconsistent for a generic
/// boundary and this is an error, or with
/// [`ConstructOptions::least_squares`] the least-squares net with
/// `exact: false`.
pub fn biharmonic(net: &TensorPatch) -> Result<Construction> {
    biharmonic_with(net, &ConstructOptions::default())
}

/// [`biharmonic`] with options.
pub fn biharmonic_with(net: &TensorPatch, opts: &ConstructOptions) -> Result<Construction> {
    let (n, m) = net.degree();
    check_degree("biharmonic surface", (n, m), 2)?;
    let inner = |i: usize, j: usize| i > 0 && i < n && j > 0 && j < m;
    let full = operator_matrix(Operator::Bilaplacian, (n, m));
    let c = identity_solve(
        Operator::Bilaplacian,
        &full,
        net,
        &inner,
        "biharmonic surface",
    )?;
    if c.report.exact {
        return finish(c, opts);
    }
    inconsistent(
        c,
        opts,
        format!(
            "no biharmonic Bézier surface of degree ({n}, {m}) has this boundary: Δ²x ≡ 0 is \
             inconsistent for it (it always exists for n = m)"
        ),
    )
}

fn inconsistent(c: Construction, opts: &ConstructOptions, what: String) -> Result<Construction> {
    if opts.least_squares {
        return finish(c, opts);
    }
    Err(Error::Inconsistent {
        what,
        residual: c.report.residual,
        hint: "use equal degrees, another method, or least_squares for the closest net".into(),
    })
}

fn finish(mut c: Construction, opts: &ConstructOptions) -> Result<Construction> {
    let t = Instant::now();
    if opts.analyse {
        c.report.measures = Some(measures(&c.patch));
    }
    c.report.timings.analyse = t.elapsed().as_secs_f64();
    c.report.timings.total += c.report.timings.analyse;
    Ok(c)
}

/// Solves op(x) ≡ 0 (`full` = [`operator_matrix`] of op) for the points
/// where `free(i, j)` holds, the others taken from `net`, in the
/// least-squares sense with refinement.
fn identity_solve(
    op: Operator,
    full: &Mat<f64>,
    net: &TensorPatch,
    free: &dyn Fn(usize, usize) -> bool,
    what: &str,
) -> Result<Construction> {
    let t_total = Instant::now();
    let (n, m) = net.degree();
    let method = match op {
        Operator::Laplacian => Method::Harmonic,
        Operator::Bilaplacian => Method::Biharmonic,
    };
    let t = Instant::now();
    let (cols, fixed): (Vec<usize>, Vec<usize>) =
        (0..net.len()).partition(|&k| free(k / (m + 1), k % (m + 1)));
    let rows = full.nrows();
    let a = Mat::from_fn(rows, cols.len(), |r, c| full[(r, cols[c])]);
    // b = −A_fixed P_fixed, each entry compensated.
    let af: Vec<Vec<f64>> = (0..rows)
        .map(|r| fixed.iter().map(|&k| full[(r, k)]).collect())
        .collect();
    let pf: Vec<Vec<f64>> = (0..3)
        .map(|c| fixed.iter().map(|&k| net.points()[k][c]).collect())
        .collect();
    let b = Mat::from_fn(rows, 3, |r, c| {
        crate::solve::compensated::dot2_residual(0.0, &af[r], &pf[c])
    });
    let assemble = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let hint = format!(
        "the {} do not determine the {} free control points of a degree ({n}, {m}) {what}",
        method.equations(),
        cols.len()
    );
    let sol = solve_lstsq(&a, &b, 30, 1e15, &hint)?;
    let solve = t.elapsed().as_secs_f64() - sol.factor_seconds;

    let mut points = net.points().to_vec();
    for (c, &k) in cols.iter().enumerate() {
        points[k] = [sol.x[(c, 0)], sol.x[(c, 1)], sol.x[(c, 2)]];
    }
    let patch = TensorPatch::try_new(n, m, points).map_err(|_| Error::NotFinite {
        what: format!("the {what} (the system overflowed)"),
    })?;
    let residual = relative_residual(op, &patch);
    let a_inf = (0..rows)
        .map(|r| (0..full.ncols()).map(|k| full[(r, k)].abs()).sum::<f64>())
        .fold(0.0f64, f64::max);
    // residual is already relative to max |P|.
    let backward_error = residual / a_inf;
    Ok(Construction {
        patch,
        report: ConstructionReport {
            method,
            equations: rows,
            unknowns: cols.len(),
            residual,
            backward_error,
            exact: backward_error <= EXACT_TOLERANCE,
            condition_estimate: sol.condition,
            refinement_steps: sol.refinement_steps,
            overridden: Vec::new(),
            measures: None,
            timings: Timings {
                assemble,
                factor: sol.factor_seconds,
                solve,
                analyse: 0.0,
                total: t_total.elapsed().as_secs_f64(),
            },
        },
    })
}
