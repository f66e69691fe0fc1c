//! The function space a quadratic form is assembled in.
//!
//! Energies are assembled over the Bernstein basis of the whole patch —
//! exactly, from closed-form integrals. The solver can also ask for a form
//! over a tensor block of free control points in a better-conditioned basis
//! (see `solve/jacobi.rs`): orthogonal Jacobi-weighted polynomials, evaluated
//! by their three-term recurrence and integrated by Gauss–Legendre rules that
//! are exact for the polynomial degrees involved. The Bernstein form stays
//! the reference; the other is used to precondition it.

use crate::basis::{bernstein_derivatives, binomial, elevation_matrix};
use faer::Mat;

/// A space of tensor-product polynomials: the whole Bernstein basis of a
/// degree (n, m) patch, or (inside the solver) a block of free control points
/// in an orthogonal basis.
#[derive(Clone, Debug)]
pub struct Space {
    degree: (usize, usize),
    pub(crate) u: Basis1d,
    pub(crate) v: Basis1d,
}

impl Space {
    /// All control points of a degree (n, m) patch, Bernstein basis.
    pub fn bernstein(degree: (usize, usize)) -> Self {
        Self {
            degree,
            u: Basis1d::Bernstein(degree.0),
            v: Basis1d::Bernstein(degree.1),
        }
    }

    /// The free block rows `a..=n−b`, columns `c..=m−d`, Jacobi-weighted basis.
    pub(crate) fn jacobi(
        degree: (usize, usize),
        (a, b): (usize, usize),
        (c, d): (usize, usize),
    ) -> Self {
        Self {
            degree,
            u: Basis1d::Jacobi(JacobiBlock::new(degree.0, a, b)),
            v: Basis1d::Jacobi(JacobiBlock::new(degree.1, c, d)),
        }
    }

    /// The patch degree (n, m).
    pub fn degree(&self) -> (usize, usize) {
        self.degree
    }

    /// Number of scalar basis functions.
    pub fn len(&self) -> usize {
        self.u.len() * self.v.len()
    }

    /// Never empty.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Whether this is the full Bernstein basis (where centres apply).
    pub fn is_bernstein(&self) -> bool {
        matches!(
            (&self.u, &self.v),
            (Basis1d::Bernstein(_), Basis1d::Bernstein(_))
        )
    }
}

/// A basis in one parameter direction.
#[derive(Clone, Debug)]
pub(crate) enum Basis1d {
    /// B_0^n … B_n^n.
    Bernstein(usize),
    /// φ_0 … φ_d of a [`JacobiBlock`].
    Jacobi(JacobiBlock),
}

impl Basis1d {
    pub(crate) fn len(&self) -> usize {
        match self {
            Basis1d::Bernstein(n) => n + 1,
            Basis1d::Jacobi(j) => j.d + 1,
        }
    }

    /// The r-th derivatives of all basis functions at t.
    pub(crate) fn eval(&self, t: f64, r: usize) -> Vec<f64> {
        match self {
            Basis1d::Bernstein(n) => bernstein_derivatives(*n, t, r).swap_remove(r),
            Basis1d::Jacobi(j) => j.eval(t, r),
        }
    }
}

/// `φ_j(t) = t^a (1−t)^b P_j^{(2b,2a)}(2t−1) / s_j`, j = 0..=d, d = n−a−b: an
/// L²-orthogonal basis of the span of `B_a^n … B_{n−b}^n`. The scale s_j makes
/// the largest Bernstein coefficient of φ_j equal to 1 in magnitude.
#[derive(Clone, Debug)]
pub(crate) struct JacobiBlock {
    pub(crate) n: usize,
    pub(crate) a: usize,
    pub(crate) b: usize,
    pub(crate) d: usize,
    /// (d+1)×(d+1) Bernstein coefficients (indices a..=n−b) of each φ_j.
    pub(crate) q: Mat<f64>,
    scales: Vec<f64>,
}

impl JacobiBlock {
    pub(crate) fn new(n: usize, a: usize, b: usize) -> Self {
        let d = n - a - b;
        let mut q = Mat::<f64>::zeros(d + 1, d + 1);
        let mut scales = vec![1.0; d + 1];
        for j in 0..=d {
            // P_j^{(α,β)}(2t−1) = Σ_i (−1)^{j−i} C(j+α, i) C(j+β, j−i) / C(j, i) · B_i^j(t)
            let c: Vec<f64> = (0..=j)
                .map(|i| {
                    let sign = if (j - i) % 2 == 0 { 1.0 } else { -1.0 };
                    sign * binomial(j + 2 * b, i) * binomial(j + 2 * a, j - i) / binomial(j, i)
                })
                .collect();
            let e = elevation_matrix(j, d - j);
            let mut s: f64 = 0.0;
            for i in 0..=d {
                let ci: f64 = (0..=j).map(|k| e[(i, k)] * c[k]).sum();
                // t^a (1−t)^b B_i^d = C(d,i)/C(n,i+a) · B_{i+a}^n
                q[(i, j)] = ci * binomial(d, i) / binomial(n, i + a);
                s = s.max(q[(i, j)].abs());
            }
            for i in 0..=d {
                q[(i, j)] /= s;
            }
            scales[j] = s;
        }
        Self {
            n,
            a,
            b,
            d,
            q,
            scales,
        }
    }

