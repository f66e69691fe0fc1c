//! Where external energy operators act on a B-spline surface: a point
//! (u₀, v₀) of the knot domain, or a convex region of it.
//!
//! The energies are those of [`super`] with the basis N_i,p(u)·N_j,q(v);
//! regions are measured in the knot domain's parameters (dA = du dv, like
//! the internal energies) and integrated exactly: the region is clipped to
//! each knot span's rectangle, where the integrand is one polynomial, and
//! each piece integrated by the trapezoids of Veltkamp & Wesselink eq. 28.
//! The director uses S_u·N and S_v·N (eq. 13–14 with the domain's
//! orthonormal directions u and v). A surface target T is a Bézier patch
//! over the knot domain mapped onto [0, 1]² (as the normal field is).
//! An edge-to-curve attractor pulls a boundary curve E of the surface (a
//! B-spline curve) toward a Bézier curve C over the edge's parameter
//! interval mapped onto [0, 1]: ∫₀¹ |E(τ) − C(τ)|² dτ (τ the mapped
//! parameter, so that without interior knots it is the Bézier patch's
//! energy), Gauss–Legendre on every span of the edge, exact. Repellors
//! (s/E_attr) go through Newton's method like the other kinds'.

use super::{Operator, OperatorOutcome, PatchEdge, Residual, Tally, Target, TensorPlace};
use crate::basis::polygon::{convex, trapezoid_rule, Uv};
use crate::basis::GaussLegendre;
use crate::bspline::BSplineSurface;
use crate::Result;

/// The highest degree of a surface attractor's target on a B-spline (the
/// region rules grow with it: degree 40 took 11 s on a unit region).
const MAX_TARGET_DEGREE: usize = 15;

/// Quadrature nodes (u, v, weight) of the knot domain.
pub(crate) type Nodes = Vec<(f64, f64, f64)>;

/// The part of a convex polygon (counter-clockwise) on the side of the
/// line `coordinate[axis] = bound` where `keep` holds (Sutherland–Hodgman).
fn clip(polygon: &[Uv], axis: usize, bound: f64, below: bool) -> Vec<Uv> {
    let inside = |p: &Uv| {
        if below {
            p[axis] <= bound
        } else {
            p[axis] >= bound
        }
    };
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for k in 0..polygon.len() {
        let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
        if inside(&a) {
            out.push(a);
        }
        if inside(&a) != inside(&b) {
            let t = (bound - a[axis]) / (b[axis] - a[axis]);
            let mut p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            p[axis] = bound;
            out.push(p);
        }
    }
    out
}

