//! External energy operators (Veltkamp & Wesselink §5, §6.1): directors,
//! attractors to a point, plane, line, surface or curve, and repellors —
//! the parts shared by triangular surfaces ([`crate::triangle::Place`]) and
//! tensor-product patches ([`TensorPlace`]).
//!
//! Every attractor and director energy is a weighted sum of squares of
//! quantities linear in the control points,
//!
//! ```text
//! E_op = s · Σ_q w_q Σ_r (J_qr · P − t_qr)²
//! ```
//!
//! where q runs over the nodes of an exact quadrature rule for the region
//! (eq. 28) or over the single point, and r over the residual's components:
//!
//! ```text
//! director        (eq. 13–14)  S_x·N, S_y·N              (N unit; x, y orthonormal domain directions)
//! point           (eq. 15–16)  S − P
//! plane           (eq. 17–18)  (n·S − a)/|n|
//! line            (eq. 20–21)  A S + b,  A = I − qqᵀ/(q·q),  b = (p·q)q/(q·q) − p
//! surface         (eq. 19)     S − T                      (T at the matching parameter)
//! edge to curve   (eq. 22)     E(t) − C(t)                (t ∈ [0, 1] along the edge, Gauss–Legendre)
//! ```
//!
//! The integrands are polynomials, so the rules give the closed forms. (The
//! paper prints A with p·p in eq. 20; the distance to the line needs q·q,
//! used here.) A repellor (eq. 23) is the reciprocal of an attractor term,
//! s / E_attr: not quadratic, so the solves minimize the total energy
//! (eq. 30) by Newton's method with a line search ([`NewtonReport`]).

pub(crate) mod bspline;
pub(crate) mod newton;
pub(crate) mod tensor;
pub(crate) mod triangle;

pub use newton::NewtonReport;
pub use tensor::{PatchEdge, TensorOperator, TensorPlace};
pub use triangle::{Place, RegionPiece};

use crate::basis::GaussLegendre;
use crate::triangle::TriPatch;
use crate::vec3::{angle, cross, dot, norm, normalize, sub, Vec3};
use crate::{BezierCurve, Error, Result, TensorPatch};

/// What an operator pulls toward (or, for a repellor, pushes from).
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// Director: the surface normal toward this direction (eq. 13–14).
    Direction(Vec3),
    /// Point attractor (eq. 15–16).
    Point(Vec3),
    /// Plane attractor n·x = offset (eq. 17–18).
    Plane {
        /// The plane's normal n (any length but 0).
        normal: Vec3,
        /// a in n·x = a.
        offset: f64,
    },
    /// Line attractor p + μq (eq. 20–21).
    Line {
        /// A point p of the line.
        point: Vec3,
        /// Its direction q (any length but 0).
        direction: Vec3,
    },
    /// Surface attractor on a triangular surface (eq. 19): a triangular
    /// patch whose corners match the corners of a triangular region (one
    /// patch, three vertices).
    Surface(TriPatch),
    /// Surface attractor on a tensor-product patch (eq. 19 over the unit
    /// square): the point S(u, v) toward T(u, v), T of any degree.
    TensorSurface(TensorPatch),
    /// Edge-to-curve attractor (eq. 22): an edge of the surface toward
    /// this curve, parameter for parameter.
    Curve(BezierCurve),
}

impl Target {
    /// The largest coordinate (or plane offset) the target places the
    /// surface at: part of the data's size that checks measure a result's
    /// rounding against (0 for a direction).
    pub(crate) fn size(&self) -> f64 {
        let max = |pts: &[crate::Vec3]| pts.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        match self {
            Target::Direction(_) => 0.0,
            Target::Point(p) | Target::Line { point: p, .. } => max(std::slice::from_ref(p)),
            Target::Plane { normal, offset } => offset.abs() / crate::vec3::norm(*normal),
            Target::Surface(t) => max(t.points()),
            Target::TensorSurface(t) => max(t.points()),
            Target::Curve(c) => max(c.points()),
        }
    }
}

/// An external energy operator with its strength, acting at a place `P`:
/// [`crate::triangle::Place`] on triangular surfaces (the default),
/// [`TensorPlace`] on tensor-product patches.
#[derive(Clone, Debug, PartialEq)]
pub struct Operator<P = Place> {
    /// How reports call it.
    pub name: String,
    /// Its target.
    pub target: Target,
    /// Where it acts.
    pub place: P,
    /// Its weight s ≥ 0 in the total energy.
    pub strength: f64,
    /// A repellor: s / E_attr instead of s · E_attr (not for directors).
    pub repel: bool,
}

