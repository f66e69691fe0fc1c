//! The Dirichlet and biharmonic functionals, exact.

use crate::energy::{Bend, EnergyTerm, Stretch};
use crate::TensorPatch;

/// Dirichlet functional `D = ½ ∫∫ |R_u|² + |R_v|² du dv` (Monterde & Ugail
/// 2004, §2), exact.
///
/// ```
/// use fairsurf::{analysis::dirichlet, TensorPatch};
/// let sq = TensorPatch::from_fn(3, 3, |i, j| [i as f64 / 3.0, j as f64 / 3.0, 0.0]);
/// assert!((dirichlet(&sq) - 1.0).abs() < 1e-14);
/// ```
pub fn dirichlet(patch: &TensorPatch) -> f64 {
    Stretch::new(1.0)
        .value(patch)
        .expect("unit weight is valid")
}

/// Biharmonic (thin-plate) functional
/// `B = ½ ∫∫ |R_uu|² + 2|R_uv|² + |R_vv|² du dv`, exact (evaluated from the
/// derivative nets, accurate at high degree).
pub fn biharmonic(patch: &TensorPatch) -> f64 {
    Bend::new(1.0).value(patch).expect("unit weight is valid")
}
