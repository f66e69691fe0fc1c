//! B-spline surfaces: more freedom at low degree (issue: the Bernstein net
//! of a degree-25+ polynomial cannot be held in double precision; a bicubic
//! B-spline of many spans can, with Gram matrices whose condition does not
//! grow with the number of spans).
//!
//! [`KnotVector`] (clamped, validated), [`BSplineSurface`] (de Boor
//! evaluation and derivatives, knot insertion, Bézier pieces), the exact
//! membrane and thin-plate energies of Wu & Yang eq. 1–2 (without the
//! guidance terms so far) and [`BSplineProblem`], which minimizes them over
//! the free control points by sparse Cholesky and confirms the energy on
//! the written net through the Bézier pieces' closed forms.
//!
//! ```
//! use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
//! // A bicubic surface of 4 × 3 spans over the unit square, a bump inside.
//! let (u, v) = (KnotVector::uniform(3, 4), KnotVector::uniform(3, 3));
//! let (cu, cv) = (u.count(), v.count());
//! let points = (0..cu * cv)
//!     .map(|k| {
//!         let (i, j) = (k / cv, k % cv);
//!         let inside = i > 1 && j > 1 && i + 2 < cu && j + 2 < cv;
//!         [i as f64, j as f64, if inside { 1.0 } else { 0.0 }]
//!     })
//!     .collect();
//! let surface = BSplineSurface::new(u, v, points).unwrap();
//! let faired = BSplineProblem::new(surface)
//!     .with_fixed_rings(2)
//!     .with_bend(1.0)
//!     .solve()
//!     .unwrap();
//! assert!(faired.report.relative_gradient < 1e-14);
//! assert!(faired.report.energy_error < 1e-10);
//! ```

mod energy;
mod guidance;
mod knots;
mod rational;
mod solve;
mod surface;

pub use knots::KnotVector;
pub use rational::{FitTolerance, RationalSurface, StandIn};
pub use solve::{BSplineProblem, BSplineReport, BSplineSolution, ENERGY_TOLERANCE};
pub use surface::{BSplineSurface, BezierPiece};

/// Gaussian elimination with partial pivoting on a small dense system
/// with right-hand sides of K components (collocation systems); None when
/// a pivot falls below 1e-14 (singular for these well-scaled matrices).
pub(crate) fn solve_dense<const K: usize>(
    mut a: Vec<Vec<f64>>,
    mut b: Vec<[f64; K]>,
) -> Option<Vec<[f64; K]>> {
    let n = a.len();
    for c in 0..n {
        let piv = (c..n).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        if a[piv][c].abs() < 1e-14 {
            return None;
        }
        a.swap(c, piv);
        b.swap(c, piv);
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            if f != 0.0 {
                for k in c..n {
                    a[r][k] -= f * a[c][k];
                }
                for k in 0..K {
                    b[r][k] -= f * b[c][k];
                }
            }
        }
    }
    let mut x = vec![[0.0; K]; n];
    for c in (0..n).rev() {
        for k in 0..K {
            let s: f64 = (c + 1..n).map(|j| a[c][j] * x[j][k]).sum();
            x[c][k] = (b[c][k] - s) / a[c][c];
        }
    }
    Some(x)
}

#[cfg(test)]
mod tests;