/// One operator's outcome on a solved surface.
#[derive(Clone, Debug, PartialEq)]
pub struct OperatorOutcome {
    /// Its name.
    pub name: String,
    /// `director`, `point_attractor`, …, or `…_repellor`.
    pub kind: String,
    /// Its strength.
    pub strength: f64,
    /// Its energy term: s·E_attr, or s/E_attr for a repellor.
    pub energy: f64,
    /// How far the target is met: the distance (root mean square over a
    /// region or edge) for attractors and repellors, the mean angle in
    /// radians between the surface normal and the direction for directors
    /// (unoriented, area-weighted over a region).
    pub measure: f64,
    /// The largest distance or angle over the quadrature nodes.
    pub max: f64,
    /// A point of the result where it acts, to draw it at: the surface
    /// point for a point operator, for a region the node nearest the
    /// weighted mean of its quadrature nodes (on the surface, inside a
    /// convex region), for an edge the edge curve's midpoint.
    pub at: Option<Vec3>,
}

/// A scalar residual J·x − t with its quadrature weight, over global
/// coordinates 3g + c (point g, coordinate c).
#[derive(Clone, Debug)]
pub(crate) struct Residual {
    pub weight: f64,
    pub terms: Vec<(usize, f64)>,
    pub target: f64,
}

/// The basis functions of the surface at one quadrature node: the global
/// indices of the points they belong to, their values, and their
/// derivatives along two orthonormal directions of the domain.
pub(crate) struct NodeBasis<'a> {
    pub points: &'a [usize],
    pub values: &'a [f64],
    pub dx: &'a [f64],
    pub dy: &'a [f64],
}

impl<P> Operator<P> {
    /// The kind as reports name it.
    pub fn kind(&self) -> String {
        let base = match self.target {
            Target::Direction(_) => "director",
            Target::Point(_) => "point_attractor",
            Target::Plane { .. } => "plane_attractor",
            Target::Line { .. } => "line_attractor",
            Target::Surface(_) | Target::TensorSurface(_) => "surface_attractor",
            Target::Curve(_) => "curve_attractor",
        };
        if self.repel {
            base.replace("attractor", "repellor")
        } else {
            base.into()
        }
    }

    /// An error about one of the operator's fields, named after it.
    pub(crate) fn bad(&self, what: &str, expected: &str, got: String) -> Error {
        Error::Mismatch {
            what: format!("{}: {what}", self.name),
            expected: expected.into(),
            got,
        }
    }

