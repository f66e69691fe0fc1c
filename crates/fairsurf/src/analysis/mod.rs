//! Measures of a surface: area, the Dirichlet and biharmonic functionals, and
//! how far its normals are from a guiding field.

mod area;
mod functionals;
mod normals;

pub use area::{area, Area};
pub use functionals::{biharmonic, dirichlet};
pub use normals::{normal_deviation, NormalDeviation};

use crate::solve::SurfaceMeasures;
use crate::TensorPatch;

/// Area (with its error estimate) and both functionals of a patch.
pub fn measures(patch: &TensorPatch) -> SurfaceMeasures {
    let a = area(patch);
    SurfaceMeasures {
        area: a.value,
        area_error: a.error,
        dirichlet: dirichlet(patch),
        biharmonic: biharmonic(patch),
    }
}
