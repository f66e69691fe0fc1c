//! Exact integrals of products of triangular Bernstein polynomials.
//!
//! The one formula behind the triangular energies (the two-variable analogue
//! of [`crate::basis::product_integral`]):
//!
//! ```text
//! ∫_Δ B_λ^p B_μ^q dA = A · C(p; λ) C(q; μ) / C(p+q; λ+μ) · 2 / ((p+q+1)(p+q+2)),
//! ```
//!
//! over any triangle Δ of area A, with C(p; λ) = p!/(λ₁! λ₂! λ₃!) the
//! trinomial coefficient. The product is `C(p; λ) C(q; μ) / C(p+q; λ+μ) ·
//! B_{λ+μ}^{p+q}`, and each of the (N+1)(N+2)/2 Bernstein polynomials of
//! degree N has the same integral (the Dirichlet integral
//! ∫ uⁱ vʲ wᵏ dA = 2A · i! j! k! / (N+2)!), so each integrates to
//! 2A / ((N+1)(N+2)); they sum to A.

use super::bernstein::trinomial;
use super::index::multi_indices;
use faer::Mat;

/// `∫_Δ B_λ^p B_μ^q dA` over a triangle of **unit area**, p = |λ|, q = |μ|:
///
/// ```text
/// C(p; λ) C(q; μ) / C(p+q; λ+μ) · 2 / ((p+q+1)(p+q+2))
/// ```
///
/// Over a triangle of area A multiply by A (the integrand is affine
/// invariant). Exact rational coefficients while the trinomials stay below
/// 2⁵³ (p + q ≤ 33), a few ulps beyond; the trinomials overflow past
/// p + q ≈ 640.
///
/// ```
/// use fairsurf::triangle::tri_product_integral;
/// // ∫ B_100 · B_100 = ∫ u² = 2·2!/4! = 1/6 over unit area.
/// assert!((tri_product_integral([1, 0, 0], [1, 0, 0]) - 1.0 / 6.0).abs() < 1e-16);
/// // Constants: ∫ 1 = A = 1.
/// assert_eq!(tri_product_integral([0, 0, 0], [0, 0, 0]), 1.0);
/// ```
pub fn tri_product_integral(lambda: [usize; 3], mu: [usize; 3]) -> f64 {
    let sum = [lambda[0] + mu[0], lambda[1] + mu[1], lambda[2] + mu[2]];
    let big = (sum[0] + sum[1] + sum[2]) as f64;
    let ratio = trinomial(lambda[0], lambda[1], lambda[2]) * trinomial(mu[0], mu[1], mu[2])
        / trinomial(sum[0], sum[1], sum[2]);
    ratio * 2.0 / ((big + 1.0) * (big + 2.0))
}

/// The Gram matrix `G[l][m] = ∫_Δ B_λ^p B_μ^q dA` over a triangle of unit
/// area, rows λ over the degree-p net and columns μ over the degree-q net,
/// both in the storage order of [`super::linear_index`]. Symmetric when
/// p = q, with positive entries.
///
/// ```
/// use fairsurf::triangle::tri_gram_matrix;
/// let g = tri_gram_matrix(2, 3);
/// assert_eq!((g.nrows(), g.ncols()), (6, 10));
/// // Partition of unity: all entries sum to ∫ 1 · 1 = 1.
/// let total: f64 = (0..6).flat_map(|i| (0..10).map(move |j| (i, j))).map(|(i, j)| g[(i, j)]).sum();
/// assert!((total - 1.0).abs() < 1e-15);
/// ```
pub fn tri_gram_matrix(p: usize, q: usize) -> Mat<f64> {
    let rows: Vec<[usize; 3]> = multi_indices(p).collect();
    let cols: Vec<[usize; 3]> = multi_indices(q).collect();
    Mat::from_fn(rows.len(), cols.len(), |l, m| {
        tri_product_integral(rows[l], cols[m])
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::triangle::point_count;

    #[test]
    fn every_basis_function_has_the_same_integral() {
        // ∫ B_λ^N · B_0^0 = 2/((N+1)(N+2)) for every λ.
        for n in 0..12 {
            for l in multi_indices(n) {
                let v = tri_product_integral(l, [0, 0, 0]);
                let expected = 2.0 / ((n + 1) * (n + 2)) as f64;
                assert!((v - expected).abs() <= 2.0 * f64::EPSILON * expected);
            }
        }
    }

    #[test]
    fn rows_of_the_gram_matrix_sum_to_the_basis_integral() {
        // Σ_μ B_μ^q = 1, so row λ sums to ∫ B_λ^p = 2/((p+1)(p+2)).
        for (p, q) in [(1, 1), (2, 4), (5, 3), (6, 6)] {
            let g = tri_gram_matrix(p, q);
            for l in 0..point_count(p) {
                let s: f64 = (0..point_count(q)).map(|m| g[(l, m)]).sum();
                let expected = 2.0 / ((p + 1) * (p + 2)) as f64;
                assert!((s - expected).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn is_symmetric_under_relabelling_the_corners() {
        let (l, m) = ([3, 1, 0], [0, 2, 2]);
        let a = tri_product_integral(l, m);
        for perm in [
            [0, 1, 2],
            [1, 2, 0],
            [2, 0, 1],
            [0, 2, 1],
            [2, 1, 0],
            [1, 0, 2],
        ] {
            let pl = perm.map(|x| l[x]);
            let pm = perm.map(|x| m[x]);
            assert_eq!(tri_product_integral(pl, pm), a);
        }
    }
}
