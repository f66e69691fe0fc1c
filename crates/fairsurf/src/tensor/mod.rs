//! Tensor-product Bézier patches.

mod constraint;
mod patch;
mod samples;

pub use constraint::{TensorConstraint, Uv};

pub(crate) use patch::{chunk3, regular_normal, GridRows, GRID_LANES};
pub use patch::{SurfaceDerivatives, TensorPatch};
