//! The independent check of a tensor solve's written net ([`crate::check`]):
//! its energy and gradient recomputed in double-double, the excess over the
//! minimum (over the constraints' rows, when there are some), and Newton
//! corrections while they lower the recomputed energy.

use super::builder::Problem;
use super::dense::norm_max;
use super::factored::{Factored, Rhs};
use super::problem::Placed;
use crate::budget;
use crate::check::{self, dd::Dd, tensor::EnergyAt};
use crate::energy::Integrand;
use crate::{Error, Result, TensorPatch};
use faer::Mat;

/// The written net after the independent check and its corrections.
pub(super) struct Checked {
    pub(super) patch: TensorPatch,
    /// The recomputed energy and gradient, the estimated excess and the
    /// scale; `None` when a term cannot be checked.
    pub(super) at: Option<(EnergyAt, f64, f64)>,
    /// The constraints' multipliers (corrected with the net).
    pub(super) lambda: Vec<f64>,
    pub(super) corrections: usize,
}

impl Factored {
    /// The net of the free values `xf`, checked on its f64 control points:
    /// energy and gradient in double-double ([`check::tensor`]), the excess
    /// ½ gᵀy with the factor, y = H_FF⁻¹g (with constraints: g the gradient
    /// of the Lagrangian g + Fᵀλ summed in double-double, y the step of
    /// [H Fᵀ; F 0][y; μ] = [g; 0], which moves along the rows). While the
    /// excess is above [`check::GOAL`], y moves the net by more than its
    /// rounding ([`check::NET_ROUNDING`]) and `correct` (no repellors),
    /// Newton corrections x ← x − y (λ ← λ − μ), kept only when they lower
    /// the recomputed energy and keep the rows to their rounding; without
    /// `polish` none once the excess meets the tolerance and y is below
    /// [`check::NET_STEP`] of the net.
    pub(super) fn checked_net(
        &self,
        problem: &Problem,
        placed: &[Placed],
        sys: &Rhs,
        rows: &[usize],
        (mut xf, mut lambda): (Mat<f64>, Vec<f64>),
        correct: bool,
        polish: bool,
    ) -> Result<Checked> {
        let integrands: Vec<_> = problem.terms.iter().map(|t| t.integrand()).collect();
        let operators: Vec<_> = problem
            .operators
            .iter()
            .zip(placed)
            .map(|(op, (_, res))| (op, &res[..]))
            .collect();
        // The rounding floor of the check's scale, from the data (known
        // points, guide surfaces), never from the solution itself.
        let max_diagonal = (0..self.h_ff.nrows())
            .map(|i| self.h_ff[(i, i)])
            .fold(0.0, f64::max);
        let data = problem
            .known()
            .into_iter()
            .flatten()
            .chain(integrands.iter().flatten().flat_map(|i| match i {
                Integrand::GuideSurface { surface, .. } => surface.points().to_vec(),
                _ => Vec::new(),
            }))
            .flatten()
            .fold(0.0, |r: f64, v| r.max(v.abs()));
        let rounding = max_diagonal * (self.h_ff.nrows() * 3 / xf.ncols()) as f64 * data * data;
        let net = |xf: &Mat<f64>| {
            TensorPatch::try_new(
                self.degree.0,
                self.degree.1,
                sys.fill(rows, xf, self.coupled),
            )
            .map_err(|_| Error::NotFinite {
                what: "the solution (the system overflowed)".into(),
            })
        };
        let mut patch = net(&xf)?;
        let mut corrections = 0;
        let Some(mut at) = check::tensor::energy_at(&integrands, &operators, &patch) else {
            return Ok(Checked {
                patch,
                at: None,
                lambda,
                corrections,
            });
        };
        let c = self.rows.rhs(&sys.x)?;
        let mut row_error = self.rows.relative_residuals(&xf, &c);
        loop {
            budget::checkpoint()?;
            let g = self.free_gradient(&at, &lambda);
            let (y, mu) = match &self.rows.system {
                Some(system) => system.apply(&self.factor, &g, &vec![0.0; c.len()]),
                None => (self.factor.apply(&g), Vec::new()),
            };
            let excess = 0.5 * (g.transpose() * &y).diagonal().column_vector().sum().abs();
            let scale = check::scale(at.total.to_f64(), rounding);
            // Unpolished, the net as solved is kept when it meets the
            // tolerance and the Newton step that would correct it moves no
            // control point by more than NET_STEP of the net's size: at high
            // degree a net can meet the energy tolerance and still be far off
            // in directions the energy barely sees (README, "verified or
            // refused"), which only the corrections remove.
            let done = !excess.is_finite()
                || excess <= check::GOAL * scale
                || norm_max(&y) <= check::NET_ROUNDING * norm_max(&xf)
                || (!polish
                    && excess <= check::TOLERANCE * scale
                    && norm_max(&y) <= check::NET_STEP * norm_max(&xf));
            if done || !correct || corrections == check::MAX_CORRECTIONS {
                return Ok(Checked {
                    patch,
                    at: Some((at, excess, scale)),
                    lambda,
                    corrections,
                });
            }
            let next_xf = &xf - &y;
            let next = net(&next_xf)?;
            let Some(next_at) = check::tensor::energy_at(&integrands, &operators, &next) else {
                unreachable!("the integrands were evaluated before");
            };
            let next_row_error = self.rows.relative_residuals(&next_xf, &c);
            // Compared in double-double: near the minimum the energies
            // differ far below a double's resolution.
            if (next_at.total - at.total).to_f64() >= 0.0
                || next_row_error > row_error.max(check::ROW_ROUNDING)
            {
                return Ok(Checked {
                    patch,
                    at: Some((at, excess, scale)),
                    lambda,
                    corrections,
                });
            }
            lambda = lambda.iter().zip(&mu).map(|(l, m)| l - m).collect();
            (xf, patch, at, row_error) = (next_xf, next, next_at, next_row_error);
            corrections += 1;
        }
    }

