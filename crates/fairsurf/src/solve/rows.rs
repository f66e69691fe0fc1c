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

use super::builder::Problem;
use super::compensated::{dot2_residual, residual};
use super::dense::SpdFactor;
use super::problem::SolveOptions;
use crate::constraint::Row;
use crate::energy::Integrand;
use crate::vec3::Vec3;
use crate::{budget, check, Error, Result, TensorPatch};
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

/// Checks a row no free coordinate enters: its known terms a·x meet its
/// right-hand side (the residual `r`, compensated) to 1e-12 of their size,
/// else an error naming the row.
pub(crate) fn known_row_met(row: &Row, a: &[f64], xs: &[f64], r: f64) -> Result<()> {
    let size = row.rhs.abs() + a.iter().zip(xs).map(|(a, x)| (a * x).abs()).sum::<f64>();
    if r.abs() > 1e-12 * size.max(f64::MIN_POSITIVE) && r != 0.0 {
        return Err(Error::Mismatch {
            what: row.name.clone(),
            expected: "an equation some free control point enters, or one the known \
                       control points meet"
                .into(),
            got: format!("one the known control points alone decide, missing it by {r:.3e}"),
        });
    }
    Ok(())
}

/// The first of `rows` that is (nearly) a combination of the ones before
/// it, by the Cholesky factorization of F Fᵀ with the range-space solve's
/// relative pivot test; `None` when they are independent. A row without
/// terms is dependent.
pub(crate) fn first_dependent_row(rows: &[Vec<(usize, f64)>]) -> Option<usize> {
    let n = rows
        .iter()
        .flatten()
        .map(|&(i, _)| i + 1)
        .max()
        .unwrap_or(0);
    let mut dense = vec![0.0; n];
    let m = rows.len();
    let mut s = Mat::zeros(m, m);
    for (i, row) in rows.iter().enumerate() {
        for &(k, a) in row {
            dense[k] += a;
        }
        for (j, other) in rows.iter().enumerate().take(i + 1) {
            let v = dot(other, &dense);
            s[(i, j)] = v;
            s[(j, i)] = v;
        }
        for &(k, _) in row {
            dense[k] = 0.0;
        }
    }
    cholesky_checked(s).err()
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

/// The constraints' rows on the free unknowns (the coupled layout: the
/// free point k's coordinate c at 3k + c).
#[derive(Debug)]
pub(super) struct FreeRows {
    /// Every row over all coordinates (3p + c), as prepared: for the
    /// mismatch test and the known part of each right-hand side.
    pub(super) all: Vec<Row>,
    /// Per row of `all`: its terms on known coordinates, and whether a free
    /// one enters it (else the known points alone decide it).
    pub(super) known_terms: Vec<(Vec<(usize, f64)>, bool)>,
    /// The rows with a free coordinate, S factored.
    pub(super) system: Option<RowSystem>,
}

impl FreeRows {
    pub(super) fn new(
        all: &[Row],
        free: &[usize],
        factor: &SpdFactor,
        h_ff: &Mat<f64>,
        opts: &SolveOptions,
    ) -> Result<Self> {
        let mut index = std::collections::HashMap::new();
        for (k, &p) in free.iter().enumerate() {
            for c in 0..3 {
                index.insert(3 * p + c, 3 * k + c);
            }
        }
        let (mut reduced, mut names, mut known_terms) = (Vec::new(), Vec::new(), Vec::new());
        for row in all {
            let (on_free, on_known): (Vec<_>, Vec<_>) =
                row.terms.iter().partition(|(i, _)| index.contains_key(i));
            known_terms.push((on_known, !on_free.is_empty()));
            if !on_free.is_empty() {
                reduced.push(on_free.iter().map(|&(i, a)| (index[&i], a)).collect());
                names.push(row.name.clone());
            }
        }
        let system = if reduced.is_empty() {
            None
        } else {
            budget::checkpoint()?;
            Some(RowSystem::new(
                factor,
                h_ff,
                reduced,
                &names,
                opts.max_refinement_steps,
            )?)
        };
        Ok(Self {
            all: all.to_vec(),
            known_terms,
            system,
        })
    }

    /// What makes `rows` differ from these (their right-hand sides may).
    pub(super) fn mismatch(&self, rows: &[Row]) -> Option<String> {
        if rows.len() != self.all.len() {
            return Some(format!(
                "{} constraint equations instead of {}",
                rows.len(),
                self.all.len()
            ));
        }
        let k = rows
            .iter()
            .zip(&self.all)
            .position(|(a, b)| a.terms != b.terms)?;
        Some(format!(
            "constraint equation {} has another place or direction",
            rows[k].name
        ))
    }

    /// The right-hand sides c = rhs − Σ known a·x of the solved rows for
    /// the known values `x` (coupled layout, one column), compensated.
    /// An error when a row no free coordinate enters is not met.
    pub(super) fn rhs(&self, x: &Mat<f64>) -> Result<Vec<f64>> {
        let mut c = Vec::new();
        for (row, (known, has_free)) in self.all.iter().zip(&self.known_terms) {
            let a: Vec<f64> = known.iter().map(|&(_, a)| a).collect();
            let xs: Vec<f64> = known.iter().map(|&(i, _)| x[(i, 0)]).collect();
            let r = super::compensated::dot2_residual(row.rhs, &a, &xs);
            if *has_free {
                c.push(r);
                continue;
            }
            known_row_met(row, &a, &xs, r)?;
        }
        Ok(c)
    }

    /// The worst row the written patch misses by more than the check's
    /// tolerance of the data's size (the largest known coordinate or
    /// right-hand side): its name and the miss over that size.
    pub(super) fn unmet(&self, problem: &Problem, patch: &TensorPatch) -> Option<(String, f64)> {
        let x: Vec<f64> = patch.points().iter().flatten().copied().collect();
        // The data's size: known points, right-hand sides, operator
        // targets, guide surfaces.
        let max_abs = |v: &[Vec3]| v.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut size = problem
            .known()
            .into_iter()
            .flatten()
            .fold(0.0f64, |m, p| m.max(max_abs(&[p])));
        for r in &self.all {
            size = size.max(r.rhs.abs());
        }
        for o in &problem.operators {
            size = size.max(o.target.size());
        }
        for t in &problem.terms {
            if let Some(Integrand::GuideSurface { surface, .. }) = t.integrand() {
                size = size.max(max_abs(surface.points()));
            }
        }
        let size = size.max(f64::MIN_POSITIVE);
        self.all
            .iter()
            .map(|row| {
                let a: Vec<f64> = row.terms.iter().map(|&(_, a)| a).collect();
                let xs: Vec<f64> = row.terms.iter().map(|&(i, _)| x[i]).collect();
                let miss = super::compensated::dot2_residual(row.rhs, &a, &xs).abs() / size;
                (row.name.clone(), miss)
            })
            .filter(|(_, miss)| miss.is_nan() || *miss > check::TOLERANCE)
            .max_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// max over the solved rows of |c − F x| / (Σ|a x| + |c|) at the free
    /// values `xf` (0 without rows).
    pub(super) fn relative_residuals(&self, xf: &Mat<f64>, c: &[f64]) -> f64 {
        let Some(system) = &self.system else {
            return 0.0;
        };
        let x = xf.col_as_slice(0);
        system
            .rows()
            .iter()
            .zip(c)
            .map(|(row, &ci)| {
                let a: Vec<f64> = row.iter().map(|&(_, a)| a).collect();
                let xs: Vec<f64> = row.iter().map(|&(i, _)| x[i]).collect();
                let r = super::compensated::dot2_residual(ci, &a, &xs);
                let size = ci.abs() + a.iter().zip(&xs).map(|(a, x)| (a * x).abs()).sum::<f64>();
                if size > 0.0 {
                    r.abs() / size
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max)
    }
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
