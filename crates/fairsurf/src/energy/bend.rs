//! The thin-plate (bend) energy `½ ∫∫ |R_uu|² + 2|R_uv|² + |R_vv|² du dv`: the
//! fairness part of Wu & Yang's E2 (eq. 2) and the biharmonic functional whose
//! Euler–Lagrange equation is Δ²R = 0.

use super::{
    check_weight, fairness, fairness_key, fairness_value, EnergyTerm, Hessian, Integrand, Measure,
    Space, TermForm, BEND_PATTERNS,
};
use crate::Result;

/// `w · ½ ∫∫ |R_uu|² + 2|R_uv|² + |R_vv|²` (exact) or the same summed over a
/// sample grid (eq. 5 applied to E2).
///
/// ```
/// use fairsurf::{Bend, EnergyTerm, TensorPatch};
/// // z = u² over the unit square: R_uu = (0,0,2), so the energy is ½·4 = 2.
/// let p = TensorPatch::from_fn(2, 1, |i, j| [i as f64 / 2.0, j as f64, if i == 2 { 1.0 } else { 0.0 }]);
/// let e = Bend::new(1.0).form((2, 1)).unwrap().value(p.points());
/// assert!((e - 2.0).abs() < 1e-14);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Bend {
    /// The weight w (≥ 0).
    pub weight: f64,
    /// Exact integral or sample sum.
    pub measure: Measure,
}

impl Bend {
    /// The exact thin-plate energy with weight w.
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

impl EnergyTerm for Bend {
    fn name(&self) -> &'static str {
        "bend"
    }

    fn hessian_key(&self) -> Option<u64> {
        Some(fairness_key(self.name(), self.weight, &self.measure))
    }

    fn integrand(&self) -> Option<Integrand<'_>> {
        Some(Integrand::Fairness {
            weight: self.weight,
            measure: &self.measure,
            patterns: BEND_PATTERNS,
        })
    }

    fn value(&self, patch: &crate::TensorPatch) -> Result<f64> {
        check_weight("bend weight", self.weight)?;
        Ok(fairness_value(
            patch.degree(),
            &self.measure,
            BEND_PATTERNS,
            self.weight,
            patch.points(),
        ))
    }

    fn form_in(&self, space: &Space) -> Result<TermForm> {
        check_weight("bend weight", self.weight)?;
        let h = fairness(space, &self.measure, BEND_PATTERNS, self.weight);
        Ok(TermForm {
            hessian: Hessian::PerCoordinate(h),
            center: None,
        })
    }
}
