//! How far a surface's normals are from a guiding normal field.

use crate::energy::NormalField;
use crate::vec3::{cross, dot, norm};
use crate::TensorPatch;

/// Unoriented angles (radians, in [0, π/2]) between the surface normal and
/// the guiding direction, over a sample grid. Unoriented because the
/// normal-field energy (R_u·N)² + (R_v·N)² does not see the sign of N.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalDeviation {
    /// Largest angle.
    pub max: f64,
    /// Mean angle.
    pub mean: f64,
    /// Root mean square angle.
    pub rms: f64,
    /// Samples used (where both normals exist).
    pub samples: usize,
}

/// The deviation measured at the (ku+1)(kv+1) points of a uniform grid (for a
/// sampled field, pass its own grid size so every sample is hit once).
pub fn normal_deviation(
    patch: &TensorPatch,
    field: &NormalField,
    (ku, kv): (usize, usize),
) -> NormalDeviation {
    let (ku, kv) = (ku.max(1), kv.max(1));
    let us: Vec<f64> = (0..=ku).map(|i| i as f64 / ku as f64).collect();
    let vs: Vec<f64> = (0..=kv).map(|j| j as f64 / kv as f64).collect();
    // Whole grids at O(degree) a point (was a full evaluation per point).
    let normals = patch.derivatives_on(&us, &vs);
    let guide = field.directions(&us, &vs);
    let (mut max, mut sum, mut sum2, mut count) = (0.0f64, 0.0, 0.0, 0usize);
    for (d, g) in normals.iter().zip(guide) {
        let (Some(n), Some(g)) = (d.normal(), g) else {
            continue;
        };
        let a = norm(cross(n, g)).atan2(dot(n, g).abs());
        max = max.max(a);
        sum += a;
        sum2 += a * a;
        count += 1;
    }
    let c = count.max(1) as f64;
    NormalDeviation {
        max,
        mean: sum / c,
        rms: (sum2 / c).sqrt(),
        samples: count,
    }
}
