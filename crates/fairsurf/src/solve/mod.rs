//! Problems, the solve, and what a solve reports; the linear algebra every
//! surface kind shares: dense SPD solves with refinement (`dense`) and their
//! compensated residuals (`compensated`), sparse
//! equality-constrained quadratic minimization (`kkt`: one matrix for x, y
//! and z when nothing couples them, local rows eliminated by `nullspace`,
//! else the KKT system by LDLᵀ or LU), a few rows on a dense factor by the
//! range-space method (`rows`), refined least squares (`lstsq`).

mod builder;
mod cache;
pub(crate) mod columns;
pub(crate) mod compensated;
pub(crate) mod dense;
mod factored;
mod jacobi;
pub(crate) mod kkt;
pub(crate) mod lstsq;
mod nullspace;
mod problem;
mod report;
mod rows;
mod verify;

pub use builder::{Problem, SurfaceKind};
pub use cache::FactorCache;
pub use factored::Factored;
pub use problem::{Solution, SolveOptions};
pub use report::{SolveReport, TermEnergy, Timings, TriFigures};
pub(crate) use rows::{first_dependent_row, known_row_met};
