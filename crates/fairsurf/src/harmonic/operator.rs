//! The Laplacian and bi-Laplacian of a Bézier patch as Bézier patches of the
//! same degree: the polynomial identities Δx ≡ 0 and Δ²x ≡ 0 are "every
//! coefficient vanishes" (Monterde & Ugail 2004, Theorem 1 and eq. 8–9).
//!
//! The r-th derivative of a degree-n Bernstein polynomial, degree-elevated
//! back to n, has integer coefficients in the control points: with the
//! difference operator Δʳ,
//!
//! ```text
//! c_k = Σ_i C(r, k−i) · k!/i! · (n−k)!/(n−r−i)! · Δʳ P_i ,   k − r ≤ i ≤ k
//! ```
//!
//! (for r = 2 these are the paper's a_{n,i,k}, for r = 4 its b_{n,i,k}). The
//! matrices here are built from those integers, so they are exact in f64 for
//! every degree fairsurf accepts (entries < 2⁵³ up to n = 40).

use crate::{Error, Result, TensorPatch};
use faer::Mat;

/// Which differential operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Operator {
    /// Δ = ∂²/∂u² + ∂²/∂v².
    Laplacian,
    /// Δ² = ∂⁴/∂u⁴ + 2 ∂⁴/∂u²∂v² + ∂⁴/∂v⁴.
    Bilaplacian,
}

impl Operator {
    /// "laplacian" / "bilaplacian".
    pub fn name(self) -> &'static str {
        match self {
            Operator::Laplacian => "laplacian",
            Operator::Bilaplacian => "bilaplacian",
        }
    }
}

/// The (n+1)×(n+1) integer matrix K with `(d/dt)ʳ Σ B_i^n c_i = Σ B_k^n (K c)_k`
/// (the derivative elevated back to degree n). Zero when r > n.
pub fn derivative_elevated(n: usize, r: usize) -> Mat<f64> {
    let mut k_mat = Mat::zeros(n + 1, n + 1);
    if r > n {
        return k_mat;
    }
    let falling = |hi: usize, lo: usize| -> f64 { ((lo + 1)..=hi).map(|v| v as f64).product() };
    let binom = |a: usize, b: usize| -> f64 { crate::basis::binomial(a, b).round() };
    for k in 0..=n {
        for i in k.saturating_sub(r)..=k.min(n - r) {
            // Weight of Δʳ P_i in coefficient k.
            let w = binom(r, k - i) * falling(k, i) * falling(n - k, n - r - i);
            for s in 0..=r {
                let sign = if (r - s) % 2 == 0 { 1.0 } else { -1.0 };
                k_mat[(k, i + s)] += w * sign * binom(r, s);
            }
        }
    }
    k_mat
}

/// The matrix of `op` on degree-(n, m) nets: row k(m+1)+l is the Bernstein
/// coefficient (k, l) of op(x), column i(m+1)+j the control point P_ij
/// (one coordinate). Built as Kronecker sums of [`derivative_elevated`].
pub fn operator_matrix(op: Operator, (n, m): (usize, usize)) -> Mat<f64> {
    let (nu, nv) = (n + 1, m + 1);
    let (k2u, k2v) = (derivative_elevated(n, 2), derivative_elevated(m, 2));
    let mut a = Mat::<f64>::zeros(nu * nv, nu * nv);
    let mut add_kron = |ku: &Mat<f64>, kv: &Mat<f64>, w: f64| {
        for k in 0..nu {
            for i in 0..nu {
                let x = ku[(k, i)];
                if x == 0.0 {
                    continue;
                }
                for l in 0..nv {
                    for j in 0..nv {
                        let y = kv[(l, j)];
                        if y != 0.0 {
                            a[(k * nv + l, i * nv + j)] += w * x * y;
                        }
                    }
                }
            }
        }
    };
    let (iu, iv) = (Mat::<f64>::identity(nu, nu), Mat::<f64>::identity(nv, nv));
    match op {
        Operator::Laplacian => {
            add_kron(&k2u, &iv, 1.0);
            add_kron(&iu, &k2v, 1.0);
        }
        Operator::Bilaplacian => {
            add_kron(&derivative_elevated(n, 4), &iv, 1.0);
            add_kron(&k2u, &k2v, 2.0);
            add_kron(&iu, &derivative_elevated(m, 4), 1.0);
        }
    }
    a
}

