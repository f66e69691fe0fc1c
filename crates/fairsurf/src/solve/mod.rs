//! Problems, the solve, and what a solve reports.

mod dense;
mod jacobi;
mod problem;
mod report;

pub use problem::{Problem, Solution, SolveOptions};
pub use report::{SolveReport, SurfaceMeasures, TermEnergy, Timings};
