//! Rational B-spline (NURBS) surfaces
//! R(u, v) = Σ w_ij N_i^p(u) N_j^q(v) P_ij / Σ w_ij N_i^p(u) N_j^q(v):
//! how CAD systems write cylinders, cones, spheres and tori exactly (Piegl
//! & Tiller, *The NURBS Book*, ch. 4 and 7). fairsurf's energies are
//! polynomial; a rational surface enters only as a neighbour of a hole or a
//! blend, through a polynomial stand-in fitted to a tolerance
//! ([`RationalSurface::polynomial`]) and measured against the exact
//! surface.

use super::{solve_dense_wide, BSplineSurface, KnotVector};
use crate::vec3::{add, angle, dist, scale, sub, Vec3};
use crate::{Error, Result, SurfaceDerivatives};

/// A rational B-spline surface: a [`BSplineSurface`] net P_ij and one
/// positive weight w_ij per control point (row-major as the points).
#[derive(Clone, Debug, PartialEq)]
pub struct RationalSurface {
    surface: BSplineSurface,
    weights: Vec<f64>,
    /// Σ w N N P as a polynomial surface (points w_ij P_ij).
    numerator: BSplineSurface,
    /// Σ w N N as a polynomial surface (points (w_ij, 0, 0)).
    denominator: BSplineSurface,
}

/// How close a polynomial stand-in must come to a rational surface along
/// its four sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitTolerance {
    /// Largest distance between the two at the same parameter.
    pub position: f64,
    /// Largest angle between their unit normals, radians.
    pub angle: f64,
}

impl Default for FitTolerance {
    /// 1e-6 in position, 0.01° in angle.
    fn default() -> Self {
        Self {
            position: 1e-6,
            angle: 0.01f64.to_radians(),
        }
    }
}

/// A polynomial B-spline standing in for a rational surface along its
/// sides, and how far from it it is.
#[derive(Clone, Debug, PartialEq)]
pub struct StandIn {
    /// The polynomial surface, on the same parameter rectangle.
    pub surface: BSplineSurface,
    /// Largest distance to the rational surface along the four sides (at
    /// the same parameter).
    pub position: f64,
    /// Largest normal angle to it along the four sides, radians.
    pub angle: f64,
}

/// Parameters compared per side when measuring a stand-in.
const SIDE_SAMPLES: usize = 129;
/// The most pieces a stand-in cuts its domain into, in one direction.
const MAX_SPANS: usize = 512;
/// The highest degree of a one-span stand-in direction
/// ([`RationalSurface::polynomial_spans`]).
pub const ONE_SPAN_DEGREE: usize = 15;

