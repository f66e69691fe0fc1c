//! # fairsurf
//!
//! Fair surfaces by exact energy minimization. This crate is the math: the
//! Bernstein basis with exact product integrals, Bézier curves and
//! tensor-product patches, energy terms assembled as exact quadratic forms,
//! and a solver that reports how good its answer is. No files, no HTTP.
//!
//! The central problem is Wu & Yang 2015 ("Variational surface design under
//! normal field guidance"): given some control points of a tensor Bézier
//! patch R, find the others minimizing
//!
//! ```text
//! E1 = ½ ∫∫ |R_u|² + |R_v|² + λ[(R_u·N)² + (R_v·N)²] + γ|R − S|²        (eq. 1)
//! E2 = ½ ∫∫ |R_uu|² + 2|R_uv|² + |R_vv|² + λ[(R_u·N)² + (R_v·N)²] + γ|R − S|²   (eq. 2)
//! ```
//!
//! or their sampled forms (eq. 5), or any weighted sum of the terms.
//!
//! ```
//! use fairsurf::{Bend, NormalField, Problem, TensorPatch};
//! // A 5×5 net: flat boundary, a bump inside.
//! let net = TensorPatch::from_fn(5, 5, |i, j| {
//!     let bump = if (1..5).contains(&i) && (1..5).contains(&j) { 1.0 } else { 0.0 };
//!     [i as f64 / 5.0, j as f64 / 5.0, bump]
//! });
//! // Thin plate guided toward the normal (0, 0, 1), two rings fixed (G1 filling).
//! let up = TensorPatch::new(0, 0, vec![[0.0, 0.0, 1.0]]);
//! let sol = Problem::new((5, 5))
//!     .with_fixed_rings(&net, 2)
//!     .with_term(Bend::new(1.0))
//!     .with_term(NormalField::new(10.0, up))
//!     .solve()
//!     .unwrap();
//! assert!(sol.report.relative_gradient < 1e-14);
//! println!("energy {} area {}", sol.report.energy, sol.report.measures.unwrap().area);
//! ```
//!
//! The same terms serve every surface kind: a B-spline surface's problem is
//! [`Problem`]`<`[`bspline::BSplineSurface`]`>` (sparse and banded), a
//! triangular surface's a [`triangle::TriProblem`] (Veltkamp & Wesselink),
//! and all of them report in one [`SolveReport`].
//!
//! ```
//! use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
//! use fairsurf::triangle::TriProblem;
//! use fairsurf::{Bend, NormalField, Stretch, TensorPatch, TriSurface};
//! // Bicubic, 6 × 6 spans: the outer two rings hold, the rest is faired.
//! let (u, v) = (KnotVector::uniform(3, 6), KnotVector::uniform(3, 6));
//! let (cu, cv) = (u.count(), v.count());
//! let points = (0..cu * cv)
//!     .map(|k| [(k / cv) as f64, (k % cv) as f64, ((k * 7) % 5) as f64 * 0.1])
//!     .collect();
//! let up = TensorPatch::new(0, 0, vec![[0.0, 0.0, 1.0]]);
//! let spline = BSplineProblem::from_surface(BSplineSurface::new(u, v, points).unwrap())
//!     .with_fixed_rings(2)
//!     .with_term(Bend::new(1.0))
//!     .with_term(NormalField::new(10.0, up))
//!     .solve()
//!     .unwrap();
//! assert_eq!(spline.report.basis, "b-spline");
//! // Two triangles, degree 3, the boundary held.
//! let mesh = TriSurface::new(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.2], [1.0, 1.0, 0.0], [0.0, 1.0, 0.1]],
//!                            &[[0, 1, 2], [0, 2, 3]], 3);
//! let tri = TriProblem::from_mesh(mesh)
//!     .with_term(Stretch::new(0.1))
//!     .with_term(Bend::new(1.0))
//!     .with_fixed_boundary()
//!     .solve()
//!     .unwrap();
//! assert!(tri.report.relative_gradient < 1e-12 && tri.report.triangular.is_some());
//! ```

mod check;
mod curve;
mod error;
mod mesh;
mod solve;
mod surface;
mod tensor;
mod vec3;

pub mod analysis;
pub mod basis;
pub mod bspline;
pub mod budget;
pub mod colour;
pub mod constraint;
pub mod energy;
pub mod fill;
pub mod harmonic;
pub mod operator;
pub mod triangle;

pub use analysis::SurfaceMeasures;
pub use check::{Check, TOLERANCE as CHECK_TOLERANCE};
pub use curve::{nearest_parameter, BezierCurve};
pub use energy::{
    Bend, EnergyTerm, Guide, GuideSurface, Integrand, Measure, NormalField, NormalGuide,
    SampleGrid, Stretch,
};
pub use error::{Error, Result};
pub use mesh::TriMesh;
pub use solve::{
    FactorCache, Factored, Problem, Solution, SolveOptions, SolveReport, SurfaceKind, TermEnergy,
    Timings, TriFigures,
};
pub use surface::{ControlNet, ParamSurface, Sample};
pub use tensor::{SurfaceDerivatives, TensorConstraint, TensorPatch};
pub use triangle::{TriPatch, TriSurface};
pub use vec3::Vec3;

/// Small vector helpers on [`Vec3`].
pub mod vector {
    pub use crate::vec3::{
        add, angle, bounding_diagonal, cross, dot, is_finite, norm, normalize, scale,
        segment_distance, sub,
    };
}