    /// r-th derivatives (r ≤ 2) of φ_0 … φ_d at t, by the Jacobi recurrence
    /// (stable) and the product rule with the weight t^a (1−t)^b.
    pub(crate) fn eval(&self, t: f64, r: usize) -> Vec<f64> {
        let (alpha, beta) = ((2 * self.b) as f64, (2 * self.a) as f64);
        let x = 2.0 * t - 1.0;
        // d/dt P_j^{(α,β)}(2t−1) = (j+α+β+1) P_{j−1}^{(α+1,β+1)}(2t−1), and again.
        let p0 = jacobi_all(self.d, alpha, beta, x);
        let p1 = jacobi_all(self.d, alpha + 1.0, beta + 1.0, x);
        let p2 = jacobi_all(self.d, alpha + 2.0, beta + 2.0, x);
        let ab = alpha + beta;
        let dp = |j: usize| {
            if j >= 1 {
                (j as f64 + ab + 1.0) * p1[j - 1]
            } else {
                0.0
            }
        };
        let ddp = |j: usize| {
            if j >= 2 {
                (j as f64 + ab + 1.0) * (j as f64 + ab + 2.0) * p2[j - 2]
            } else {
                0.0
            }
        };
        let w = weight_derivatives(t, self.a, self.b);
        (0..=self.d)
            .map(|j| {
                let v = match r {
                    0 => w[0] * p0[j],
                    1 => w[1] * p0[j] + w[0] * dp(j),
                    2 => w[2] * p0[j] + 2.0 * w[1] * dp(j) + w[0] * ddp(j),
                    _ => unimplemented!("derivatives above second order"),
                };
                v / self.scales[j]
            })
            .collect()
    }
}

/// P_0 … P_d of the Jacobi family (α, β) at x, by the three-term recurrence.
fn jacobi_all(d: usize, alpha: f64, beta: f64, x: f64) -> Vec<f64> {
    let mut p = vec![0.0; d + 1];
    p[0] = 1.0;
    if d >= 1 {
        p[1] = (alpha + 1.0) + (alpha + beta + 2.0) * (x - 1.0) / 2.0;
    }
    for k in 2..=d {
        let k_ = k as f64;
        let s = 2.0 * k_ + alpha + beta;
        let a1 = 2.0 * k_ * (k_ + alpha + beta) * (s - 2.0);
        let a2 = (s - 1.0) * (s * (s - 2.0) * x + alpha * alpha - beta * beta);
        let a3 = 2.0 * (k_ + alpha - 1.0) * (k_ + beta - 1.0) * s;
        p[k] = (a2 * p[k - 1] - a3 * p[k - 2]) / a1;
    }
    p
}

/// [w, w', w''] of w(t) = t^a (1−t)^b (negative powers only ever meet a zero
/// coefficient, so they count as 0).
fn weight_derivatives(t: f64, a: usize, b: usize) -> [f64; 3] {
    let pw = |base: f64, k: i64| if k < 0 { 0.0 } else { base.powi(k as i32) };
    let (a_, b_) = (a as i64, b as i64);
    let s = 1.0 - t;
    let (af, bf) = (a as f64, b as f64);
    let w0 = pw(t, a_) * pw(s, b_);
    let w1 = af * pw(t, a_ - 1) * pw(s, b_) - bf * pw(t, a_) * pw(s, b_ - 1);
    let w2 = af * (af - 1.0) * pw(t, a_ - 2) * pw(s, b_)
        - 2.0 * af * bf * pw(t, a_ - 1) * pw(s, b_ - 1)
        + bf * (bf - 1.0) * pw(t, a_) * pw(s, b_ - 2);
    [w0, w1, w2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::{bernstein_derivatives, GaussLegendre};

    /// The recurrence evaluation equals the Bernstein coefficients in q, for
    /// values and both derivatives.
    #[test]
    fn recurrence_matches_bernstein_coefficients() {
        for &(n, a, b) in &[(10, 1, 1), (12, 2, 2), (9, 0, 2), (7, 3, 1), (5, 0, 0)] {
            let jb = JacobiBlock::new(n, a, b);
            for &t in &[0.0, 0.13, 0.5, 0.91, 1.0] {
                for r in 0..=2 {
                    let bd = bernstein_derivatives(n, t, r).swap_remove(r);
                    let ev = jb.eval(t, r);
                    for j in 0..=jb.d {
                        let via_q: f64 = (0..=jb.d).map(|i| jb.q[(i, j)] * bd[i + a]).sum();
                        let tol = 1e-9 * (1.0 + via_q.abs()) * (n * n) as f64;
                        assert!(
                            (via_q - ev[j]).abs() < tol,
                            "n={n} a={a} b={b} t={t} r={r} j={j}: {via_q} vs {}",
                            ev[j]
                        );
                    }
                }
            }
        }
    }

    /// The basis functions are L²-orthogonal.
    #[test]
    fn basis_functions_are_orthogonal() {
        let jb = JacobiBlock::new(14, 2, 1);
        let gl = GaussLegendre::new(16);
        let vals: Vec<Vec<f64>> = gl.nodes.iter().map(|&t| jb.eval(t, 0)).collect();
        let ip = |j: usize, k: usize| -> f64 {
            gl.weights
                .iter()
                .zip(&vals)
                .map(|(w, v)| w * v[j] * v[k])
                .sum()
        };
        for j in 0..=jb.d {
            for k in 0..j {
                assert!(
                    ip(j, k).abs() < 1e-13 * (ip(j, j) * ip(k, k)).sqrt(),
                    "⟨φ{j}, φ{k}⟩"
                );
            }
        }
    }
}
