//! Harmonic and biharmonic Bézier surfaces, the discrete masks, and the
//! extremals of the Dirichlet and biharmonic functionals — the four ways of
//! filling a boundary compared by Monterde & Ugail (2004).
//!
//! | construction | determined by | equations |
//! |---|---|---|
//! | [`harmonic`] | first and last rows (Prop. 1) | Δx ≡ 0 (Theorem 1) |
//! | [`biharmonic`] | the boundary ring (Prop. 2) | Δ²x ≡ 0 (Theorem 2, eq. 8) |
//! | [`harmonic_mask`] | the boundary ring | ¼[0 1 0; 1 • 1; 0 1 0] (eq. 5–6) |
//! | [`biharmonic_mask`] | the two outer rings | the 13-point mask (eq. 7) |
//! | [`extremal`] | the boundary ring | ∇D = 0 or ∇B = 0 (Prop. 3, §4.1) |
//!
//! The polynomial identities are solved as dense least-squares systems in the
//! Bernstein basis with exact integer matrices ([`operator_matrix`]) and
//! iterative refinement with compensated residuals; each result reports how
//! well its defining equations hold. [`compare`] builds the paper's §4 table.

mod compare;
mod mask;
mod operator;
mod surface;

pub use compare::{compare, extremal, Column, Comparison, Functional};
pub use mask::{biharmonic_mask, biharmonic_mask_with, harmonic_mask, harmonic_mask_with};
pub use operator::{apply, derivative_elevated, operator_matrix, relative_residual, Operator};
pub use surface::{biharmonic, biharmonic_with, harmonic, harmonic_with, ConstructOptions};

use crate::analysis::SurfaceMeasures;
use crate::solve::Timings;
use crate::{TensorPatch, Vec3};

/// How a surface was made from its boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Δx ≡ 0 from the first and last rows.
    Harmonic,
    /// Δ²x ≡ 0 from the boundary ring.
    Biharmonic,
    /// The discrete harmonic (Coons) mask.
    HarmonicMask,
    /// The discrete biharmonic mask.
    BiharmonicMask,
}

impl Method {
    /// The scene-file name: "harmonic", "biharmonic", "harmonic_mask", "biharmonic_mask".
    pub fn name(self) -> &'static str {
        match self {
            Method::Harmonic => "harmonic",
            Method::Biharmonic => "biharmonic",
            Method::HarmonicMask => "harmonic_mask",
            Method::BiharmonicMask => "biharmonic_mask",
        }
    }

    /// Builds this surface from the boundary of `net`.
    pub fn construct(
        self,
        net: &TensorPatch,
        opts: &ConstructOptions,
    ) -> crate::Result<Construction> {
        match self {
            Method::Harmonic => harmonic_with(net, opts),
            Method::Biharmonic => biharmonic_with(net, opts),
            Method::HarmonicMask => harmonic_mask_with(net, opts),
            Method::BiharmonicMask => biharmonic_mask_with(net, opts),
        }
    }

    /// What the residual of this method measures.
    pub fn equations(self) -> &'static str {
        match self {
            Method::Harmonic => "Bernstein coefficients of Δx",
            Method::Biharmonic => "Bernstein coefficients of Δ²x",
            Method::HarmonicMask => "harmonic mask equations 4P_ij − Σ neighbours",
            Method::BiharmonicMask => "biharmonic mask equations (13-point stencil)",
        }
    }
}

/// A given control point that the construction had to replace.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Override {
    /// (i, j) of the point.
    pub index: (usize, usize),
    /// The value in the input.
    pub given: Vec3,
    /// The value the construction determined.
    pub determined: Vec3,
}

/// What a construction says about its result.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstructionReport {
    /// Which construction.
    pub method: Method,
    /// Scalar equations per coordinate.
    pub equations: usize,
    /// Control points solved for.
    pub unknowns: usize,
    /// max |equation value| / max |P_ij| at the returned net: for the
    /// polynomial identities the largest Bernstein coefficient of Δx or Δ²x
    /// relative to the size of the net.
    pub residual: f64,
    /// Normwise backward error of the equations: max |equation| / (‖A‖∞·max|P|),
    /// about ε when they hold in double precision.
    pub backward_error: f64,
    /// Whether the equations hold (backward error ≤ 1e-11). False only for a
    /// least-squares result asked for with [`ConstructOptions::least_squares`].
    pub exact: bool,
    /// Estimated 2-norm condition number of the (column-scaled) system.
    pub condition_estimate: f64,
    /// Iterative refinement steps taken.
    pub refinement_steps: usize,
    /// Given points that the construction determined differently (the corner
    /// P_nm of an even-degree harmonic surface, Prop. 1(2)).
    pub overridden: Vec<Override>,
    /// Area, functionals and curvature of the result.
    pub measures: Option<SurfaceMeasures>,
    /// Time per stage (assemble, factor, solve, analyse, total).
    pub timings: Timings,
}

/// A surface made by one of the constructions, and its report.
#[derive(Clone, Debug)]
pub struct Construction {
    /// The surface.
    pub patch: TensorPatch,
    /// How well its defining equations hold.
    pub report: ConstructionReport,
}

/// Backward errors at or below this count as "the equations hold".
pub const EXACT_TOLERANCE: f64 = 1e-11;
