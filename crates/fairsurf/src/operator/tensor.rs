//! Where external energy operators act on a tensor-product patch: a point
//! (u₀, v₀), a convex region of the parameter square, or a boundary edge.
//!
//! The energies are those of [`super`] with the tensor basis
//! B_i^n(u)·B_j^m(v); regions are measured in the patch's own parameters
//! (dA = du dv over [0, 1]², like the internal energies of Wu & Yang eq.
//! 1–2) and integrated exactly by the trapezoids of Veltkamp & Wesselink
//! eq. 28; the director uses S_u·N and S_v·N (eq. 13–14 with the square's
//! orthonormal directions u and v).

use super::{Operator, OperatorOutcome, Residual, Tally, Target};
use crate::basis::bernstein_derivatives;
use crate::basis::polygon::{convex, trapezoid_rule, Uv};
use crate::{BezierCurve, Result, TensorPatch};

/// Where an operator acts on a tensor-product patch of degree (n, m).
#[derive(Clone, Debug, PartialEq)]
pub enum TensorPlace {
    /// One surface point (u₀, v₀) ∈ [0, 1]².
    Point([f64; 2]),
    /// A convex polygon in the parameter square [0, 1]², vertices (u, v).
    Region(Vec<Uv>),
    /// A boundary curve of the patch (for the edge-to-curve attractor).
    Edge(PatchEdge),
}

/// A boundary curve of a tensor-product patch, with the direction the
/// curve's parameter t runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatchEdge {
    /// u = 0: control points P_0j, t = v.
    U0,
    /// u = 1: control points P_nj, t = v.
    U1,
    /// v = 0: control points P_i0, t = u.
    V0,
    /// v = 1: control points P_im, t = u.
    V1,
}

impl PatchEdge {
    /// The indices (row-major, i·(m+1) + j) of the edge's control points in
    /// the order of its parameter.
    pub fn points(self, (n, m): (usize, usize)) -> Vec<usize> {
        match self {
            PatchEdge::U0 => (0..=m).collect(),
            PatchEdge::U1 => (0..=m).map(|j| n * (m + 1) + j).collect(),
            PatchEdge::V0 => (0..=n).map(|i| i * (m + 1)).collect(),
            PatchEdge::V1 => (0..=n).map(|i| i * (m + 1) + m).collect(),
        }
    }
}

/// An operator on a tensor-product patch.
pub type TensorOperator = Operator<TensorPlace>;

/// Quadrature nodes (u, v, weight), or an edge's point indices.
#[derive(Clone, Debug)]
pub(crate) struct TensorLocated {
    nodes: Vec<(f64, f64, f64)>,
    edge: Option<Vec<usize>>,
}

impl Operator<TensorPlace> {
    /// Checks the operator: strength, target, place, and that they fit
    /// together; errors name the operator.
    pub fn validate(&self) -> Result<()> {
        self.check_target()?;
        let inside = |uv: Uv| {
            (-1e-12..=1.0 + 1e-12).contains(&uv[0]) && (-1e-12..=1.0 + 1e-12).contains(&uv[1])
        };
        match (&self.place, &self.target) {
            (_, Target::Surface(_)) => {
                return Err(self.bad(
                    "surface",
                    "a tensor-product patch (a triangular attractor surface is for triangular surfaces)",
                    "a triangular patch".into(),
                ))
            }
            (TensorPlace::Edge(_), Target::Curve(_)) => {}
            (_, Target::Curve(_)) => {
                return Err(self.bad(
                    "place",
                    "an edge (edge-to-curve attractor)",
                    "not an edge".into(),
                ))
            }
            (TensorPlace::Edge(_), _) => {
                return Err(self.bad("place", "a point or a region", "an edge".into()))
            }
            _ => {}
        }
        match &self.place {
            TensorPlace::Point(uv) if !inside(*uv) => {
                return Err(self.bad("point", "(u, v) in [0, 1]²", format!("{uv:?}")))
            }
            TensorPlace::Region(polygon) => {
                let p = convex(polygon, &format!("{}: region", self.name))?;
                if let Some(uv) = p.iter().find(|uv| !inside(**uv)) {
                    return Err(self.bad(
                        "region",
                        "vertices (u, v) in [0, 1]²",
                        format!("{uv:?}"),
                    ));
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// The quadrature nodes for a patch of degree (n, m) (validated).
    pub(crate) fn locate(&self, (n, m): (usize, usize)) -> Result<TensorLocated> {
        // The residual is a polynomial of total degree ≤ n + m (or T's).
        let total = match &self.target {
            Target::TensorSurface(t) => (n + m).max(t.degree().0 + t.degree().1),
            _ => n + m,
        };
        Ok(match &self.place {
            TensorPlace::Point(uv) => TensorLocated {
                nodes: vec![(uv[0], uv[1], 1.0)],
                edge: None,
            },
            TensorPlace::Region(polygon) => TensorLocated {
                nodes: trapezoid_rule(&convex(polygon, &self.name)?, 2 * total)
                    .into_iter()
                    .map(|(p, w)| (p[0], p[1], w))
                    .collect(),
                edge: None,
            },
            TensorPlace::Edge(e) => TensorLocated {
                nodes: Vec::new(),
                edge: Some(e.points((n, m))),
            },
        })
    }

    /// The scalar residuals for a patch of degree (n, m), over coordinates
    /// 3p + c of the row-major control points.
    pub(crate) fn residuals(&self, at: &TensorLocated, (n, m): (usize, usize)) -> Vec<Residual> {
        let mut out = Vec::new();
        if let Some(pts) = &at.edge {
            self.edge_residuals(pts, &mut out);
            return out;
        }
        let points: Vec<usize> = (0..(n + 1) * (m + 1)).collect();
        for &(u, v, w) in &at.nodes {
            let bu = bernstein_derivatives(n, u, 1);
            let bv = bernstein_derivatives(m, v, 1);
            self.tensor_node_residuals(w, &points, (&bu, &bv), self.surface_point(u, v), &mut out);
        }
        out
    }

    fn surface_point(&self, u: f64, v: f64) -> Option<crate::Vec3> {
        match &self.target {
            Target::TensorSurface(t) => Some(t.eval(u, v)),
            _ => None,
        }
    }

    /// Its outcome on the solved patch, given its [`Self::residuals`] and
    /// the coordinates x (3p + c).
    pub(crate) fn outcome(
        &self,
        at: &TensorLocated,
        residuals: &[Residual],
        patch: &TensorPatch,
        x: &[f64],
    ) -> OperatorOutcome {
        let mut tally = Tally::new(self);
        if let Some(pts) = &at.edge {
            let edge = BezierCurve::new(pts.iter().map(|&p| patch.points()[p]).collect());
            tally.edge(self, &edge);
        }
        for &(u, v, w) in &at.nodes {
            tally.node(
                self,
                w,
                patch.eval(u, v),
                patch.normal(u, v),
                self.surface_point(u, v),
            );
        }
        tally.finish(self, self.energy(residuals, x))
    }
}
