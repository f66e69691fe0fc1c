//! Exact integrals of products of Bernstein polynomials.
//!
//! The one formula behind every energy of fairsurf:
//!
//! ```text
//! ∫₀¹ Π_r B_{i_r}^{n_r}(t) dt = Π_r C(n_r, i_r) / ((N+1) · C(N, I)),   N = Σ n_r,  I = Σ i_r
//! ```
//!
//! (the product is `Π C(n_r,i_r) / C(N,I) · B_I^N`, and every `B_I^N`
//! integrates to 1/(N+1)).

use super::bernstein::binomial;
use faer::Mat;

/// ∫₀¹ Π B_{i_r}^{n_r}(t) dt for the factors `(n_r, i_r)`; 0 if some i_r > n_r.
/// The empty product integrates to 1.
///
/// ```
/// use fairsurf::basis::product_integral;
/// // ∫ B_1^2 · B_1^2 = ∫ 4t²(1−t)² = 2/15
/// assert!((product_integral(&[(2, 1), (2, 1)]) - 2.0 / 15.0).abs() < 1e-16);
/// ```
pub fn product_integral(factors: &[(usize, usize)]) -> f64 {
    if factors.iter().any(|&(n, i)| i > n) {
        return 0.0;
    }
    let big_n: usize = factors.iter().map(|f| f.0).sum();
    let big_i: usize = factors.iter().map(|f| f.1).sum();
    if big_n <= 1000 {
        let num: f64 = factors.iter().map(|&(n, i)| binomial(n, i)).product();
        num / ((big_n + 1) as f64 * binomial(big_n, big_i))
    } else {
        // Past C(1029, 514) ≈ 1e308 the direct form overflows; the logarithmic
        // form costs a few ulps per factor but never overflows.
        let ln: f64 = factors.iter().map(|&(n, i)| ln_binomial(n, i)).sum::<f64>()
            - ln_binomial(big_n, big_i)
            - ((big_n + 1) as f64).ln();
        ln.exp()
    }
}

fn ln_binomial(n: usize, k: usize) -> f64 {
    let k = k.min(n - k);
    (0..k).map(|i| ((n - i) as f64 / (i + 1) as f64).ln()).sum()
}

/// The (n+1)×(m+1) Gram matrix `G_ij = ∫₀¹ B_i^n B_j^m dt`.
pub fn gram_matrix(n: usize, m: usize) -> Mat<f64> {
    Mat::from_fn(n + 1, m + 1, |i, j| product_integral(&[(n, i), (m, j)]))
}

/// For each α = 0..=w the (n+1)×(m+1) matrix `T_α[i][j] = ∫₀¹ B_i^n B_α^w B_j^m dt`:
/// the Gram matrix of degrees n and m weighted by the Bernstein polynomial `B_α^w`.
pub fn triple_product_integrals(n: usize, w: usize, m: usize) -> Vec<Mat<f64>> {
    let big_n = n + w + m;
    if big_n > 1000 {
        return (0..=w)
            .map(|a| {
                Mat::from_fn(n + 1, m + 1, |i, j| {
                    product_integral(&[(n, i), (w, a), (m, j)])
                })
            })
            .collect();
    }
    // The direct form of `product_integral` with every binomial computed
    // once (the same operations in the same order, so the same values).
    let row = |d: usize| (0..=d).map(|k| binomial(d, k)).collect::<Vec<f64>>();
    let (cn, cw, cm, cbig) = (row(n), row(w), row(m), row(big_n));
    (0..=w)
        .map(|a| {
            Mat::from_fn(n + 1, m + 1, |i, j| {
                cn[i] * cw[a] * cm[j] / ((big_n + 1) as f64 * cbig[i + a + j])
            })
        })
        .collect()
}

