//! Tensor-product Bézier patches.

mod constraint;
mod patch;

pub use constraint::{TensorConstraint, Uv};

pub(crate) use patch::{GridRows, GRID_LANES};
pub use patch::{SurfaceDerivatives, TensorPatch};
