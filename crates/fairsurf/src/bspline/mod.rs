//! B-spline surfaces: more freedom at low degree (issue: the Bernstein net
//! of a degree-25+ polynomial cannot be held in double precision; a bicubic
//! B-spline of many spans can, with Gram matrices whose condition does not
//! grow with the number of spans).
//!
//! [`KnotVector`] (clamped, validated), [`BSplineSurface`] (de Boor
//! evaluation and derivatives, knot insertion, elevation, Bézier pieces),
//! the exact energies of Wu & Yang eq. 1–2 on B-spline bases (membrane,
//! thin plate, normal field, guide surface; the sampled normal field of
//! eq. 5) and [`BSplineProblem`] — the core's [`crate::Problem`] over a
//! B-spline surface, with the same energy terms, constraints and operators
//! as a Bézier patch — which minimizes them over the free control points by
//! Cholesky (dense up to 160 unknowns, else sparse) and confirms the energy on the written net through the
//! Bézier pieces' closed forms.
//!
//! ```
//! use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
//! use fairsurf::Bend;
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
//! let faired = BSplineProblem::from_surface(surface)
//!     .with_fixed_rings(2)
//!     .with_term(Bend::new(1.0))
//!     .solve()
//!     .unwrap();
//! assert!(faired.report.relative_gradient < 1e-14);
//! assert!(faired.report.check.unwrap().energy_error < 1e-10);
//! ```

mod constraint;
mod energy;
mod guidance;
mod knots;
mod problem;
mod project;
mod rational;
mod solve;
mod strip;
mod surface;
mod system;

pub use knots::KnotVector;
pub(crate) use knots::{Bases, BasesView};
pub use problem::BSplineProblem;
pub use rational::{FitTolerance, RationalSurface, StandIn, ONE_SPAN_DEGREE};
pub use solve::{BSplineSolution, ENERGY_TOLERANCE};
pub use strip::{
    edge_stand_in, strip_stand_in, strip_stand_in_towards, Break, EdgeFrame, TrueEdge,
};
pub use surface::{BSplineSurface, BezierPiece};
pub(crate) use system::{BSplineFactor, Reuse};

/// Gaussian elimination with partial pivoting on a small dense system
/// with right-hand sides of K components (collocation systems); None when
/// a pivot falls below 1e-14 (singular for these well-scaled matrices).
pub(crate) fn solve_dense<const K: usize>(
    a: Vec<Vec<f64>>,
    b: Vec<[f64; K]>,
) -> Option<Vec<[f64; K]>> {
    let x = solve_dense_wide(a, b.concat(), K)?;
    Some(
        x.chunks_exact(K)
            .map(|r| std::array::from_fn(|k| r[k]))
            .collect(),
    )
}

/// [`solve_dense`] with `width` right-hand sides at once (`b` row-major,
/// n × width): one elimination for all of them.
pub(crate) fn solve_dense_wide(
    mut a: Vec<Vec<f64>>,
    mut b: Vec<f64>,
    width: usize,
) -> Option<Vec<f64>> {
    let n = a.len();
    debug_assert_eq!(b.len(), n * width);
    for c in 0..n {
        let piv = (c..n).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        if a[piv][c].abs() < 1e-14 {
            return None;
        }
        a.swap(c, piv);
        for k in 0..width {
            b.swap(c * width + k, piv * width + k);
        }
        let (top, rest) = a.split_at_mut(c + 1);
        let pivot_row = &top[c];
        let (b_top, b_rest) = b.split_at_mut((c + 1) * width);
        let b_pivot = &b_top[c * width..];
        for (r, row) in rest.iter_mut().enumerate() {
            let f = row[c] / pivot_row[c];
            if f != 0.0 {
                for k in c..n {
                    row[k] -= f * pivot_row[k];
                }
                for (x, y) in b_rest[r * width..(r + 1) * width].iter_mut().zip(b_pivot) {
                    *x -= f * y;
                }
            }
        }
    }
    for c in (0..n).rev() {
        for k in 0..width {
            let s: f64 = (c + 1..n).map(|j| a[c][j] * b[j * width + k]).sum();
            b[c * width + k] = (b[c * width + k] - s) / a[c][c];
        }
    }
    Some(b)
}

#[cfg(test)]
mod tests;
