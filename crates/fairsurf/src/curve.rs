//! Bézier curves `C(t) = Σ_i B_i^n(t) P_i`, t ∈ [0, 1].

use crate::basis::{bernstein_all, binomial};
use crate::vec3::{add, scale, sub, Vec3};
use crate::{Error, Result};

/// A Bézier curve of degree n = points.len() − 1 in ℝ³.
///
/// ```
/// use fairsurf::BezierCurve;
/// let c = BezierCurve::new(vec![[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [2.0, 0.0, 0.0]]);
/// assert_eq!(c.eval(0.5), [1.0, 1.0, 0.0]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BezierCurve {
    points: Vec<Vec3>,
}

impl BezierCurve {
    /// A curve through its control points.
    ///
    /// # Panics
    /// If `points` is empty; see [`BezierCurve::try_new`].
    pub fn new(points: Vec<Vec3>) -> Self {
        Self::try_new(points).expect("BezierCurve::new")
    }

    /// A curve through its control points, or an error when there are none.
    pub fn try_new(points: Vec<Vec3>) -> Result<Self> {
        if points.is_empty() {
            return Err(Error::EmptyCurve);
        }
        Ok(Self { points })
    }

    /// The degree n.
    pub fn degree(&self) -> usize {
        self.points.len() - 1
    }

    /// The control points P_0 … P_n.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// C(t).
    pub fn eval(&self, t: f64) -> Vec3 {
        let b = bernstein_all(self.degree(), t);
        self.points
            .iter()
            .zip(b)
            .fold([0.0; 3], |acc, (&p, w)| add(acc, scale(p, w)))
    }

    /// The hodograph C'(t) as a curve of degree n−1: `n (P_{i+1} − P_i)`.
    /// The derivative of a constant curve is the zero point.
    pub fn derivative(&self) -> BezierCurve {
        let n = self.degree();
        if n == 0 {
            return BezierCurve::new(vec![[0.0; 3]]);
        }
        let pts = self
            .points
            .windows(2)
            .map(|w| scale(sub(w[1], w[0]), n as f64))
            .collect();
        BezierCurve::new(pts)
    }

    /// Splits at t into the curves on [0, t] and [t, 1] (de Casteljau).
    pub fn subdivide(&self, t: f64) -> (BezierCurve, BezierCurve) {
        let (left, right) = de_casteljau_split(&self.points, t);
        (BezierCurve::new(left), BezierCurve::new(right))
    }

    /// The same curve written with degree n + r.
    pub fn elevate(&self, r: usize) -> BezierCurve {
        BezierCurve::new(elevate_points(&self.points, r))
    }
}

/// De Casteljau's split of a control polygon at t: the control polygons of
/// the pieces on [0, t] and [t, 1].
pub(crate) fn de_casteljau_split(points: &[Vec3], t: f64) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut work = points.to_vec();
    let n = work.len();
    let mut left = Vec::with_capacity(n);
    let mut right = Vec::with_capacity(n);
    for level in 0..n {
        left.push(work[0]);
        right.push(work[n - 1 - level]);
        for i in 0..n - 1 - level {
            work[i] = add(scale(work[i], 1.0 - t), scale(work[i + 1], t));
        }
    }
    right.reverse();
    (left, right)
}

/// Degree elevation by r of a control polygon:
/// `Q_k = Σ_i C(n,i) C(r,k−i) / C(n+r,k) P_i`.
pub(crate) fn elevate_points(points: &[Vec3], r: usize) -> Vec<Vec3> {
    let n = points.len() - 1;
    (0..=n + r)
        .map(|k| {
            let lo = k.saturating_sub(r);
            (lo..=k.min(n)).fold([0.0; 3], |acc, i| {
                let w = binomial(n, i) * binomial(r, k - i) / binomial(n + r, k);
                add(acc, scale(points[i], w))
            })
        })
        .collect()
}

/// The parameter in [lo, hi] of the point of a curve nearest to p, and the
/// distance: the nearest of 33 samples, then Newton steps on
/// (C(t) − p)·C′(t) = 0 kept in the range while they come closer. `c(t)`
/// gives C, C′ and C″ at t.
pub fn nearest_parameter(c: impl Fn(f64) -> [Vec3; 3], range: (f64, f64), p: Vec3) -> (f64, f64) {
    nearest_parameter_by(|t| c(t)[0], &c, range, p)
}

/// [`nearest_parameter`] with the curve's points from `point` alone (the
/// 33 samples and the distance after each step need no derivatives).
pub(crate) fn nearest_parameter_by(
    point: impl Fn(f64) -> Vec3,
    c: impl Fn(f64) -> [Vec3; 3],
    (lo, hi): (f64, f64),
    p: Vec3,
) -> (f64, f64) {
    use crate::vec3::{dist, dot, sub};
    let (mut best, mut t) = (f64::MAX, lo);
    for k in 0..=32 {
        let x = lo + (hi - lo) * k as f64 / 32.0;
        let d = dist(point(x), p);
        if d < best {
            (best, t) = (d, x);
        }
    }
    for _ in 0..30 {
        let [at, d1, d2] = c(t);
        let r = sub(at, p);
        let h = dot(d1, d1) + dot(r, d2);
        if h.is_nan() || h <= 0.0 {
            break;
        }
        let next = (t - dot(r, d1) / h).clamp(lo, hi);
        let d = dist(point(next), p);
        if d.is_nan() || d >= best {
            break;
        }
        (best, t) = (d, next);
    }
    (t, best)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::norm;

    fn sample() -> BezierCurve {
        BezierCurve::new(vec![
            [0.0, 0.0, 0.0],
            [1.0, 3.0, -1.0],
            [2.5, -1.0, 2.0],
            [4.0, 0.5, 0.0],
        ])
    }

    #[test]
    fn interpolates_end_points() {
        let c = sample();
        assert_eq!(c.eval(0.0), c.points()[0]);
        assert!(norm(sub(c.eval(1.0), c.points()[3])) < 1e-15);
    }

    #[test]
    fn derivative_matches_finite_difference() {
        let c = sample();
        let d = c.derivative();
        let h = 1e-6;
        for &t in &[0.1, 0.5, 0.9] {
            let fd = scale(sub(c.eval(t + h), c.eval(t - h)), 0.5 / h);
            assert!(norm(sub(fd, d.eval(t))) < 1e-8);
        }
    }

    #[test]
    fn subdivision_reproduces_both_halves() {
        let c = sample();
        let t0 = 0.3;
        let (l, r) = c.subdivide(t0);
        for &s in &[0.0, 0.2, 0.7, 1.0] {
            assert!(norm(sub(l.eval(s), c.eval(t0 * s))) < 1e-14);
            assert!(norm(sub(r.eval(s), c.eval(t0 + (1.0 - t0) * s))) < 1e-14);
        }
    }

    #[test]
    fn elevation_keeps_the_curve() {
        let c = sample();
        let e = c.elevate(3);
        assert_eq!(e.degree(), 6);
        for &s in &[0.0, 0.33, 0.8] {
            assert!(norm(sub(e.eval(s), c.eval(s))) < 1e-14);
        }
    }

    #[test]
    fn empty_curve_is_an_error() {
        assert_eq!(BezierCurve::try_new(vec![]), Err(Error::EmptyCurve));
    }
}
