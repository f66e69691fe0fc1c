//! The independent check of a solve: the energy and its gradient recomputed
//! on the net exactly as written (the f64 control points), in double-double
//! arithmetic and by quadrature rather than the solve's closed-form double
//! precision assembly.
//!
//! The report's energies are the recomputed ones (the double-precision
//! closed forms, which lose digits on high-degree nets, are compared with
//! them in [`Check::energy_error`]), and a solve is accepted only when the
//! written net is a minimizer to [`TOLERANCE`]: the energy excess
//! E(x) − E(x*) = ½ gᵀ H_FF⁻¹ g, estimated from the exact gradient g with the
//! solve's well-conditioned factor, is at most [`TOLERANCE`] of the energy
//! (or of the change rounding the free points to doubles can make, when the
//! energy is smaller: [`Check::scale`]).
//!
//! The relative gradient alone is no evidence: its denominator grows with
//! the net's coefficients, and past degree ~24 a Bernstein net can be wrong
//! by 1e12 with a relative gradient of 1e-18. When the excess is too large,
//! the solve first takes Newton corrections x ← x − H⁻¹g with the exact
//! gradient; when that does not reach the tolerance, the solve is refused
//! ([`crate::Error::Unverified`]).
//!
//! Tensor problems: [`tensor`] (Gauss–Legendre tensor rules, the excess
//! from the solve's Cholesky factor). Triangular problems: [`triangle`]
//! (collapsed Gauss rules on every patch; with constraint rows the excess is
//! that of the minimizer within the rows, from the solve's KKT
//! factorization).

pub(crate) mod dd;
mod nodes;
pub(crate) mod tensor;
pub(crate) mod triangle;

use crate::operator::Residual;
use dd::Dd;

/// Relative tolerance of the check's energy excess.
pub const TOLERANCE: f64 = 1e-10;

/// At most this many Newton corrections with the exact gradient.
pub(crate) const MAX_CORRECTIONS: usize = 6;

/// Corrections continue while the relative excess is above this (and they
/// lower the recomputed energy and move the net by more than its rounding,
/// [`NET_ROUNDING`]): about double-double's resolution, so the
/// corrections also remove the large, nearly energy-free components a
/// high-degree net picks up from the double-precision solve (harmonic
/// polynomial at degree 15: net error 6.4e-4 → 1.5e-14).
pub(crate) const GOAL: f64 = 1e-32;

/// Without polishing (`SolveOptions::polish` off: the editor's quick
/// answers), the net as solved is kept when its excess meets [`TOLERANCE`]
/// and the Newton correction would move no free coordinate by more than this
/// fraction of the largest one: far below what a drawing shows, and a net
/// a degree-10 solve leaves (~5e-8 off) passes, where degree 15 and up,
/// further off in nearly energy-free directions, are corrected.
pub(crate) const NET_STEP: f64 = 1e-6;
/// A correction (of a Bézier patch's or a triangular surface's check) whose
/// step moves no free coordinate by more than this fraction of the largest
/// free coordinate is not taken: it is below the net's own rounding
/// (a few units of ε), so it cannot bring the written net nearer its
/// minimizer, only trade one rounding for another. (Measured: after the
/// first correction of a 1,000- or 10,000-patch triangular G1 solve the
/// steps were 3–6e-16 of the net, and whether the double-double energy
/// came out lower — so whether another correction was taken — was
/// rounding luck: 0 to 3 more, each a solve with the factor.)
pub(crate) const NET_ROUNDING: f64 = 4.0 * f64::EPSILON;
/// A correction may leave a constraint row's residual at this many units
/// of its size (the rounding of the written net), or where it was if larger.
pub(crate) const ROW_ROUNDING: f64 = 16.0 * f64::EPSILON;

/// What the independent check found on the written net.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Check {
    /// The energy recomputed on the written net by a second road: in
    /// double-double by quadrature (Bézier patches and triangular
    /// surfaces, where the report's energy is this one), or by Gauss
    /// quadrature span by span in doubles (B-spline surfaces, whose
    /// report keeps the closed forms' energy).
    pub energy: f64,
    /// |closed-form energy in double precision − recomputed energy| / scale:
    /// how many digits the solve's own evaluation kept (not a criterion for
    /// Bézier patches; a B-spline solve refuses above
    /// [`crate::bspline::ENERGY_TOLERANCE`]).
    pub energy_error: f64,
    /// Estimated E(x) − min E, over scale: how far above its minimum the
    /// written net is. 0 when not measured: a B-spline surface with
    /// repellors, where Newton's relative gradient (the report's `newton`)
    /// stands for it.
    pub excess: f64,
    /// The scale of the relative figures: the recomputed energy, or when it
    /// is smaller the change rounding the free points to doubles can make
    /// (ε² · max H_ii · Σ x_i²) over the tolerance.
    pub scale: f64,
    /// Newton corrections with the exact gradient taken after the solve.
    pub corrections: usize,
    /// The tolerance the excess met ([`TOLERANCE`]).
    pub tolerance: f64,
    /// Seconds spent checking (and correcting); for a B-spline surface the
    /// energy's second road (its excess is in the solve's time).
    pub seconds: f64,
}

impl Check {
    /// Whether the written net is a minimizer to the tolerance.
    pub fn passed(&self) -> bool {
        self.energy.is_finite() && self.excess <= self.tolerance
    }
}

/// The scale of the relative figures: the energy, or when it is smaller the
/// energy that rounding the free points to doubles can change by,
/// ε² · max H_ii · Σ x_i² (`rounding` is max H_ii · Σ x_i²), over the
/// tolerance: below that, no net of doubles can be told from the minimizer.
pub(crate) fn scale(energy: f64, rounding: f64) -> f64 {
    let floor = f64::EPSILON * f64::EPSILON * rounding / TOLERANCE;
    energy.max(floor).max(f64::MIN_POSITIVE)
}

/// An attractor's s·q or a repellor's s/q with q = Σ w (a·x − t)²
/// (Veltkamp & Wesselink §5), in double-double at the flattened
/// coordinates `x`; each gradient entry (index, ∂E/∂x_index) goes to `add`.
pub(crate) fn operator_energy(
    strength: f64,
    repel: bool,
    residuals: &[Residual],
    x: &[Dd],
    mut add: impl FnMut(usize, Dd),
) -> Dd {
    let mut q = Dd::new(0.0);
    let mut dq: Vec<(usize, Dd)> = Vec::new();
    for r in residuals {
        let v = r
            .terms
            .iter()
            .fold(Dd::new(-r.target), |s, &(i, a)| s + x[i] * a);
        q += v * v * r.weight;
        let two_wv = v * (2.0 * r.weight);
        dq.extend(r.terms.iter().map(|&(i, a)| (i, two_wv * a)));
    }
    let s = Dd::new(strength);
    let (e, scale) = if repel {
        (s / q, -(s / (q * q)))
    } else {
        (s * q, s)
    };
    for (i, d) in dq {
        add(i, d * scale);
    }
    e
}
