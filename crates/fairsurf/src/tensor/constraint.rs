//! The constraints of [`crate::constraint`] on a tensor-product patch, at
//! (u, v) ∈ [0, 1]²:
//!
//! ```text
//! point     R(u, v) = Σ_ij B_i^n(u) B_j^m(v) P_ij
//! normal    N·R_u = N·R_v = 0,   R_u = Σ_ij B_i^n′(u) B_j^m(v) P_ij, R_v alike
//! ```

use super::TensorPatch;
use crate::basis::bernstein_derivatives;
use crate::constraint::ConstraintSurface;
use crate::vec3::Vec3;
use crate::Result;

pub use crate::basis::polygon::Uv;

/// One linear constraint of a tensor-product patch (eq. 31 of Veltkamp &
/// Wesselink, at (u, v)).
pub type TensorConstraint = crate::constraint::Constraint<Uv>;

impl TensorPatch {
    /// (index i·(m+1) + j, dᵃB_i^n(u)·dᵇB_j^m(v)) for the a-th u- and
    /// b-th v-derivative, zeros left out.
    fn weights(&self, [u, v]: Uv, a: usize, b: usize) -> Vec<(usize, f64)> {
        let (n, m) = self.degree();
        let bu = &bernstein_derivatives(n, u, a)[a];
        let bv = &bernstein_derivatives(m, v, b)[b];
        let mut out = Vec::with_capacity((n + 1) * (m + 1));
        for (i, &x) in bu.iter().enumerate() {
            for (j, &y) in bv.iter().enumerate() {
                if x * y != 0.0 {
                    out.push((i * (m + 1) + j, x * y));
                }
            }
        }
        out
    }
}

impl ConstraintSurface for TensorPatch {
    type At = Uv;

    fn check_at(&self, at: Uv, what: &str) -> Result<()> {
        crate::constraint::check_in_rectangle(at, [(0.0, 1.0); 2], what, || {
            "a point of the parameter square [0, 1]²".into()
        })
    }

    fn point_weights(&self, at: Uv) -> Vec<(usize, f64)> {
        self.weights(at, 0, 0)
    }

    fn tangent_weights(&self, at: Uv) -> [(Vec<(usize, f64)>, &'static str); 2] {
        [
            (self.weights(at, 1, 0), "∂R/∂u"),
            (self.weights(at, 0, 1), "∂R/∂v"),
        ]
    }

    fn value_at(&self, [u, v]: Uv) -> Vec3 {
        self.eval(u, v)
    }

    fn normal_at(&self, [u, v]: Uv) -> Option<Vec3> {
        self.normal(u, v)
    }

    fn control_points(&self) -> &[Vec3] {
        self.points()
    }
}
