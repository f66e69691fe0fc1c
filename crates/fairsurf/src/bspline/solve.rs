//! Minimizing a B-spline surface's energy over its free control points:
//! the Hessian Σ c · M_r^u ⊗ M_s^v restricted to the free points (one
//! sparse matrix for x, y and z), the fixed points moved to the right-hand
//! side, sparse Cholesky with AMD ordering, one step of iterative
//! refinement, and the energy on the written net by two roads: the Bézier
//! pieces' closed forms and Gauss quadrature span by span.

use super::energy::{energy_by_pieces, energy_by_quadrature, patterns, Gram1d};
use super::BSplineSurface;
use crate::energy::check_weight;
use crate::solve::kkt::{sparse_llt, LltFailure};
use crate::{Error, Result, Timings, Vec3};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::LltRef;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par};
use std::time::Instant;

/// Relative agreement required between the two roads to the energy of the
/// written net.
pub const ENERGY_TOLERANCE: f64 = 1e-10;

/// A B-spline surface to fair: which control points are free, and the
/// weights of the membrane and thin-plate energies (Wu & Yang's E1/E2
/// without guidance).
#[derive(Clone, Debug)]
pub struct BSplineProblem {
    surface: BSplineSurface,
    free: Vec<bool>,
    stretch: f64,
    bend: f64,
}

/// What a B-spline solve reports; the figures mean what they mean in
/// [`crate::SolveReport`].
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineReport {
    /// The minimized energy.
    pub energy: f64,
    /// The membrane part (weight included).
    pub stretch: f64,
    /// The thin-plate part (weight included).
    pub bend: f64,
    /// The energy recomputed on the written net by Gauss quadrature of the
    /// integrand span by span (`energy` comes from the pieces' closed forms).
    pub check_energy: f64,
    /// |energy − check_energy| / energy.
    pub energy_error: f64,
    /// Free control points.
    pub free_points: usize,
    /// Scalar unknowns (3 per free point).
    pub unknowns: usize,
    /// ‖H x − b‖∞ over the free coordinates.
    pub gradient_norm: f64,
    /// That over ‖H‖∞‖x‖∞ + ‖b‖∞.
    pub relative_gradient: f64,
    /// ‖b − Hx‖∞ / ‖b‖∞ (the absolute figure when b = 0).
    pub residual: f64,
    /// Nonzeros of the Cholesky factor.
    pub factor_nonzeros: usize,
    /// Seconds by phase (`analyse` is the check's second road).
    pub timings: Timings,
}

/// The faired surface and its report.
#[derive(Clone, Debug)]
pub struct BSplineSolution {
    /// The surface with the free points solved.
    pub surface: BSplineSurface,
    /// How good it is.
    pub report: BSplineReport,
}

impl BSplineProblem {
    /// Every control point of `surface` fixed; no energy yet.
    pub fn new(surface: BSplineSurface) -> Self {
        let n = surface.points().len();
        Self {
            surface,
            free: vec![false; n],
            stretch: 0.0,
            bend: 0.0,
        }
    }

    /// The outer `k` rings fixed, every other point free (k = 2: position
    /// and tangent plane along the boundary, G1 hole filling).
    pub fn with_fixed_rings(mut self, k: usize) -> Self {
        let (cu, cv) = self.surface.counts();
        for i in 0..cu {
            for j in 0..cv {
                let inside = i >= k && j >= k && i + k < cu && j + k < cv;
                self.free[i * cv + j] = inside;
            }
        }
        self
    }

    /// Which control points are free (row-major, one flag per point).
    pub fn with_free(mut self, free: Vec<bool>) -> Result<Self> {
        if free.len() != self.free.len() {
            return Err(Error::Mismatch {
                what: "free flags of the B-spline net".into(),
                expected: self.free.len().to_string(),
                got: free.len().to_string(),
            });
        }
        self.free = free;
        Ok(self)
    }

    /// The free flags (row-major).
    pub fn free(&self) -> &[bool] {
        &self.free
    }

    /// The membrane energy with weight `w` ≥ 0.
    pub fn with_stretch(mut self, w: f64) -> Self {
        self.stretch = w;
        self
    }

    /// The thin-plate energy with weight `w` ≥ 0.
    pub fn with_bend(mut self, w: f64) -> Self {
        self.bend = w;
        self
    }

