//! fairsurf's integration tests, one binary (each file a module; one link
//! instead of twenty: about 40 s less of CI's compile). Run one file's tests
//! with a filter: `cargo test -p fairsurf --test suite triangle_solve::`.

mod common;

mod analysis;
mod bspline_constraints;
mod bspline_guides;
mod bspline_normal_field;
mod bspline_operators;
mod check_sweep;
mod energies;
mod factored;
mod harmonic;
mod problem_kinds;
mod solve;
mod tensor_constraints;
mod tensor_operators;
mod triangle;
mod triangle_energy;
mod triangle_factored;
mod triangle_operators;
mod triangle_refine;
mod triangle_solve;
