//! Problems, the solve, and what a solve reports.

mod cache;
pub(crate) mod dense;
mod jacobi;
pub(crate) mod lstsq;
mod problem;
mod report;

pub use cache::FactorCache;
pub use problem::{Factored, Problem, Solution, SolveOptions};
pub use report::{SolveReport, SurfaceMeasures, TermEnergy, Timings};
