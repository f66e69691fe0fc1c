//! Bernstein polynomials `B_i^n(t) = C(n,i) tⁱ (1−t)ⁿ⁻ⁱ` and the linear maps
//! between Bernstein coefficient vectors (differentiation, degree elevation).

use faer::Mat;

/// Binomial coefficient C(n, k) as a float; 0 when k > n.
///
/// Computed by the multiplicative formula, exact for every value below 2⁵³
/// and correct to a few ulps beyond; overflows to ∞ only past n ≈ 1029.
pub fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    let mut c = 1.0;
    for i in 0..k {
        // C(n, i+1) = C(n, i) · (n−i) / (i+1); each step stays an integer.
        c = c * (n - i) as f64 / (i + 1) as f64;
    }
    c.round_if_exact()
}

trait RoundIfExact {
    fn round_if_exact(self) -> Self;
}

impl RoundIfExact for f64 {
    /// Below 2⁵³ the true value is an integer: snap away accumulated rounding.
    fn round_if_exact(self) -> f64 {
        if self < 9.007_199_254_740_992e15 {
            self.round()
        } else {
            self
        }
    }
}

/// `B_i^n(t)`; 0 when i > n.
pub fn bernstein(n: usize, i: usize, t: f64) -> f64 {
    if i > n {
        return 0.0;
    }
    bernstein_all(n, t)[i]
}

/// All `B_0^n(t) … B_n^n(t)`, by the triangular recurrence
/// `B_i^k = (1−t) B_i^{k−1} + t B_{i−1}^{k−1}` (stable: only convex combinations
/// for t ∈ [0, 1]).
pub fn bernstein_all(n: usize, t: f64) -> Vec<f64> {
    let mut b = vec![0.0; n + 1];
    bernstein_all_into(t, &mut b);
    b
}

/// [`bernstein_all`] into `b`, whose length is n + 1 (no allocation).
pub fn bernstein_all_into(t: f64, b: &mut [f64]) {
    let n = b.len().saturating_sub(1);
    b.fill(0.0);
    b[0] = 1.0;
    let s = 1.0 - t;
    for k in 1..=n {
        let mut prev = 0.0;
        for i in 0..=k {
            let cur = b[i];
            b[i] = s * cur + t * prev;
            prev = cur;
        }
    }
}

/// Derivatives of all degree-n Bernstein polynomials up to `order`:
/// `out[r][i] = dʳ/dtʳ B_i^n(t)`, for r = 0..=order.
///
/// Uses `dʳ B_i^n = n!/(n−r)! Σ_s (−1)^{r−s} C(r,s) B_{i−s}^{n−r}`: each order is
/// the forward difference of the next lower degree's values.
pub fn bernstein_derivatives(n: usize, t: f64, order: usize) -> Vec<Vec<f64>> {
    let mut flat = vec![0.0; (order + 1) * (n + 1)];
    bernstein_derivatives_into(n, t, &mut flat);
    flat.chunks(n + 1).map(<[f64]>::to_vec).collect()
}

/// [`bernstein_derivatives`] into `out` without allocating: `out` holds
/// rows of n + 1 values, one per order r = 0, 1, … (its length over n + 1).
///
/// One pass of the triangle `B_i^k = (1−t) B_i^{k−1} + t B_{i−1}^{k−1}` up to
/// degree n: order r's row holds B^{n−r} when the pass reaches degree n − r
/// (each row then carries on to degree n alone), and is then differenced r
/// times, `c_i ← k (c_{i−1} − c_i)` raising the degree k − 1 → k — the
/// formula above, at (n + 1)(n + 2)/2 + r(n + 1) steps per order instead of
/// a triangle per order.
pub fn bernstein_derivatives_into(n: usize, t: f64, out: &mut [f64]) {
    let w = n + 1;
    debug_assert_eq!(out.len() % w, 0, "rows of n + 1 values");
    let orders = out.len() / w;
    let out = &mut out[..orders * w];
    out.fill(0.0);
    let top = orders.min(w); // orders above n are zero
    if top == 0 {
        return;
    }
    let s = 1.0 - t;
    // Row `top − 1` (the highest order) runs the triangle up to its
    // degree n − (top − 1); each lower row goes on from the one above.
    let last = top - 1;
    bernstein_all_into(t, &mut out[last * w..last * w + n - last + 1]);
    // Degrees n − last + 1 … n: each lower order's row starts as a copy of
    // the one above it, raised one degree.
    for r in (0..last).rev() {
        let k = n - r;
        let (lo, hi) = out.split_at_mut((r + 1) * w);
        let row = &mut lo[r * w..];
        let above = &hi[..w];
        let mut prev = 0.0;
        for i in 0..=k {
            let cur = above[i];
            row[i] = s * cur + t * prev;
            prev = cur;
        }
    }
    // Row r holds B^{n−r}: difference it r times up to degree n.
    for r in 1..top {
        let row = &mut out[r * w..(r + 1) * w];
        for k in n - r + 1..=n {
            let kf = k as f64;
            let mut left = 0.0;
            for i in 0..=k {
                let here = if i < k { row[i] } else { 0.0 };
                row[i] = kf * (left - here);
                left = here;
            }
        }
    }
}

