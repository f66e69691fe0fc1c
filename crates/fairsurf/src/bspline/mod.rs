//! B-spline surfaces: more freedom at low degree (issue: the Bernstein net
//! of a degree-25+ polynomial cannot be held in double precision; a bicubic
//! B-spline of many spans can, with Gram matrices whose condition does not
//! grow with the number of spans).
//!
//! [`KnotVector`] (clamped, validated), [`BSplineSurface`] (de Boor
//! evaluation and derivatives, knot insertion, Bézier pieces), the exact
//! membrane and thin-plate energies of Wu & Yang eq. 1–2 (without the
//! guidance terms so far) and [`BSplineProblem`], which minimizes them over
//! the free control points by sparse Cholesky and confirms the energy on
//! the written net through the Bézier pieces' closed forms.
//!
//! ```
//! use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
//! // A bicubic surface of 4 × 3 spans over the unit square, a bump inside.
//! let (u, v) = (KnotVector::uniform(3, 4), KnotVector::uniform(3, 3));
//! let (cu, cv) = (u.count(), v.count());
//! let points = (0..cu * cv)
//!     .map(|k| {
//!         let (i, j) = (k / cv, k % cv);
//!         let inside = i > 1 && j > 1 && i + 2 < cu && j + 2 < cv;
//!         [i as f64, j as f64, if inside { 1.0 } else { 0.0 }]
//!     })
//!     .collect();
//! let surface = BSplineSurface::new(u, v, points).unwrap();
//! let faired = BSplineProblem::new(surface)
//!     .with_fixed_rings(2)
//!     .with_bend(1.0)
//!     .solve()
//!     .unwrap();
//! assert!(faired.report.relative_gradient < 1e-14);
//! assert!(faired.report.energy_error < 1e-10);
//! ```

mod energy;
mod guidance;
mod knots;
mod solve;
mod surface;

pub use knots::KnotVector;
pub use solve::{BSplineProblem, BSplineReport, BSplineSolution, ENERGY_TOLERANCE};
pub use surface::{BSplineSurface, BezierPiece};

#[cfg(test)]
mod tests;
