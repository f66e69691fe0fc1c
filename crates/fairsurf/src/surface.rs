//! What every tensor kind of surface is to the code that samples it: a map
//! R(u, v) of a parameter rectangle with first and second derivatives (after
//! kurbo's `ParamCurve` and truck's `ParametricSurface`). A Bézier patch
//! ([`TensorPatch`], over [0, 1]²), a B-spline surface
//! ([`BSplineSurface`], over its knot domain) and a rational one
//! ([`RationalSurface`]) implement it; meshes ([`crate::TriMesh`]), |H|
//! statistics and the normal turn ([`crate::analysis`]) are written once
//! against it.

use crate::analysis::{curvature_from, Curvature};
use crate::bspline::{BSplineSurface, RationalSurface};
use crate::{SurfaceDerivatives, TensorPatch, Vec3};

/// What a mesh needs at one parameter point: the position, the unit
/// normal and the curvatures (both `None` where the surface is not
/// regular there).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// R(u, v).
    pub point: Vec3,
    /// [`SurfaceDerivatives::normal`].
    pub normal: Option<Vec3>,
    /// [`curvature_from`] the derivatives.
    pub curvature: Option<Curvature>,
}

impl Sample {
    /// The sample from the derivatives at the point.
    pub fn of(d: &SurfaceDerivatives) -> Self {
        Sample {
            point: d.point,
            normal: d.normal(),
            curvature: curvature_from(d),
        }
    }
}

/// A parametric surface over a rectangle of (u, v). The kinds' inherent
/// methods of the same names do the same; generic code calls these.
pub trait ParamSurface {
    /// The parameter rectangle [u₀, u₁] × [v₀, v₁].
    fn domain(&self) -> [(f64, f64); 2];

    /// R(u, v).
    fn eval(&self, u: f64, v: f64) -> Vec3;

    /// R and its first and second partial derivatives at (u, v).
    fn derivatives(&self, u: f64, v: f64) -> SurfaceDerivatives;

    /// [`Self::derivatives`] on the grid `us` × `vs`, u-major (entry
    /// i·|vs| + j at (`us[i]`, `vs[j]`)); kinds compute it with each
    /// direction's basis evaluated once per parameter.
    fn derivatives_on(&self, us: &[f64], vs: &[f64]) -> Vec<SurfaceDerivatives> {
        us.iter()
            .flat_map(|&u| vs.iter().map(move |&v| self.derivatives(u, v)))
            .collect()
    }

    /// R on the grid `us` × `vs`, u-major as [`Self::derivatives_on`].
    fn eval_on(&self, us: &[f64], vs: &[f64]) -> Vec<Vec3> {
        us.iter()
            .flat_map(|&u| vs.iter().map(move |&v| self.eval(u, v)))
            .collect()
    }

    /// [`Sample`]s on the grid `us` × `vs`, u-major, as [`Sample::of`]
    /// gives them from [`Self::derivatives_on`] (a Bézier patch computes
    /// the same bits a row at a time in vector registers).
    fn samples_on(&self, us: &[f64], vs: &[f64]) -> Vec<Sample> {
        self.derivatives_on(us, vs).iter().map(Sample::of).collect()
    }

    /// The unit normal R_u × R_v / |R_u × R_v| at (u, v), `None` where the
    /// surface is not regular.
    fn normal(&self, u: f64, v: f64) -> Option<Vec3> {
        self.derivatives(u, v).normal()
    }

    /// The point at (s, t) of [0, 1]² mapped linearly onto the domain.
    fn eval_unit(&self, s: f64, t: f64) -> Vec3 {
        let [(a, b), (c, d)] = self.domain();
        self.eval(a + (b - a) * s, c + (d - c) * t)
    }

    /// The four boundary curves as polylines of `samples` + 1 points, in
    /// turn around the domain: u = u₀ (v rising), v = v₁ (u rising), u = u₁
    /// (v falling), v = v₀ (u falling).
    fn boundary(&self, samples: usize) -> [Vec<Vec3>; 4] {
        let [(a, b), (c, d)] = self.domain();
        let (us, vs) = self.uniform_grid(samples, samples);
        let reversed = |mut p: Vec<Vec3>| {
            p.reverse();
            p
        };
        [
            self.eval_on(&[a], &vs),
            self.eval_on(&us, &[d]),
            reversed(self.eval_on(&[b], &vs)),
            reversed(self.eval_on(&us, &[c])),
        ]
    }

    /// k + 1 uniform parameters over each side of the domain (k at least
    /// 1), ends exact.
    fn uniform_grid(&self, ku: usize, kv: usize) -> (Vec<f64>, Vec<f64>) {
        let [(a, b), (c, d)] = self.domain();
        (uniform(a, b, ku.max(1)), uniform(c, d, kv.max(1)))
    }
}

/// k + 1 parameters from `a` to `b`, both ends exact.
fn uniform(a: f64, b: f64, k: usize) -> Vec<f64> {
    (0..=k)
        .map(|i| match i {
            0 => a,
            i if i == k => b,
            i => a + (b - a) * i as f64 / k as f64,
        })
        .collect()
}

/// A surface kind the solver core minimizes over ([`crate::Problem`]): a
/// tensor net of control points, row-major, which are the unknowns. A
/// Bézier patch and a B-spline surface implement it; a rational surface
/// does not (its energies are not quadratic in the points).
pub trait ControlNet: ParamSurface + Clone + std::fmt::Debug {
    /// Control points per direction, (rows, columns): point (i, j) is
    /// `points()[i · columns + j]`.
    fn counts(&self) -> (usize, usize);

    /// The control points, row-major.
    fn points(&self) -> &[Vec3];

    /// The control points, row-major, to change in place.
    fn points_mut(&mut self) -> &mut [Vec3];
}

