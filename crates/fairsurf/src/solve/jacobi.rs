//! A better-conditioned basis for the free control points.
//!
//! The Bernstein basis makes energy systems exponentially ill-conditioned in
//! the degree: measured after symmetric equilibration, ≈1e8 at degree 10,
//! ≈1e14 at 15, and past 1/ε (Cholesky fails) from degree 18 on
//! (`cargo run --release -p fairsurf --example conditioning`). When the free
//! control points form a tensor block `I × J` of contiguous index ranges
//! (fixed rings always do), the free functions in u span
//! `t^a (1−t)^b · Π_d` (I = a..=n−b, d = n−a−b), which has the basis
//!
//! ```text
//! φ_j(t) = t^a (1−t)^b · P_j^{(2b, 2a)}(2t − 1),   j = 0..=d,
//! ```
//!
//! Jacobi polynomials orthogonal for the weight t^{2a}(1−t)^{2b}, so the φ_j
//! are L²-orthogonal. The solver factors the system in the basis φ_j(u)ψ_k(v)
//! and uses that factorization to refine the solution of the exact Bernstein
//! system, whose residual it keeps measuring.

use crate::energy::{Basis1d, Space};
use faer::Mat;

/// The change of basis `x = (Q_u ⊗ Q_v ⊗ I_c) y` over a tensor block of free
/// control points (c = 3 when the coordinates are coupled, else 1).
#[derive(Clone, Debug)]
pub(crate) struct TensorBasis {
    qu: Mat<f64>,
    qv: Mat<f64>,
    inner: usize,
}

impl TensorBasis {
    /// The change of basis of a Jacobi [`Space`] (`None` for a Bernstein one).
    pub(crate) fn from_space(space: &Space, inner: usize) -> Option<Self> {
        match (&space.u, &space.v) {
            (Basis1d::Jacobi(u), Basis1d::Jacobi(v)) => Some(Self {
                qu: u.q.clone(),
                qv: v.q.clone(),
                inner,
            }),
            _ => None,
        }
    }

    /// x ← Q x (transpose = false) or Qᵀ x (transpose = true), column by column.
    pub(crate) fn apply(&self, x: &Mat<f64>, transpose: bool) -> Mat<f64> {
        let (ni, nj, nc) = (self.qu.nrows(), self.qv.nrows(), self.inner);
        debug_assert_eq!(x.nrows(), ni * nj * nc);
        let q = |m: &Mat<f64>, r: usize, s: usize| if transpose { m[(s, r)] } else { m[(r, s)] };
        let mut out = Mat::<f64>::zeros(x.nrows(), x.ncols());
        let mut w = vec![0.0; x.nrows()];
        for col in 0..x.ncols() {
            let v = x.col_as_slice(col);
            // Along v: w[i][b][c] = Σ_j q_v(b, j) v[i][j][c]
            for i in 0..ni {
                for bb in 0..nj {
                    for c in 0..nc {
                        let mut s = 0.0;
                        for j in 0..nj {
                            s += q(&self.qv, bb, j) * v[(i * nj + j) * nc + c];
                        }
                        w[(i * nj + bb) * nc + c] = s;
                    }
                }
            }
            // Along u: out[a][b][c] = Σ_i q_u(a, i) w[i][b][c]
            let o = out.col_as_slice_mut(col);
            for aa in 0..ni {
                for i in 0..ni {
                    let f = q(&self.qu, aa, i);
                    if f == 0.0 {
                        continue;
                    }
                    let src = &w[i * nj * nc..(i + 1) * nj * nc];
                    let dst = &mut o[aa * nj * nc..(aa + 1) * nj * nc];
                    for (d, s) in dst.iter_mut().zip(src) {
                        *d += f * s;
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apply_and_transpose_are_adjoint() {
        let tb = TensorBasis::from_space(&Space::jacobi((6, 5), (1, 1), (2, 1)), 3).unwrap();
        let len = 5 * 3 * 3;
        let x = Mat::from_fn(len, 1, |i, _| (i as f64 * 0.37).sin());
        let y = Mat::from_fn(len, 1, |i, _| (i as f64 * 0.11).cos());
        let qx = tb.apply(&x, false);
        let qty = tb.apply(&y, true);
        let lhs: f64 = (0..len).map(|i| qx[(i, 0)] * y[(i, 0)]).sum();
        let rhs: f64 = (0..len).map(|i| x[(i, 0)] * qty[(i, 0)]).sum();
        assert!((lhs - rhs).abs() < 1e-12 * lhs.abs().max(1.0));
    }
}