    /// Checks what does not depend on the surface: the strength, the
    /// target's numbers, and that a director does not repel.
    pub(crate) fn check_target(&self) -> Result<()> {
        if !(self.strength.is_finite() && self.strength >= 0.0) {
            return Err(self.bad("strength", "a finite number ≥ 0", self.strength.to_string()));
        }
        let nonzero = |v: Vec3, what: &str| {
            if v.iter().all(|x| x.is_finite()) && norm(v) > 0.0 {
                Ok(())
            } else {
                Err(self.bad(what, "a finite non-zero vector", format!("{v:?}")))
            }
        };
        let finite = |v: Vec3, what: &str| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(self.bad(what, "finite coordinates", format!("{v:?}")))
            }
        };
        match &self.target {
            Target::Direction(d) => nonzero(*d, "direction")?,
            Target::Point(p) => finite(*p, "point")?,
            Target::Plane { normal, offset } => {
                nonzero(*normal, "normal")?;
                if !offset.is_finite() {
                    return Err(self.bad("offset", "a finite number", offset.to_string()));
                }
            }
            Target::Line { point, direction } => {
                finite(*point, "point")?;
                nonzero(*direction, "direction")?;
            }
            Target::Surface(t) => {
                for p in t.points() {
                    finite(*p, "surface control point")?;
                }
            }
            Target::TensorSurface(t) => {
                for p in t.points() {
                    finite(*p, "surface control point")?;
                }
            }
            Target::Curve(c) => {
                for p in c.points() {
                    finite(*p, "curve control point")?;
                }
            }
        }
        if self.repel && matches!(self.target, Target::Direction(_)) {
            return Err(self.bad(
                "repel",
                "an attractor (a director has no repelling form)",
                "a director".into(),
            ));
        }
        Ok(())
    }

    /// E_attr = Σ w r² of the residuals at the coordinates x.
    pub(crate) fn attraction(residuals: &[Residual], x: &[f64]) -> f64 {
        residuals
            .iter()
            .map(|r| {
                let v = r.terms.iter().map(|&(i, a)| a * x[i]).sum::<f64>() - r.target;
                r.weight * v * v
            })
            .sum()
    }

    /// The operator's energy term at x: s·E_attr or s/E_attr.
    pub(crate) fn energy(&self, residuals: &[Residual], x: &[f64]) -> f64 {
        let q = Self::attraction(residuals, x);
        if self.repel {
            self.strength / q
        } else {
            self.strength * q
        }
    }

    /// Appends the residuals of one quadrature node with weight `weight`;
    /// `surface_point` is T at the node for a surface target.
    pub(crate) fn node_residuals(
        &self,
        weight: f64,
        basis: &NodeBasis<'_>,
        surface_point: Option<Vec3>,
        out: &mut Vec<Residual>,
    ) {
        let linear = |coef: &dyn Fn(usize) -> f64, values: &[f64]| -> Vec<(usize, f64)> {
            let mut terms = Vec::with_capacity(3 * values.len());
            for (a, &g) in basis.points.iter().enumerate() {
                for k in 0..3 {
                    let v = values[a] * coef(k);
                    if v != 0.0 {
                        terms.push((3 * g + k, v));
                    }
                }
            }
            terms
        };
        let mut push = |terms: Vec<(usize, f64)>, target: f64| {
            out.push(Residual {
                weight,
                terms,
                target,
            })
        };
        match &self.target {
            Target::Direction(d) => {
                let nn = normalize(*d).expect("validated");
                for values in [basis.dx, basis.dy] {
                    push(linear(&|k| nn[k], values), 0.0);
                }
            }
            Target::Point(_) | Target::Surface(_) | Target::TensorSurface(_) | Target::Curve(_) => {
                // S − P, or S − T at the matching point of T (of the target
                // curve C at a B-spline edge's node).
                let p = match &self.target {
                    Target::Point(p) => *p,
                    _ => surface_point.expect("a surface or curve target's point"),
                };
                for k in 0..3 {
                    push(
                        linear(&|c| if c == k { 1.0 } else { 0.0 }, basis.values),
                        p[k],
                    );
                }
            }
            Target::Plane { normal, offset } => {
                let l = norm(*normal);
                push(linear(&|k| normal[k] / l, basis.values), offset / l);
            }
            Target::Line { point, direction } => {
                let qq = dot(*direction, *direction);
                let pq = dot(*point, *direction);
                for r in 0..3 {
                    let a = |c: usize| {
                        (if r == c { 1.0 } else { 0.0 }) - direction[r] * direction[c] / qq
                    };
                    let b = pq * direction[r] / qq - point[r];
                    push(linear(&a, basis.values), -b);
                }
            }
        }
    }

    /// Appends the residuals of one quadrature node of a tensor-product
    /// basis: `points` the node's control points (row-major over its u- and
    /// v-functions), `bu[r]` and `bv[r]` the r-th derivatives (r = 0, 1) of
    /// the u- and v-functions there, `surface_point` T for a surface target.
    pub(crate) fn tensor_node_residuals(
        &self,
        weight: f64,
        points: &[usize],
        (bu, bv): (&[Vec<f64>], &[Vec<f64>]),
        surface_point: Option<Vec3>,
        out: &mut Vec<Residual>,
    ) {
        let product = |a: &[f64], b: &[f64]| -> Vec<f64> {
            a.iter()
                .flat_map(|x| b.iter().map(move |y| x * y))
                .collect()
        };
        let values = product(&bu[0], &bv[0]);
        let (dx, dy) = match self.target {
            Target::Direction(_) => (product(&bu[1], &bv[0]), product(&bu[0], &bv[1])),
            _ => (Vec::new(), Vec::new()),
        };
        let basis = NodeBasis {
            points,
            values: &values,
            dx: &dx,
            dy: &dy,
        };
        self.node_residuals(weight, &basis, surface_point, out);
    }

    /// Appends the edge-to-curve residuals E(t) − C(t) at Gauss–Legendre
    /// nodes, E the Bézier curve of the edge's global points `points`.
    pub(crate) fn edge_residuals(&self, points: &[usize], out: &mut Vec<Residual>) {
        let Target::Curve(c) = &self.target else {
            unreachable!("a curve target")
        };
        let n = points.len() - 1;
        let g = GaussLegendre::new(n.max(c.degree()) + 1);
        for (t, w) in g.nodes.iter().zip(&g.weights) {
            let b = crate::basis::bernstein_all(n, *t);
            let target = c.eval(*t);
            for k in 0..3 {
                out.push(Residual {
                    weight: *w,
                    terms: points
                        .iter()
                        .zip(&b)
                        .map(|(&g, &v)| (3 * g + k, v))
                        .collect(),
                    target: target[k],
                });
            }
        }
    }
}

