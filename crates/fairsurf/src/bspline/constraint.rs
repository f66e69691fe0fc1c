//! The constraints of [`crate::constraint`] on a B-spline surface, at a
//! point (u, v) of its knot domain [u_p, u_c] × [v_q, v_d]:
//!
//! ```text
//! point     R(u, v) = Σ_ij N_i,p(u) N_j,q(v) P_ij
//! normal    N·R_u = N·R_v = 0,   R_u = Σ_ij N′_i,p(u) N_j,q(v) P_ij, R_v alike
//! ```
//!
//! (the (p + 1)(q + 1) basis functions that do not vanish at (u, v), de
//! Boor's A2.3), and their solve: the free block's Hessian with the rows
//! F x = c as a KKT system through the solver core ([`crate::solve`]'s
//! sparse KKT back ends), checked on the written net like every solve.

use super::system::System;
use super::BSplineSurface;
use crate::basis::polygon::Uv;
use crate::constraint::{ConstraintSurface, Row};
use crate::solve::compensated::dot2_residual;
use crate::solve::kkt::{try_kkt, KktInfo, KktOutcome};
use crate::vec3::Vec3;
use crate::{check, Error, Result};
use faer::sparse::{SparseColMat, Triplet};

impl BSplineSurface {
    /// (index i·c_v + j, N_i^(a)(u)·N_j^(b)(v)) for the a-th u- and b-th
    /// v-derivative, zeros left out.
    fn weights(&self, [u, v]: Uv, a: usize, b: usize) -> Vec<(usize, f64)> {
        let (ku, kv) = self.knots();
        let ((p, q), (_, cv)) = (self.degree(), self.counts());
        let (su, sv) = (ku.span(u), kv.span(v));
        let bu = &ku.basis_derivatives(su, u, a)[a];
        let bv = &kv.basis_derivatives(sv, v, b)[b];
        let mut out = Vec::with_capacity((p + 1) * (q + 1));
        for (i, &x) in bu.iter().enumerate() {
            for (j, &y) in bv.iter().enumerate() {
                if x * y != 0.0 {
                    out.push(((su - p + i) * cv + sv - q + j, x * y));
                }
            }
        }
        out
    }
}

impl ConstraintSurface for BSplineSurface {
    type At = Uv;

    fn check_at(&self, at: Uv, what: &str) -> Result<()> {
        let (ku, kv) = self.knots();
        let [(u0, u1), (v0, v1)] = [ku.domain(), kv.domain()];
        crate::constraint::check_in_rectangle(at, [(u0, u1), (v0, v1)], what, || {
            format!("a point of the knot domain [{u0}, {u1}] × [{v0}, {v1}]")
        })
    }

    fn point_weights(&self, at: Uv) -> Vec<(usize, f64)> {
        self.weights(at, 0, 0)
    }

