//! fairsurf-io's integration tests, one binary (each file a module; one link
//! instead of five). Run one file's tests with a filter:
//! `cargo test -p fairsurf-io --test suite fuzz::`.

#[path = "../mutate/mod.rs"]
mod mutate;

mod exports;
mod fill_fuzz;
mod fuzz;
mod monterde_ugail;
mod revolved;
mod scenes;