/// Twice the signed area of a polygon.
fn area2(p: &[Uv]) -> f64 {
    (0..p.len())
        .map(|k| {
            let (a, b) = (p[k], p[(k + 1) % p.len()]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum()
}

impl Operator<TensorPlace> {
    /// The map from the knot domain onto [0, 1]² (for a surface target).
    fn unit(s: &BSplineSurface, u: f64, v: f64) -> (f64, f64) {
        let ((u0, u1), (v0, v1)) = (s.knots().0.domain(), s.knots().1.domain());
        ((u - u0) / (u1 - u0), (v - v0) / (v1 - v0))
    }

    /// Checks the operator on a B-spline surface: strength and target, a
    /// place in the knot domain, a curve target exactly at an edge; refuses
    /// triangular surface targets.
    pub fn validate_on(&self, s: &BSplineSurface) -> Result<()> {
        self.check_target()?;
        if let Target::TensorSurface(t) = &self.target {
            let (n, m) = t.degree();
            if n.max(m) > MAX_TARGET_DEGREE {
                return Err(self.bad(
                    "surface",
                    &format!("a target patch of degree at most {MAX_TARGET_DEGREE} each way"),
                    format!("degree ({n}, {m})"),
                ));
            }
        }
        match (&self.target, &self.place) {
            (Target::Surface(_), _) => {
                return Err(self.bad(
                    "surface",
                    "a tensor Bézier patch over the knot domain (a triangular attractor surface \
                     is for triangular surfaces)",
                    "a triangular patch".into(),
                ))
            }
            (Target::Curve(_), TensorPlace::Edge(_)) => return Ok(()),
            (Target::Curve(_), _) => {
                return Err(self.bad(
                    "place",
                    "an edge (edge-to-curve attractor)",
                    "not an edge".into(),
                ))
            }
            (_, TensorPlace::Edge(_)) => {
                return Err(self.bad("place", "a point or a region", "an edge".into()))
            }
            _ => {}
        }
        let ((u0, u1), (v0, v1)) = (s.knots().0.domain(), s.knots().1.domain());
        let inside = |uv: &Uv| {
            let slack = 1e-12 * (u1 - u0).max(v1 - v0).max(1.0);
            (u0 - slack..=u1 + slack).contains(&uv[0]) && (v0 - slack..=v1 + slack).contains(&uv[1])
        };
        let expected = format!("(u, v) in the knot domain [{u0}, {u1}] × [{v0}, {v1}]");
        match &self.place {
            TensorPlace::Point(uv) if !inside(uv) => {
                Err(self.bad("point", &expected, format!("{uv:?}")))
            }
            TensorPlace::Region(polygon) => {
                let p = convex(polygon, &format!("{}: region", self.name))?;
                match p.iter().find(|uv| !inside(uv)) {
                    Some(uv) => Err(self.bad("region", &expected, format!("{uv:?}"))),
                    None => Ok(()),
                }
            }
            _ => Ok(()),
        }
    }

    /// The quadrature nodes on `s` (validated): the point, or the region
    /// clipped to every knot span's rectangle, each piece integrated by a
    /// rule exact for the residuals' squares there.
    pub(crate) fn locate_on(&self, s: &BSplineSurface) -> Result<Nodes> {
        let (p, q) = s.degree();
        let total = match &self.target {
            Target::TensorSurface(t) => (p + q).max(t.degree().0 + t.degree().1),
            _ => p + q,
        };
        Ok(match &self.place {
            TensorPlace::Point(uv) => vec![(uv[0], uv[1], 1.0)],
            TensorPlace::Region(polygon) => {
                let polygon = convex(polygon, &self.name)?;
                let (ku, kv) = s.knots();
                let mut nodes = Vec::new();
                for &(_, a, b) in &ku.spans() {
                    let strip = clip(&clip(&polygon, 0, a, false), 0, b, true);
                    if strip.len() < 3 {
                        continue;
                    }
                    for &(_, c, d) in &kv.spans() {
                        let piece = clip(&clip(&strip, 1, c, false), 1, d, true);
                        if piece.len() < 3 || area2(&piece) <= 0.0 {
                            continue;
                        }
                        nodes.extend(
                            trapezoid_rule(&piece, 2 * total)
                                .into_iter()
                                .map(|(x, w)| (x[0], x[1], w)),
                        );
                    }
                }
                nodes
            }
            TensorPlace::Edge(e) => {
                let Target::Curve(c) = &self.target else {
                    unreachable!("validate_on pairs an edge with a curve")
                };
                // |E − C|² has degree ≤ 2·max(p, deg C) on every span of
                // the edge: max(p, deg C) + 1 Gauss nodes are exact.
                let (ku, kv) = s.knots();
                let ((u0, u1), (v0, v1)) = (ku.domain(), kv.domain());
                let (along, fixed) = match e {
                    PatchEdge::U0 => (kv, (0, u0)),
                    PatchEdge::U1 => (kv, (0, u1)),
                    PatchEdge::V0 => (ku, (1, v0)),
                    PatchEdge::V1 => (ku, (1, v1)),
                };
                let (a, b) = along.domain();
                let g = GaussLegendre::new(along.degree().max(c.degree()) + 1);
                let mut nodes = Vec::new();
                for &(_, lo, hi) in &along.spans() {
                    for (x, wx) in g.nodes.iter().zip(&g.weights) {
                        let t = lo + (hi - lo) * x;
                        let w = wx * (hi - lo) / (b - a);
                        nodes.push(match fixed {
                            (0, u) => (u, t, w),
                            (_, v) => (t, v, w),
                        });
                    }
                }
                nodes
            }
        })
    }

    /// The scalar residuals on `s` at `nodes`, over coordinates 3g + c of
    /// the row-major control points.
    pub(crate) fn residuals_on(&self, nodes: &Nodes, s: &BSplineSurface) -> Vec<Residual> {
        let ((p, q), (_, cv)) = (s.degree(), s.counts());
        let (ku, kv) = s.knots();
        let mut out = Vec::new();
        for &(u, v, w) in nodes {
            let (su, sv) = (ku.span(u), kv.span(v));
            let bu = ku.basis_derivatives(su, u, 1);
            let bv = kv.basis_derivatives(sv, v, 1);
            let points: Vec<usize> = (0..=p)
                .flat_map(|i| (0..=q).map(move |j| (su - p + i) * cv + sv - q + j))
                .collect();
            let t = self.target_point(s, u, v);
            self.tensor_node_residuals(w, &points, (&bu, &bv), t, &mut out);
        }
        out
    }

    /// T at the node for a surface target; C at the node's mapped edge
    /// parameter τ for a curve target.
    fn target_point(&self, s: &BSplineSurface, u: f64, v: f64) -> Option<crate::Vec3> {
        let (a, b) = Self::unit(s, u, v);
        match (&self.target, &self.place) {
            (Target::TensorSurface(t), _) => Some(t.eval(a, b)),
            (Target::Curve(c), TensorPlace::Edge(PatchEdge::U0 | PatchEdge::U1)) => Some(c.eval(b)),
            (Target::Curve(c), _) => Some(c.eval(a)),
            _ => None,
        }
    }

    /// Its outcome on the solved surface, given its residuals and the
    /// coordinates x (3g + c): the measure from evaluating the surface.
    pub(crate) fn outcome_on(
        &self,
        nodes: &Nodes,
        residuals: &[Residual],
        s: &BSplineSurface,
        x: &[f64],
    ) -> OperatorOutcome {
        let mut tally = Tally::new(self);
        for &(u, v, w) in nodes {
            tally.node(
                self,
                w,
                s.eval(u, v),
                s.normal(u, v),
                self.target_point(s, u, v),
            );
        }
        if let TensorPlace::Edge(e) = &self.place {
            // The edge's midpoint, as on a Bézier patch.
            let ((u0, u1), (v0, v1)) = (s.knots().0.domain(), s.knots().1.domain());
            let (um, vm) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
            tally.mark_at(match e {
                PatchEdge::U0 => s.eval(u0, vm),
                PatchEdge::U1 => s.eval(u1, vm),
                PatchEdge::V0 => s.eval(um, v0),
                PatchEdge::V1 => s.eval(um, v1),
            });
        }
        tally.finish(self, self.energy(residuals, x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bspline::KnotVector;

    /// A surface over 3 × 2 spans of the knot domain [0, 2] × [0, 1].
    fn sheet() -> BSplineSurface {
        let (u, v) = (
            KnotVector::new(3, vec![0., 0., 0., 0., 0.5, 1.2, 2., 2., 2., 2.]).unwrap(),
            KnotVector::new(2, vec![0., 0., 0., 0.4, 1., 1., 1.]).unwrap(),
        );
        let n = u.count() * v.count();
        BSplineSurface::new(u, v, vec![[0.0; 3]; n]).unwrap()
    }

    fn nodes(region: Vec<Uv>) -> Nodes {
        let op = Operator {
            name: "t".into(),
            target: Target::Point([0.0; 3]),
            place: TensorPlace::Region(region),
            strength: 1.0,
            repel: false,
        };
        op.validate_on(&sheet()).unwrap();
        op.locate_on(&sheet()).unwrap()
    }

    #[test]
    fn clipped_pieces_integrate_piecewise_polynomials_exactly() {
        // Truncated powers kink at the knots 0.5 and 1.2 (u) and 0.4 (v):
        // one polynomial per span, as a B-spline integrand is. Over the
        // rectangle [0.1, 1.9] × [0.1, 0.9] their integrals are closed forms.
        let rect = nodes(vec![[0.1, 0.1], [1.9, 0.1], [1.9, 0.9], [0.1, 0.9]]);
        let sum = |f: &dyn Fn(f64, f64) -> f64| -> f64 {
            rect.iter().map(|&(u, v, w)| w * f(u, v)).sum()
        };
        let plus = |x: f64| x.max(0.0);
        assert!((sum(&|_, _| 1.0) - 1.8 * 0.8).abs() < 1e-14);
        let want = 1.4f64.powi(3) / 3.0 * (0.5f64.powi(2) / 2.0);
        let got = sum(&|u, v| plus(u - 0.5).powi(2) * plus(v - 0.4));
        assert!((got - want).abs() < 1e-14 * want, "{got} vs {want}");
        let want = 0.8 * 0.7f64.powi(4) / 4.0;
        let got = sum(&|u, _| plus(u - 1.2).powi(3));
        assert!((got - want).abs() < 1e-14 * want, "{got} vs {want}");
        // A triangle across the knot lines: its area and centroid.
        let [a, b, c] = [[0.1, 0.1], [1.9, 0.2], [0.6, 0.9]];
        let tri = nodes(vec![a, b, c]);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
        let total: f64 = tri.iter().map(|n| n.2).sum();
        let ubar: f64 = tri.iter().map(|n| n.2 * n.0).sum::<f64>() / area;
        assert!((total - area).abs() < 1e-15);
        assert!((ubar - (a[0] + b[0] + c[0]) / 3.0).abs() < 1e-14);
    }

    #[test]
    fn places_outside_the_knot_domain_and_unsupported_kinds_are_refused() {
        let s = sheet();
        let op = |target, place, repel| Operator {
            name: "op".into(),
            target,
            place,
            strength: 1.0,
            repel,
        };
        let far = op(
            Target::Point([0.0; 3]),
            TensorPlace::Point([2.5, 0.5]),
            false,
        );
        let e = far.validate_on(&s).unwrap_err().to_string();
        assert!(
            e.contains("op") && e.contains("knot domain [0, 2] × [0, 1]"),
            "{e}"
        );
        let push = op(
            Target::Point([0.0; 3]),
            TensorPlace::Point([0.5, 0.5]),
            true,
        );
        push.validate_on(&s).unwrap();
        let turn = op(
            Target::Direction([0.0, 0.0, 1.0]),
            TensorPlace::Point([0.5, 0.5]),
            true,
        );
        assert!(turn
            .validate_on(&s)
            .unwrap_err()
            .to_string()
            .contains("director"));
        let curve = || Target::Curve(crate::BezierCurve::new(vec![[0.0; 3], [1.0; 3]]));
        op(curve(), TensorPlace::Edge(PatchEdge::U0), false)
            .validate_on(&s)
            .unwrap();
        let off = op(curve(), TensorPlace::Point([0.5, 0.5]), false);
        let e = off.validate_on(&s).unwrap_err().to_string();
        assert!(e.contains("an edge") && e.contains("not an edge"), "{e}");
        let pin = op(
            Target::Point([0.0; 3]),
            TensorPlace::Edge(PatchEdge::V1),
            false,
        );
        let e = pin.validate_on(&s).unwrap_err().to_string();
        assert!(e.contains("a point or a region"), "{e}");
    }

    #[test]
    fn edge_nodes_integrate_along_the_edge_in_the_mapped_parameter() {
        // Along u (knots 0, 0.5, 1.2, 2 on [0, 2]) with a cubic curve: the
        // weights sum to 1 (dτ over [0, 1]) and integrate τ⁷ exactly
        // (degree 2·max(p, deg C) + 1 = 7 per span).
        let c = crate::BezierCurve::new(vec![[0.0; 3], [1.0; 3], [2.0; 3], [3.0; 3]]);
        let s = sheet();
        for edge in [PatchEdge::V0, PatchEdge::V1, PatchEdge::U0, PatchEdge::U1] {
            let op = Operator {
                name: "e".into(),
                target: Target::Curve(c.clone()),
                place: TensorPlace::Edge(edge),
                strength: 1.0,
                repel: false,
            };
            let nodes = op.locate_on(&s).unwrap();
            let (along_u, fixed) = match edge {
                PatchEdge::V0 => (true, 0.0),
                PatchEdge::V1 => (true, 1.0),
                PatchEdge::U0 => (false, 0.0),
                PatchEdge::U1 => (false, 2.0),
            };
            let tau = |&(u, v, _): &(f64, f64, f64)| if along_u { u / 2.0 } else { v };
            assert!(nodes
                .iter()
                .all(|n| if along_u { n.1 == fixed } else { n.0 == fixed }));
            let total: f64 = nodes.iter().map(|n| n.2).sum();
            assert!((total - 1.0).abs() < 1e-15, "{edge:?}: {total}");
            let m7: f64 = nodes.iter().map(|n| n.2 * tau(n).powi(7)).sum();
            assert!((m7 - 1.0 / 8.0).abs() < 1e-15, "{edge:?}: {m7}");
        }
    }
}
