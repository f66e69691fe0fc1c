//! Derivatives of a triangular Bézier patch (Farin 1993; Veltkamp &
//! Wesselink §2).
//!
//! A direction in the domain is a triple d = (d_u, d_v, d_w) with
//! d_u + d_v + d_w = 0 (the difference of two barycentric points). The
//! directional derivatives are blossom values, i.e. de Casteljau's algorithm
//! with d in place of (u, v, w) at one level:
//!
//! ```text
//! D_d T(x)     = n b(d, x, …, x)         = n Σ_{|λ|=n−1} (d_u P_{λ+e₁} + d_v P_{λ+e₂} + d_w P_{λ+e₃}) B_λ^{n−1}(x)
//! D_d D_e T(x) = n(n−1) b(d, e, x, …, x)
//! ```
//!
//! With the two free parameters (u, v) and w = 1 − u − v, the parametric
//! derivatives are the directional ones along e_u = (1, 0, −1) and
//! e_v = (0, 1, −1):
//!
//! ```text
//! T_u = D_{e_u} T,  T_v = D_{e_v} T,  T_uu = D_{e_u}D_{e_u} T,  T_uv = D_{e_u}D_{e_v} T,  T_vv = D_{e_v}D_{e_v} T
//! D_d T = d_u T_u + d_v T_v,   D_d D_e T = d_u e_u T_uu + (d_u e_v + d_v e_u) T_uv + d_v e_v T_vv.
//! ```
//!
//! In the (u, v) parameters T_u points from V₃ towards V₁ and T_v from V₃
//! towards V₂, so the normal T_u × T_v is that of the triangle V₁V₂V₃.

use super::bernstein::Bary;
use super::patch::{de_casteljau_step, TriPatch};
use crate::vec3::{add, cross, normalize, scale, Vec3};
use crate::SurfaceDerivatives;

/// The direction of ∂/∂u when w = 1 − u − v.
const E_U: Bary = [1.0, 0.0, -1.0];
/// The direction of ∂/∂v when w = 1 − u − v.
const E_V: Bary = [0.0, 1.0, -1.0];

impl TriPatch {
    /// T and its derivatives with respect to (u, v), w = 1 − u − v, at the
    /// barycentric point b: n − 2 de Casteljau levels at b, then the last two
    /// levels with b, e_u or e_v. The same type as a tensor patch's, so the
    /// curvature analysis applies unchanged:
    ///
    /// ```
    /// use fairsurf::{analysis::curvature_from, TriPatch};
    /// // z = (x² + y²)/2 over the triangle (0,0), (1,0), (0,1), written with
    /// // x = u, y = v; at the corner V₃ (the origin) K = 1 and H = 1.
    /// let t = TriPatch::from_fn(2, |i, j, _k| {
    ///     let z = [0.0, 0.0, 0.5][i] + [0.0, 0.0, 0.5][j];
    ///     [i as f64 / 2.0, j as f64 / 2.0, z]
    /// });
    /// let c = curvature_from(&t.derivatives([0.0, 0.0, 1.0])).unwrap();
    /// assert!((c.gaussian - 1.0).abs() < 1e-14 && (c.mean - 1.0).abs() < 1e-14);
    /// ```
    pub fn derivatives(&self, b: Bary) -> SurfaceDerivatives {
        let n = self.degree();
        let zero = [0.0; 3];
        match n {
            0 => SurfaceDerivatives {
                point: self.points()[0],
                du: zero,
                dv: zero,
                duu: zero,
                duv: zero,
                dvv: zero,
            },
            1 => {
                let net = self.points();
                SurfaceDerivatives {
                    point: de_casteljau_step(net, 1, b)[0],
                    du: de_casteljau_step(net, 1, E_U)[0],
                    dv: de_casteljau_step(net, 1, E_V)[0],
                    duu: zero,
                    duv: zero,
                    dvv: zero,
                }
            }
            _ => {
                let q = self.reduce_to(b, 2);
                let last =
                    |x: Bary, y: Bary| de_casteljau_step(&de_casteljau_step(&q, 2, x), 1, y)[0];
                let (n1, n2) = (n as f64, (n * (n - 1)) as f64);
                SurfaceDerivatives {
                    point: last(b, b),
                    du: scale(last(b, E_U), n1),
                    dv: scale(last(b, E_V), n1),
                    duu: scale(last(E_U, E_U), n2),
                    duv: scale(last(E_U, E_V), n2),
                    dvv: scale(last(E_V, E_V), n2),
                }
            }
        }
    }