/// The (n−r+1)×(n+1) matrix `D` taking the Bernstein coefficients of a
/// degree-n polynomial to those of its r-th derivative (degree n−r):
/// `p⁽ʳ⁾ = Σ_k (D c)_k B_k^{n−r}`, `(D c)_k = n!/(n−r)! Σ_s (−1)^{r−s} C(r,s) c_{k+s}`.
/// For r > n the derivative is zero and the matrix has one zero row.
pub fn derivative_matrix(n: usize, r: usize) -> Mat<f64> {
    if r > n {
        return Mat::zeros(1, n + 1);
    }
    let falling: f64 = (0..r).map(|q| (n - q) as f64).product();
    let mut d = Mat::zeros(n - r + 1, n + 1);
    for k in 0..=n - r {
        for s in 0..=r {
            let sign = if (r - s) % 2 == 0 { 1.0 } else { -1.0 };
            d[(k, k + s)] = falling * sign * binomial(r, s);
        }
    }
    d
}

/// The (n+r+1)×(n+1) degree-elevation matrix from degree n to degree n+r:
/// `c'_k = Σ_i C(n,i) C(r,k−i) / C(n+r,k) c_i`.
pub fn elevation_matrix(n: usize, r: usize) -> Mat<f64> {
    Mat::from_fn(n + r + 1, n + 1, |k, i| {
        if k < i || k - i > r {
            0.0
        } else {
            binomial(n, i) * binomial(r, k - i) / binomial(n + r, k)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binomials_are_pascal() {
        for n in 1..60 {
            for k in 1..n {
                let lhs = binomial(n, k);
                let rhs = binomial(n - 1, k - 1) + binomial(n - 1, k);
                assert!((lhs - rhs).abs() <= 1e-15 * lhs, "C({n},{k})");
            }
        }
        assert_eq!(binomial(5, 7), 0.0);
        assert_eq!(binomial(52, 26), 495_918_532_948_104.0);
    }

    #[test]
    fn partition_of_unity_and_closed_form() {
        for n in 0..25 {
            for &t in &[0.0, 0.1, 0.37, 0.5, 0.99, 1.0] {
                let b = bernstein_all(n, t);
                let s: f64 = b.iter().sum();
                assert!((s - 1.0).abs() < 1e-14);
                for (i, &bi) in b.iter().enumerate() {
                    let direct = binomial(n, i) * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32);
                    assert!((bi - direct).abs() < 1e-13, "n={n} i={i} t={t}");
                }
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-5;
        for n in 1..12 {
            for &t in &[0.2, 0.5, 0.81] {
                let d = bernstein_derivatives(n, t, 3);
                let lo = bernstein_derivatives(n, t - h, 2);
                let hi = bernstein_derivatives(n, t + h, 2);
                for r in 1..=3 {
                    for i in 0..=n {
                        let fd = (hi[r - 1][i] - lo[r - 1][i]) / (2.0 * h);
                        let scale = 1.0 + d[r][i].abs();
                        assert!((fd - d[r][i]).abs() < 1e-5 * scale * (n * n) as f64);
                    }
                }
            }
        }
    }

    #[test]
    fn derivatives_beyond_degree_vanish() {
        let d = bernstein_derivatives(2, 0.3, 4);
        assert!(d[3].iter().chain(&d[4]).all(|&x| x == 0.0));
    }

    /// Each order equals the closed form n!/(n−r)! Σ_s (−1)^{r−s} C(r,s)
    /// B_{i−s}^{n−r}, with B^{n−r} by its own triangle, and equally for
    /// every number of orders asked (each row is made from the next's).
    #[test]
    fn derivatives_match_their_closed_form() {
        for n in 0..25 {
            for &t in &[0.0, 0.13, 0.5, 0.97, 1.0] {
                for orders in 1..=n + 3 {
                    let d = bernstein_derivatives(n, t, orders - 1);
                    for (r, row) in d.iter().enumerate() {
                        let want: Vec<f64> = if r > n {
                            vec![0.0; n + 1]
                        } else {
                            let b = bernstein_all(n - r, t);
                            let falling: f64 = (0..r).map(|q| (n - q) as f64).product();
                            (0..=n)
                                .map(|i| {
                                    falling
                                        * (0..=r.min(i))
                                            .filter(|&s| i - s <= n - r)
                                            .map(|s| {
                                                let sign =
                                                    if (r - s) % 2 == 0 { 1.0 } else { -1.0 };
                                                sign * binomial(r, s) * b[i - s]
                                            })
                                            .sum::<f64>()
                                })
                                .collect()
                        };
                        let scale = want.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
                        for i in 0..=n {
                            assert!(
                                (row[i] - want[i]).abs() <= 1e-13 * scale,
                                "n {n} t {t} r {r} i {i}: {} vs {}",
                                row[i],
                                want[i]
                            );
                        }
                    }
                }
            }
        }
    }
    #[test]
    fn elevation_preserves_the_polynomial() {
        let c = [0.3, -1.2, 2.0, 0.7, 5.0];
        let n = c.len() - 1;
        for r in 1..5 {
            let e = elevation_matrix(n, r);
            for &t in &[0.0, 0.25, 0.6, 1.0] {
                let b = bernstein_all(n, t);
                let be = bernstein_all(n + r, t);
                let p: f64 = (0..=n).map(|i| c[i] * b[i]).sum();
                let q: f64 = (0..=n + r)
                    .map(|k| (0..=n).map(|i| e[(k, i)] * c[i]).sum::<f64>() * be[k])
                    .sum();
                assert!((p - q).abs() < 1e-13);
            }
        }
    }
}
