//! The guide-surface term of Wu & Yang 2015: `½ γ ∫∫ |R − S|² du dv` (eq. 1–2)
//! or `½ Σ γ_ij |R(u_i,v_j) − S(u_i,v_j)|²` (eq. 5). It keeps the surface close
//! to a given Bézier surface S (by default the initial one).

use super::{
    check_weight, check_weights, derivative_net, form, pattern_value, EnergyTerm, Hessian,
    HessianKey, Integrand, Measure, Space, TermForm,
};
use crate::{Error, Result, TensorPatch};

/// `γ · ½ ∫∫ |R − S|²` (exact) or the sampled sum with per-sample weights.
#[derive(Clone, Debug, PartialEq)]
pub struct GuideSurface {
    /// γ (≥ 0).
    pub weight: f64,
    /// S; of the solved patch's degree or lower (then degree-elevated, exactly).
    pub surface: TensorPatch,
    /// Exact integral or sample sum.
    pub measure: Measure,
    /// Per-sample weights γ_ij for [`Measure::Grid`] (multiplied with `weight`).
    pub sample_weights: Option<Vec<f64>>,
}

impl GuideSurface {
    /// The exact term.
    pub fn new(weight: f64, surface: TensorPatch) -> Self {
        Self {
            weight,
            surface,
            measure: Measure::Exact,
            sample_weights: None,
        }
    }

    /// The same term measured by `measure`, with optional per-sample weights.
    pub fn with_measure(mut self, measure: Measure, sample_weights: Option<Vec<f64>>) -> Self {
        self.measure = measure;
        self.sample_weights = sample_weights;
        self
    }

    /// S written at degree (n, m).
    fn surface_at(&self, (n, m): (usize, usize)) -> Result<TensorPatch> {
        let (a, b) = self.surface.degree();
        if a > n || b > m {
            return Err(Error::Mismatch {
                what: "guide surface degree".into(),
                expected: format!("at most the surface's ({n}, {m})"),
                got: format!("({a}, {b})"),
            });
        }
        Ok(self.surface.elevate(n - a, m - b))
    }
}

impl EnergyTerm for GuideSurface {
    fn name(&self) -> &'static str {
        "guide_surface"
    }

    /// γ, the measure and the sample weights: S enters only the centre.
    fn hessian_key(&self) -> Option<u64> {
        Some(
            HessianKey::new(self.name())
                .number(self.weight)
                .with(&self.measure)
                .with(&self.sample_weights.is_some())
                .numbers(self.sample_weights.as_deref().unwrap_or(&[]))
                .finish(),
        )
    }

    fn center(&self, degree: (usize, usize)) -> Result<Option<Vec<crate::Vec3>>> {
        Ok(Some(self.surface_at(degree)?.points().to_vec()))
    }

    fn integrand(&self) -> Option<Integrand<'_>> {
        Some(Integrand::GuideSurface {
            weight: self.weight,
            surface: &self.surface,
            measure: &self.measure,
            sample_weights: self.sample_weights.as_deref(),
        })
    }

    fn value(&self, patch: &TensorPatch) -> Result<f64> {
        check_weight("guide_surface weight", self.weight)?;
        let degree = patch.degree();
        let s = self.surface_at(degree)?;
        let diff: Vec<crate::Vec3> = patch
            .points()
            .iter()
            .zip(s.points())
            .map(|(a, b)| crate::vector::sub(*a, *b))
            .collect();
        let ((au, av), w) = match &self.measure {
            Measure::Exact => self.measure.unit(),
            Measure::Grid(g) => {
                if let Some(w) = &self.sample_weights {
                    g.check_len("guide_surface sample weights", w.len())?;
                    check_weights("guide_surface sample weight", w)?;
                }
                (g.axes(), g.weight_table(self.sample_weights.as_deref()))
            }
        };
        let total: f64 = (0..3)
            .map(|c| {
                let d = derivative_net(&diff, degree, (0, 0), c);
                pattern_value(degree, (0, 0), (&au, &av), &w, &d, &d)
            })
            .sum();
        Ok(0.5 * self.weight * total)
    }

    fn form_in(&self, space: &Space) -> Result<TermForm> {
        let degree = space.degree();
        check_weight("guide_surface weight", self.weight)?;
        let s = self.surface_at(degree)?;
        let h = match &self.measure {
            Measure::Exact => {
                let ((au, av), w) = self.measure.unit();
                form(space, &[((0, 0), self.weight)], (&au, &av), &w)
            }
            Measure::Grid(g) => {
                if let Some(w) = &self.sample_weights {
                    g.check_len("guide_surface sample weights", w.len())?;
                    check_weights("guide_surface sample weight", w)?;
                }
                let (au, av) = g.axes();
                let w = g.weight_table(self.sample_weights.as_deref());
                form(space, &[((0, 0), self.weight)], (&au, &av), &w)
            }
        };
        Ok(TermForm {
            hessian: Hessian::PerCoordinate(h),
            center: space.is_bernstein().then(|| s.points().to_vec()),
        })
    }
}