    /// The directional derivative D_d T at the barycentric point b, for a
    /// direction d with d_u + d_v + d_w = 0: `n b(d, b, …, b)`.
    pub fn directional_derivative(&self, b: Bary, d: Bary) -> Vec3 {
        let n = self.degree();
        if n == 0 {
            return [0.0; 3];
        }
        let q = self.reduce_to(b, 1);
        scale(de_casteljau_step(&q, 1, d)[0], n as f64)
    }

    /// The second directional derivative D_d D_e T at the barycentric point
    /// b, for directions d and e (each summing to 0): `n(n−1) b(d, e, b, …, b)`.
    /// Symmetric in d and e.
    pub fn second_directional_derivative(&self, b: Bary, d: Bary, e: Bary) -> Vec3 {
        let n = self.degree();
        if n < 2 {
            return [0.0; 3];
        }
        let q = self.reduce_to(b, 2);
        let r = de_casteljau_step(&de_casteljau_step(&q, 2, d), 1, e)[0];
        scale(r, (n * (n - 1)) as f64)
    }

    /// T, T_u and T_v at the barycentric point b (the first three of
    /// [`derivatives`](Self::derivatives), from one de Casteljau reduction
    /// to degree 1 instead of 2).
    pub(crate) fn tangents(&self, b: Bary) -> [Vec3; 3] {
        let n = self.degree();
        if n == 0 {
            return [self.points()[0], [0.0; 3], [0.0; 3]];
        }
        let q = self.reduce_to(b, 1);
        let at = |x: Bary| add(add(scale(q[0], x[0]), scale(q[1], x[1])), scale(q[2], x[2]));
        [at(b), scale(at(E_U), n as f64), scale(at(E_V), n as f64)]
    }