impl RationalSurface {
    /// The surface of net `surface` and `weights` (one per control point,
    /// finite and positive).
    pub fn new(surface: BSplineSurface, weights: Vec<f64>) -> Result<Self> {
        let n = surface.points().len();
        if weights.len() != n {
            return Err(Error::Mismatch {
                what: "rational B-spline weights".into(),
                expected: format!("{n} (one per control point)"),
                got: weights.len().to_string(),
            });
        }
        if let Some(k) = weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
            let cv = surface.counts().1;
            return Err(Error::Fill {
                why: format!(
                    "weight ({}, {}) is {}: weights must be finite and positive",
                    k / cv,
                    k % cv,
                    weights[k]
                ),
            });
        }
        let (u, v) = surface.knots();
        let numerator = BSplineSurface::new(
            u.clone(),
            v.clone(),
            surface
                .points()
                .iter()
                .zip(&weights)
                .map(|(p, w)| scale(*p, *w))
                .collect(),
        )?;
        let denominator = BSplineSurface::new(
            u.clone(),
            v.clone(),
            weights.iter().map(|w| [*w, 0.0, 0.0]).collect(),
        )?;
        Ok(Self {
            surface,
            weights,
            numerator,
            denominator,
        })
    }

    /// The net (knots, degrees, points P_ij).
    pub fn net(&self) -> &BSplineSurface {
        &self.surface
    }

    /// The weights, row-major.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Whether every weight is the same (the surface is then its net's
    /// polynomial B-spline).
    pub fn is_polynomial(&self) -> bool {
        let w0 = self.weights[0];
        self.weights.iter().all(|w| (w - w0).abs() <= 1e-14 * w0)
    }

    /// R(u, v).
    pub fn eval(&self, u: f64, v: f64) -> Vec3 {
        scale(
            self.numerator.eval(u, v),
            1.0 / self.denominator.eval(u, v)[0],
        )
    }

    /// R and its first and second derivatives at (u, v), by the quotient
    /// rule on the homogeneous form A = w R (The NURBS Book, eq. 4.20).
    pub fn derivatives(&self, u: f64, v: f64) -> SurfaceDerivatives {
        quotient(
            &self.numerator.derivatives(u, v),
            &self.denominator.derivatives(u, v),
        )
    }

    /// [`derivatives`](Self::derivatives) on the grid `us` × `vs`
    /// (u-major, as [`BSplineSurface::derivatives_on`]).
    pub fn derivatives_on(&self, us: &[f64], vs: &[f64]) -> Vec<SurfaceDerivatives> {
        let a = self.numerator.derivatives_on(us, vs);
        let w = self.denominator.derivatives_on(us, vs);
        a.iter().zip(&w).map(|(a, w)| quotient(a, w)).collect()
    }

    /// R, R_u and R_v on the grid `us` × `vs` (u-major), by the quotient
    /// rule on A = w R ([`BSplineSurface::tangents_on`]'s lines).
    pub(crate) fn tangents_on(&self, us: &[f64], vs: &[f64]) -> Vec<[Vec3; 3]> {
        let a = self.numerator.tangents_on(us, vs);
        let w = self.denominator.tangents_on(us, vs);
        a.iter()
            .zip(&w)
            .map(|(a, w)| {
                let r = 1.0 / w[0][0];
                let point = scale(a[0], r);
                let du = scale(sub(a[1], scale(point, w[1][0])), r);
                let dv = scale(sub(a[2], scale(point, w[2][0])), r);
                [point, du, dv]
            })
            .collect()
    }

    /// A polynomial B-spline on the same parameter rectangle within
    /// `tolerance` of this surface along its four sides: interpolation at
    /// the Greville abscissae; in a direction where the weights do not
    /// vary the net's own knots and degree (exact there), in the others
    /// degree max(p + 3, 5), the net's knots kept (with the multiplicity
    /// that allows its continuity) and its spans cut in pieces of about
    /// equal length, their number doubled until the sides are within
    /// tolerance. Errors when 512 pieces are not enough.
    pub fn polynomial(&self, tolerance: FitTolerance) -> Result<StandIn> {
        self.polynomial_spans(tolerance, [false, false])
    }

    /// [`Self::polynomial`], but one Bézier span in u (`one_span[0]`)
    /// and/or v (`one_span[1]`) where the weights vary: its degree raised
    /// from max(p + 3, 5) by one until the sides are within tolerance, at
    /// most [`ONE_SPAN_DEGREE`] — for a fill whose sides must each be one
    /// polynomial piece (a fan of triangular patches). A quarter circle of
    /// radius 1 is within 1e-6 and 0.01° at degree 10. Errors when the net has
    /// interior knots in such a direction (a polynomial across a knot of
    /// the net converges only as fast as the net is smooth there), or when
    /// the degree is not enough.
    pub fn polynomial_spans(
        &self,
        tolerance: FitTolerance,
        one_span: [bool; 2],
    ) -> Result<StandIn> {
        let (ku, kv) = self.surface.knots();
        let (cu, cv) = self.surface.counts();
        let w = |i: usize, j: usize| self.weights[i * cv + j];
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-14 * a.max(b);
        let varies_u = (0..cu).any(|i| (0..cv).any(|j| !same(w(i, j), w(0, j))));
        let varies_v = (0..cu).any(|i| (0..cv).any(|j| !same(w(i, j), w(i, 0))));
        let one = [one_span[0] && varies_u, one_span[1] && varies_v];
        for (k, dir) in [(ku, 'u'), (kv, 'v')].into_iter().zip(one) {
            let spans = k.0.spans().len();
            if dir && spans > 1 {
                return Err(Error::Fill {
                    why: format!(
                        "a rational face of {spans} spans in {} cannot stand in as one polynomial \
                         piece there",
                        k.1
                    ),
                });
            }
        }
        // Pieces over the whole domain (each span of the net gets its share
        // by length, at least one): at first two; one-span directions
        // count degrees instead, from max(p + 3, 5).
        let first_degree = |k: &KnotVector| (k.degree() + 3).max(5);
        let (mut su, mut sv) = (
            if one[0] { first_degree(ku) } else { 2 },
            if one[1] { first_degree(kv) } else { 2 },
        );
        loop {
            // Degree d = max(p + 3, 5); the net's own knots kept with the
            // multiplicity that allows its continuity there (C^(p−m) at a
            // knot of multiplicity m: d − p + m), each of its spans cut in
            // equal pieces about (b − a)/`pieces` long. A stand-in across a
            // knot of the net would converge as slowly as the net is smooth
            // there.
            let knots = |k: &KnotVector, varies: bool, one: bool, pieces: usize| {
                if !varies {
                    return Ok(k.clone());
                }
                let (a, b) = k.domain();
                if one {
                    let d = pieces;
                    let t = [vec![a; d + 1], vec![b; d + 1]].concat();
                    return KnotVector::new(d, t);
                }
                let (p, d) = (k.degree(), first_degree(k));
                let mut t = vec![a; d + 1];
                let spans = k.spans();
                for (n, &(_, x0, x1)) in spans.iter().enumerate() {
                    let cut = ((x1 - x0) / (b - a) * pieces as f64).ceil().max(1.0) as usize;
                    t.extend((1..cut).map(|s| x0 + (x1 - x0) * s as f64 / cut as f64));
                    if n + 1 < spans.len() {
                        let m = k.multiplicity(x1);
                        t.extend(std::iter::repeat_n(x1, (d + m).saturating_sub(p).min(d)));
                    }
                }
                t.extend(std::iter::repeat_n(b, d + 1));
                KnotVector::new(d, t)
            };
            let nu = knots(ku, varies_u, one[0], su)?;
            let nv = knots(kv, varies_v, one[1], sv)?;
            let surface = self.interpolate(nu, nv)?;
            let (position, angle) = self.side_deviation(&surface);
            if position <= tolerance.position && angle <= tolerance.angle {
                return Ok(StandIn {
                    surface,
                    position,
                    angle,
                });
            }
            let limit = |one: bool| if one { ONE_SPAN_DEGREE } else { MAX_SPANS };
            let done_u = !varies_u || su >= limit(one[0]);
            let done_v = !varies_v || sv >= limit(one[1]);
            if done_u && done_v {
                let what = |varies: bool, one: bool, n: usize| {
                    if !varies {
                        "the net's knots".to_string()
                    } else if one {
                        format!("one span of degree {n}")
                    } else {
                        format!("{n} pieces")
                    }
                };
                // The tolerance is a distance: on a large face it asks for
                // more digits than doubles hold.
                let size = crate::vec3::bounding_diagonal(self.surface.points());
                return Err(Error::Fill {
                    why: format!(
                        "a rational face could not be approximated by a polynomial one within \
                         {:e} in position and {:e}° in angle (reached {position:e} and {:e}° \
                         with {} in u and {} in v; the face is {size:.3e} across, the position \
                         tolerance {:.0e} of that: a looser one may do)",
                        tolerance.position,
                        tolerance.angle.to_degrees(),
                        angle.to_degrees(),
                        what(varies_u, one[0], su),
                        what(varies_v, one[1], sv),
                        tolerance.position / size,
                    ),
                });
            }
            if !done_u {
                su = if one[0] { su + 1 } else { su * 2 };
            }
            if !done_v {
                sv = if one[1] { sv + 1 } else { sv * 2 };
            }
        }
    }

    /// The polynomial surface on `u` × `v` through this one's points at
    /// their Greville abscissae.
    fn interpolate(&self, u: KnotVector, v: KnotVector) -> Result<BSplineSurface> {
        let (gu, gv) = (u.greville(), v.greville());
        let (nu, nv) = (gu.len(), gv.len());
        let mut data: Vec<Vec3> = gu
            .iter()
            .flat_map(|&a| gv.iter().map(move |&b| (a, b)))
            .map(|(a, b)| self.eval(a, b))
            .collect();
        // Rows of the collocation systems: B_u X = D along u for each j,
        // then along v for each i.
        let bu = u.collocation(&gu);
        let bv = v.collocation(&gv);
        let singular = || Error::Fill {
            why: "the collocation system of a rational face's stand-in is singular".into(),
        };
        // Along u: the nu × nv data (rows i) for all j at once.
        let flat: Vec<f64> = data.iter().flatten().copied().collect();
        let x = solve_dense_wide(bu, flat, 3 * nv).ok_or_else(singular)?;
        // Along v: the transpose, nv × nu, for all i at once.
        let x = &x;
        let transposed: Vec<f64> = (0..nv)
            .flat_map(|j| (0..nu).flat_map(move |i| (0..3).map(move |c| x[(i * nv + j) * 3 + c])))
            .collect();
        let y = solve_dense_wide(bv, transposed, 3 * nu).ok_or_else(singular)?;
        for i in 0..nu {
            for j in 0..nv {
                let k = (j * nu + i) * 3;
                data[i * nv + j] = [y[k], y[k + 1], y[k + 2]];
            }
        }
        BSplineSurface::new(u, v, data)
    }

    /// Largest distance and normal angle between `s` and this surface
    /// along the four sides, at Chebyshev–Lobatto parameters on every
    /// span of `s` (at least 9 per span, about 129 per side in all).
    fn side_deviation(&self, s: &BSplineSurface) -> (f64, f64) {
        let ((a, b), (c, d)) = {
            let (ku, kv) = self.surface.knots();
            (ku.domain(), kv.domain())
        };
        let (us, vs) = (side_parameters(s.knots().0), side_parameters(s.knots().1));
        let (mut gap, mut ang) = (0.0f64, 0.0f64);
        for (gu, gv) in [(us.clone(), vec![c, d]), (vec![a, b], vs.clone())] {
            let x = self.derivatives_on(&gu, &gv);
            let y = s.derivatives_on(&gu, &gv);
            for (x, y) in x.iter().zip(&y) {
                gap = gap.max(dist(x.point, y.point));
                // Where the exact surface has a normal, the stand-in must
                // have the same one (no normal at all counts as the worst).
                if let Some(n) = x.regular_normal() {
                    ang = ang.max(
                        y.regular_normal()
                            .map_or(std::f64::consts::PI, |m| angle(n, m)),
                    );
                }
            }
        }
        (gap, ang)
    }
}

