//! Problems, the solve, and what a solve reports.

pub(crate) mod dense;
mod jacobi;
pub(crate) mod lstsq;
mod problem;
mod report;

pub use problem::{Problem, Solution, SolveOptions};
pub use report::{SolveReport, SurfaceMeasures, TermEnergy, Timings};