    /// Minimizes; refuses no free point, no energy, a negative weight, a
    /// singular system, and an answer whose energy the second road does
    /// not confirm.
    pub fn solve(&self) -> Result<BSplineSolution> {
        check_weight("stretch weight", self.stretch)?;
        check_weight("bend weight", self.bend)?;
        let pats = patterns(self.stretch, self.bend);
        if pats.is_empty() {
            return Err(Error::NoEnergy);
        }
        let free: Vec<usize> = (0..self.free.len()).filter(|&k| self.free[k]).collect();
        if free.is_empty() {
            let (cu, cv) = self.surface.counts();
            return Err(Error::NoFreePoints {
                why: format!("every control point of the {cu} × {cv} net is fixed"),
            });
        }
        let t0 = Instant::now();
        let (ku, kv) = self.surface.knots();
        let (gu, gv) = (Gram1d::new(ku), Gram1d::new(kv));
        let cv = kv.count();
        let mut slot = vec![usize::MAX; self.free.len()];
        for (s, &k) in free.iter().enumerate() {
            slot[k] = s;
        }
        let x0 = self.surface.points();
        // H[(i,j),(i2,j2)] = Σ c M_r^u[i][i2] M_s^v[j][j2]; lower triangle of
        // the free block, and b = −H_fk x_k.
        let nf = free.len();
        let mut triplets = Vec::new();
        let mut b = Mat::<f64>::zeros(nf, 3);
        let mut h_inf = vec![0.0f64; nf];
        for (row, &k) in free.iter().enumerate() {
            let (i, j) = (k / cv, k % cv);
            for i2 in gu.band(i) {
                for j2 in gv.band(j) {
                    let h: f64 = pats
                        .iter()
                        .map(|&(c, r, s)| c * gu.at(r, i, i2) * gv.at(s, j, j2))
                        .sum();
                    if h == 0.0 {
                        continue;
                    }
                    let k2 = i2 * cv + j2;
                    h_inf[row] += h.abs();
                    match slot[k2] {
                        usize::MAX => {
                            for c in 0..3 {
                                b[(row, c)] -= h * x0[k2][c];
                            }
                        }
                        col if col <= row => triplets.push(Triplet::new(row, col, h)),
                        _ => {}
                    }
                }
            }
        }
        let lower = SparseColMat::try_new_from_triplets(nf, nf, &triplets)
            .expect("the triplets index the free block");
        let assemble = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let (symbolic, values) = sparse_llt(&lower, None).map_err(|e| match e {
            LltFailure::NotPositive => Error::NotPositiveDefinite {
                unknowns: 3 * nf,
                pivot: 0,
                hint: "the energy does not determine the free control points: add bend or \
                       stretch, or fix more points"
                    .into(),
            },
            LltFailure::Symbolic(why) => Error::Mismatch {
                what: "B-spline system".into(),
                expected: "a size that fits in memory".into(),
                got: format!("{nf} free points ({why})"),
            },
        })?;
        let factor = t1.elapsed().as_secs_f64();
        let t2 = Instant::now();
        let llt = LltRef::new(symbolic.as_ref(), &values);
        let par = Par::Seq;
        let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(3, par));
        let mut solve = |rhs: &mut Mat<f64>| {
            llt.solve_in_place_with_conj(Conj::No, rhs.as_mut(), par, MemStack::new(&mut mem));
        };
        let mut x = b.clone();
        solve(&mut x);
        // One step of iterative refinement: x += H⁻¹(b − Hx).
        let residual = |x: &Mat<f64>| {
            let mut r = b.clone();
            for (row, col, h) in triplets.iter().map(|t| (t.row, t.col, t.val)) {
                for c in 0..3 {
                    r[(row, c)] -= h * x[(col, c)];
                    if row != col {
                        r[(col, c)] -= h * x[(row, c)];
                    }
                }
            }
            r
        };
        let mut d = residual(&x);
        solve(&mut d);
        x += &d;
        let r = residual(&x);
        let solve_s = t2.elapsed().as_secs_f64();

        let mut points: Vec<Vec3> = x0.to_vec();
        for (row, &k) in free.iter().enumerate() {
            points[k] = [x[(row, 0)], x[(row, 1)], x[(row, 2)]];
        }
        let surface = self.surface.with_points(points);
        let inf = |m: &Mat<f64>| {
            (0..m.nrows())
                .flat_map(|i| (0..3).map(move |c| (i, c)))
                .fold(0.0f64, |a, (i, c)| a.max(m[(i, c)].abs()))
        };
        let gradient_norm = inf(&r);
        let denom = h_inf.iter().fold(0.0f64, |a, &v| a.max(v)) * inf(&x) + inf(&b);
        let relative_gradient = if denom > 0.0 {
            gradient_norm / denom
        } else {
            gradient_norm
        };
        let t3 = Instant::now();
        let (pieces, degree) = (surface.bezier_pieces(), surface.degree());
        let residual = if inf(&b) > 0.0 {
            gradient_norm / inf(&b)
        } else {
            gradient_norm
        };
        let part = |pats: Vec<(f64, usize, usize)>| energy_by_pieces(&pieces, degree, &pats);
        let (stretch, bend) = (
            part(patterns(self.stretch, 0.0)),
            part(patterns(0.0, self.bend)),
        );
        let total = stretch + bend;
        let check_energy = energy_by_quadrature(&pieces, degree, &pats);
        let analyse = t3.elapsed().as_secs_f64();
        let energy_error = (total - check_energy).abs() / total.abs().max(f64::MIN_POSITIVE);
        // A zero energy (a reproduced linear surface) is confirmed when the
        // second road finds it at rounding level of the data.
        if energy_error > ENERGY_TOLERANCE && (total - check_energy).abs() > 1e-24 {
            return Err(Error::Unverified {
                degree: format!("{:?} (B-spline)", surface.degree()),
                checked: check_energy,
                excess: energy_error,
                tolerance: ENERGY_TOLERANCE,
                hint: "the closed forms and the quadrature of its energy disagree".into(),
            });
        }
        Ok(BSplineSolution {
            surface,
            report: BSplineReport {
                energy: total,
                stretch,
                bend,
                check_energy,
                energy_error,
                free_points: nf,
                unknowns: 3 * nf,
                gradient_norm,
                relative_gradient,
                residual,
                factor_nonzeros: values.len(),
                timings: Timings {
                    assemble,
                    factor,
                    solve: solve_s,
                    analyse,
                    total: t0.elapsed().as_secs_f64(),
                },
            },
        })
    }
}