/// Chebyshev–Lobatto parameters on every span of `k`: at least 9 per
/// span, about [`SIDE_SAMPLES`] in all (a span's ends once).
pub(super) fn side_parameters(k: &KnotVector) -> Vec<f64> {
    let spans = k.spans();
    let n = ((SIDE_SAMPLES - 1) / spans.len()).max(8);
    let mut xs = vec![k.domain().0];
    for &(_, lo, hi) in &spans {
        xs.extend((1..=n).map(|i| {
            let x = 0.5 - 0.5 * (std::f64::consts::PI * i as f64 / n as f64).cos();
            if i == n {
                hi
            } else {
                lo + (hi - lo) * x
            }
        }));
    }
    xs
}

/// R's derivatives from those of A = w R and w (w in the first
/// coordinate of `w`).
fn quotient(a: &SurfaceDerivatives, w: &SurfaceDerivatives) -> SurfaceDerivatives {
    let (w0, wu, wv) = (w.point[0], w.du[0], w.dv[0]);
    let (wuu, wuv, wvv) = (w.duu[0], w.duv[0], w.dvv[0]);
    let r = 1.0 / w0;
    let point = scale(a.point, r);
    let du = scale(sub(a.du, scale(point, wu)), r);
    let dv = scale(sub(a.dv, scale(point, wv)), r);
    let duu = scale(sub(a.duu, add(scale(du, 2.0 * wu), scale(point, wuu))), r);
    let dvv = scale(sub(a.dvv, add(scale(dv, 2.0 * wv), scale(point, wvv))), r);
    let duv = scale(
        sub(
            a.duv,
            add(add(scale(du, wv), scale(dv, wu)), scale(point, wuv)),
        ),
        r,
    );
    SurfaceDerivatives {
        point,
        du,
        dv,
        duu,
        duv,
        dvv,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::norm;

    /// A quarter of the cylinder x² + z² = r² (|y| ≤ h), as CAD writes it:
    /// rational quadratic in u (weights 1, √½, 1), linear in v.
    pub(crate) fn quarter_cylinder(r: f64, h: f64) -> RationalSurface {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let arc = [[r, 0.0], [r, r], [0.0, r]];
        let points = arc
            .iter()
            .flat_map(|&[x, z]| [[x, -h, z], [x, h, z]])
            .collect();
        let net =
            BSplineSurface::new(KnotVector::bezier(2), KnotVector::bezier(1), points).unwrap();
        RationalSurface::new(net, vec![1.0, 1.0, s, s, 1.0, 1.0]).unwrap()
    }

    /// Sides are compared on every span, however many: at least 9
    /// parameters per span, its ends among them.
    #[test]
    fn sides_are_sampled_on_every_span() {
        let mut t = vec![0.0; 6];
        t.extend((1..300).map(|k| k as f64 / 300.0));
        t.extend([1.0; 6]);
        let k = KnotVector::new(5, t).unwrap();
        let xs = side_parameters(&k);
        for &(_, lo, hi) in &k.spans() {
            let inside = xs.iter().filter(|&&x| lo <= x && x <= hi).count();
            assert!(inside >= 9, "{inside} on [{lo}, {hi}]");
            assert!(xs.contains(&lo) && xs.contains(&hi));
        }
        assert!(xs.windows(2).all(|w| w[0] < w[1]));
        let few = side_parameters(&KnotVector::bezier(3));
        assert_eq!(few.len(), 129);
    }

    #[test]
    fn a_rational_quarter_cylinder_is_on_the_cylinder() {
        let c = quarter_cylinder(2.0, 1.0);
        for k in 0..=20 {
            for l in 0..=4 {
                let p = c.eval(k as f64 / 20.0, l as f64 / 4.0);
                assert!((p[0].hypot(p[2]) - 2.0).abs() < 1e-14, "{p:?}");
            }
        }
        assert!(!c.is_polynomial());
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let c = quarter_cylinder(1.5, 0.7);
        // Uneven weights in both directions too.
        let net = c.net().elevated(1, 1).unwrap();
        let weights: Vec<f64> = (0..net.points().len())
            .map(|k| 1.0 + 0.3 * ((k * 7) % 5) as f64 / 5.0)
            .collect();
        for s in [c, RationalSurface::new(net, weights).unwrap()] {
            let (u, v, h) = (0.37, 0.61, 1e-5);
            let d = s.derivatives(u, v);
            let fd = |f: &dyn Fn(f64, f64) -> Vec3, du: f64, dv: f64| {
                scale(sub(f(u + du, v + dv), f(u - du, v - dv)), 0.5 / h)
            };
            let e = |a: Vec3, b: Vec3| norm(sub(a, b));
            let p = |a, b| s.eval(a, b);
            assert!(e(d.du, fd(&p, h, 0.0)) < 1e-8);
            assert!(e(d.dv, fd(&p, 0.0, h)) < 1e-8);
            let su = |a, b| s.derivatives(a, b).du;
            let sv = |a, b| s.derivatives(a, b).dv;
            assert!(e(d.duu, fd(&su, h, 0.0)) < 1e-7);
            assert!(e(d.duv, fd(&su, 0.0, h)) < 1e-7);
            assert!(e(d.duv, fd(&sv, h, 0.0)) < 1e-7);
            assert!(e(d.dvv, fd(&sv, 0.0, h)) < 1e-7);
            let g = s.derivatives_on(&[u], &[v])[0];
            for (a, b) in [
                (g.point, d.point),
                (g.du, d.du),
                (g.dvv, d.dvv),
                (g.duv, d.duv),
            ] {
                assert!(e(a, b) < 1e-13);
            }
            // The first derivatives along lines of either direction.
            let ts = [0.0, 0.2, 0.61, 1.0];
            for (us, vs) in [(&ts[..], &[v][..]), (&[u][..], &ts[..])] {
                for (k, t) in s.tangents_on(us, vs).iter().enumerate() {
                    let d = s.derivatives(us[k / vs.len()], vs[k % vs.len()]);
                    for (a, b) in t.iter().zip([d.point, d.du, d.dv]) {
                        assert!(e(*a, b) < 1e-13);
                    }
                }
            }
        }
    }

    #[test]
    fn a_stand_in_meets_its_tolerance_and_tighter_needs_more_spans() {
        let c = quarter_cylinder(1.0, 1.0);
        let loose = c.polynomial(FitTolerance::default()).unwrap();
        assert!(loose.position <= 1e-6 && loose.angle <= 0.01f64.to_radians());
        // Linear along the cylinder's axis: the v direction is kept.
        assert_eq!(loose.surface.degree().1, 1);
        let tight = c
            .polynomial(FitTolerance {
                position: 1e-12,
                angle: 1e-10,
            })
            .unwrap();
        assert!(tight.position <= 1e-12 && tight.angle <= 1e-10);
        let spans = |s: &StandIn| s.surface.knots().0.spans().len();
        assert!(
            spans(&tight) > spans(&loose),
            "{} {}",
            spans(&tight),
            spans(&loose)
        );
        // Independently of the measure: points inside are on the cylinder.
        for k in 0..=50 {
            let p = tight.surface.eval(k as f64 / 50.0, 0.3);
            assert!((p[0].hypot(p[2]) - 1.0).abs() < 1e-11, "{p:?}");
        }
        // A polynomial surface in rational form is reproduced exactly.
        let net = c.net().clone();
        let flat = RationalSurface::new(net.clone(), vec![2.0; 6]).unwrap();
        assert!(flat.is_polynomial());
        let s = flat.polynomial(FitTolerance::default()).unwrap();
        assert!(s.position < 1e-15, "{}", s.position);
        assert_eq!(s.surface.knots(), net.knots());
    }

    /// One span along the arc: the degree rises until the tolerance holds
    /// (a quarter circle of radius 1 within 1e-6: degree 10; tighter needs
    /// more), the sides within it by the measure and, independently, by
    /// the circle; a net of two spans there is refused by name.
    #[test]
    fn a_one_span_stand_in_raises_its_degree() {
        let c = quarter_cylinder(1.0, 1.0);
        let one = c
            .polynomial_spans(FitTolerance::default(), [true, false])
            .unwrap();
        assert_eq!(one.surface.knots().0.spans().len(), 1);
        assert_eq!(one.surface.degree(), (10, 1));
        assert!(one.position <= 1e-6 && one.angle <= 0.01f64.to_radians());
        let tight = FitTolerance {
            position: 1e-8,
            angle: 1e-6,
        };
        let t = c.polynomial_spans(tight, [true, false]).unwrap();
        // Degree 15 reaches ~1e-9: 1e-10 is refused, saying how far it got.
        let e = c
            .polynomial_spans(
                FitTolerance {
                    position: 1e-10,
                    angle: 1e-8,
                },
                [true, false],
            )
            .unwrap_err();
        assert!(e.to_string().contains("one span of degree 15 in u"), "{e}");
        assert!(
            t.surface.degree().0 > 10 && t.surface.degree().0 <= ONE_SPAN_DEGREE,
            "{:?}",
            t.surface.degree()
        );
        for s in [&one, &t] {
            let tol = if std::ptr::eq(s, &one) { 1e-6 } else { 1e-8 };
            for k in 0..=200 {
                let p = s.surface.eval(k as f64 / 200.0, 0.0);
                assert!((p[0].hypot(p[2]) - 1.0).abs() <= tol, "{p:?}");
            }
        }
        // A half cylinder as two rational spans: not one piece.
        let u = KnotVector::new(2, vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0]).unwrap();
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let arc = [[1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [-1.0, 1.0], [-1.0, 0.0]];
        let points: Vec<Vec3> = arc
            .iter()
            .flat_map(|a| [[a[0], 0.0, a[1]], [a[0], 1.0, a[1]]])
            .collect();
        let weights = [1.0, r, 1.0, r, 1.0].iter().flat_map(|&w| [w, w]).collect();
        let half = RationalSurface::new(
            BSplineSurface::new(u, KnotVector::bezier(1), points).unwrap(),
            weights,
        )
        .unwrap();
        assert!(half.polynomial(FitTolerance::default()).is_ok());
        let e = half
            .polynomial_spans(FitTolerance::default(), [true, false])
            .unwrap_err();
        assert!(e.to_string().contains("of 2 spans in u"), "{e}");
    }

    /// A net only C¹ at an interior knot: the stand-in keeps that knot
    /// (multiplicity d − p + 1 = 4 at degree 5) and so needs few pieces.
    #[test]
    fn a_stand_in_keeps_the_nets_knots() {
        let u = KnotVector::new(2, vec![0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0]).unwrap();
        let points: Vec<Vec3> = (0..8)
            .map(|k| {
                let (i, j) = ((k / 2) as f64, (k % 2) as f64);
                [i, j, 0.4 * (i * 1.3).sin() + 0.1 * j]
            })
            .collect();
        let net = BSplineSurface::new(u, KnotVector::bezier(1), points).unwrap();
        let r = RationalSurface::new(net, vec![1.0, 1.0, 0.8, 0.8, 1.1, 1.1, 0.9, 0.9]).unwrap();
        let s = r.polynomial(FitTolerance::default()).unwrap();
        let ku = s.surface.knots().0;
        assert_eq!((ku.degree(), ku.multiplicity(0.3)), (5, 4));
        assert!(ku.spans().len() <= 20, "{}", ku.spans().len());
        assert!(s.position <= 1e-6 && s.angle <= 0.01f64.to_radians());
    }

    #[test]
    fn bad_weights_are_refused() {
        let net = quarter_cylinder(1.0, 1.0).net().clone();
        assert!(RationalSurface::new(net.clone(), vec![1.0; 5]).is_err());
        let e = RationalSurface::new(net, vec![1.0, 1.0, 0.0, 1.0, 1.0, 1.0])
            .unwrap_err()
            .to_string();
        assert!(e.contains("weight (1, 0) is 0"), "{e}");
    }
}
