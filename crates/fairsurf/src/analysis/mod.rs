//! Measures of a surface: area, the Dirichlet and biharmonic functionals,
//! curvature, and how far its normals are from a guiding field.

mod area;
mod continuity;
mod curvature;
mod folds;
mod functionals;
mod normals;
mod scan;

pub use area::{area, Area, AREA_TOLERANCE};
pub use continuity::{continuity, Continuity, Edge, Stat};
pub(crate) use curvature::is_regular;
pub(crate) use curvature::PointForms;
pub use curvature::{abs_mean_curvature, curvature, curvature_from, AbsMeanCurvature, Curvature};
pub use folds::{largest_normal_turn, largest_tri_normal_turn, NormalTurn, TriNormalTurn};
pub use functionals::{biharmonic, dirichlet};
pub use normals::{normal_deviation, NormalDeviation};

use crate::TensorPatch;

/// Grid size (k) of the absolute mean curvature statistics in reports.
pub const CURVATURE_GRID: usize = 64;

/// Geometric measures of a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceMeasures {
    /// Area ∫∫ |R_u × R_v| by adaptive Gauss–Legendre quadrature.
    pub area: f64,
    /// Estimated absolute error of `area`.
    pub area_error: f64,
    /// Dirichlet functional D = ½ ∫∫ |R_u|² + |R_v|², exact.
    pub dirichlet: f64,
    /// Biharmonic (thin-plate) functional B = ½ ∫∫ |R_uu|² + 2|R_uv|² + |R_vv|², exact.
    pub biharmonic: f64,
    /// |H| on the 65×65 grid (Monterde & Ugail §4.4).
    pub abs_mean_curvature: AbsMeanCurvature,
    /// The largest turn of the unit normal between neighbouring samples of
    /// the same grid; more than 90° is a fold, which reports note.
    pub normal_turn: Option<NormalTurn>,
}

/// Area (with its error estimate), both functionals and |H| statistics of a
/// patch.
pub fn measures(patch: &TensorPatch) -> SurfaceMeasures {
    let a = area(patch);
    // One pass over the derivative grid serves the |H| statistics and the
    // normal turn.
    let (abs_mean_curvature, normal_turn) = scan::curvature_and_turn(patch, CURVATURE_GRID);
    SurfaceMeasures {
        area: a.value,
        area_error: a.error,
        dirichlet: dirichlet(patch),
        biharmonic: biharmonic(patch),
        abs_mean_curvature,
        normal_turn,
    }
}