    /// The recomputed gradient on the free rows, in the system's layout.
    /// (‖g‖∞, normwise backward error ‖g‖∞ / (‖H‖∞‖X‖∞ + ‖B‖∞)) of the
    /// check's exact gradient g at the free coordinates: the figures of
    /// [`Rhs::gradient`] without recomputing them.
    pub(super) fn exact_gradient(
        &self,
        at: &EnergyAt,
        lambda: &[f64],
        sys: &Rhs,
        rows: &[usize],
        patch: &TensorPatch,
    ) -> (f64, f64) {
        let g = self.free_gradient(at, lambda);
        let g_inf = norm_max(&g);
        let b_inf = rows
            .iter()
            .flat_map(|&r| (0..sys.b.ncols()).map(move |c| (r, c)))
            .fold(0.0f64, |m, (r, c)| m.max(sys.b[(r, c)].abs()));
        let x_inf = patch
            .points()
            .iter()
            .flatten()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let denom = self.h_row_norm * x_inf + b_inf;
        (g_inf, if denom > 0.0 { g_inf / denom } else { g_inf })
    }

    /// The gradient of the Lagrangian g + Fᵀλ on the free rows (g the
    /// recomputed one, in the system's layout), summed in double-double:
    /// about zero at a solution, its large parts cancel exactly.
    fn free_gradient(&self, at: &EnergyAt, lambda: &[f64]) -> Mat<f64> {
        let g = &at.gradient;
        if self.coupled {
            let mut sum: Vec<Dd> = (0..3 * self.free.len())
                .map(|r| g[r % 3].v[self.free[r / 3]])
                .collect();
            if let Some(system) = &self.rows.system {
                for (row, &l) in system.rows().iter().zip(lambda) {
                    for &(i, a) in row {
                        sum[i] += Dd::new(a) * l;
                    }
                }
            }
            Mat::from_fn(sum.len(), 1, |r, _| sum[r].to_f64())
        } else {
            Mat::from_fn(self.free.len(), 3, |i, c| g[c].v[self.free[i]].to_f64())
        }
    }
}