/// Accumulates an operator's measure over its nodes: the distance or the
/// angle at each node, weighted.
pub(crate) struct Tally {
    squared: bool,
    sum: f64,
    total: f64,
    max: f64,
    /// The surface points of the nodes with their weights, or an edge's
    /// midpoint.
    points: Vec<(Vec3, f64)>,
}

/// Of weighted points, the one nearest their weighted mean (None if none).
fn nearest_to_mean(points: &[(Vec3, f64)]) -> Option<Vec3> {
    let total: f64 = points.iter().map(|(_, w)| w.abs()).sum();
    let mean = if total > 0.0 {
        points.iter().fold([0.0; 3], |m, (p, w)| {
            crate::vec3::add(m, crate::vec3::scale(*p, w.abs() / total))
        })
    } else {
        points.first()?.0
    };
    points
        .iter()
        .map(|(p, _)| *p)
        .min_by(|a, b| norm(sub(*a, mean)).total_cmp(&norm(sub(*b, mean))))
}

impl Tally {
    pub(crate) fn new<P>(op: &Operator<P>) -> Self {
        Tally {
            squared: !matches!(op.target, Target::Direction(_)),
            sum: 0.0,
            total: 0.0,
            max: 0.0,
            points: Vec::new(),
        }
    }

    /// Adds the node where the surface is at `s` with normal `normal`;
    /// `surface_point` is T there for a surface target.
    pub(crate) fn node<P>(
        &mut self,
        op: &Operator<P>,
        weight: f64,
        s: Vec3,
        normal: Option<Vec3>,
        surface_point: Option<Vec3>,
    ) {
        let value = match &op.target {
            Target::Direction(d) => match normal {
                Some(nrm) => {
                    let a = angle(nrm, *d);
                    a.min(std::f64::consts::PI - a)
                }
                None => std::f64::consts::FRAC_PI_2,
            },
            Target::Point(p) => norm(sub(s, *p)),
            Target::Plane { normal, offset } => (dot(*normal, s) - offset).abs() / norm(*normal),
            Target::Line { point, direction } => {
                norm(cross(sub(s, *point), *direction)) / norm(*direction)
            }
            Target::Surface(_) | Target::TensorSurface(_) | Target::Curve(_) => norm(sub(
                s,
                surface_point.expect("a surface or curve target's point"),
            )),
        };
        self.add(value, weight);
        self.points.push((s, weight));
    }

    /// Marks the operator at `p` alone (an edge's midpoint) instead of the
    /// node nearest the nodes' weighted mean.
    pub(crate) fn mark_at(&mut self, p: Vec3) {
        self.points = vec![(p, 1.0)];
    }

    /// Adds the distances between the edge curve and the target curve.
    pub(crate) fn edge<P>(&mut self, op: &Operator<P>, edge: &BezierCurve) {
        let Target::Curve(c) = &op.target else {
            unreachable!("a curve target")
        };
        self.points = vec![(edge.eval(0.5), 1.0)];
        let g = GaussLegendre::new(2 * edge.degree().max(c.degree()) + 2);
        for (t, w) in g.nodes.iter().zip(&g.weights) {
            self.add(norm(sub(edge.eval(*t), c.eval(*t))), *w);
        }
    }

    fn add(&mut self, value: f64, weight: f64) {
        self.sum += weight * if self.squared { value * value } else { value };
        self.total += weight;
        self.max = self.max.max(value);
    }

    /// The outcome, with the operator's energy.
    pub(crate) fn finish<P>(self, op: &Operator<P>, energy: f64) -> OperatorOutcome {
        let mean = if self.total > 0.0 {
            self.sum / self.total
        } else {
            0.0
        };
        OperatorOutcome {
            name: op.name.clone(),
            kind: op.kind(),
            strength: op.strength,
            energy,
            measure: if self.squared { mean.sqrt() } else { mean },
            max: self.max,
            at: nearest_to_mean(&self.points),
        }
    }
}
