//! Linear rows F x = c on top of a factored dense SPD system: the
//! range-space (Schur complement) method for
//!
//! ```text
//! minimize ½ xᵀHx − bᵀx   subject to   F x = c
//! H x + Fᵀλ = b,  F x = c   ⇒   S λ = F H⁻¹b − c,  x = H⁻¹(b − Fᵀλ),  S = F H⁻¹ Fᵀ
//! ```
//!
//! H is already factored ([`SpdFactor`], refined against H itself); the
//! rows are few (a constraint gives one to three), so Y = H⁻¹Fᵀ costs a
//! solve per row and S = F Y is small and dense. Every solve is refined on
//! the whole system [H Fᵀ; F 0] with compensated residuals.

use super::dense::{dot2_residual, residual, SpdFactor};
use crate::{Error, Result};
use faer::Mat;

/// The rows, H⁻¹Fᵀ and the Cholesky factor of S.
#[derive(Debug)]
pub(crate) struct RowSystem {
    /// F over the unknowns: (unknown, coefficient) per row.
    rows: Vec<Vec<(usize, f64)>>,
    /// Y = H⁻¹Fᵀ, one column per row.
    y: Mat<f64>,
    /// L of S = F Y = L Lᵀ (lower).
    l: Mat<f64>,
}

/// A row of S whose pivot falls below this fraction of its diagonal is
/// (nearly) a combination of the rows before it.
const DEPENDENT: f64 = 1e-10;

impl RowSystem {
    /// Factors S for the rows (over the unknowns of `h`, named by `names`
    /// in errors). An error names the first row that depends on the ones
    /// before it.
    pub(crate) fn new(
        factor: &SpdFactor,
        h: &Mat<f64>,
        rows: Vec<Vec<(usize, f64)>>,
        names: &[String],
        steps: usize,
    ) -> Result<Self> {
        let n = h.nrows();
        let ft = Mat::from_fn(n, rows.len(), |_, _| 0.0);
        let mut ft = ft;
        for (r, row) in rows.iter().enumerate() {
            for &(i, a) in row {
                ft[(i, r)] += a;
            }
        }
        let y = factor.solve(h, &ft, steps).x;
        let m = rows.len();
        let mut s = Mat::from_fn(m, m, |i, j| dot(&rows[i], y.col_as_slice(j)));
        // Symmetric to rounding: take the mean.
        for i in 0..m {
            for j in 0..i {
                let v = 0.5 * (s[(i, j)] + s[(j, i)]);
                s[(i, j)] = v;
                s[(j, i)] = v;
            }
        }
        let l = cholesky_checked(s).map_err(|k| Error::DependentConstraint {
            row: names[k].clone(),
        })?;
        Ok(Self { rows, y, l })
    }

    /// The rows over the unknowns.
    pub(crate) fn rows(&self) -> &[Vec<(usize, f64)>] {
        &self.rows
    }

    /// (dx, dλ) of [H Fᵀ; F 0][dx; dλ] = [r; q] given u = H⁻¹ r:
    /// dλ = S⁻¹(F u − q), dx = u − Y dλ.
    fn complete(&self, u: Mat<f64>, q: &[f64]) -> (Mat<f64>, Vec<f64>) {
        let mut t: Vec<f64> = self
            .rows
            .iter()
            .zip(q)
            .map(|(row, &qi)| dot(row, u.col_as_slice(0)) - qi)
            .collect();
        self.s_solve(&mut t);
        let mut dx = u;
        for (k, &l) in t.iter().enumerate() {
            for (d, &yk) in dx
                .col_as_slice_mut(0)
                .iter_mut()
                .zip(self.y.col_as_slice(k))
            {
                *d -= yk * l;
            }
        }
        (dx, t)
    }

    /// [H Fᵀ; F 0]⁻¹ [r; q] with the factor of H (no refinement).
    pub(crate) fn apply(
        &self,
        factor: &SpdFactor,
        r: &Mat<f64>,
        q: &[f64],
    ) -> (Mat<f64>, Vec<f64>) {
        self.complete(factor.apply(r), q)
    }

    /// Solves H x + Fᵀλ = b, F x = c from the unconstrained solution
    /// x_u = H⁻¹b, refined on the whole system while its residual falls.
    /// Returns (x, λ, residual of the first block, steps).
    pub(crate) fn solve(
        &self,
        factor: &SpdFactor,
        h: &Mat<f64>,
        b: &Mat<f64>,
        c: &[f64],
        x_u: Mat<f64>,
        max_steps: usize,
    ) -> (Mat<f64>, Vec<f64>, Mat<f64>, usize) {
        let (mut x, mut lambda) = self.complete(x_u, c);
        let residuals = |x: &Mat<f64>, lambda: &[f64]| {
            let mut r1 = residual(h, x, b);
            for (row, &l) in self.rows.iter().zip(lambda) {
                for &(i, a) in row {
                    r1[(i, 0)] -= a * l;
                }
            }
            let r2: Vec<f64> = self
                .rows
                .iter()
                .zip(c)
                .map(|(row, &ci)| row_residual(row, ci, x.col_as_slice(0)))
                .collect();
            (r1, r2)
        };
        let size = |r1: &Mat<f64>, r2: &[f64]| r1.norm_l2().hypot(norm2(r2));
        let (mut r1, mut r2) = residuals(&x, &lambda);
        let mut best = size(&r1, &r2);
        let mut steps = 0;
        while steps < max_steps && best > 0.0 {
            let (dx, dl) = self.apply(factor, &r1, &r2);
            let nx = &x + &dx;
            let nl: Vec<f64> = lambda.iter().zip(&dl).map(|(a, b)| a + b).collect();
            let (n1, n2) = residuals(&nx, &nl);
            let now = size(&n1, &n2);
            if now.is_nan() || now > best * (1.0 + 1e-8) {
                break;
            }
            steps += 1;
            let settled = super::dense::norm_max(&dx) <= f64::EPSILON * super::dense::norm_max(&nx);
            (x, lambda, r1, r2, best) = (nx, nl, n1, n2, best.min(now));
            if settled {
                break;
            }
        }
        (x, lambda, r1, steps)
    }

