//! The Bernstein basis: values, derivatives, degree elevation, and exact
//! integrals of products of Bernstein polynomials.
//!
//! `B_i^n(t) = C(n,i) tⁱ (1−t)ⁿ⁻ⁱ`, `0 ≤ i ≤ n`, on the domain `t ∈ [0, 1]`.

mod bernstein;
mod gauss;
mod integral;
pub mod polygon;

pub use bernstein::{
    bernstein, bernstein_all, bernstein_all_into, bernstein_derivatives,
    bernstein_derivatives_into, binomial, derivative_matrix, elevation_matrix,
};
pub use gauss::GaussLegendre;
pub use integral::{gram_matrix, product_coefficients, product_integral, triple_product_integrals};
