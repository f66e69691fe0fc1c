//! The membrane (stretch) energy `½ ∫∫ |R_u|² + |R_v|² du dv`: the Dirichlet
//! functional, the fairness part of Wu & Yang's E1 (eq. 1); Veltkamp &
//! Wesselink's stretch (eq. 6) in the parametric form.

use super::{
    check_weight, fairness, fairness_key, fairness_value, EnergyTerm, Hessian, Integrand, Measure,
    Space, TermForm, STRETCH_PATTERNS,
};
use crate::Result;

/// `w · ½ ∫∫ |R_u|² + |R_v|²` (exact) or `w · ½ Σ_samples |R_u|² + |R_v|²` (eq. 5).
///
/// ```
/// use fairsurf::{EnergyTerm, Stretch, TensorPatch};
/// // The unit square as a bilinear patch: R_u = (1,0,0), R_v = (0,1,0), D = 1.
/// let sq = TensorPatch::from_fn(1, 1, |i, j| [i as f64, j as f64, 0.0]);
/// let d = Stretch::new(1.0).form((1, 1)).unwrap().value(sq.points());
/// assert!((d - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Stretch {
    /// The weight w (≥ 0).
    pub weight: f64,
    /// Exact integral or sample sum.
    pub measure: Measure,
}

impl Stretch {
    /// The exact membrane energy with weight w.
    pub fn new(weight: f64) -> Self {
        Self {
            weight,
            measure: Measure::Exact,
        }
    }

    /// The same term measured by `measure`.
    pub fn with_measure(mut self, measure: Measure) -> Self {
        self.measure = measure;
        self
    }
}

impl EnergyTerm for Stretch {
    fn name(&self) -> &'static str {
        "stretch"
    }

    fn hessian_key(&self) -> Option<u64> {
        Some(fairness_key(self.name(), self.weight, &self.measure))
    }

    fn integrand(&self) -> Option<Integrand<'_>> {
        Some(Integrand::Fairness {
            weight: self.weight,
            measure: &self.measure,
            patterns: STRETCH_PATTERNS,
        })
    }

    fn value(&self, patch: &crate::TensorPatch) -> Result<f64> {
        check_weight("stretch weight", self.weight)?;
        Ok(fairness_value(
            patch.degree(),
            &self.measure,
            STRETCH_PATTERNS,
            self.weight,
            patch.points(),
        ))
    }

    fn form_in(&self, space: &Space) -> Result<TermForm> {
        check_weight("stretch weight", self.weight)?;
        let h = fairness(space, &self.measure, STRETCH_PATTERNS, self.weight);
        Ok(TermForm {
            hessian: Hessian::PerCoordinate(h),
            center: None,
        })
    }
}
