//! Measures of a surface: area, the Dirichlet and biharmonic functionals,
//! curvature, and how far its normals are from a guiding field.

mod area;
mod continuity;
mod curvature;
mod folds;
mod functionals;
mod normals;

pub use area::{area, Area, AREA_TOLERANCE};
pub use continuity::{continuity, Continuity, Edge, Stat};
pub use curvature::{abs_mean_curvature, curvature, curvature_from, AbsMeanCurvature, Curvature};
pub use folds::{largest_normal_turn, largest_tri_normal_turn, NormalTurn, TriNormalTurn};
pub use functionals::{biharmonic, dirichlet};
pub use normals::{normal_deviation, NormalDeviation};

use crate::solve::SurfaceMeasures;
use crate::TensorPatch;

/// Grid size (k) of the absolute mean curvature statistics in reports.
pub const CURVATURE_GRID: usize = 64;

/// Area (with its error estimate), both functionals and |H| statistics of a
/// patch.
pub fn measures(patch: &TensorPatch) -> SurfaceMeasures {
    let a = area(patch);
    // One derivative grid serves the |H| statistics and the normal turn.
    let k = CURVATURE_GRID;
    let ts = curvature::unit_grid(k);
    let grid = patch.grid_derivatives(&ts, &ts);
    SurfaceMeasures {
        area: a.value,
        area_error: a.error,
        dirichlet: dirichlet(patch),
        biharmonic: biharmonic(patch),
        abs_mean_curvature: curvature::abs_mean_curvature_on(&grid, k),
        normal_turn: folds::largest_normal_turn_on(&grid, k),
    }
}