    /// z ← S⁻¹ z.
    fn s_solve(&self, z: &mut [f64]) {
        let (l, m) = (&self.l, z.len());
        for i in 0..m {
            let s: f64 = (0..i).map(|k| l[(i, k)] * z[k]).sum();
            z[i] = (z[i] - s) / l[(i, i)];
        }
        for i in (0..m).rev() {
            let s: f64 = (i + 1..m).map(|k| l[(k, i)] * z[k]).sum();
            z[i] = (z[i] - s) / l[(i, i)];
        }
    }
}

/// c − Σ a_i x_i (compensated): the residual of the second block.
fn row_residual(row: &[(usize, f64)], c: f64, x: &[f64]) -> f64 {
    let a: Vec<f64> = row.iter().map(|&(_, a)| a).collect();
    let xs: Vec<f64> = row.iter().map(|&(i, _)| x[i]).collect();
    dot2_residual(c, &a, &xs)
}

fn dot(row: &[(usize, f64)], x: &[f64]) -> f64 {
    row.iter().map(|&(i, a)| a * x[i]).sum()
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// S = L Lᵀ for small dense SPD S; `Err(k)` when row k's pivot falls below
/// [`DEPENDENT`] of its diagonal (it depends on the rows before it).
fn cholesky_checked(mut s: Mat<f64>) -> std::result::Result<Mat<f64>, usize> {
    let m = s.nrows();
    for j in 0..m {
        let diagonal = s[(j, j)];
        let d = diagonal - (0..j).map(|k| s[(j, k)] * s[(j, k)]).sum::<f64>();
        if !(d > DEPENDENT * diagonal && d.is_finite()) {
            return Err(j);
        }
        let d = d.sqrt();
        s[(j, j)] = d;
        for i in j + 1..m {
            let v = s[(i, j)] - (0..j).map(|k| s[(i, k)] * s[(j, k)]).sum::<f64>();
            s[(i, j)] = v / d;
        }
    }
    for j in 0..m {
        for i in 0..j {
            s[(i, j)] = 0.0;
        }
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::dense::SpdOptions;

    fn opts() -> SpdOptions {
        SpdOptions {
            estimate_condition: false,
            singular_condition: 1e15,
        }
    }

    /// min ½|x|² − bᵀx subject to x₀ + x₁ = 1, x₂ = 2 has the closed form
    /// of a projection; the multipliers follow from H x + Fᵀλ = b.
    #[test]
    fn rows_give_the_projected_minimum() {
        let h = Mat::<f64>::identity(4, 4);
        let b = Mat::from_fn(4, 1, |i, _| [3.0, 0.0, 0.0, 5.0][i]);
        let f = SpdFactor::new(&h, opts(), "t", None).unwrap();
        let rows = vec![vec![(0, 1.0), (1, 1.0)], vec![(2, 1.0)]];
        let names = vec!["a".to_string(), "b".to_string()];
        let sys = RowSystem::new(&f, &h, rows, &names, 5).unwrap();
        let x_u = f.solve(&h, &b, 5).x;
        let (x, lambda, r, _) = sys.solve(&f, &h, &b, &[1.0, 2.0], x_u, 5);
        // x₀ − x₁ stays as b's (3), x₀ + x₁ = 1: x = (2, −1, 2, 5).
        let want = [2.0, -1.0, 2.0, 5.0];
        for i in 0..4 {
            assert!((x[(i, 0)] - want[i]).abs() < 1e-15, "{:?}", x);
        }
        // λ = b − H x on the rows: λ₀ = 3 − 2 = 1, λ₁ = 0 − 2 = −2.
        assert!((lambda[0] - 1.0).abs() < 1e-15 && (lambda[1] + 2.0).abs() < 1e-15);
        assert!(super::super::dense::norm_max(&r) < 1e-15);
    }

    /// A repeated row is named.
    #[test]
    fn a_dependent_row_is_named() {
        let h = Mat::<f64>::identity(3, 3);
        let f = SpdFactor::new(&h, opts(), "t", None).unwrap();
        let rows = vec![
            vec![(0, 1.0), (1, 1.0)],
            vec![(2, 1.0)],
            vec![(0, 2.0), (1, 2.0)],
        ];
        let names: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
        let e = RowSystem::new(&f, &h, rows, &names, 5).unwrap_err();
        assert!(
            matches!(e, Error::DependentConstraint { ref row } if row == "c"),
            "{e}"
        );
    }
}
