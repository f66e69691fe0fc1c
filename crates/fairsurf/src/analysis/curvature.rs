//! Curvature from exact derivatives: the fundamental forms of a patch, its
//! Gaussian, mean and principal curvatures, and statistics of the absolute
//! mean curvature (Monterde & Ugail 2004, §4.4, Fig. 8–9).
//!
//! With E = x_u·x_u, F = x_u·x_v, G = x_v·x_v and e = x_uu·n, f = x_uv·n,
//! g = x_vv·n for the unit normal n = x_u×x_v/|x_u×x_v|:
//!
//! ```text
//! K = (eg − f²) / (EG − F²)        H = (eG − 2fF + gE) / (2(EG − F²))
//! κ₁,₂ = H ± √(H² − K)
//! ```

use crate::vec3::{cross, dot, norm, Vec3};
use crate::{ParamSurface, SurfaceDerivatives, TensorPatch};

/// Curvatures at one surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curvature {
    /// Gaussian curvature K.
    pub gaussian: f64,
    /// Mean curvature H (sign follows the normal x_u × x_v).
    pub mean: f64,
    /// Principal curvatures κ₁ ≥ κ₂.
    pub principal: (f64, f64),
}

/// The curvatures from second-order derivatives, `None` where the surface is
/// not regular (|x_u × x_v|² ≤ 1e-24 · (|x_u|² |x_v|²), e.g. at a collapsed corner).
pub fn curvature_from(d: &SurfaceDerivatives) -> Option<Curvature> {
    PointForms::at(d.du, d.dv, d.duu, d.duv, d.dvv).curvature()
}

/// [`PointForms::regular`] from its parts: EG − F², E, G and |R_u × R_v|.
#[inline(always)]
pub(crate) fn is_regular(det: f64, e: f64, g: f64, l: f64) -> bool {
    !(det.is_nan() || det <= 1e-24 * e * g || l == 0.0)
}

/// What [`curvature_from`] computes at one point, branch-free (a loop of
/// it over a grid's row vectorizes): ñ = R_u × R_v, |ñ|, E = R_u·R_u,
/// G = R_v·R_v, EG − F², K, H and √max(H² − K, 0). Meaningful where
/// [`PointForms::regular`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct PointForms {
    pub(crate) nn: Vec3,
    pub(crate) l: f64,
    pub(crate) e: f64,
    pub(crate) g: f64,
    pub(crate) det: f64,
    pub(crate) k: f64,
    pub(crate) h: f64,
    pub(crate) s: f64,
}

impl PointForms {
    /// From the first and second derivatives.
    #[inline(always)]
    pub(crate) fn at(du: Vec3, dv: Vec3, duu: Vec3, duv: Vec3, dvv: Vec3) -> Self {
        let nn = cross(du, dv);
        let (e_, f_, g_) = (dot(du, du), dot(du, dv), dot(dv, dv));
        let det = e_ * g_ - f_ * f_;
        let l = norm(nn);
        let n = [nn[0] / l, nn[1] / l, nn[2] / l];
        let (e, f, g) = (dot(duu, n), dot(duv, n), dot(dvv, n));
        let k = (e * g - f * f) / det;
        let h = (e * g_ - 2.0 * f * f_ + g * e_) / (2.0 * det);
        let s = (h * h - k).max(0.0).sqrt();
        PointForms {
            nn,
            l,
            e: e_,
            g: g_,
            det,
            k,
            h,
            s,
        }
    }

    /// Whether the surface is regular here: not |R_u × R_v|² ≤ 1e-24 ·
    /// |R_u|² |R_v|² (nor NaN, nor a zero normal).
    #[inline(always)]
    pub(crate) fn regular(&self) -> bool {
        is_regular(self.det, self.e, self.g, self.l)
    }

    /// The curvatures, where regular.
    #[inline(always)]
    pub(crate) fn curvature(&self) -> Option<Curvature> {
        self.regular().then_some(Curvature {
            gaussian: self.k,
            mean: self.h,
            principal: (self.h + self.s, self.h - self.s),
        })
    }
}

/// The curvatures of a patch at (u, v).
///
/// ```
/// use fairsurf::{analysis::curvature, TensorPatch};
/// // z = (x² + y²)/2 at the origin: K = 1, H = 1 (normal +z).
/// let p = TensorPatch::from_fn(2, 2, |i, j| {
///     let z = [0.0, 0.0, 0.5][i] + [0.0, 0.0, 0.5][j];
///     [i as f64 / 2.0, j as f64 / 2.0, z]
/// });
/// let c = curvature(&p, 0.0, 0.0).unwrap();
/// assert!((c.gaussian - 1.0).abs() < 1e-12 && (c.mean - 1.0).abs() < 1e-12);
/// ```
pub fn curvature(patch: &TensorPatch, u: f64, v: f64) -> Option<Curvature> {
    curvature_from(&patch.derivatives(u, v))
}