    fn tangent_weights(&self, at: Uv) -> [(Vec<(usize, f64)>, &'static str); 2] {
        [
            (self.weights(at, 1, 0), "∂R/∂u"),
            (self.weights(at, 0, 1), "∂R/∂v"),
        ]
    }

    fn value_at(&self, [u, v]: Uv) -> Vec3 {
        self.eval(u, v)
    }

    fn normal_at(&self, [u, v]: Uv) -> Option<Vec3> {
        self.normal(u, v)
    }

    fn control_points(&self) -> &[Vec3] {
        self.points()
    }
}

/// What the constrained solve hands back: the free points and the figures
/// of the report that depend on how they were solved.
pub(super) struct Constrained {
    /// The free points' coordinates, interleaved (3·slot + c).
    pub x: Vec<f64>,
    /// ‖b − Hx − Fᵀλ‖∞: the Lagrangian's gradient, compensated.
    pub gradient_norm: f64,
    /// ‖b‖∞ of the interleaved right-hand side.
    pub b_inf: f64,
    /// E(x) − min over the rows (½ gᵀy, y the constrained Newton step).
    pub excess: f64,
    /// Newton corrections taken.
    pub corrections: usize,
    /// The KKT solve.
    pub kkt: KktInfo,
}

/// A row's (unknown, coefficient) pairs.
pub(super) type SparseRow = Vec<(usize, f64)>;

/// The excess ½gᵀy, the Lagrangian's gradient g, the step y and the
/// multipliers' step.
type Step = (f64, Vec<f64>, Vec<f64>, Vec<f64>);

/// The rows over the free block's interleaved unknowns (3·slot + c), the
/// fixed points' part moved to the right-hand side (compensated). A row no
/// free coordinate enters is left out when the fixed points meet it (to
/// 1e-12 of its terms) and an error otherwise; the first row that is
/// (nearly) a combination of the ones before it is an error naming it.
pub(super) fn reduced_rows(
    rows: &[Row],
    slot: &[usize],
    x0: &[Vec3],
) -> Result<(Vec<SparseRow>, Vec<f64>)> {
    let mut terms = Vec::with_capacity(rows.len());
    let mut rhs = Vec::with_capacity(rows.len());
    let mut names = Vec::with_capacity(rows.len());
    for row in rows {
        let mut t = Vec::new();
        let (mut a, mut xs) = (Vec::new(), Vec::new());
        for &(i, coef) in &row.terms {
            let (g, d) = (i / 3, i % 3);
            match slot[g] {
                usize::MAX => {
                    a.push(coef);
                    xs.push(x0[g][d]);
                }
                s => t.push((3 * s + d, coef)),
            }
        }
        let c = dot2_residual(row.rhs, &a, &xs);
        if t.is_empty() {
            crate::solve::known_row_met(row, &a, &xs, c)?;
            continue;
        }
        terms.push(t);
        rhs.push(c);
        names.push(&row.name);
    }
    if let Some(k) = crate::solve::first_dependent_row(&terms) {
        return Err(Error::DependentConstraint {
            row: names[k].clone(),
        });
    }
    Ok((terms, rhs))
}

/// The free block as one interleaved system (unknown 3·slot + c): H with
/// both triangles (K ⊗ I₃ when uncoupled: the core then factors K once for
/// x, y and z when the rows allow it), its rows as (column, value) lists,
/// and the right-hand side b of H x = b.
pub(super) struct Interleaved {
    pub h: SparseColMat<usize, f64>,
    pub full: Vec<SparseRow>,
    pub b: Vec<f64>,
}

pub(super) fn interleaved(sys: &System, coupled: bool) -> Interleaved {
    let n = if coupled { sys.dim } else { 3 * sys.dim };
    let mut full: Vec<SparseRow> = vec![Vec::new(); n];
    let mut triplets = Vec::with_capacity(2 * sys.lower.len() * if coupled { 1 } else { 3 });
    let mut push = |r: usize, col: usize, v: f64| {
        triplets.push(Triplet::new(r, col, v));
        full[r].push((col, v));
        if r != col {
            triplets.push(Triplet::new(col, r, v));
            full[col].push((r, v));
        }
    };
    for t in &sys.lower {
        if coupled {
            push(t.row, t.col, t.val);
        } else {
            for d in 0..3 {
                push(3 * t.row + d, 3 * t.col + d, t.val);
            }
        }
    }
    let h = SparseColMat::try_new_from_triplets(n, n, &triplets)
        .expect("the triplets index the free block");
    let b: Vec<f64> = (0..n)
        .map(|i| {
            if coupled {
                sys.b[(i, 0)]
            } else {
                sys.b[(i / 3, i % 3)]
            }
        })
        .collect();
    Interleaved { h, full, b }
}

/// Minimizes ½xᵀHx − bᵀx over the free block subject to the rows, through
/// the core's KKT solve, then checks the answer like the unconstrained
/// solve: the Lagrangian's gradient in compensated arithmetic, the excess
/// ½ gᵀy over the rows' null space (y the constrained Newton step, through
/// the same factor) and corrections while it falls.
pub(super) fn solve(
    sys: &System,
    coupled: bool,
    rows: &[Row],
    slot: &[usize],
    x0: &[Vec3],
) -> Result<Constrained> {
    let (f, c) = reduced_rows(rows, slot, x0)?;
    let Interleaved { h, full, b } = interleaved(sys, coupled);
    let n = b.len();
    let minus_b: Vec<f64> = b.iter().map(|v| -v).collect();
    let fs: Vec<&[(usize, f64)]> = f.iter().map(Vec::as_slice).collect();
    let (factor, solution) = match try_kkt(&h, &fs, &minus_b, &c) {
        KktOutcome::Solved {
            factor, solution, ..
        } => (factor, solution),
        KktOutcome::Unfactorable(e) | KktOutcome::Failed(e) => return Err(e),
    };
    // Fᵀ by unknown: (row, coefficient).
    let mut ft: Vec<SparseRow> = vec![Vec::new(); n];
    for (k, row) in f.iter().enumerate() {
        for &(i, a) in row {
            ft[i].push((k, a));
        }
    }
    // b − Hx − Fᵀλ, every entry one compensated dot product.
    let lagrangian = |x: &[f64], lambda: &[f64]| -> Vec<f64> {
        let (mut a, mut xs) = (Vec::new(), Vec::new());
        (0..n)
            .map(|i| {
                a.clear();
                xs.clear();
                for &(j, v) in &full[i] {
                    a.push(v);
                    xs.push(x[j]);
                }
                for &(k, v) in &ft[i] {
                    a.push(v);
                    xs.push(lambda[k]);
                }
                dot2_residual(b[i], &a, &xs)
            })
            .collect()
    };
    let zeros = vec![0.0; f.len()];
    let excess_at = |x: &[f64], lambda: &[f64]| -> Result<Step> {
        let g = lagrangian(x, lambda);
        let minus_g: Vec<f64> = g.iter().map(|v| -v).collect();
        let step = factor.solve(&minus_g, &zeros)?;
        let e = 0.5 * g.iter().zip(&step.x).map(|(a, b)| a * b).sum::<f64>();
        Ok((e, g, step.x, step.lambda))
    };
    let (mut x, mut lambda) = (solution.x, solution.lambda);
    let (mut excess, mut g, mut y, mut mu) = excess_at(&x, &lambda)?;
    let mut corrections = 0;
    while corrections < check::MAX_CORRECTIONS && excess > 0.0 {
        let next: Vec<f64> = x.iter().zip(&y).map(|(a, b)| a + b).collect();
        let next_lambda: Vec<f64> = lambda.iter().zip(&mu).map(|(a, b)| a + b).collect();
        let (e2, g2, y2, mu2) = excess_at(&next, &next_lambda)?;
        if e2.is_nan() || e2 >= excess {
            break;
        }
        (x, lambda, excess, g, y, mu) = (next, next_lambda, e2, g2, y2, mu2);
        corrections += 1;
    }
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    Ok(Constrained {
        gradient_norm: inf(&g),
        b_inf: inf(&b),
        x,
        excess,
        corrections,
        kkt: solution.info,
    })
}

/// The row missed the most on the written net, when above the check's
/// tolerance of its size: the larger of the data's (`size`: fixed points,
/// right-hand sides, guide net, operator targets) and the row's own
/// Σ|a_i x_i| + |rhs| — a net the arithmetic could not make meet its rows.
pub(super) fn unmet(rows: &[Row], surface: &BSplineSurface, size: f64) -> Option<(String, f64)> {
    let x: Vec<f64> = surface.points().iter().flatten().copied().collect();
    rows.iter()
        .map(|row| {
            let a: Vec<f64> = row.terms.iter().map(|&(_, a)| a).collect();
            let xs: Vec<f64> = row.terms.iter().map(|&(i, _)| x[i]).collect();
            let own = row.rhs.abs() + a.iter().zip(&xs).map(|(a, x)| (a * x).abs()).sum::<f64>();
            let scale = own.max(size).max(f64::MIN_POSITIVE);
            (
                row.name.clone(),
                dot2_residual(row.rhs, &a, &xs).abs() / scale,
            )
        })
        .filter(|(_, miss)| miss.is_nan() || *miss > check::TOLERANCE)
        .max_by(|a, b| a.1.total_cmp(&b.1))
}