/// op(x) as a patch of the same degree: Δx (Theorem 1) or Δ²x (eq. 8). The
/// surface is harmonic / biharmonic exactly when every control point of the
/// result is zero.
///
/// ```
/// use fairsurf::{harmonic::{apply, Operator}, TensorPatch};
/// // x = u² − v² is harmonic: written at degree (2, 2) its Laplacian net is 0.
/// let p = TensorPatch::from_fn(2, 2, |i, j| {
///     let (a, b) = ([0.0, 0.0, 1.0][i], [0.0, 0.0, 1.0][j]);
///     [a - b, 0.0, 0.0]
/// });
/// let lap = apply(Operator::Laplacian, &p);
/// assert!(lap.points().iter().all(|q| q[0].abs() < 1e-15));
/// ```
pub fn apply(op: Operator, patch: &TensorPatch) -> TensorPatch {
    let (n, m) = patch.degree();
    // Applies K (acting on the u index) to every column of p.
    let apply_u = |k: &Mat<f64>, p: &TensorPatch| {
        let (pn, pm) = p.degree();
        TensorPatch::from_fn(pn, pm, |a, j| {
            let mut s = [0.0; 3];
            for i in 0..=pn {
                let w = k[(a, i)];
                if w != 0.0 {
                    let q = p.point(i, j);
                    for c in 0..3 {
                        s[c] += w * q[c];
                    }
                }
            }
            s
        })
    };
    let apply_v = |k: &Mat<f64>, p: &TensorPatch| apply_u(k, &p.transposed()).transposed();
    let (k2u, k2v) = (derivative_elevated(n, 2), derivative_elevated(m, 2));
    let parts = match op {
        Operator::Laplacian => vec![(apply_u(&k2u, patch), 1.0), (apply_v(&k2v, patch), 1.0)],
        Operator::Bilaplacian => vec![
            (apply_u(&derivative_elevated(n, 4), patch), 1.0),
            (apply_v(&k2v, &apply_u(&k2u, patch)), 2.0),
            (apply_v(&derivative_elevated(m, 4), patch), 1.0),
        ],
    };
    TensorPatch::from_fn(n, m, |i, j| {
        let mut s = [0.0; 3];
        for (p, w) in &parts {
            let q = p.point(i, j);
            for c in 0..3 {
                s[c] += w * q[c];
            }
        }
        s
    })
}

/// max |coefficient of op(x)| / max |P_ij|: how far the surface is from
/// harmonic / biharmonic, relative to the size of its net (0 for a zero net).
pub fn relative_residual(op: Operator, patch: &TensorPatch) -> f64 {
    let q = apply(op, patch);
    let size = max_abs(patch);
    let r = max_abs(&q);
    if size > 0.0 {
        r / size
    } else {
        r
    }
}

pub(crate) fn max_abs(p: &TensorPatch) -> f64 {
    p.points()
        .iter()
        .flat_map(|q| q.iter())
        .fold(0.0f64, |a, v| a.max(v.abs()))
}

/// Checks that the net's degrees allow the operator to say anything.
pub(crate) fn check_degree(what: &str, (n, m): (usize, usize), min: usize) -> Result<()> {
    if n < min || m < min {
        return Err(Error::Mismatch {
            what: format!("degree of a {what}"),
            expected: format!("n, m ≥ {min}"),
            got: format!("({n}, {m})"),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K agrees with differentiating and elevating in floating point.
    #[test]
    fn integer_operator_is_derivative_then_elevation() {
        use crate::basis::{derivative_matrix, elevation_matrix};
        for n in 0..=14 {
            for r in 0..=5 {
                let k = derivative_elevated(n, r);
                let ref_m = if r > n {
                    Mat::zeros(n + 1, n + 1)
                } else {
                    elevation_matrix(n - r, r) * derivative_matrix(n, r)
                };
                for a in 0..=n {
                    for b in 0..=n {
                        let (x, y) = (k[(a, b)], ref_m[(a, b)]);
                        assert_eq!(x, x.round());
                        assert!(
                            (x - y).abs() <= 1e-9 * (1.0 + y.abs()),
                            "n={n} r={r}: {x} vs {y}"
                        );
                    }
                }
            }
        }
    }

    /// The paper's a_{n,i,k} (Theorem 1) are the rows of K for r = 2.
    #[test]
    fn second_derivative_rows_are_the_papers_a_coefficients() {
        let n = 7;
        let a = |i: usize, k: usize| -> f64 {
            if i > n - 2 {
                return 0.0;
            }
            let (n, i) = (n as f64, i as f64);
            match k {
                0 => (n - i) * (n - i - 1.0),
                1 => 2.0 * (i + 1.0) * (n - i - 1.0),
                _ => (i + 1.0) * (i + 2.0),
            }
        };
        let k2 = derivative_elevated(n, 2);
        for row in 0..=n {
            // Coefficient of Δ²P_q in row `row` is a_{n,q,row−q}.
            let mut expect = vec![0.0; n + 1];
            for q in row.saturating_sub(2)..=row.min(n - 2) {
                let w = a(q, row - q);
                expect[q] += w;
                expect[q + 1] -= 2.0 * w;
                expect[q + 2] += w;
            }
            for c in 0..=n {
                assert_eq!(k2[(row, c)], expect[c], "row {row} col {c}");
            }
        }
    }
}