/// Statistics of |H| over a uniform grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AbsMeanCurvature {
    /// Smallest |H| at a regular grid point.
    pub min: f64,
    /// Largest |H| at a regular grid point.
    pub max: f64,
    /// Area-weighted mean ∫|H| dA / ∫dA on the grid (trapezoid weights).
    pub mean: f64,
    /// Grid points used.
    pub samples: usize,
    /// Grid points skipped because the surface is not regular there (|H| is
    /// unbounded near them, as at the collapsed corners of Fig. 9).
    pub singular: usize,
}

/// |H| on the (k+1)×(k+1) uniform grid of the surface's domain (u, v = 0,
/// 1/k, …, 1 for a Bézier patch).
pub fn abs_mean_curvature(surface: &impl ParamSurface, k: usize) -> AbsMeanCurvature {
    let k = k.max(1);
    let (us, vs) = surface.uniform_grid(k, k);
    abs_mean_curvature_on(&surface.derivatives_on(&us, &vs), k)
}

/// 0, 1/k, …, 1.
pub(crate) fn unit_grid(k: usize) -> Vec<f64> {
    (0..=k).map(|i| i as f64 / k as f64).collect()
}

/// [`abs_mean_curvature`] from the derivatives on that grid (u-major).
pub(crate) fn abs_mean_curvature_on(d: &[SurfaceDerivatives], k: usize) -> AbsMeanCurvature {
    let w = |i: usize| if i == 0 || i == k { 0.5 } else { 1.0 };
    let mut stats = HStats::default();
    for (idx, x) in d.iter().enumerate() {
        match curvature_from(x) {
            Some(c) => {
                let da = w(idx / (k + 1)) * w(idx % (k + 1)) * norm(cross(x.du, x.dv));
                stats.add(c.mean.abs(), da);
            }
            None => stats.singular += 1,
        }
    }
    stats.finish()
}

/// Running |H| statistics: min, max and the area-weighted mean Σ|H| dA / Σ dA
/// summed in the order the points come.
pub(crate) struct HStats {
    min: f64,
    max: f64,
    num: f64,
    den: f64,
    samples: usize,
    /// Points without a curvature.
    pub(crate) singular: usize,
}

impl Default for HStats {
    fn default() -> Self {
        HStats {
            min: f64::INFINITY,
            max: 0.0,
            num: 0.0,
            den: 0.0,
            samples: 0,
            singular: 0,
        }
    }
}

impl HStats {
    /// One regular point: |H| and its area weight.
    #[inline(always)]
    pub(crate) fn add(&mut self, h: f64, da: f64) {
        self.min = self.min.min(h);
        self.max = self.max.max(h);
        self.num += h * da;
        self.den += da;
        self.samples += 1;
    }

    /// The statistics (NaN where no point was regular).
    pub(crate) fn finish(self) -> AbsMeanCurvature {
        let some = self.samples > 0;
        AbsMeanCurvature {
            min: if some { self.min } else { f64::NAN },
            max: if some { self.max } else { f64::NAN },
            mean: if self.den > 0.0 {
                self.num / self.den
            } else {
                f64::NAN
            },
            samples: self.samples,
            singular: self.singular,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cylinder of radius r approximated by a rational-free cubic arc:
    /// |H| → 1/(2r) and K → 0 as the arc gets shorter.
    #[test]
    fn cylinder_has_half_inverse_radius_mean_curvature() {
        let r = 2.0;
        // Cubic Bézier arc of angle θ (the standard 4/3·tan(θ/4) handle).
        let theta: f64 = 0.5;
        let h = 4.0 / 3.0 * (theta / 4.0).tan();
        let arc = [
            [r, 0.0],
            [r, r * h],
            [
                r * (theta.cos() + h * theta.sin()),
                r * (theta.sin() - h * theta.cos()),
            ],
            [r * theta.cos(), r * theta.sin()],
        ];
        let p = TensorPatch::from_fn(3, 1, |i, j| [arc[i][0], arc[i][1], j as f64]);
        for &(u, v) in &[(0.0, 0.0), (0.5, 0.5), (0.3, 1.0)] {
            let c = curvature(&p, u, v).unwrap();
            assert!(c.gaussian.abs() < 1e-12, "K {}", c.gaussian);
            assert!((c.mean.abs() - 0.5 / r).abs() < 1e-4, "H {}", c.mean);
            assert!((c.principal.0.abs().max(c.principal.1.abs()) - 1.0 / r).abs() < 2e-4);
        }
    }

    #[test]
    fn plane_has_zero_curvature_and_collapsed_corners_are_skipped() {
        let p = TensorPatch::from_fn(2, 2, |i, j| [i as f64, j as f64, 0.0]);
        let s = abs_mean_curvature(&p, 8);
        assert_eq!((s.max, s.samples, s.singular), (0.0, 81, 0));
        // Collapse the corner (0,0): P00 = P10 = P01 makes x_u = x_v = 0 there.
        let mut q = TensorPatch::from_fn(2, 2, |i, j| [i as f64, j as f64, (i * j) as f64]);
        q.set_point(1, 0, q.point(0, 0));
        q.set_point(0, 1, q.point(0, 0));
        let s = abs_mean_curvature(&q, 8);
        assert_eq!(s.singular, 1);
        assert_eq!(s.samples, 80);
    }
}
