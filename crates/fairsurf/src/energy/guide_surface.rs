//! The guide-surface term of Wu & Yang 2015: `½ γ ∫∫ |R − S|² du dv` (eq. 1–2)
//! or `½ Σ γ_ij |R(u_i,v_j) − S(u_i,v_j)|²` (eq. 5). It keeps the surface close
//! to a given surface S (by default the initial one): a Bézier patch, or
//! for a B-spline surface a B-spline on any knots over its domain.

use super::{
    check_weight, check_weights, derivative_net, form, pattern_value, EnergyTerm, Hessian,
    HessianKey, Integrand, Measure, Space, TermForm,
};
use crate::bspline::BSplineSurface;
use crate::{Error, Result, TensorPatch};

/// The guide surface S.
#[derive(Clone, Debug, PartialEq)]
pub enum Guide {
    /// A Bézier patch: of the solved patch's degree or lower (then
    /// degree-elevated, exactly); on a B-spline surface, over its knot
    /// domain mapped onto [0, 1]².
    Bezier(TensorPatch),
    /// A B-spline surface on its own knots and degrees over the solved
    /// B-spline surface's knot domain: the term is its L² projection onto
    /// the surface's space plus the constant ∫|S − PS|², exact by Gauss
    /// rules between both surfaces' knot lines. For B-spline surfaces only;
    /// a Bézier patch's problem refuses it.
    Spline(BSplineSurface),
}

/// `γ · ½ ∫∫ |R − S|²` (exact) or the sampled sum with per-sample weights.
#[derive(Clone, Debug, PartialEq)]
pub struct GuideSurface {
    /// γ (≥ 0).
    pub weight: f64,
    /// S.
    pub surface: Guide,
    /// Exact integral or sample sum.
    pub measure: Measure,
    /// Per-sample weights γ_ij for [`Measure::Grid`] (multiplied with `weight`).
    pub sample_weights: Option<Vec<f64>>,
}

impl GuideSurface {
    /// The exact term with a Bézier guide.
    pub fn new(weight: f64, surface: TensorPatch) -> Self {
        Self {
            weight,
            surface: Guide::Bezier(surface),
            measure: Measure::Exact,
            sample_weights: None,
        }
    }

    /// The exact term with a B-spline guide over the solved B-spline
    /// surface's knot domain (B-spline surfaces only; the surface itself on
    /// its own knots is the usual "stay near the initial net").
    pub fn spline(weight: f64, surface: BSplineSurface) -> Self {
        Self {
            weight,
            surface: Guide::Spline(surface),
            measure: Measure::Exact,
            sample_weights: None,
        }
    }

    /// The Bézier guide, or an error for a B-spline one (which only a
    /// B-spline surface's problem takes).
    pub fn bezier(&self) -> Result<&TensorPatch> {
        match &self.surface {
            Guide::Bezier(p) => Ok(p),
            Guide::Spline(_) => Err(Error::Mismatch {
                what: "guide surface".into(),
                expected: "a Bézier patch (a B-spline guide is for B-spline surfaces)".into(),
                got: "a B-spline surface".into(),
            }),
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
        let surface = self.bezier()?;
        let (a, b) = surface.degree();
        if a > n || b > m {
            return Err(Error::Mismatch {
                what: "guide surface degree".into(),
                expected: format!("at most the surface's ({n}, {m})"),
                got: format!("({a}, {b})"),
            });
        }
        Ok(surface.elevate(n - a, m - b))
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
        Some(match &self.surface {
            Guide::Spline(surface) => Integrand::GuideSpline {
                weight: self.weight,
                surface,
                measure: &self.measure,
                sample_weights: self.sample_weights.as_deref(),
            },
            Guide::Bezier(surface) => Integrand::GuideSurface {
                weight: self.weight,
                surface,
                measure: &self.measure,
                sample_weights: self.sample_weights.as_deref(),
            },
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
