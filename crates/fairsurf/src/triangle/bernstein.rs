//! The Bernstein polynomials over a triangle (Veltkamp & Wesselink, §2):
//!
//! ```text
//! B_ijk^n(u, v, w) = n!/(i! j! k!) uⁱ vʲ wᵏ,   i + j + k = n,   u + v + w = 1,
//! ```
//!
//! with (u, v, w) the barycentric coordinates of a point of the domain
//! triangle V₁V₂V₃: u = 1 at V₁, v = 1 at V₂, w = 1 at V₃. On the triangle
//! (u, v, w ≥ 0) they are ≥ 0 and sum to (u + v + w)ⁿ = 1.

use super::index::{multi_indices, point_count};
use crate::basis::binomial;

/// Barycentric coordinates (u, v, w) of a point of the domain triangle, with
/// u + v + w = 1 (u = 1 at corner 0, v = 1 at corner 1, w = 1 at corner 2);
/// or, where a method says so, a direction (d_u, d_v, d_w) with
/// d_u + d_v + d_w = 0.
///
/// Nothing checks the sums: every formula in this module is a homogeneous
/// polynomial of degree n in (u, v, w), so a triple that sums to s ≠ 1
/// gives sⁿ times the value at the normalised point.
pub type Bary = [f64; 3];

/// The trinomial coefficient n!/(i! j! k!) = C(n, i) C(n − i, j), with
/// n = i + j + k; exact below 2⁵³ (see [`crate::basis::binomial`]).
///
/// ```
/// use fairsurf::triangle::trinomial;
/// assert_eq!(trinomial(1, 1, 1), 6.0);
/// assert_eq!(trinomial(3, 0, 0), 1.0);
/// ```
pub fn trinomial(i: usize, j: usize, k: usize) -> f64 {
    let n = i + j + k;
    binomial(n, i) * binomial(n - i, j)
}

/// `B_ijk^n(u, v, w) = n!/(i! j! k!) uⁱ vʲ wᵏ` with n = i + j + k, by the
/// explicit formula (0⁰ = 1).
///
/// ```
/// use fairsurf::triangle::tri_bernstein;
/// // B_111^3 = 6uvw, 6/27 at the centroid.
/// let c = 1.0 / 3.0;
/// assert!((tri_bernstein(1, 1, 1, [c, c, c]) - 6.0 / 27.0).abs() < 1e-15);
/// ```
pub fn tri_bernstein(i: usize, j: usize, k: usize, b: Bary) -> f64 {
    trinomial(i, j, k) * b[0].powi(exp(i)) * b[1].powi(exp(j)) * b[2].powi(exp(k))
}

/// All B_ijk^n(u, v, w), i + j + k = n, in the storage order of
/// [`super::linear_index`], by the explicit formula with tables of powers.
///
/// ```
/// use fairsurf::triangle::tri_bernstein_all;
/// let b = tri_bernstein_all(4, [0.2, 0.3, 0.5]);
/// assert_eq!(b.len(), 15);
/// assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
/// ```
pub fn tri_bernstein_all(n: usize, b: Bary) -> Vec<f64> {
    let powers = |x: f64| -> Vec<f64> {
        std::iter::successors(Some(1.0), |p| Some(p * x))
            .take(n + 1)
            .collect()
    };
    let (pu, pv, pw) = (powers(b[0]), powers(b[1]), powers(b[2]));
    let mut out = Vec::with_capacity(point_count(n));
    for [i, j, k] in multi_indices(n) {
        out.push(trinomial(i, j, k) * pu[i] * pv[j] * pw[k]);
    }
    out
}

/// An exponent as the `i32` that `powi` wants (degrees beyond i32::MAX are
/// far past where the coefficients overflow anyway).
fn exp(e: usize) -> i32 {
    i32::try_from(e).unwrap_or(i32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::triangle::linear_index;

    #[test]
    fn trinomials_sum_to_three_to_the_n() {
        for n in 0..25 {
            let s: f64 = multi_indices(n).map(|[i, j, k]| trinomial(i, j, k)).sum();
            assert_eq!(s, 3f64.powi(n as i32));
        }
    }

    #[test]
    fn all_agrees_with_one_at_a_time() {
        let b = [0.15, 0.6, 0.25];
        for n in 0..10 {
            let all = tri_bernstein_all(n, b);
            for [i, j, k] in multi_indices(n) {
                let one = tri_bernstein(i, j, k, b);
                let l = linear_index(n, i, j, k);
                assert!((all[l] - one).abs() <= 4.0 * f64::EPSILON * one);
            }
        }
    }

    #[test]
    fn corners_select_one_function() {
        // At corner V₁ (u = 1) only B_n00 is nonzero, and it is 1.
        let b = tri_bernstein_all(5, [1.0, 0.0, 0.0]);
        assert_eq!(b[0], 1.0);
        assert!(b[1..].iter().all(|&x| x == 0.0));
        let b = tri_bernstein_all(5, [0.0, 0.0, 1.0]);
        assert_eq!(*b.last().unwrap(), 1.0);
    }

    #[test]
    fn on_an_edge_they_are_the_univariate_bernstein_polynomials() {
        // w = 0: B_{n−l,l,0}^n(1−t, t, 0) = B_l^n(t).
        let (n, t) = (6, 0.3);
        let tri = tri_bernstein_all(n, [1.0 - t, t, 0.0]);
        let uni = crate::basis::bernstein_all(n, t);
        for l in 0..=n {
            // bernstein_all(n, t)[l] is the coefficient of tˡ(1−t)ⁿ⁻ˡ.
            assert!((tri[l] - uni[l]).abs() < 1e-15);
        }
    }
}
