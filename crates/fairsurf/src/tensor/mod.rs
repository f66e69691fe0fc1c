//! Tensor-product Bézier patches.

mod patch;

pub use patch::{SurfaceDerivatives, TensorPatch};
