//! Newton's method for the total energy with repellors (Veltkamp &
//! Wesselink eq. 30), shared by the triangular and the tensor-product
//! solves: the quadratic energy ½xᵀHx + bᵀx over the free coordinates,
//! linear constraints F x = F x₀, and Σ s/q(x) for the repellors.

use super::{Operator, Residual};
use crate::solve::kkt::{solve_kkt, KktFactor};
use crate::Vec3;
use crate::{Error, Result};
use faer::sparse::{SparseColMat, Triplet};
use std::collections::HashMap;

/// How the nonlinear solve with repellors went (Newton's method with a
/// backtracking line search from the quadratic solution, linear
/// constraints kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonReport {
    /// Newton steps taken.
    pub iterations: usize,
    /// Steps that fell back to the convex part of the repellors' Hessian
    /// (the full one gave no descent direction).
    pub convex_steps: usize,
    /// The objective ½xᵀHx + bᵀx + Σ s/q(x) over the free coordinates (the
    /// total energy less a constant) at the quadratic start.
    pub start_energy: f64,
    /// The same at the end (never above the start).
    pub energy: f64,
    /// Steps whose KKT matrix was factored with the symbolic analysis
    /// (ordering) of an earlier step's: the pattern stays while the values
    /// change, so only the first step of each kind orders it.
    pub reused_orderings: usize,
    /// ‖∇E + Fᵀλ‖∞ at the end.
    pub gradient_norm: f64,
    /// The same, relative (≤ 1e-9 when converged).
    pub relative_gradient: f64,
}

/// The repellors among `operators` (zipped with their placed residuals)
/// over the free coordinates: `known[p]` is a fixed point's value (`None`
/// for a free one) and `free` lists the free points in the unknowns' order
/// (unknown 3·k + c is coordinate c of `free[k]`).
pub(crate) fn repellors<P, N>(
    operators: &[Operator<P>],
    placed: &[(N, Vec<Residual>)],
    known: &[Option<Vec3>],
    free: &[usize],
) -> Vec<FreeResiduals> {
    let known_coord: Vec<Option<f64>> = (0..3 * known.len())
        .map(|i| known[i / 3].map(|p| p[i % 3]))
        .collect();
    let mut free_index = vec![usize::MAX; known_coord.len()];
    for (k, &p) in free.iter().enumerate() {
        for c in 0..3 {
            free_index[3 * p + c] = 3 * k + c;
        }
    }
    operators
        .iter()
        .zip(placed)
        .filter(|(op, _)| op.repel)
        .map(|(op, (_, res))| FreeResiduals::new(op.strength, res, &known_coord, &free_index))
        .collect()
}

/// An operator's residuals over the free coordinates: r = Σ a·x_f + c, with
/// the known coordinates and the target folded into c.
pub(crate) struct FreeResiduals {
    pub(crate) strength: f64,
    rows: Vec<FreeRow>,
}

/// (quadrature weight, Σ a·x_f terms, constant c).
type FreeRow = (f64, Vec<(usize, f64)>, f64);

impl FreeResiduals {
    pub(crate) fn new(
        strength: f64,
        residuals: &[Residual],
        known: &[Option<f64>],
        free_index: &[usize],
    ) -> Self {
        let rows = residuals
            .iter()
            .map(|r| {
                let mut c = -r.target;
                let mut terms = Vec::with_capacity(r.terms.len());
                for &(i, a) in &r.terms {
                    match known[i] {
                        Some(v) => c += a * v,
                        None => terms.push((free_index[i], a)),
                    }
                }
                (r.weight, terms, c)
            })
            .collect();
        FreeResiduals { strength, rows }
    }

    /// q(x) = Σ w r² and ∇q = 2 Σ w r ∂r (sparse, unmerged).
    pub(crate) fn value_and_gradient(&self, x: &[f64]) -> (f64, Vec<(usize, f64)>) {
        let mut q = 0.0;
        let mut grad = Vec::new();
        for (w, terms, c) in &self.rows {
            let r = terms.iter().map(|&(i, a)| a * x[i]).sum::<f64>() + c;
            q += w * r * r;
            grad.extend(terms.iter().map(|&(i, a)| (i, 2.0 * w * r * a)));
        }
        (q, grad)
    }

    fn value(&self, x: &[f64]) -> f64 {
        self.value_and_gradient(x).0
    }