/// Implements [`ParamSurface`] by the kind's inherent methods (and any
/// further items given).
macro_rules! by_inherent {
    ($kind:ty, $domain:expr $(, { $($more:item)* })?) => {
        impl ParamSurface for $kind {
            fn domain(&self) -> [(f64, f64); 2] {
                $domain(self)
            }
            fn eval(&self, u: f64, v: f64) -> Vec3 {
                <$kind>::eval(self, u, v)
            }
            fn derivatives(&self, u: f64, v: f64) -> SurfaceDerivatives {
                <$kind>::derivatives(self, u, v)
            }
            fn derivatives_on(&self, us: &[f64], vs: &[f64]) -> Vec<SurfaceDerivatives> {
                <$kind>::derivatives_on(self, us, vs)
            }
            $($($more)*)?
        }
    };
}

by_inherent!(TensorPatch, |_: &TensorPatch| [(0.0, 1.0), (0.0, 1.0)], {
    fn eval_on(&self, us: &[f64], vs: &[f64]) -> Vec<Vec3> {
        TensorPatch::eval_on(self, us, vs)
    }
    fn samples_on(&self, us: &[f64], vs: &[f64]) -> Vec<Sample> {
        TensorPatch::samples_on(self, us, vs)
    }
});
by_inherent!(BSplineSurface, |s: &BSplineSurface| [
    s.knots().0.domain(),
    s.knots().1.domain()
]);
by_inherent!(RationalSurface, |s: &RationalSurface| {
    let (u, v) = s.net().knots();
    [u.domain(), v.domain()]
});

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bspline::KnotVector;

    /// The kinds' grid derivatives are their pointwise ones, and the
    /// default grid (the pointwise loop) is the same as a kind's own.
    #[test]
    fn grids_agree_with_pointwise_derivatives_for_every_kind() {
        let patch = TensorPatch::from_fn(3, 2, |i, j| {
            [i as f64, j as f64, ((3 * i + j) as f64).sin()]
        });
        let u = KnotVector::new(2, vec![0.0, 0.0, 0.0, 0.5, 2.0, 2.0, 2.0]).unwrap();
        let v = KnotVector::new(2, vec![1.0, 1.0, 1.0, 3.0, 3.0, 3.0]).unwrap();
        let points: Vec<Vec3> = (0..12)
            .map(|k| [(k / 3) as f64, (k % 3) as f64, (k as f64).cos()])
            .collect();
        let spline = BSplineSurface::new(u, v, points).unwrap();
        fn check(s: &impl ParamSurface) {
            let (us, vs) = s.uniform_grid(5, 4);
            let [(a, b), (c, d)] = s.domain();
            assert_eq!((us[0], us[5], vs[0], vs[4]), (a, b, c, d));
            let grid = ParamSurface::derivatives_on(s, &us, &vs);
            for (i, &u) in us.iter().enumerate() {
                for (j, &v) in vs.iter().enumerate() {
                    let (g, p) = (grid[i * vs.len() + j], s.derivatives(u, v));
                    for (x, y) in [(g.point, p.point), (g.du, p.du), (g.duv, p.duv)] {
                        for c in 0..3 {
                            assert!((x[c] - y[c]).abs() < 1e-12, "({u}, {v})");
                        }
                    }
                    assert_eq!(p.point, s.eval(u, v));
                }
            }
            let mid = s.eval_unit(0.5, 0.5);
            assert_eq!(mid, s.eval(0.5 * (a + b), 0.5 * (c + d)));
        }
        check(&patch);
        check(&spline);
        // A rational surface: its quotient grid, over its net's domain.
        let weights: Vec<f64> = (0..12).map(|k| 1.0 + 0.1 * (k % 5) as f64).collect();
        let nurbs = RationalSurface::new(spline.clone(), weights).unwrap();
        check(&nurbs);
        assert_eq!(nurbs.domain(), spline.domain());
        // The trait's own defaults (a kind that gives only the required
        // methods) agree with a kind's fast ones.
        struct Plain<'a>(&'a BSplineSurface);
        impl ParamSurface for Plain<'_> {
            fn domain(&self) -> [(f64, f64); 2] {
                self.0.domain()
            }
            fn eval(&self, u: f64, v: f64) -> Vec3 {
                self.0.eval(u, v)
            }
            fn derivatives(&self, u: f64, v: f64) -> SurfaceDerivatives {
                self.0.derivatives(u, v)
            }
        }
        let plain = Plain(&spline);
        check(&plain);
        let (us, vs) = plain.uniform_grid(3, 3);
        let (a, b) = (
            plain.derivatives_on(&us, &vs),
            spline.derivatives_on(&us, &vs),
        );
        for (x, y) in a.iter().zip(&b) {
            for c in 0..3 {
                assert!((x.dvv[c] - y.dvv[c]).abs() < 1e-12);
            }
        }
        assert_eq!(plain.normal(0.3, 2.0), spline.normal(0.3, 2.0));
        assert_eq!(plain.boundary(4), spline.boundary(4));
        // The boundary runs around the domain, corner to corner.
        let [s0, s1, s2, s3] = spline.boundary(8);
        assert_eq!(s0.len(), 9);
        assert_eq!(
            (s0[0], s0[8]),
            (spline.eval(0.0, 1.0), spline.eval(0.0, 3.0))
        );
        assert_eq!(
            (s1[8], s2[8], s3[8]),
            (spline.eval(2.0, 3.0), spline.eval(2.0, 1.0), s0[0])
        );
        assert_eq!(patch.domain(), [(0.0, 1.0), (0.0, 1.0)]);
        assert_eq!(spline.domain(), [(0.0, 2.0), (1.0, 3.0)]);
    }
}
