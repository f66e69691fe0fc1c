//! External energy operators (Veltkamp & Wesselink §5, §6.1): directors,
//! attractors to a point, plane, line, surface or curve, and repellors.
//!
//! Every attractor and director energy is a weighted sum of squares of
//! quantities linear in the control points,
//!
//! ```text
//! E_op = s · Σ_q w_q Σ_r (J_qr · P − t_qr)²
//! ```
//!
//! where q runs over the nodes of an exact quadrature rule for the region
//! ([`super::region`], eq. 28) or over the single point (u₀, v₀), and r
//! over the residual's components:
//!
//! ```text
//! director        (eq. 13–14)  S_x·N, S_y·N              (N unit; x, y orthonormal on the equilateral domain)
//! point           (eq. 15–16)  S − P
//! plane           (eq. 17–18)  (n·S − a)/|n|
//! line            (eq. 20–21)  A S + b,  A = I − qqᵀ/(q·q),  b = (p·q)q/(q·q) − p
//! surface         (eq. 19)     S − T                      (T over the triangular region, corner to corner)
//! edge to curve   (eq. 22)     E(t) − C(t)                (t ∈ [0, 1] along the edge, Gauss–Legendre)
//! ```
//!
//! The integrands are polynomials, so the rules give the closed forms. Regions
//! are measured like the internal energy (§6.1, eq. 25): over the unit-side
//! equilateral triangle, so dA = (√3/2) du dv. (The paper prints A with p·p
//! in eq. 20; the distance to the line needs q·q, used here.)
//!
//! A repellor (eq. 23) is the reciprocal of an attractor term: s / E_attr,
//! not quadratic; the solve minimizes the total energy (eq. 30) by Newton's
//! method (see [`super::TriProblem::solve`]).

use super::bernstein::{tri_bernstein_all, Bary};
use super::energy::EQUILATERAL_AREA;
use super::index::multi_indices;
use super::patch::TriPatch;
use super::refine::{check_point, DomainPoint, Refinement};
use super::region::{clip_to_triangle, convex, signed_area, trapezoid_rule, Uv};
use super::surface::TriSurface;
use crate::basis::GaussLegendre;
use crate::vec3::{angle, cross, dot, norm, normalize, sub, Vec3};
use crate::{BezierCurve, Error, Result};

/// √3/2: du dv on the barycentric (u, v) triangle to area on the unit-side
/// equilateral triangle.
const AREA_FACTOR: f64 = 2.0 * EQUILATERAL_AREA;
const INV_SQRT3: f64 = 0.577_350_269_189_625_8;
/// Unit directions x and y of the equilateral domain (V₁V₂ and its normal)
/// as barycentric differences.
const DIR_X: Bary = [-1.0, 1.0, 0.0];
const DIR_Y: Bary = [-INV_SQRT3, -INV_SQRT3, 2.0 * INV_SQRT3];

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
    /// Surface attractor (eq. 19): a triangular patch whose corners match
    /// the corners of a triangular region (one patch, three vertices).
    Surface(TriPatch),
    /// Edge-to-curve attractor (eq. 22): the patch edge placed by
    /// [`Place::Edge`] toward this curve, parameter for parameter.
    Curve(BezierCurve),
}

/// Where an operator acts.
#[derive(Clone, Debug, PartialEq)]
pub enum Place {
    /// One surface point (u₀, v₀, w₀) of one patch.
    Point(DomainPoint),
    /// Convex polygons in the (u, v) barycentric plane of single patches
    /// (w = 1 − u − v), e.g. a region split across patches by hand.
    Patches(Vec<RegionPiece>),
    /// One convex polygon in the (x, y) plane of the mesh as given (its
    /// vertices' x and y): split per patch automatically, each piece
    /// measured in its own patch's parameters like [`Place::Patches`].
    Domain(Vec<Uv>),
    /// The mesh edge from vertex a to vertex b.
    Edge([usize; 2]),
}

/// A convex polygon in one patch's (u, v) plane.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionPiece {
    /// The patch (triangle).
    pub triangle: usize,
    /// Its vertices (u, v), either orientation.
    pub polygon: Vec<Uv>,
}