    /// s·∇²q = 2s Σ w ∂rᵀ∂r, as triplets (both triangles), times `factor`.
    /// Rows over the same coordinates (a region's nodes in one patch) are
    /// summed densely first, in order, so each coordinate set gives one
    /// block of triplets (measured: a domain region's 10 ms of sorting
    /// triplets became 0.3 ms).
    fn hessian_triplets(&self, factor: f64, out: &mut Vec<Triplet<usize, usize, f64>>) {
        let mut which: HashMap<Vec<usize>, usize> = HashMap::new();
        let mut blocks: Vec<(Vec<usize>, Vec<f64>)> = Vec::new();
        for (w, terms, _) in &self.rows {
            let idx: Vec<usize> = terms.iter().map(|t| t.0).collect();
            let m = idx.len();
            let k = *which.entry(idx.clone()).or_insert_with(|| {
                blocks.push((idx, vec![0.0; m * m]));
                blocks.len() - 1
            });
            let block = &mut blocks[k].1;
            for (p, &(_, a)) in terms.iter().enumerate() {
                let wa = w * a;
                for (q, &(_, b)) in terms.iter().enumerate() {
                    block[p * m + q] += wa * b;
                }
            }
        }
        for (idx, block) in &blocks {
            let m = idx.len();
            for (p, &i) in idx.iter().enumerate() {
                for (q, &j) in idx.iter().enumerate() {
                    out.push(Triplet::new(i, j, factor * 2.0 * block[p * m + q]));
                }
            }
        }
    }
}

/// H + 2s Σ w ∂rᵀ∂r and b + 2s Σ w c ∂r for the attractors and directors.
pub(crate) fn add_quadratic(
    h: SparseColMat<usize, f64>,
    b: &mut [f64],
    terms: &[FreeResiduals],
) -> Result<SparseColMat<usize, f64>> {
    if terms.is_empty() {
        return Ok(h);
    }
    let mut triplets = triplets_of(&h);
    for t in terms {
        t.hessian_triplets(t.strength, &mut triplets);
        for (w, row, c) in &t.rows {
            for &(i, a) in row {
                b[i] += 2.0 * t.strength * w * c * a;
            }
        }
    }
    sparse(h.nrows(), &triplets)
}

fn triplets_of(h: &SparseColMat<usize, f64>) -> Vec<Triplet<usize, usize, f64>> {
    let mut out = Vec::with_capacity(h.compute_nnz());
    for j in 0..h.ncols() {
        for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
            out.push(Triplet::new(i, j, *v));
        }
    }
    out
}

pub(crate) fn sparse(
    n: usize,
    t: &[Triplet<usize, usize, f64>],
) -> Result<SparseColMat<usize, f64>> {
    SparseColMat::try_new_from_triplets(n, n, t).map_err(|e| Error::Mismatch {
        what: "energy matrix".into(),
        expected: "a size that fits in memory".into(),
        got: format!("{e:?}"),
    })
}

/// Relative stationarity that ends the Newton iterations.
const NEWTON_TOLERANCE: f64 = 1e-10;
const NEWTON_ITERATIONS: usize = 100;

