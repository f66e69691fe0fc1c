//! Tensor-product Bézier patches.

mod constraint;
mod patch;

pub use constraint::{TensorConstraint, Uv};

pub use patch::{SurfaceDerivatives, TensorPatch};