/// Bernstein coefficients (degree n+m) of the product of two polynomials
/// given by their Bernstein coefficients `a` (degree n) and `b` (degree m):
/// `(ab)_k = Σ_{i+j=k} C(n,i) C(m,j) / C(n+m,k) · a_i b_j`.
pub fn product_coefficients(a: &[f64], b: &[f64]) -> Vec<f64> {
    assert!(
        !a.is_empty() && !b.is_empty(),
        "a polynomial has at least one coefficient"
    );
    let (n, m) = (a.len() - 1, b.len() - 1);
    let mut out = vec![0.0; n + m + 1];
    for (i, &ai) in a.iter().enumerate() {
        for (j, &bj) in b.iter().enumerate() {
            out[i + j] += binomial(n, i) * binomial(m, j) * ai * bj;
        }
    }
    for (k, o) in out.iter_mut().enumerate() {
        *o /= binomial(n + m, k);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::{bernstein_all, GaussLegendre};

    /// The closed form agrees with Gauss–Legendre quadrature that is exact
    /// for the degree (q points integrate degree 2q−1 exactly).
    #[test]
    fn closed_form_equals_exact_quadrature() {
        let cases: &[&[(usize, usize)]] = &[
            &[(3, 1)],
            &[(5, 2), (5, 3)],
            &[(7, 0), (4, 4), (9, 5)],
            &[(6, 3), (2, 1), (6, 2), (3, 3)],
            &[(12, 6), (12, 7), (10, 4), (10, 5)],
            &[(29, 14), (60, 31), (29, 15)],
        ];
        for f in cases {
            let deg: usize = f.iter().map(|x| x.0).sum();
            let gl = GaussLegendre::new(deg / 2 + 2);
            let q = gl.integrate(|t| f.iter().map(|&(n, i)| bernstein_all(n, t)[i]).product());
            let c = product_integral(f);
            assert!(
                (q - c).abs() <= 1e-14 * c.abs().max(1e-300) + 1e-300,
                "{f:?}: {q} vs {c}"
            );
        }
    }

    #[test]
    fn single_bernstein_integrates_to_one_over_n_plus_one() {
        for n in 0..40 {
            for i in 0..=n {
                let v = product_integral(&[(n, i)]);
                assert!((v - 1.0 / (n + 1) as f64).abs() < 1e-16);
            }
        }
        assert_eq!(product_integral(&[]), 1.0);
        assert_eq!(product_integral(&[(3, 4)]), 0.0);
    }

    #[test]
    fn logarithmic_branch_matches_direct_branch() {
        // N = 1001 takes the logarithmic branch; compare against splitting the
        // same integral into one direct product of a smaller degree.
        let f = [(500, 250), (501, 260)];
        let big = product_integral(&f);
        let direct = binomial(500, 250) * binomial(501, 260) / (1002.0 * binomial(1001, 510));
        assert!((big - direct).abs() < 1e-12 * direct);
    }

    /// The tables with shared binomials are the closed form entry for entry,
    /// bit for bit, on both sides of the logarithmic branch.
    #[test]
    fn triple_tables_equal_the_closed_form() {
        for (n, w, m) in [
            (0, 0, 0),
            (3, 2, 5),
            (10, 6, 10),
            (40, 12, 39),
            (990, 1, 10),
        ] {
            for (a, t) in triple_product_integrals(n, w, m).iter().enumerate() {
                for i in 0..=n {
                    for j in 0..=m {
                        let c = product_integral(&[(n, i), (w, a), (m, j)]);
                        assert_eq!(t[(i, j)].to_bits(), c.to_bits(), "{n} {w} {m}: {a} {i} {j}");
                    }
                }
            }
        }
    }

    #[test]
    fn gram_rows_sum_to_one_over_n_plus_one() {
        // Σ_j ∫ B_i^n B_j^m = ∫ B_i^n = 1/(n+1) (partition of unity).
        let g = gram_matrix(6, 9);
        for i in 0..7 {
            let s: f64 = (0..10).map(|j| g[(i, j)]).sum();
            assert!((s - 1.0 / 7.0).abs() < 1e-15);
        }
    }

    #[test]
    fn product_coefficients_evaluate_to_the_product() {
        let a = [1.0, -2.0, 0.5, 3.0];
        let b = [0.25, 4.0, -1.0];
        let p = product_coefficients(&a, &b);
        for &t in &[0.0, 0.3, 0.77, 1.0] {
            let ev = |c: &[f64]| {
                let bb = bernstein_all(c.len() - 1, t);
                c.iter().zip(bb).map(|(x, y)| x * y).sum::<f64>()
            };
            assert!((ev(&a) * ev(&b) - ev(&p)).abs() < 1e-13);
        }
    }
}
