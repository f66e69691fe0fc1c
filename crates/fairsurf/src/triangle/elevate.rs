//! Degree elevation of triangular Bézier patches (Farin 1993, 1986).
//!
//! Multiplying T by (u + v + w)ʳ = 1 writes the same surface with degree
//! n + r. For r = 1:
//!
//! ```text
//! Q_ijk = (i P_{i−1,j,k} + j P_{i,j−1,k} + k P_{i,j,k−1}) / (n + 1),   i + j + k = n + 1,
//! ```
//!
//! and in general, with multinomials C(n; μ) = n!/(μ₁! μ₂! μ₃!):
//!
//! ```text
//! Q_λ = Σ_{μ ≤ λ, |μ| = n} C(n; μ) C(r; λ − μ) / C(n + r; λ) · P_μ,   |λ| = n + r.
//! ```
//!
//! Every Q_λ is a convex combination of the P_μ, so the elevated net lies in
//! the convex hull of the original one.

use super::bernstein::trinomial;
use super::index::index_of;
use super::patch::TriPatch;
use crate::vec3::{add, scale};

impl TriPatch {
    /// The same surface written with degree n + r (r = 0 gives a copy): the
    /// elevated patch evaluates identically, up to rounding.
    ///
    /// The weights C(n; μ) C(r; λ − μ) / C(n + r; λ) are formed in floating
    /// point from exact integer binomials, so degrees n + r up to ≈ 30 have
    /// exact coefficients and larger ones are correct to a few ulps.
    ///
    /// ```
    /// use fairsurf::TriPatch;
    /// let t = TriPatch::from_fn(2, |i, j, k| [i as f64, j as f64, (i * j * k) as f64 + k as f64]);
    /// let e = t.elevate(3);
    /// assert_eq!(e.degree(), 5);
    /// let (a, b) = (t.eval([0.1, 0.6, 0.3]), e.eval([0.1, 0.6, 0.3]));
    /// assert!((0..3).all(|x| (a[x] - b[x]).abs() < 1e-14));
    /// ```
    pub fn elevate(&self, r: usize) -> TriPatch {
        let n = self.degree();
        if r == 0 {
            return self.clone();
        }
        TriPatch::from_fn(n + r, |l0, l1, l2| {
            let denominator = trinomial(l0, l1, l2);
            let mut q = [0.0; 3];
            // μ ≤ λ componentwise with |μ| = n; then ν = λ − μ has |ν| = r.
            for i in l0.saturating_sub(r)..=l0.min(n) {
                for j in l1.saturating_sub(r)..=l1.min(n - i) {
                    let k = n - i - j;
                    if k > l2 {
                        continue;
                    }
                    let nu = [l0 - i, l1 - j, l2 - k];
                    let w = trinomial(i, j, k) * trinomial(nu[0], nu[1], nu[2]) / denominator;
                    q = add(q, scale(self.points()[index_of(n, [i, j, k])], w));
                }
            }
            q
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::triangle::multi_indices;
    use crate::vec3::{norm, sub, Vec3};

    fn sample() -> TriPatch {
        TriPatch::from_fn(3, |i, j, k| {
            [
                i as f64 + 0.5 * j as f64,
                (j * k) as f64,
                ((i + 2 * k) as f64).sin(),
            ]
        })
    }

    /// The textbook one-step formula, written independently.
    fn elevate_once(t: &TriPatch) -> TriPatch {
        let n = t.degree();
        let get = |i: usize, j: usize, k: usize| t.point(i, j, k);
        TriPatch::from_fn(n + 1, |i, j, k| {
            let mut q = [0.0; 3];
            if i > 0 {
                q = add(q, scale(get(i - 1, j, k), i as f64));
            }
            if j > 0 {
                q = add(q, scale(get(i, j - 1, k), j as f64));
            }
            if k > 0 {
                q = add(q, scale(get(i, j, k - 1), k as f64));
            }
            scale(q, 1.0 / (n + 1) as f64)
        })
    }

    fn max_gap(a: &TriPatch, b: &TriPatch) -> f64 {
        a.points()
            .iter()
            .zip(b.points())
            .map(|(p, q): (&Vec3, &Vec3)| norm(sub(*p, *q)))
            .fold(0.0, f64::max)
    }

    #[test]
    fn by_one_is_the_textbook_formula() {
        let t = sample();
        assert!(max_gap(&t.elevate(1), &elevate_once(&t)) < 1e-15);
    }

    #[test]
    fn corners_stay_and_weights_are_convex() {
        let t = sample();
        let e = t.elevate(4);
        for m in 0..3 {
            assert_eq!(e.corner(m), t.corner(m));
        }
        // Elevating the constant 1 (in each coordinate) keeps it 1: the
        // weights of every Q_λ sum to 1.
        let one = TriPatch::from_fn(5, |_, _, _| [1.0; 3]).elevate(7);
        for [i, j, k] in multi_indices(12) {
            assert!((one.point(i, j, k)[0] - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn zero_is_a_copy() {
        let t = sample();
        assert_eq!(t.elevate(0), t);
    }
}