    /// The unit normal T_u × T_v / |T_u × T_v| at the barycentric point b, or
    /// `None` where the patch is not regular (T_u × T_v = 0, e.g. at a corner
    /// whose two neighbouring control points coincide with it).
    pub fn normal(&self, b: Bary) -> Option<Vec3> {
        if self.degree() == 0 {
            return None;
        }
        let q = self.reduce_to(b, 1);
        // One linear level: Σ x_c q_c (the degree-1 net's three points).
        let at = |x: Bary| add(add(scale(q[0], x[0]), scale(q[1], x[1])), scale(q[2], x[2]));
        normalize(cross(at(E_U), at(E_V)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::{add, norm, sub};

    /// [`TriPatch::tangents`] are [`TriPatch::derivatives`]' first three,
    /// at degrees 0 to 5 and inside, on a side and at a corner.
    #[test]
    fn tangents_are_the_first_derivatives() {
        for n in 0..=5 {
            let t = TriPatch::from_fn(n, |i, j, k| {
                let (x, y, z) = (i as f64, j as f64, k as f64);
                [x + 0.3 * y * y, y - 0.2 * x * z, (x * y + z).sin()]
            });
            for b in [[0.2, 0.3, 0.5], [0.0, 0.6, 0.4], [1.0, 0.0, 0.0]] {
                let d = t.derivatives(b);
                for (x, y) in t.tangents(b).iter().zip([d.point, d.du, d.dv]) {
                    assert!(norm(sub(*x, y)) <= 1e-12 * (1.0 + norm(y)), "{n} {b:?}");
                }
            }
        }
    }

    fn wavy(n: usize) -> TriPatch {
        TriPatch::from_fn(n, |i, j, k| {
            let (x, y, z) = (
                i as f64 / n as f64,
                j as f64 / n as f64,
                k as f64 / n as f64,
            );
            [
                x + 0.2 * z * y,
                y + 0.1 * x * x,
                (2.0 * x - y + 3.0 * z).cos(),
            ]
        })
    }

    fn close(a: Vec3, b: Vec3, tol: f64) -> bool {
        norm(sub(a, b)) <= tol * (1.0 + norm(b))
    }

    #[test]
    fn directional_derivatives_combine_the_parametric_ones() {
        for n in 1..7 {
            let t = wavy(n);
            let x = [0.3, 0.25, 0.45];
            let p = t.derivatives(x);
            let (d, e) = ([0.4, -1.0, 0.6], [-0.3, 0.1, 0.2]);
            let dd = add(scale(p.du, d[0]), scale(p.dv, d[1]));
            assert!(close(t.directional_derivative(x, d), dd, 1e-14));
            let de = add(
                add(
                    scale(p.duu, d[0] * e[0]),
                    scale(p.duv, d[0] * e[1] + d[1] * e[0]),
                ),
                scale(p.dvv, d[1] * e[1]),
            );
            assert!(close(t.second_directional_derivative(x, d, e), de, 1e-13));
            assert!(close(t.second_directional_derivative(x, e, d), de, 1e-13));
        }
    }

    #[test]
    fn parametric_derivatives_match_finite_differences() {
        let h = 1e-5;
        for n in 1..6 {
            let t = wavy(n);
            let (u, v) = (0.35, 0.2);
            let at = |u: f64, v: f64| t.derivatives([u, v, 1.0 - u - v]);
            let d = at(u, v);
            let fd = |a: Vec3, b: Vec3| scale(sub(a, b), 0.5 / h);
            let (up, um, vp, vm) = (at(u + h, v), at(u - h, v), at(u, v + h), at(u, v - h));
            assert!(close(fd(up.point, um.point), d.du, 1e-9));
            assert!(close(fd(vp.point, vm.point), d.dv, 1e-9));
            assert!(close(fd(up.du, um.du), d.duu, 1e-8));
            assert!(close(fd(vp.du, vm.du), d.duv, 1e-8));
            assert!(close(fd(up.dv, um.dv), d.duv, 1e-8));
            assert!(close(fd(vp.dv, vm.dv), d.dvv, 1e-8));
        }
    }

    #[test]
    fn a_collapsed_corner_has_no_normal() {
        // P_n00, P_{n−1,1,0} and P_{n−1,0,1} coincide: T_u = T_v = 0 at V₁.
        let mut t = wavy(3);
        let c = t.point(3, 0, 0);
        t.set_point(2, 1, 0, c);
        t.set_point(2, 0, 1, c);
        assert_eq!(t.normal([1.0, 0.0, 0.0]), None);
        assert_eq!(t.derivatives([1.0, 0.0, 0.0]).normal(), None);
        assert!(t.normal([0.5, 0.25, 0.25]).is_some());
    }

    #[test]
    fn low_degrees_have_zero_higher_derivatives() {
        let t0 = TriPatch::new(0, vec![[1.0, 1.0, 1.0]]);
        let d = t0.derivatives([0.2, 0.3, 0.5]);
        assert_eq!((d.point, d.du, d.duu), ([1.0; 3], [0.0; 3], [0.0; 3]));
        assert_eq!(t0.normal([0.2, 0.3, 0.5]), None);
        let t1 = wavy(1);
        let d = t1.derivatives([0.2, 0.3, 0.5]);
        assert_eq!(d.du, sub(t1.point(1, 0, 0), t1.point(0, 0, 1)));
        assert_eq!(d.dv, sub(t1.point(0, 1, 0), t1.point(0, 0, 1)));
        assert_eq!([d.duu, d.duv, d.dvv], [[0.0; 3]; 3]);
        let x = [0.2, 0.3, 0.5];
        assert_eq!(t1.second_directional_derivative(x, E_U, E_V), [0.0; 3]);
    }
}