/// Minimizes ½xᵀHx + bᵀx + Σ s/q(x) subject to F x = F x₀ (x₀ feasible:
/// the quadratic solution) by Newton's method with a backtracking
/// (Armijo) line search. The full Hessian H + Σ s(2∇q∇qᵀ/q³ − ∇²q/q²) is
/// used when it gives a descent direction, else its convex part without
/// −∇²q/q². Stops when ‖∇E + Fᵀλ‖∞ ≤ 1e-10 of the scale of the terms.
pub(crate) fn newton(
    h: &SparseColMat<usize, f64>,
    b: &[f64],
    f: &[&[(usize, f64)]],
    repellors: &[FreeResiduals],
    mut x: Vec<f64>,
) -> Result<(Vec<f64>, NewtonReport)> {
    let n = x.len();
    let base = triplets_of(h);
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let row_sums = {
        let mut r = vec![0.0f64; n];
        for t in &base {
            r[t.row] += t.val.abs();
        }
        inf(&r)
    };
    let energy = |x: &[f64]| -> f64 {
        let mut e = 0.0;
        for j in 0..n {
            for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
                e += 0.5 * x[i] * v * x[j];
            }
            e += b[j] * x[j];
        }
        e + repellors
            .iter()
            .map(|r| r.strength / r.value(x))
            .sum::<f64>()
    };
    let start_energy = energy(&x);
    let mut current = start_energy;
    let zeros = vec![0.0; f.len()];
    let (mut iterations, mut convex_steps) = (0, 0);
    // The last factorization with and without the curvature terms: the
    // next step's matrix has its pattern, new values.
    let mut last: [Option<KktFactor>; 2] = [None, None];
    let mut reused_orderings = 0;
    loop {
        // Gradient and the repellors' Hessian terms at x.
        let mut grad = b.to_vec();
        for j in 0..n {
            for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
                grad[i] += v * x[j];
            }
        }
        let mut rank_one = Vec::new();
        let mut curvature = Vec::new();
        let mut repel_scale = 0.0f64;
        for r in repellors {
            let (q, dq) = r.value_and_gradient(&x);
            if !(q > 0.0 && q.is_finite()) {
                return Err(Error::NotConverged {
                    what: "the repellor solve".into(),
                    iterations,
                    relative_gradient: f64::INFINITY,
                    tolerance: NEWTON_TOLERANCE,
                    hint: "the surface reached a repelling target (its energy is infinite there)"
                        .into(),
                });
            }
            // ∇q with its repeated coordinates summed.
            let mut dq = dq;
            dq.sort_unstable_by_key(|&(i, _)| i);
            let (mut index, mut merged): (Vec<usize>, Vec<f64>) = (Vec::new(), Vec::new());
            for (i, g) in dq {
                if index.last() == Some(&i) {
                    *merged.last_mut().expect("same length") += g;
                } else {
                    index.push(i);
                    merged.push(g);
                }
            }
            for (&i, &g) in index.iter().zip(&merged) {
                grad[i] -= r.strength * g / (q * q);
                repel_scale = repel_scale.max((r.strength * g / (q * q)).abs());
            }
            let c = 2.0 * r.strength / (q * q * q);
            for (&i, &gi) in index.iter().zip(&merged) {
                for (&j, &gj) in index.iter().zip(&merged) {
                    rank_one.push(Triplet::new(i, j, c * gi * gj));
                }
            }
            r.hessian_triplets(-r.strength / (q * q), &mut curvature);
        }
        let scale = row_sums * inf(&x) + inf(b) + repel_scale;
        let mut step = |with_curvature: bool| -> Result<(Vec<f64>, Vec<f64>)> {
            let mut t = base.clone();
            t.extend_from_slice(&rank_one);
            if with_curvature {
                t.extend_from_slice(&curvature);
            }
            let hk = sparse(n, &t)?;
            let kept = &mut last[usize::from(with_curvature)];
            // (An LU, or a matrix the kept ordering does not suit,
            // is factored afresh.)
            let again = kept.as_ref().and_then(|k| {
                let k = k.refactored(&hk)?;
                let sol = k.solve(&grad, &zeros).ok()?;
                (sol.info.relative_residual <= 1e-12).then_some((k, sol))
            });
            let (factor, sol) = match again {
                Some(done) => {
                    reused_orderings += 1;
                    done
                }
                None => solve_kkt(&hk, f, &grad, &zeros)?,
            };
            *kept = Some(factor);
            Ok((sol.x, sol.lambda))
        };
        let (mut dx, mut lambda) = match step(true) {
            Ok(s) => s,
            Err(_) => {
                convex_steps += 1;
                step(false)?
            }
        };
        let mut slope: f64 = grad.iter().zip(&dx).map(|(g, d)| g * d).sum();
        if slope >= 0.0 {
            convex_steps += 1;
            (dx, lambda) = step(false)?;
            slope = grad.iter().zip(&dx).map(|(g, d)| g * d).sum();
        }
        // Stationarity: ∇E + Fᵀλ.
        let mut lagrangian = grad.clone();
        for (row, l) in f.iter().zip(&lambda) {
            for &(i, a) in row.iter() {
                lagrangian[i] += a * l;
            }
        }
        let gradient_norm = inf(&lagrangian);
        let relative_gradient = gradient_norm / scale.max(f64::MIN_POSITIVE);
        if relative_gradient <= NEWTON_TOLERANCE || slope >= 0.0 {
            if relative_gradient > NEWTON_TOLERANCE {
                return Err(Error::NotConverged {
                    what: "the repellor solve (Newton's method)".into(),
                    iterations,
                    relative_gradient,
                    tolerance: NEWTON_TOLERANCE,
                    hint: "no descent direction is left at working precision".into(),
                });
            }
            return Ok((
                x,
                NewtonReport {
                    iterations,
                    convex_steps,
                    start_energy,
                    energy: current,
                    gradient_norm,
                    relative_gradient,
                    reused_orderings,
                },
            ));
        }
        if iterations == NEWTON_ITERATIONS {
            return Err(Error::NotConverged {
                what: "the repellor solve (Newton's method)".into(),
                iterations,
                relative_gradient,
                tolerance: NEWTON_TOLERANCE,
                hint: "lower the repellors' strengths or move their targets".into(),
            });
        }
        // Armijo backtracking, unless the predicted decrease is below what
        // the energy's rounding can show: then the full Newton step (the
        // iteration is in its quadratic phase and the energy test is noise).
        let mut t = 1.0;
        if -slope <= 1e-13 * current.abs().max(f64::MIN_POSITIVE) {
            x.iter_mut().zip(&dx).for_each(|(a, d)| *a += d);
            current = energy(&x);
            iterations += 1;
            continue;
        }
        loop {
            let trial: Vec<f64> = x.iter().zip(&dx).map(|(a, d)| a + t * d).collect();
            let e = energy(&trial);
            if e.is_finite() && e <= current + 1e-4 * t * slope {
                x = trial;
                current = e;
                break;
            }
            t *= 0.5;
            if t < 1e-12 {
                // No decrease representable: x is as good as it gets.
                return Err(Error::NotConverged {
                    what: "the repellor solve (Newton's method)".into(),
                    iterations,
                    relative_gradient,
                    tolerance: NEWTON_TOLERANCE,
                    hint: "the line search found no decrease".into(),
                });
            }
        }
        iterations += 1;
    }
}