/// An external energy operator with its strength.
#[derive(Clone, Debug, PartialEq)]
pub struct Operator {
    /// How reports call it.
    pub name: String,
    /// Its target.
    pub target: Target,
    /// Where it acts.
    pub place: Place,
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
}

/// A scalar residual J·x − t with its quadrature weight.
#[derive(Clone, Debug)]
pub(crate) struct Residual {
    pub weight: f64,
    pub terms: Vec<(usize, f64)>,
    pub target: f64,
}

/// Quadrature nodes of an operator on the (refined) surface: per node the
/// patch, barycentrics, weight (area on the equilateral domain, or length
/// along an edge) and, for a surface target, the barycentrics in T.
#[derive(Clone, Debug)]
pub(crate) struct Located {
    nodes: Vec<Node>,
    /// For an edge: its global points, a to b.
    edge: Option<Vec<usize>>,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    triangle: usize,
    bary: Bary,
    weight: f64,
    target_bary: Bary,
}

impl Operator {
    /// The kind as reports name it.
    pub fn kind(&self) -> String {
        let base = match self.target {
            Target::Direction(_) => "director",
            Target::Point(_) => "point_attractor",
            Target::Plane { .. } => "plane_attractor",
            Target::Line { .. } => "line_attractor",
            Target::Surface(_) => "surface_attractor",
            Target::Curve(_) => "curve_attractor",
        };
        if self.repel {
            base.replace("attractor", "repellor")
        } else {
            base.into()
        }
    }

