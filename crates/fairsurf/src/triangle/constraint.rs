//! The constraints of [`crate::constraint`] on a triangular surface, at
//! points of its domain ([`DomainPoint`]: a triangle and barycentrics):
//!
//! ```text
//! point     T(p) = Σ_J B_J(p) P_J
//! normal    N·∂T/∂u = N·∂T/∂v = 0   eq. (8), w = 1 − u − v
//! ```
//!
//! B_J are the degree-n triangular Bernstein polynomials of the patch that
//! holds p; J runs over its control points, mapped to globals.

use super::bernstein::{tri_bernstein_all, Bary};
use super::index::multi_indices;
use super::refine::{check_point, DomainPoint};
use super::surface::TriSurface;
use crate::constraint::ConstraintSurface;
use crate::vec3::Vec3;
use crate::Result;

/// One linear constraint of a triangular surface (eq. 31).
pub type Constraint = crate::constraint::Constraint<DomainPoint>;
/// A constraint of a triangular surface with its name.
pub type NamedConstraint = crate::constraint::NamedConstraint<DomainPoint>;

impl ConstraintSurface for TriSurface {
    type At = DomainPoint;

    fn check_at(&self, at: DomainPoint, what: &str) -> Result<()> {
        check_point(self, at, what)
    }

    fn point_weights(&self, at: DomainPoint) -> Vec<(usize, f64)> {
        point_weights(self, at)
    }

    fn tangent_weights(&self, at: DomainPoint) -> [(Vec<(usize, f64)>, &'static str); 2] {
        [
            (derivative_weights(self, at, [1.0, 0.0, -1.0]), "∂T/∂u"),
            (derivative_weights(self, at, [0.0, 1.0, -1.0]), "∂T/∂v"),
        ]
    }

    fn value_at(&self, at: DomainPoint) -> Vec3 {
        self.patch(at.triangle).eval(at.bary)
    }

    fn normal_at(&self, at: DomainPoint) -> Option<Vec3> {
        self.patch(at.triangle).normal(at.bary)
    }

    fn control_points(&self) -> &[Vec3] {
        self.points()
    }
}

/// (global point, B_J(p)) for the patch holding p.
fn point_weights(surface: &TriSurface, at: DomainPoint) -> Vec<(usize, f64)> {
    let g = surface.patch_indices(at.triangle);
    let b = tri_bernstein_all(surface.degree(), at.bary);
    g.iter()
        .copied()
        .zip(b)
        .filter(|&(_, w)| w != 0.0)
        .collect()
}

/// (global point, weight) with D_d T(p) = Σ weight · P_g for a direction d
/// (components summing to 0): n Σ_m d_m B^{n−1}_{J−e_m}(p).
pub(crate) fn derivative_weights(
    surface: &TriSurface,
    at: DomainPoint,
    d: Bary,
) -> Vec<(usize, f64)> {
    let n = surface.degree();
    let lower = tri_bernstein_all(n - 1, at.bary);
    let g = surface.patch_indices(at.triangle);
    multi_indices(n)
        .zip(g.iter().copied())
        .filter_map(|(j, gi)| {
            let w: f64 = (0..3)
                .filter(|&m| j[m] > 0)
                .map(|m| {
                    let mut l = j;
                    l[m] -= 1;
                    d[m] * lower[super::index::index_of(n - 1, l)]
                })
                .sum();
            (w != 0.0).then_some((gi, n as f64 * w))
        })
        .collect()
}
