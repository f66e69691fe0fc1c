//! Triangular Bézier patches (Veltkamp & Wesselink, §2):
//!
//! ```text
//! T(u, v, w) = Σ_{i+j+k=n} P_ijk B_ijk^n(u, v, w),   B_ijk^n = n!/(i! j! k!) uⁱ vʲ wᵏ,
//! ```
//!
//! over a domain triangle V₁V₂V₃ with barycentric coordinates (u, v, w),
//! u + v + w = 1, of any degree n (n = 0 is a constant, the paper uses
//! cubics).
//!
//! - **Index order** ([`linear_index`]): rows of constant k from k = 0 to n,
//!   each by increasing j: `P_ijk` is stored at `k(2n+3−k)/2 + j`. The first
//!   n + 1 points are the edge w = 0 from P_n00 to P_0n0.
//! - **Corners**: 0 = V₁ = P_n00 (u = 1), 1 = V₂ = P_0n0 (v = 1),
//!   2 = V₃ = P_00n (w = 1).
//! - **Edges**: edge k is opposite corner k (barycentric k is 0) and runs from
//!   corner k+1 to corner k+2 (mod 3), counter-clockwise about the normal.
//! - **Evaluation**: de Casteljau ([`TriPatch::eval`]) or the Bernstein form
//!   ([`TriPatch::eval_bernstein`]); the blossom ([`TriPatch::blossom`]).
//! - **Derivatives**: directional (D_d, D_d D_e for directions summing to 0)
//!   and with respect to (u, v) with w = 1 − u − v (a [`crate::SurfaceDerivatives`],
//!   the tensor patches' type, so the curvature analysis applies unchanged).
//! - **Degree elevation** ([`TriPatch::elevate`]) and **subdivision**
//!   (Goldman 1983): into three at an interior point, into two at a point of
//!   an edge, or onto any sub-triangle ([`TriPatch::restrict`]).
//! - **Surfaces** ([`TriSurface`]): patches over a triangle mesh sharing
//!   their vertex and edge control points (C0 by construction), any valence,
//!   N-sided regions, boundary found; initial points are the degree-raised
//!   flat triangles.
//! - **Internal energy** ([`InternalEnergy`]): α·stretch + β·bend (eq. 6–7)
//!   integrated exactly over the equilateral domain triangle of side 1
//!   (eq. 25–27), so each patch's matrix is invariant under permuting its
//!   corners; ½∫ as for the tensor terms; assembled over a surface as a
//!   sparse matrix. A [`TriProblem`] is given the same [`crate::Stretch`]
//!   (α) and [`crate::Bend`] (β) terms as a tensor surface's
//!   [`crate::Problem`]; `InternalEnergy` is their triangular assembly.
//!
//! Sources: R. C. Veltkamp, W. Wesselink, variational modeling of triangular
//! Bézier surfaces, §2, eq. (2)–(3); G. Farin, "Triangular Bernstein–Bézier
//! patches", CAGD 3 (1986), and "Curves and Surfaces for CAGD" (1993) for de
//! Casteljau, derivatives and degree elevation; R. N. Goldman, "Subdivision
//! algorithms for Bézier triangles", Computer-Aided Design 15 (1983) for
//! subdivision.
//!
//! ```
//! use fairsurf::{analysis::curvature_from, TriPatch};
//! // A cubic patch over the unit right triangle bulging upwards in the middle.
//! let t = TriPatch::from_fn(3, |i, j, k| {
//!     let bump = if i > 0 && j > 0 && k > 0 { 1.0 } else { 0.0 };
//!     [i as f64 / 3.0, j as f64 / 3.0, bump]
//! });
//! let centre = [1.0 / 3.0; 3];
//! // de Casteljau and Bernstein agree; the bump is 6uvw = 2/9 high there.
//! let (p, q) = (t.eval(centre), t.eval_bernstein(centre));
//! assert!((p[2] - 2.0 / 9.0).abs() < 1e-15 && (p[2] - q[2]).abs() < 1e-15);
//! // Derivatives with respect to (u, v), the normal and the curvature.
//! let d = t.derivatives(centre);
//! assert!(d.du[2].abs() < 1e-15 && d.dv[2].abs() < 1e-15); // the top of the bump
//! assert!(t.normal(centre).unwrap()[2] > 1.0 - 1e-15);
//! assert!(curvature_from(&d).unwrap().mean < 0.0);
//! // Elevation and subdivision keep the surface.
//! let e = t.elevate(2);
//! let [a, _, _] = t.subdivide_interior(centre);
//! assert!((e.eval(centre)[2] - p[2]).abs() < 1e-15);
//! assert!((a.corner(0)[2] - p[2]).abs() < 1e-15);
//! // Each boundary edge is a Bézier curve.
//! assert_eq!(t.edge(2).points()[0], t.corner(0));
//! ```

mod assemble;
mod bernstein;
mod constraint;
mod continuity;
mod convert;
pub(crate) use convert::tensor_weights;
mod derivatives;
mod elevate;
pub(crate) mod energy;
mod index;
mod integral;
mod patch;
mod reduce;
pub(crate) mod refine;
pub(crate) mod solve;
mod subdivide;
mod surface;

pub use crate::constraint::{ConstraintOutcome, Row};
pub use crate::operator::{NewtonReport, Operator, OperatorOutcome, Place, RegionPiece, Target};
pub use crate::solve::kkt::{Factorization, KktInfo};
pub use bernstein::{tri_bernstein, tri_bernstein_all, trinomial, Bary};
pub use constraint::{Constraint, NamedConstraint};
pub use continuity::{max_edge_normal_angle, BoundaryRule, Continuity, EdgeContinuity};
pub use energy::{
    bend_matrix, bend_value, stretch_matrix, stretch_value, InternalEnergy, EQUILATERAL,
    EQUILATERAL_AREA,
};
pub use index::{linear_index, multi_index, multi_indices, point_count};
pub use integral::{tri_gram_matrix, tri_product_integral};
pub use patch::TriPatch;
pub use refine::{embed_curve, CurvePath, DomainPoint, Refinement};
pub use solve::{CurveConstraint, DroppedRow, TriExtra, TriFactored, TriProblem, TriSolution};
pub use surface::{MeshEdge, TriSurface};