    /// Checks the operator against the surface it will act on: strength,
    /// target, place, and that they fit together; errors name the operator.
    pub fn validate(&self, surface: &TriSurface) -> Result<()> {
        let bad = |what: &str, expected: &str, got: String| Error::Mismatch {
            what: format!("{}: {what}", self.name),
            expected: expected.into(),
            got,
        };
        if !(self.strength.is_finite() && self.strength >= 0.0) {
            return Err(bad(
                "strength",
                "a finite number ≥ 0",
                self.strength.to_string(),
            ));
        }
        let nonzero = |v: Vec3, what: &str| {
            if v.iter().all(|x| x.is_finite()) && norm(v) > 0.0 {
                Ok(())
            } else {
                Err(bad(what, "a finite non-zero vector", format!("{v:?}")))
            }
        };
        let finite = |v: Vec3, what: &str| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(bad(what, "finite coordinates", format!("{v:?}")))
            }
        };
        match &self.target {
            Target::Direction(d) => nonzero(*d, "direction")?,
            Target::Point(p) => finite(*p, "point")?,
            Target::Plane { normal, offset } => {
                nonzero(*normal, "normal")?;
                if !offset.is_finite() {
                    return Err(bad("offset", "a finite number", offset.to_string()));
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
            Target::Curve(c) => {
                for p in c.points() {
                    finite(*p, "curve control point")?;
                }
            }
        }
        if self.repel && matches!(self.target, Target::Direction(_)) {
            return Err(bad(
                "repel",
                "an attractor (a director has no repelling form)",
                "a director".into(),
            ));
        }
        match (&self.place, &self.target) {
            (Place::Edge(_), Target::Curve(_)) => {}
            (_, Target::Curve(_)) => {
                return Err(bad(
                    "place",
                    "an edge (edge-to-curve attractor)",
                    "not an edge".into(),
                ))
            }
            (Place::Edge(_), _) => {
                return Err(bad("place", "a point or a region", "an edge".into()))
            }
            (Place::Patches(p), Target::Surface(_)) if p.len() == 1 && p[0].polygon.len() == 3 => {}
            (_, Target::Surface(_)) => {
                return Err(bad(
                    "region",
                    "a triangular region in one patch (its corners match the attractor surface's)",
                    "another place".into(),
                ))
            }
            _ => {}
        }
        match &self.place {
            Place::Point(p) => check_point(surface, *p, &format!("{}: point", self.name))?,
            Place::Patches(pieces) => {
                if pieces.is_empty() {
                    return Err(bad("region", "at least one piece", "none".into()));
                }
                for (k, piece) in pieces.iter().enumerate() {
                    if piece.triangle >= surface.patch_count() {
                        return Err(bad(
                            &format!("region[{k}].triangle"),
                            &format!("a triangle index < {}", surface.patch_count()),
                            piece.triangle.to_string(),
                        ));
                    }
                    let p = convex(&piece.polygon, &format!("{}: region[{k}]", self.name))?;
                    for uv in &p {
                        let w = 1.0 - uv[0] - uv[1];
                        if uv[0] < -1e-12 || uv[1] < -1e-12 || w < -1e-12 {
                            return Err(bad(
                                &format!("region[{k}]"),
                                "vertices (u, v) with u, v ≥ 0 and u + v ≤ 1",
                                format!("{uv:?}"),
                            ));
                        }
                    }
                }
            }
            Place::Domain(polygon) => {
                convex(polygon, &format!("{}: region", self.name))?;
            }
            Place::Edge([a, b]) => {
                if surface.edge_between(*a, *b).is_none() || a == b {
                    return Err(bad(
                        "edge",
                        "two vertices joined by a mesh edge",
                        format!("[{a}, {b}]"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// A [`Place::Domain`] region as the per-patch pieces it is split into
    /// on `surface` (None for the other places): what a result file keeps,
    /// since the solved mesh's (x, y) differ from the chart's.
    pub fn domain_pieces(&self, surface: &TriSurface) -> Result<Option<Vec<RegionPiece>>> {
        match &self.place {
            Place::Domain(polygon) => split_domain(surface, polygon, &self.name).map(Some),
            _ => Ok(None),
        }
    }

    /// The quadrature nodes on the refined surface `r.surface`, from the
    /// place on the `original` surface (validated).
    pub(crate) fn locate(&self, original: &TriSurface, r: &Refinement) -> Result<Located> {
        let surface = &r.surface;
        let n = surface.degree();
        let degree = 2 * match &self.target {
            Target::Surface(t) => n.max(t.degree()),
            _ => n,
        };
        let mut nodes = Vec::new();
        let mut region = |pieces: Vec<RegionPiece>| {
            for piece in pieces {
                let poly = convex(&piece.polygon, &self.name)?;
                // Its corners, for a surface target: T is over this triangle.
                let corners = (poly.len() == 3).then(|| [poly[0], poly[1], poly[2]]);
                for (child, (t, tri)) in r.origin.iter().enumerate() {
                    if *t != piece.triangle {
                        continue;
                    }
                    let mut uv: [Uv; 3] = std::array::from_fn(|k| [tri[k][0], tri[k][1]]);
                    let mut order = [0, 1, 2];
                    if signed_area(&uv) < 0.0 {
                        uv.swap(1, 2);
                        order.swap(1, 2);
                    }
                    let Some(part) = clip_to_triangle(&poly, uv) else {
                        continue;
                    };
                    // The child's own parameters: its (u, v) triangle has
                    // area ½, so the piece's measure scales by ½/area.
                    let scale = AREA_FACTOR / (2.0 * signed_area(&uv).abs());
                    for (p, w) in trapezoid_rule(&part, degree) {
                        let original_bary = [p[0], p[1], 1.0 - p[0] - p[1]];
                        // Barycentrics in the child (corners in `order`).
                        let s = bary_in(uv, p);
                        let mut bary = [0.0; 3];
                        for k in 0..3 {
                            bary[order[k]] = s[k];
                        }
                        let target_bary = match corners {
                            Some(c) => bary_in(c, p),
                            None => original_bary,
                        };
                        nodes.push(Node {
                            triangle: child,
                            bary,
                            weight: w * scale,
                            target_bary,
                        });
                    }
                }
            }
            Ok::<_, Error>(())
        };
        let mut edge = None;
        match &self.place {
            Place::Point(p) => {
                let at = r.locate(*p).ok_or_else(|| Error::Mismatch {
                    what: format!("{}: point", self.name),
                    expected: "a point of the surface".into(),
                    got: format!("{p:?}"),
                })?;
                nodes.push(Node {
                    triangle: at.triangle,
                    bary: at.bary,
                    weight: 1.0,
                    target_bary: p.bary,
                });
            }
            Place::Patches(pieces) => region(pieces.clone())?,
            Place::Domain(polygon) => region(split_domain(original, polygon, &self.name)?)?,
            Place::Edge([a, b]) => {
                let e = surface
                    .edge_between(*a, *b)
                    .ok_or_else(|| Error::Mismatch {
                        what: format!("{}: edge [{a}, {b}]", self.name),
                        expected: "an edge that curve constraints did not split".into(),
                        got: "a split edge".into(),
                    })?;
                let mut pts = surface.edge_points(e);
                if a > b {
                    pts.reverse();
                }
                edge = Some(pts);
            }
        }
        if nodes.is_empty() && edge.is_none() {
            return Err(Error::Mismatch {
                what: format!("{}: region", self.name),
                expected: "a region overlapping the surface".into(),
                got: "no overlap with any patch".into(),
            });
        }
        Ok(Located { nodes, edge })
    }

    /// The scalar residuals on `surface` (global coordinates 3g + c).
    pub(crate) fn residuals(&self, at: &Located, surface: &TriSurface) -> Vec<Residual> {
        let n = surface.degree();
        let mut out = Vec::new();
        if let (Some(pts), Target::Curve(c)) = (&at.edge, &self.target) {
            let g = GaussLegendre::new(n.max(c.degree()) + 1);
            for (t, w) in g.nodes.iter().zip(&g.weights) {
                let b = crate::basis::bernstein_all(n, *t);
                let target = c.eval(*t);
                for k in 0..3 {
                    out.push(Residual {
                        weight: *w,
                        terms: pts.iter().zip(&b).map(|(&g, &v)| (3 * g + k, v)).collect(),
                        target: target[k],
                    });
                }
            }
            return out;
        }
        for node in &at.nodes {
            let idx = surface.patch_indices(node.triangle);
            let values = tri_bernstein_all(n, node.bary);
            let linear = |coef: &dyn Fn(usize) -> f64, basis: &[f64]| -> Vec<(usize, f64)> {
                let mut terms = Vec::with_capacity(3 * basis.len());
                for (a, &g) in idx.iter().enumerate() {
                    for k in 0..3 {
                        let v = basis[a] * coef(k);
                        if v != 0.0 {
                            terms.push((3 * g + k, v));
                        }
                    }
                }
                terms
            };
            let w = node.weight;
            let mut push = |terms: Vec<(usize, f64)>, target: f64| {
                out.push(Residual {
                    weight: w,
                    terms,
                    target,
                })
            };
            match &self.target {
                Target::Direction(d) => {
                    let nn = normalize(*d).expect("validated");
                    for dir in [DIR_X, DIR_Y] {
                        let basis = derivative_basis(n, node.bary, dir);
                        push(linear(&|k| nn[k], &basis), 0.0);
                    }
                }
                Target::Point(_) | Target::Surface(_) => {
                    // S − P, or S − T at the matching point of T.
                    let p = match &self.target {
                        Target::Surface(t) => t.eval(node.target_bary),
                        Target::Point(p) => *p,
                        _ => unreachable!(),
                    };
                    for k in 0..3 {
                        push(linear(&|c| if c == k { 1.0 } else { 0.0 }, &values), p[k]);
                    }
                }
                Target::Plane { normal, offset } => {
                    let l = norm(*normal);
                    push(linear(&|k| normal[k] / l, &values), offset / l);
                }
                Target::Line { point, direction } => {
                    let qq = dot(*direction, *direction);
                    let pq = dot(*point, *direction);
                    for r in 0..3 {
                        let a = |c: usize| {
                            (if r == c { 1.0 } else { 0.0 }) - direction[r] * direction[c] / qq
                        };
                        let b = pq * direction[r] / qq - point[r];
                        push(linear(&a, &values), -b);
                    }
                }
                Target::Curve(_) => unreachable!("an edge place"),
            }
        }
        out
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

    /// Its outcome on the solved surface, given its [`Self::residuals`]
    /// (they depend on the mesh only).
    pub(crate) fn outcome(
        &self,
        at: &Located,
        residuals: &[Residual],
        surface: &TriSurface,
        x: &[f64],
    ) -> OperatorOutcome {
        let energy = self.energy(residuals, x);
        let (mut sum, mut total, mut max) = (0.0, 0.0, 0.0f64);
        let mut add = |value: f64, weight: f64, squared: bool| {
            sum += weight * if squared { value * value } else { value };
            total += weight;
            max = max.max(value);
        };
        let squared = !matches!(self.target, Target::Direction(_));
        if let (Some(pts), Target::Curve(c)) = (&at.edge, &self.target) {
            let edge = BezierCurve::new(pts.iter().map(|&g| surface.points()[g]).collect());
            let g = GaussLegendre::new(2 * surface.degree().max(c.degree()) + 2);
            for (t, w) in g.nodes.iter().zip(&g.weights) {
                add(norm(sub(edge.eval(*t), c.eval(*t))), *w, true);
            }
        }
        for node in &at.nodes {
            let patch = surface.patch(node.triangle);
            let s = patch.eval(node.bary);
            let value = match &self.target {
                Target::Direction(d) => match patch.normal(node.bary) {
                    Some(nrm) => {
                        let a = angle(nrm, *d);
                        a.min(std::f64::consts::PI - a)
                    }
                    None => std::f64::consts::FRAC_PI_2,
                },
                Target::Point(p) => norm(sub(s, *p)),
                Target::Plane { normal, offset } => {
                    (dot(*normal, s) - offset).abs() / norm(*normal)
                }
                Target::Line { point, direction } => {
                    norm(cross(sub(s, *point), *direction)) / norm(*direction)
                }
                Target::Surface(t) => norm(sub(s, t.eval(node.target_bary))),
                Target::Curve(_) => unreachable!("an edge place"),
            };
            add(value, node.weight, squared);
        }
        let mean = if total > 0.0 { sum / total } else { 0.0 };
        OperatorOutcome {
            name: self.name.clone(),
            kind: self.kind(),
            strength: self.strength,
            energy,
            measure: if squared { mean.sqrt() } else { mean },
            max,
        }
    }
}

/// ∂_d B^n_λ(b) for all λ: n Σ_m d_m B^{n−1}_{λ−e_m}(b).
fn derivative_basis(n: usize, b: Bary, d: Bary) -> Vec<f64> {
    if n == 0 {
        return vec![0.0];
    }
    let lower = tri_bernstein_all(n - 1, b);
    let index = |l: [usize; 3]| super::index::linear_index(n - 1, l[0], l[1], l[2]);
    multi_indices(n)
        .map(|lam| {
            (0..3)
                .filter(|&m| lam[m] > 0)
                .map(|m| {
                    let mut l = lam;
                    l[m] -= 1;
                    d[m] * lower[index(l)]
                })
                .sum::<f64>()
                * n as f64
        })
        .collect()
}

/// The barycentrics of p in the (u, v) triangle c.
fn bary_in(c: [Uv; 3], p: Uv) -> Bary {
    let det = (c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
    let s1 =
        ((p[0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (p[1] - c[0][1])) / det;
    let s2 =
        ((c[1][0] - c[0][0]) * (p[1] - c[0][1]) - (p[0] - c[0][0]) * (c[1][1] - c[0][1])) / det;
    [1.0 - s1 - s2, s1, s2]
}

/// A polygon in the mesh's (x, y) plane split into pieces per patch, in
/// each patch's (u, v): u, v, w are the barycentrics of the point in the
/// triangle of the patch's corner points (the mesh as given).
fn split_domain(surface: &TriSurface, polygon: &[Uv], name: &str) -> Result<Vec<RegionPiece>> {
    let poly = convex(polygon, &format!("{name}: region"))?;
    let mut pieces = Vec::new();
    for (t, tri) in surface.triangles().iter().enumerate() {
        let xy: [Uv; 3] = std::array::from_fn(|k| {
            let p = surface.points()[tri[k]];
            [p[0], p[1]]
        });
        let mut ccw = xy;
        let flipped = signed_area(&xy) < 0.0;
        if flipped {
            ccw.swap(1, 2);
        }
        if signed_area(&ccw) <= 1e-14 * scale_of(&ccw) {
            continue; // edge-on in (x, y): no area to cover there
        }
        let Some(part) = clip_to_triangle(&poly, ccw) else {
            continue;
        };
        let polygon = part
            .iter()
            .map(|&p| {
                let b = bary_in(xy, p);
                [b[0], b[1]]
            })
            .collect();
        pieces.push(RegionPiece {
            triangle: t,
            polygon,
        });
    }
    Ok(pieces)
}

fn scale_of(t: &[Uv; 3]) -> f64 {
    let s = t.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    s * s
}
