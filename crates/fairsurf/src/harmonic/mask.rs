//! The discrete masks of Monterde & Ugail §1.2 and §4.2: each inner control
//! point is a fixed combination of its neighbours, a sparse linear system.
//!
//! - Harmonic mask (eq. 5–6, the discrete Coons patch of Farin & Hansford):
//!   `P_ij = ¼ (P_i+1,j + P_i−1,j + P_i,j+1 + P_i,j−1)` for every inner
//!   point; the boundary ring is given.
//! - Biharmonic mask (eq. 7): `20 P_ij = 8 Σ(axial neighbours) − 2 Σ(diagonal
//!   neighbours) − Σ(axial neighbours at distance 2)` for every point of
//!   ring ≥ 2; the two outer rings are given.
//!
//! Both matrices are symmetric positive definite (the 5-point Laplacian, and
//! the 13-point stencil is LᵀL restricted to the unknowns), factored by
//! faer's sparse Cholesky.

use super::operator::{check_degree, max_abs};
use super::{ConstructOptions, Construction, ConstructionReport, Method, EXACT_TOLERANCE};
use crate::analysis::measures;
use crate::solve::Timings;
use crate::{Error, Result, TensorPatch};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use std::time::Instant;

/// The harmonic-mask surface with the boundary ring of `net` (the inner
/// points of `net` are ignored). Needs n, m ≥ 2.
///
/// ```
/// use fairsurf::{harmonic::harmonic_mask, TensorPatch};
/// // A bilinear boundary: the mask reproduces the bilinear net exactly.
/// let net = TensorPatch::from_fn(4, 5, |i, j| [i as f64, j as f64, (i * j) as f64]);
/// let c = harmonic_mask(&net).unwrap();
/// assert!((c.patch.point(2, 3)[2] - 6.0).abs() < 1e-12);
/// ```
pub fn harmonic_mask(net: &TensorPatch) -> Result<Construction> {
    harmonic_mask_with(net, &ConstructOptions::default())
}

/// [`harmonic_mask`] with options (`least_squares` does not apply: the mask
/// system is always solvable).
pub fn harmonic_mask_with(net: &TensorPatch, opts: &ConstructOptions) -> Result<Construction> {
    check_degree("harmonic mask surface", net.degree(), 2)?;
    let stencil: &[((isize, isize), f64)] = &[
        ((0, 0), 4.0),
        ((1, 0), -1.0),
        ((-1, 0), -1.0),
        ((0, 1), -1.0),
        ((0, -1), -1.0),
    ];
    mask_solve(net, 1, stencil, Method::HarmonicMask, opts.analyse)
}

/// The biharmonic-mask surface with the two outer rings of `net`. Needs
/// n, m ≥ 4 (so that some point lies in ring 2).
pub fn biharmonic_mask(net: &TensorPatch) -> Result<Construction> {
    biharmonic_mask_with(net, &ConstructOptions::default())
}

/// [`biharmonic_mask`] with options.
pub fn biharmonic_mask_with(net: &TensorPatch, opts: &ConstructOptions) -> Result<Construction> {
    check_degree("biharmonic mask surface", net.degree(), 4)?;
    let mut stencil = vec![((0, 0), 20.0)];
    for (di, dj) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
        stencil.push(((di, dj), -8.0));
        stencil.push(((2 * di, 2 * dj), 1.0));
    }
    for (di, dj) in [(1, 1), (1, -1), (-1, 1), (-1, -1)] {
        stencil.push(((di, dj), 2.0));
    }
    mask_solve(net, 2, &stencil, Method::BiharmonicMask, opts.analyse)
}

fn mask_solve(
    net: &TensorPatch,
    rings: usize,
    stencil: &[((isize, isize), f64)],
    method: Method,
    analyse: bool,
) -> Result<Construction> {
    let t_total = Instant::now();
    let (n, m) = net.degree();
    let t = Instant::now();
    // Unknowns: points of ring ≥ `rings`, numbered row-major.
    let (rn, rm) = (n + 1 - 2 * rings, m + 1 - 2 * rings);
    let unknown = |i: usize, j: usize| (i - rings) * rm + (j - rings);
    let count = rn * rm;
    let mut triplets = Vec::new();
    let mut rhs = Mat::<f64>::zeros(count, 3);
    for i in rings..=n - rings {
        for j in rings..=m - rings {
            let row = unknown(i, j);
            for &((di, dj), w) in stencil {
                let (a, b) = ((i as isize + di) as usize, (j as isize + dj) as usize);
                let inside = (rings..=n - rings).contains(&a) && (rings..=m - rings).contains(&b);
                if inside {
                    triplets.push(Triplet::new(row, unknown(a, b), w));
                } else {
                    let p = net.point(a, b);
                    for c in 0..3 {
                        rhs[(row, c)] -= w * p[c];
                    }
                }
            }
        }
    }
    let mat = SparseColMat::<usize, f64>::try_new_from_triplets(count, count, &triplets)
        .expect("indices are in range");
    let assemble = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let llt = mat
        .sp_cholesky(Side::Lower)
        .map_err(|_| Error::NotPositiveDefinite {
            unknowns: count,
            pivot: 0,
            hint: format!("the {} matrix should be positive definite", method.name()),
        })?;
    let factor = t.elapsed().as_secs_f64();
    let t = Instant::now();
    use faer::linalg::solvers::Solve;
    let x = llt.solve(&rhs);
    let mut points = net.points().to_vec();
    for i in rings..=n - rings {
        for j in rings..=m - rings {
            let r = unknown(i, j);
            points[i * (m + 1) + j] = [x[(r, 0)], x[(r, 1)], x[(r, 2)]];
        }
    }
    let patch = TensorPatch::try_new(n, m, points).map_err(|_| Error::NotFinite {
        what: format!("the {} surface", method.name()),
    })?;
    // Residual of the mask equations at the returned net.
    let w_sum: f64 = stencil.iter().map(|(_, w)| w.abs()).sum();
    let size = max_abs(&patch);
    let mut res = 0.0f64;
    for i in rings..=n - rings {
        for j in rings..=m - rings {
            for c in 0..3 {
                let mut s = 0.0;
                for &((di, dj), w) in stencil {
                    let (a, b) = ((i as isize + di) as usize, (j as isize + dj) as usize);
                    s += w * patch.point(a, b)[c];
                }
                res = res.max(s.abs());
            }
        }
    }
    let residual = if size > 0.0 { res / size } else { res };
    let backward_error = residual / w_sum;
    let solve = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let measures = analyse.then(|| measures(&patch));
    let analyse = t.elapsed().as_secs_f64();
    Ok(Construction {
        patch,
        report: ConstructionReport {
            method,
            equations: count,
            unknowns: count,
            residual,
            backward_error,
            exact: backward_error <= EXACT_TOLERANCE,
            condition_estimate: f64::NAN,
            refinement_steps: 0,
            overridden: Vec::new(),
            measures,
            timings: Timings {
                assemble,
                factor,
                solve,
                analyse,
                total: t_total.elapsed().as_secs_f64(),
            },
        },
    })
}
