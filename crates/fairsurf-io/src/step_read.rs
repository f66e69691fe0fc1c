//! Reading STEP files (ISO 10303-21) for `fill` and `blend`: the faces of
//! every shell (OPEN_SHELL, CLOSED_SHELL, in whichever representation holds
//! them), by the `truck-stepio` crate (ruststep's parser), each as a
//! polynomial or rational B-spline bounded by its four sides
//! ([`read_step`]): B-spline and Bézier faces (rational or not), planes
//! bounded by four straight edges, cylinders and cones bounded by two arcs
//! and two rulings, spheres and tori bounded by two parallels and two
//! meridians. Every other face is refused by name, nothing is dropped
//! silently.

use crate::{Error, Result};
use fairsurf::bspline::{BSplineSurface, KnotVector, RationalSurface};
use fairsurf::Vec3;
use truck_stepio::r#in::alias::{
    Curve3D, ElementarySurface, ParametricCurve, ParametricSurface, ParametricSurface3D, Point3,
    SearchNearestParameter, Surface as StepSurface, Vector3, D2,
};
use truck_stepio::r#in::Table;
use truck_topology::compress::{CompressedEdgeIndex, CompressedFace, CompressedShell};

/// The error for a STEP file's content (as a scene error with the entity
/// or face as its path).
fn bad(path: impl Into<String>, message: impl Into<String>) -> Error {
    Error::scene(path, message)
}

/// A face's surface, exactly as the file gives it.
#[derive(Clone, Debug, PartialEq)]
pub enum FaceSurface {
    /// A polynomial B-spline (Bézier faces, B-spline faces, rational ones
    /// with equal weights, planes bounded by four straight edges).
    Polynomial(BSplineSurface),
    /// A rational B-spline (rational faces with unequal weights, cylinders
    /// and cones bounded by two arcs and two rulings).
    Rational(RationalSurface),
}

/// A face of a STEP file bounded by four sides of its surface.
#[derive(Clone, Debug, PartialEq)]
pub struct StepFace {
    /// What the file's surface is: "B-spline", "rational B-spline",
    /// "plane", "cylinder", "cone", "sphere" or "torus".
    pub kind: &'static str,
    /// The surface, whose four sides are the face's boundary.
    pub surface: FaceSurface,
}

impl StepFace {
    /// The surface as a polynomial B-spline, when it is one.
    pub fn polynomial(&self) -> Option<&BSplineSurface> {
        match &self.surface {
            FaceSurface::Polynomial(s) => Some(s),
            FaceSurface::Rational(_) => None,
        }
    }
}

/// The polynomial faces of every shell in a STEP file's text ([`read_step`]
/// with every face polynomial); a rational face (a cylinder, …) is an
/// error naming it.
pub fn read_step_faces(text: &str) -> Result<Vec<BSplineSurface>> {
    read_step(text)?
        .into_iter()
        .enumerate()
        .map(|(k, f)| match f.surface {
            FaceSurface::Polynomial(s) => Ok(s),
            FaceSurface::Rational(_) => Err(bad(
                format!("face {k}"),
                format!(
                    "a {} face (a rational surface): only polynomial faces are taken here",
                    f.kind
                ),
            )),
        })
        .collect()
}

/// The faces of every shell in a STEP file's text, in the order of the
/// shells' entity numbers and their faces in each, each exactly as a
/// polynomial or rational B-spline bounded by its four sides:
/// B-spline and Bézier faces (rational or not) whose boundary is their
/// surface's four sides; planes bounded by four straight edges (a
/// bilinear patch); cylinders and cones bounded by two circular arcs and
/// two rulings (rational quadratic in the arcs' direction, The NURBS Book
/// §7.5); spheres and tori bounded by two parallels and two meridians (the
/// rational biquadratic surface of revolution, §8.5) — each conversion
/// checked against the file's own surface and edges.
///
/// Errors name what is wrong: not STEP (with the parser's message), no
/// shell, a face of another kind (a swept surface; a sphere or torus
/// face bounded otherwise), a face
/// with holes or with a boundary that is not four sides of its surface
/// (trimmed), a face the reader could not convert.
pub fn read_step(text: &str) -> Result<Vec<StepFace>> {
    // A SURFACE_CURVE's preferred representation is read as its 3-D curve:
    // truck-stepio follows a PCURVE_S1/S2 preference through the pcurve on
    // the surface, and on a periodic surface (a torus, a sphere) its
    // parameters wrap to [0, 2π) — an arc from v = −0.4 to 1.2 came out as
    // the other 4.68 rad of the circle. The 3-D curve is the edge's own
    // geometry; the pcurves only describe it on each face.
    let text = text
        .replace(".PCURVE_S1.", ".CURVE_3D.")
        .replace(".PCURVE_S2.", ".CURVE_3D.");
    let exchange = ruststep::parser::parse(&text).map_err(|e| {
        bad(
            "",
            format!("not a STEP file (ISO 10303-21) this reader can parse: {e}"),
        )
    })?;
    let mut exchange = exchange;
    let Some(data) = exchange.data.first_mut() else {
        return Err(bad("", "the STEP file has no DATA section"));
    };
    same_sense_edges(data);
    let data = &*data;
    let table = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        Table::from_data_section(data)
    }))
    .map_err(|_| bad("", "the STEP reader (truck-stepio) failed on this file"))?;
    let mut shells: Vec<_> = table.shell.iter().collect();
    if shells.is_empty() {
        return Err(bad(
            "",
            "no shell (OPEN_SHELL or CLOSED_SHELL) in the STEP file: fill reads the faces of shells",
        ));
    }
    shells.sort_by_key(|(id, _)| **id);
    let mut faces = Vec::new();
    for (id, shell) in shells {
        let compressed = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            table.to_compressed_shell(shell)
        }))
        .map_err(|_| {
            bad(
                format!("#{id}"),
                "the STEP reader (truck-stepio) failed on the shell",
            )
        })?
        .map_err(|e| bad(format!("#{id}"), format!("cannot read the shell: {e}")))?;
        if compressed.faces.len() != shell.cfs_faces.len() {
            return Err(bad(
                format!("#{id}"),
                format!(
                    "the shell has {} faces and the reader converted {}: some face's surface is \
                     of a kind it does not read",
                    shell.cfs_faces.len(),
                    compressed.faces.len()
                ),
            ));
        }
        for (k, face) in compressed.faces.iter().enumerate() {
            let path = format!("#{id} face {k}");
            let f = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                step_face(face, &compressed)
            }))
            .unwrap_or_else(|_| Err("the face's geometry could not be evaluated".into()))
            .map_err(|m| bad(&path, m))?;
            faces.push(f);
        }
    }
    Ok(faces)
}

/// Every EDGE_CURVE of same_sense `.F.` rewritten as its equal of
/// same_sense `.T.` (its vertices swapped), and the ORIENTED_EDGEs that
/// use it turned: truck-stepio turns a `.F.` edge's curve twice on the
/// path of a SURFACE_CURVE read by its 3-D curve (which [`read_step`]
/// asks for), so such an edge would run backwards.
fn same_sense_edges(data: &mut ruststep::ast::DataSection) {
    use ruststep::ast::{EntityInstance, Name, Parameter};
    let (yes, no) = (
        Parameter::Enumeration("T".into()),
        Parameter::Enumeration("F".into()),
    );
    let mut turned = std::collections::HashSet::new();
    for e in &mut data.entities {
        if let EntityInstance::Simple { id, record } = e {
            if record.name != "EDGE_CURVE" {
                continue;
            }
            if let Parameter::List(ps) = &mut record.parameter {
                if ps.len() == 5 && ps[4] == no {
                    ps.swap(1, 2);
                    ps[4] = yes.clone();
                    turned.insert(*id);
                }
            }
        }
    }
    if turned.is_empty() {
        return;
    }
    for e in &mut data.entities {
        if let EntityInstance::Simple { record, .. } = e {
            if record.name != "ORIENTED_EDGE" {
                continue;
            }
            if let Parameter::List(ps) = &mut record.parameter {
                let uses = matches!(ps.get(3), Some(Parameter::Ref(Name::Entity(k))) if turned.contains(k));
                if ps.len() == 5 && uses {
                    ps[4] = if ps[4] == yes {
                        no.clone()
                    } else {
                        yes.clone()
                    };
                }
            }
        }
    }
}

type Shell = CompressedShell<Point3, Curve3D, StepSurface>;
type Face = CompressedFace<StepSurface>;

fn v3(p: Point3) -> Vec3 {
    [p.x, p.y, p.z]
}

fn dist(a: Vec3, b: Vec3) -> f64 {
    fairsurf::vector::norm(fairsurf::vector::sub(a, b))
}

/// One face as a polynomial or rational B-spline bounded by its four
/// sides, or why not.
fn step_face(face: &Face, shell: &Shell) -> std::result::Result<StepFace, String> {
    if face.boundaries.len() != 1 {
        return Err(format!(
            "the face has {} boundary loops: faces with holes in them are not filled around yet",
            face.boundaries.len()
        ));
    }
    let edges: Vec<LoopEdge> = face.boundaries[0]
        .iter()
        .map(|e| LoopEdge::new(shell, *e))
        .collect::<std::result::Result<_, String>>()?;
    let (kind, surface) = match &face.surface {
        StepSurface::BSplineSurface(_) | StepSurface::NurbsSurface(_) => {
            let (kind, surface) = spline(&face.surface)?;
            (kind, restricted(surface, &edges)?)
        }
        StepSurface::ElementarySurface(e) => match e.as_ref() {
            ElementarySurface::Plane(_) => ("plane", plane(&edges)?),
            ElementarySurface::CylindricalSurface(_) => ("cylinder", ruled(&edges)?),
            ElementarySurface::ConicalSurface(_) => ("cone", ruled(&edges)?),
            ElementarySurface::Sphere(_) => ("sphere", revolved(&edges, "sphere")?),
            ElementarySurface::ToroidalSurface(_) => ("torus", revolved(&edges, "torus")?),
        },
        StepSurface::SweptCurve(_) => {
            return Err("a swept surface (extrusion or revolution): not filled around yet".into())
        }
    };
    // A B-spline face is the file's surface itself; a converted one is
    // checked against it.
    let converted = !matches!(kind, "B-spline" | "rational B-spline");
    let surface = oriented_like(surface, face, &edges, converted)?;
    Ok(StepFace { kind, surface })
}

/// An edge of a face's loop, as the loop runs.
struct LoopEdge {
    curve: Curve3D,
    /// The curve's parameters at the loop's start and end of the edge; on
    /// a closed curve, past the end of its domain when the edge runs
    /// through the curve's seam.
    range: (f64, f64),
    /// The domain of a closed curve whose edge runs through its seam
    /// (parameters past its end wrap to its start).
    seam: Option<(f64, f64)>,
    start: Vec3,
    end: Vec3,
}

impl LoopEdge {
    fn new(shell: &Shell, e: CompressedEdgeIndex) -> std::result::Result<Self, String> {
        let edge = shell
            .edges
            .get(e.index)
            .ok_or("a loop names an edge the shell does not have")?;
        let (front, back) = (
            v3(shell.vertices[edge.vertices.0]),
            v3(shell.vertices[edge.vertices.1]),
        );
        let (r0, r1) = edge
            .curve
            .try_range_tuple()
            .ok_or("an edge whose curve is unbounded")?;
        // The reader turns a curve used against its sense: it runs from
        // the edge's front vertex to its back one.
        let mut whole = Self {
            curve: edge.curve.clone(),
            range: (r0, r1),
            seam: None,
            start: front,
            end: back,
        };
        let size = dist(front, back).max(1.0);
        let tol = (1e-8 * size).max(EDGE_TOLERANCE);
        // The curve's parameters at the vertices: its ends, or where the
        // vertices lie on it when the curve runs further (a closed or
        // extended curve).
        let at = |p: Vec3, end: f64| -> std::result::Result<f64, String> {
            if dist(whole.point(end), p) <= tol {
                return Ok(end);
            }
            let (t, off) = whole.nearest(p);
            if off <= tol {
                Ok(t)
            } else {
                Err(format!("an edge whose vertex is {off:e} off its curve"))
            }
        };
        let (t0, t1) = (at(front, r0)?, at(back, r1)?);
        let closed = dist(whole.point(r0), whole.point(r1)) <= tol;
        whole.range = if t0 < t1 {
            (t0, t1)
        } else if closed && t0 > t1 {
            // From the front vertex through the seam to the back one.
            whole.seam = Some((r0, r1));
            (t0, t1 + (r1 - r0))
        } else if t0 > t1 {
            return Err(format!(
                "an edge whose curve runs from its end vertex to its start vertex (parameters \
                 {t0} to {t1})"
            ));
        } else {
            return Err("an edge whose two vertices are one point of its curve".into());
        };
        if !e.orientation {
            whole = whole.reversed();
        }
        Ok(whole)
    }

    /// The same edge run the other way.
    fn reversed(&self) -> Self {
        Self {
            curve: self.curve.clone(),
            range: (self.range.1, self.range.0),
            seam: self.seam,
            start: self.end,
            end: self.start,
        }
    }

    /// The curve's parameter for t (wrapped through the seam).
    fn wrap(&self, t: f64) -> f64 {
        match self.seam {
            Some((lo, hi)) if t > hi => t - (hi - lo),
            _ => t,
        }
    }

    fn point(&self, t: f64) -> Vec3 {
        v3(self.curve.subs(self.wrap(t)))
    }

    /// The point at s ∈ [0, 1] along the loop, and the derivative by s.
    fn at(&self, s: f64) -> (Vec3, Vec3) {
        let (a, b) = self.range;
        let t = self.wrap(a + (b - a) * s);
        let d = self.curve.der(t);
        (
            v3(self.curve.subs(t)),
            [d.x * (b - a), d.y * (b - a), d.z * (b - a)],
        )
    }

    /// Whether the edge is a straight segment: points at seven parameters
    /// inside it within `tol` of its chord, whatever its parameterization.
    fn straight(&self, tol: f64) -> bool {
        (1..8).all(|k| {
            let p = self.at(k as f64 / 8.0).0;
            fairsurf::vector::segment_distance(p, self.start, self.end) <= tol
        })
    }

    /// How far the edge's tangent turns (the sum of its turns between 17
    /// samples), and in how many pieces of at most 90° an arc of it is
    /// written.
    fn turning(&self) -> (f64, usize) {
        let turning: f64 = (0..16)
            .map(|k| {
                let (a, b) = (self.at(k as f64 / 16.0).1, self.at((k + 1) as f64 / 16.0).1);
                fairsurf::vector::angle(a, b)
            })
            .sum();
        let pieces = ((turning / std::f64::consts::FRAC_PI_2) - 1e-9)
            .ceil()
            .max(1.0);
        (turning, pieces as usize)
    }

    /// The distance from p to the edge's curve (within the edge).
    fn distance(&self, p: Vec3) -> f64 {
        self.nearest(p).1
    }

    /// The parameter of the point of the edge nearest to p, and the
    /// distance: the nearest of 33 samples, then Newton steps on
    /// (C(t) − p)·C′(t) = 0 kept in the edge.
    fn nearest(&self, p: Vec3) -> (f64, f64) {
        let range = (
            self.range.0.min(self.range.1),
            self.range.0.max(self.range.1),
        );
        let curve = |t: f64| {
            let w = self.wrap(t);
            let (d1, d2) = (self.curve.der(w), self.curve.der2(w));
            [self.point(t), [d1.x, d1.y, d1.z], [d2.x, d2.y, d2.z]]
        };
        fairsurf::nearest_parameter(curve, range, p)
    }
}

/// How far a file's vertices and edge curves may lie from the faces they
/// bound (at least; 1e-8 of the face's size when larger): CAD systems write
/// edge curves that approximate their faces' boundaries (Open CASCADE's
/// edges of a rational face's iso-lines were 1.1e-7 off in a test).
const EDGE_TOLERANCE: f64 = 1e-6;

/// [`EDGE_TOLERANCE`], or 1e-8 of the size of the loop's vertices.
fn edge_tolerance(edges: &[LoopEdge]) -> f64 {
    let pts: Vec<Vec3> = edges.iter().map(|e| e.start).collect();
    (1e-8 * fairsurf::vector::bounding_diagonal(&pts)).max(EDGE_TOLERANCE)
}

/// 1e-9 of the size of the loop's vertices, at least 1e-7.
fn loop_tolerance(edges: &[LoopEdge]) -> f64 {
    let pts: Vec<Vec3> = edges.iter().map(|e| e.start).collect();
    (1e-9 * fairsurf::vector::bounding_diagonal(&pts)).max(1e-7)
}

/// A B-spline or NURBS surface of the file.
fn spline(s: &StepSurface) -> std::result::Result<(&'static str, FaceSurface), String> {
    type Net = Vec<Vec<Vec3>>;
    type Knots = (Vec<f64>, Vec<f64>);
    let (knots, points, weights): (Knots, Net, Option<Vec<f64>>) = match s {
        StepSurface::BSplineSurface(b) => (
            (b.uknot_vec().to_vec(), b.vknot_vec().to_vec()),
            b.control_points()
                .iter()
                .map(|row| row.iter().map(|p| v3(*p)).collect())
                .collect(),
            None,
        ),
        StepSurface::NurbsSurface(n) => {
            let b = n.non_rationalized();
            let cp = b.control_points();
            if cp.iter().flatten().any(|p| !(p.w.is_finite() && p.w > 0.0)) {
                return Err("a rational B-spline face with a weight that is not positive".into());
            }
            (
                (b.uknot_vec().to_vec(), b.vknot_vec().to_vec()),
                cp.iter()
                    .map(|row| {
                        row.iter()
                            .map(|p| [p.x / p.w, p.y / p.w, p.z / p.w])
                            .collect()
                    })
                    .collect(),
                Some(cp.iter().flatten().map(|p| p.w).collect()),
            )
        }
        _ => unreachable!("called for B-spline surfaces"),
    };
    let (cu, cv) = (points.len(), points.first().map_or(0, Vec::len));
    if points.iter().any(|r| r.len() != cv) {
        return Err(format!(
            "a control net of {cu} rows that are not all {cv} long"
        ));
    }
    if cu < 2 || cv < 2 {
        return Err(format!(
            "a control net of {cu} × {cv} points: a surface needs at least 2 × 2"
        ));
    }
    let (p, q) = (
        knots.0.len().saturating_sub(cu + 1),
        knots.1.len().saturating_sub(cv + 1),
    );
    let kv = |d: usize, k: Vec<f64>, name: &str| {
        KnotVector::new(d, k).map_err(|e| format!("its {name} knots: {e}"))
    };
    let u = kv(p, knots.0, "u")?;
    let v = kv(q, knots.1, "v")?;
    let net = BSplineSurface::new(u, v, points.into_iter().flatten().collect())
        .map_err(|e| e.to_string())?;
    match weights {
        None => Ok(("B-spline", FaceSurface::Polynomial(net))),
        Some(w) => {
            let r = RationalSurface::new(net, w).map_err(|e| e.to_string())?;
            Ok(if r.is_polynomial() {
                ("B-spline", FaceSurface::Polynomial(r.net().clone()))
            } else {
                ("rational B-spline", FaceSurface::Rational(r))
            })
        }
    }
}

fn eval(s: &FaceSurface, u: f64, v: f64) -> Vec3 {
    match s {
        FaceSurface::Polynomial(b) => b.eval(u, v),
        FaceSurface::Rational(r) => r.eval(u, v),
    }
}

fn net(s: &FaceSurface) -> &BSplineSurface {
    match s {
        FaceSurface::Polynomial(b) => b,
        FaceSurface::Rational(r) => r.net(),
    }
}

fn derivatives(s: &FaceSurface, u: f64, v: f64) -> fairsurf::SurfaceDerivatives {
    match s {
        FaceSurface::Polynomial(b) => b.derivatives(u, v),
        FaceSurface::Rational(r) => r.derivatives(u, v),
    }
}

/// The parameters of the point of `s` nearest to p, and the distance: the
/// best of a 17 × 17 grid, then Newton steps on (S − p)·S_u = (S − p)·S_v
/// = 0 kept in the domain.
fn nearest(s: &FaceSurface, p: Vec3) -> ((f64, f64), f64) {
    let (ku, kv) = net(s).knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    let (mut best, mut at) = (f64::MAX, (a, c));
    for i in 0..=16 {
        for j in 0..=16 {
            let (u, v) = (a + (b - a) * i as f64 / 16.0, c + (d - c) * j as f64 / 16.0);
            let e = dist(eval(s, u, v), p);
            if e < best {
                (best, at) = (e, (u, v));
            }
        }
    }
    foot(&|u, v| derivatives(s, u, v), p, at, best, ((a, b), (c, d)))
}

/// Newton steps on (S − p)·S_u = (S − p)·S_v = 0 from `at` (at `best`
/// from p), kept in `domain`, while they bring the point closer: the
/// parameters of the foot of p and its distance.
fn foot(
    s: &dyn Fn(f64, f64) -> fairsurf::SurfaceDerivatives,
    p: Vec3,
    mut at: (f64, f64),
    mut best: f64,
    ((a, b), (c, d)): ((f64, f64), (f64, f64)),
) -> ((f64, f64), f64) {
    let dot = fairsurf::vector::dot;
    for _ in 0..40 {
        let (u, v) = at;
        let x = s(u, v);
        let r = fairsurf::vector::sub(x.point, p);
        let (f1, f2) = (dot(r, x.du), dot(r, x.dv));
        let a11 = dot(x.du, x.du) + dot(r, x.duu);
        let a12 = dot(x.du, x.dv) + dot(r, x.duv);
        let a22 = dot(x.dv, x.dv) + dot(r, x.dvv);
        let det = a11 * a22 - a12 * a12;
        if det == 0.0 || det.is_nan() {
            break;
        }
        let next = (
            (u - (a22 * f1 - a12 * f2) / det).clamp(a, b),
            (v - (a11 * f2 - a12 * f1) / det).clamp(c, d),
        );
        let e = dist(s(next.0, next.1).point, p);
        if e.is_nan() || e >= best {
            break;
        }
        (best, at) = (e, next);
    }
    (at, best)
}

/// The face's surface cut to the parameter rectangle its loop bounds: the
/// whole surface when the loop runs around its four sides, else (Open
/// CASCADE's `MakeFace(surface, u0, u1, v0, v1)`) the surface cut to the
/// rectangle exactly (knot insertion). A side may be made of several
/// edges (a writer splits a side where another face's corner lies on it).
/// Checked: every vertex and edge lies on the rectangle's sides, each of
/// its corners is a vertex, and its sides lie on the edges. Other trimmed
/// faces are refused.
fn restricted(s: FaceSurface, edges: &[LoopEdge]) -> std::result::Result<FaceSurface, String> {
    let tol = edge_tolerance(edges);
    let trimmed = |why: &str| {
        format!(
            "the face is trimmed ({why}): only faces bounded by the four sides of a parameter \
             rectangle of their surface are filled around so far"
        )
    };
    // The parameters of every vertex and of seven points inside every edge
    // (each found by Newton steps from the point before it).
    let (ku, kv) = net(&s).knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    let mut vertices = Vec::with_capacity(edges.len());
    let mut inside = Vec::with_capacity(7 * edges.len());
    for e in edges {
        let (mut uv, off) = nearest(&s, e.start);
        if off > tol {
            return Err(trimmed(&format!("a vertex is {off:e} off its surface")));
        }
        vertices.push(uv);
        for k in 1..8 {
            let p = e.at(k as f64 / 8.0).0;
            let start = dist(eval(&s, uv.0, uv.1), p);
            let ders = |u: f64, v: f64| derivatives(&s, u, v);
            let (mut q, mut off) = foot(&ders, p, uv, start, ((a, b), (c, d)));
            if off > tol {
                (q, off) = nearest(&s, p);
            }
            if off > tol {
                return Err(trimmed(&format!("an edge is {off:e} off its surface")));
            }
            inside.push(q);
            uv = q;
        }
    }
    let (eu, ev) = (1e-6 * (b - a), 1e-6 * (d - c));
    // Which sides of [u0, u1] × [v0, v1] a parameter pair lies on.
    let sides = |(u, v): (f64, f64), [u0, u1, v0, v1]: [f64; 4]| {
        [
            (u - u0).abs() <= eu,
            (u - u1).abs() <= eu,
            (v - v0).abs() <= ev,
            (v - v1).abs() <= ev,
        ]
    };
    // The whole surface: every vertex a corner of it in space (a side may
    // be collapsed to a point, and then has no edge) and every edge along
    // the domain's sides.
    let corners = [
        eval(&s, a, c),
        eval(&s, b, c),
        eval(&s, a, d),
        eval(&s, b, d),
    ];
    let whole = edges
        .iter()
        .all(|e| corners.iter().any(|k| dist(*k, e.start) <= tol))
        && inside
            .iter()
            .all(|&uv| sides(uv, [a, b, c, d]).iter().any(|&on| on));
    if whole {
        return Ok(s);
    }
    if edges.len() < 4 {
        return Err(trimmed(&format!("its loop has {} edges", edges.len())));
    }
    let range = |pick: fn(&(f64, f64)) -> f64| {
        let xs: Vec<f64> = vertices.iter().map(pick).collect();
        (
            xs.iter().copied().fold(f64::MAX, f64::min),
            xs.iter().copied().fold(f64::MIN, f64::max),
        )
    };
    let ((u0, u1), (v0, v1)) = (range(|p| p.0), range(|p| p.1));
    // Every vertex and edge point on a side of [u0, u1] × [v0, v1], each
    // corner a vertex once.
    let rect = [u0, u1, v0, v1];
    if inside
        .iter()
        .chain(&vertices)
        .any(|&uv| !sides(uv, rect).iter().any(|&on| on))
    {
        return Err(trimmed(
            "its boundary does not run along the sides of a parameter rectangle",
        ));
    }
    let mut corners = [0; 4];
    for &uv in &vertices {
        let [lo_u, hi_u, lo_v, hi_v] = sides(uv, rect);
        if (lo_u || hi_u) && (lo_v || hi_v) {
            corners[2 * usize::from(hi_u) + usize::from(hi_v)] += 1;
        }
    }
    if corners != [1; 4] || u1 - u0 <= eu || v1 - v0 <= ev {
        return Err(trimmed(
            "its vertices are not the corners of a parameter rectangle",
        ));
    }
    let snap = |x: f64, lo: f64, hi: f64, e: f64| {
        if (x - lo).abs() <= e {
            lo
        } else if (x - hi).abs() <= e {
            hi
        } else {
            x
        }
    };
    let (u0, u1) = (snap(u0, a, b, eu), snap(u1, a, b, eu));
    let (v0, v1) = (snap(v0, c, d, ev), snap(v1, c, d, ev));
    let cut = |x: &BSplineSurface| x.restricted_u(u0, u1)?.restricted_v(v0, v1);
    let sub = match &s {
        FaceSurface::Polynomial(p) => FaceSurface::Polynomial(cut(p).map_err(|e| e.to_string())?),
        FaceSurface::Rational(r) => {
            // The homogeneous surfaces w·P and w cut alike.
            let scaled = |f: &dyn Fn(usize) -> Vec3| {
                BSplineSurface::new(
                    r.net().knots().0.clone(),
                    r.net().knots().1.clone(),
                    (0..r.weights().len()).map(f).collect(),
                )
            };
            let w = r.weights();
            let pts = r.net().points();
            let num = scaled(&|k| fairsurf::vector::scale(pts[k], w[k]))
                .and_then(|x| cut(&x))
                .map_err(|e| e.to_string())?;
            let den = scaled(&|k| [w[k], 0.0, 0.0])
                .and_then(|x| cut(&x))
                .map_err(|e| e.to_string())?;
            let weights: Vec<f64> = den.points().iter().map(|p| p[0]).collect();
            let points = num
                .points()
                .iter()
                .zip(&weights)
                .map(|(p, w)| fairsurf::vector::scale(*p, 1.0 / w))
                .collect();
            let (nu, nv) = num.knots();
            let net =
                BSplineSurface::new(nu.clone(), nv.clone(), points).map_err(|e| e.to_string())?;
            FaceSurface::Rational(RationalSurface::new(net, weights).map_err(|e| e.to_string())?)
        }
    };
    // Its four sides lie on the face's edges.
    let (ku, kv) = net(&sub).knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    for k in 0..=8 {
        let t = k as f64 / 8.0;
        for (u, v) in [
            (a + (b - a) * t, c),
            (a + (b - a) * t, d),
            (a, c + (d - c) * t),
            (b, c + (d - c) * t),
        ] {
            let p = eval(&sub, u, v);
            let off = edges.iter().map(|e| e.distance(p)).fold(f64::MAX, f64::min);
            if off > tol {
                return Err(trimmed(&format!(
                    "its edges are not the sides of a parameter rectangle (off by {off:e})"
                )));
            }
        }
    }
    Ok(sub)
}

/// A plane face bounded by four straight edges: the bilinear patch of its
/// corners (exactly the face when the quadrilateral is convex).
fn plane(edges: &[LoopEdge]) -> std::result::Result<FaceSurface, String> {
    let tol = loop_tolerance(edges);
    let straight = edges.iter().filter(|e| e.straight(tol)).count();
    if edges.len() != 4 || straight != 4 {
        let n = edges.len();
        return Err(format!(
            "a plane face bounded by {n} edge{}{}: only planes bounded by four straight edges \
             are filled around so far",
            if n == 1 { "" } else { "s" },
            match (n, straight) {
                (1, 0) => ", not straight".to_string(),
                (n, s) if s < n => format!(", {} not straight", n - s),
                _ => String::new(),
            }
        ));
    }
    let c: Vec<Vec3> = edges.iter().map(|e| e.start).collect();
    // A convex quadrilateral: the turn at every corner the same way.
    let turn = |k: usize| {
        let (a, b, d) = (c[(k + 3) % 4], c[k], c[(k + 1) % 4]);
        fairsurf::vector::cross(fairsurf::vector::sub(b, a), fairsurf::vector::sub(d, b))
    };
    let n0 = turn(0);
    if (1..4).any(|k| fairsurf::vector::dot(turn(k), n0) <= 0.0) {
        return Err("a plane face whose four corners are not a convex quadrilateral".into());
    }
    let net = BSplineSurface::new(
        KnotVector::bezier(1),
        KnotVector::bezier(1),
        vec![c[0], c[3], c[1], c[2]],
    )
    .map_err(|e| e.to_string())?;
    Ok(FaceSurface::Polynomial(net))
}

/// Control points, weights and full knot vector of a rational curve.
type Arc = (Vec<Vec3>, Vec<f64>, Vec<f64>);

/// A circular arc as a rational quadratic B-spline (The NURBS Book
/// §7.5): pieces of at most 90°, each with its end points, the meeting
/// point of its end tangents, and weights 1, cos(φ/2), 1; double interior
/// knots. Control points, weights, full knot vector.
fn arc(e: &LoopEdge) -> std::result::Result<Arc, String> {
    let (_, pieces) = e.turning();
    let (mut points, mut weights) = (vec![e.start], vec![1.0]);
    let mut knots = vec![0.0; 3];
    for k in 0..pieces {
        let (s0, s1) = (k as f64 / pieces as f64, (k + 1) as f64 / pieces as f64);
        let ((p0, t0), (p2, t2)) = (e.at(s0), e.at(s1));
        // p0 + a t0 = p2 - b t2, least squares in (a, b).
        let r = fairsurf::vector::sub(p2, p0);
        let dot = fairsurf::vector::dot;
        let (g11, g12, g22) = (dot(t0, t0), dot(t0, t2), dot(t2, t2));
        let (r1, r2) = (dot(t0, r), dot(t2, r));
        let det = g11 * g22 - g12 * g12;
        if det.abs() <= 1e-12 * g11 * g22 {
            return Err("an edge that is neither straight nor an arc of less than 360°".into());
        }
        let a = (r1 * g22 - r2 * g12) / det;
        let p1 = fairsurf::vector::add(p0, fairsurf::vector::scale(t0, a));
        let phi = fairsurf::vector::angle(t0, t2);
        points.extend([p1, p2]);
        weights.extend([(phi / 2.0).cos(), 1.0]);
        let t = s1;
        knots.extend(if k + 1 == pieces {
            vec![1.0; 3]
        } else {
            vec![t, t]
        });
    }
    Ok((points, weights, knots))
}

/// A cylinder or cone face bounded by two circular arcs and two straight
/// rulings: the rational ruled surface between the two arcs (exact when
/// the arcs are coaxial circles, checked against the face's edges).
fn ruled(edges: &[LoopEdge]) -> std::result::Result<FaceSurface, String> {
    let tol = loop_tolerance(edges);
    let straight: Vec<bool> = edges.iter().map(|e| e.straight(tol)).collect();
    let refuse = || {
        format!(
            "a cylinder or cone face bounded by {} edges that are not two arcs and two rulings, \
             alternating: only such faces are filled around so far",
            edges.len()
        )
    };
    if edges.len() != 4 {
        return Err(refuse());
    }
    let Some(first) = (0..4).find(|&k| !straight[k] && straight[(k + 1) % 4]) else {
        return Err(refuse());
    };
    if straight[(first + 2) % 4] || !straight[(first + 3) % 4] {
        return Err(refuse());
    }
    let a = &edges[first];
    let b = &edges[(first + 2) % 4];
    let (pa, wa, knots) = arc(a)?;
    // B runs against A in the loop: its arc from its end to its start.
    let (pb, wb, kb) = arc(&b.reversed())?;
    if pa.len() != pb.len() || kb != knots || wa.iter().zip(&wb).any(|(x, y)| (x - y).abs() > 1e-9)
    {
        return Err("a cylinder or cone face whose two arcs do not turn by the same angle".into());
    }
    let points: Vec<Vec3> = pa.iter().zip(&pb).flat_map(|(p, q)| [*p, *q]).collect();
    let weights: Vec<f64> = wa.iter().flat_map(|&w| [w, w]).collect();
    let u = KnotVector::new(2, knots).map_err(|e| e.to_string())?;
    let net = BSplineSurface::new(u, KnotVector::bezier(1), points).map_err(|e| e.to_string())?;
    let r = RationalSurface::new(net, weights).map_err(|e| e.to_string())?;
    // The arcs as built lie on the file's edges.
    for k in 0..=16 {
        let u = k as f64 / 16.0;
        for (v, e) in [(0.0, a), (1.0, b)] {
            let d = e.distance(r.eval(u, v));
            if d > tol {
                return Err(format!(
                    "a face edge that is not a circular arc (off the arc through its ends and \
                     tangents by {d:e})"
                ));
            }
        }
    }
    Ok(FaceSurface::Rational(r))
}

/// The circle an arc edge lies on: centre, unit normal (the arc's turning
/// sense), radius — through its ends and middle.
fn circle_of(e: &LoopEdge) -> Option<(Vec3, Vec3, f64)> {
    use fairsurf::vector::{add, cross, dot, normalize, scale, sub};
    let (a, b, c) = (e.start, e.at(0.5).0, e.end);
    let (ab, ac) = (sub(b, a), sub(c, a));
    let n = cross(ab, ac);
    let nn = dot(n, n);
    if nn.is_nan() || nn <= 1e-24 * dot(ab, ab) * dot(ac, ac) {
        return None;
    }
    // Circumcentre: a + (|ab|² (ac × n) + |ac|² (n × ab)) / (2|n|²).
    let centre = add(
        a,
        scale(
            add(
                scale(cross(ac, n), dot(ab, ab)),
                scale(cross(n, ab), dot(ac, ac)),
            ),
            0.5 / nn,
        ),
    );
    Some((centre, normalize(n)?, dist(centre, a)))
}

/// p turned by `angle` about the axis through `o` along the unit vector
/// `k` (Rodrigues).
fn rotated(p: Vec3, o: Vec3, k: Vec3, angle: f64) -> Vec3 {
    use fairsurf::vector::{add, cross, dot, scale, sub};
    let v = sub(p, o);
    let (s, c) = angle.sin_cos();
    add(
        o,
        add(
            add(scale(v, c), scale(cross(k, v), s)),
            scale(k, dot(k, v) * (1.0 - c)),
        ),
    )
}

/// A sphere or torus face bounded by four circular arcs — two parallels
/// (circles about the surface's axis) and two meridians — or a sphere
/// face bounded by one parallel and two meridians meeting at a pole, as
/// the rational biquadratic surface of revolution of one meridian (The
/// NURBS Book §8.5, algorithm A8.1; at a pole a side collapsed to a
/// point). The axis is the parallel's normal through its centre; the
/// result is checked against the face's edges (and, by the caller,
/// against the file's surface).
fn revolved(edges: &[LoopEdge], kind: &str) -> std::result::Result<FaceSurface, String> {
    use fairsurf::vector::{cross, norm, sub};
    let tol = edge_tolerance(edges);
    let refuse = |why: &str| {
        format!(
            "a {kind} face {why}: only {kind} faces bounded by two parallels and two meridians \
             (four circular arcs), or by a parallel and two meridians through a pole, are \
             filled around so far"
        )
    };
    let circles: Vec<(Vec3, Vec3, f64)> = edges
        .iter()
        .map(circle_of)
        .collect::<Option<_>>()
        .ok_or_else(|| refuse("with a straight edge"))?;
    // The parallels to try, each with the meridian that ends at its start
    // as the profile. Four arcs: opposite ones with parallel normals whose
    // centres lie on one line along them, apart or of different radii.
    let candidates: Vec<usize> = match edges.len() {
        3 => vec![0, 1, 2],
        4 => {
            let parallel = |a: usize, b: usize| {
                let ((ca, na, ra), (cb, nb, rb)) = (circles[a], circles[b]);
                let d = sub(cb, ca);
                norm(cross(na, nb)) <= 1e-9
                    && norm(cross(d, na)) <= tol
                    && (norm(d) > tol || (ra - rb).abs() > tol)
            };
            match (parallel(0, 2), parallel(1, 3)) {
                (true, _) => vec![2],
                (_, true) => vec![1],
                _ => return Err(refuse("whose arcs are not two parallels and two meridians")),
            }
        }
        n => return Err(refuse(&format!("bounded by {n} edges"))),
    };
    let n = edges.len();
    let mut missed = f64::INFINITY;
    for along in candidates {
        let profile = &edges[(along + n - 1) % n];
        let Ok(r) = revolve(profile, &edges[along], circles[along]) else {
            continue;
        };
        // Its four sides lie on the face's edges.
        let off = (0..=16)
            .flat_map(|i| {
                let t = i as f64 / 16.0;
                [(t, 0.0), (t, 1.0), (0.0, t), (1.0, t)]
            })
            .map(|(a, b)| {
                let p = r.eval(a, b);
                edges.iter().map(|e| e.distance(p)).fold(f64::MAX, f64::min)
            })
            .fold(0.0, f64::max);
        if off <= tol {
            return Ok(FaceSurface::Rational(r));
        }
        missed = missed.min(off);
    }
    Err(refuse(&format!(
        "whose edges the surface of revolution misses by {missed:e}"
    )))
}

/// The surface swept by the arc `profile` about the axis of the arc
/// `along` (its circle: centre, unit normal, radius), which starts at the
/// profile's end, through `along`'s angle: control points and weights of
/// the profile's arc pieces (≤ 90°) swept in pieces of at most 90° (the
/// middle points pushed out by 1/cos(φ/2), weights multiplied).
fn revolve(
    profile: &LoopEdge,
    along: &LoopEdge,
    (o, k, _): (Vec3, Vec3, f64),
) -> std::result::Result<RationalSurface, String> {
    use fairsurf::vector::{add, dot, scale, sub};
    // The circle's normal turns with the arc (circle_of): a positive turn.
    let (q, v, kv) = arc(profile)?;
    let (turning, pieces) = along.turning();
    let step = turning / pieces as f64;
    let half = (step / 2.0).cos();
    let (mut points, mut weights) = (Vec::new(), Vec::new());
    let mut ku = vec![0.0; 3];
    for i in 0..=2 * pieces {
        let middle = i % 2 == 1;
        for (qj, vj) in q.iter().zip(&v) {
            // The control point about the axis at its own height, pushed to
            // the tangents' meeting point in the middle of a piece.
            let foot = add(o, scale(k, dot(sub(*qj, o), k)));
            let mut p = rotated(*qj, o, k, step * i as f64 / 2.0);
            if middle {
                p = add(foot, scale(sub(p, foot), 1.0 / half));
            }
            points.push(p);
            weights.push(vj * if middle { half } else { 1.0 });
        }
        if i % 2 == 0 && i > 0 && i < 2 * pieces {
            let t = i as f64 / (2 * pieces) as f64;
            ku.extend([t, t]);
        }
    }
    ku.extend([1.0; 3]);
    let u = KnotVector::new(2, ku).map_err(|e| e.to_string())?;
    let vk = KnotVector::new(2, kv).map_err(|e| e.to_string())?;
    let net = BSplineSurface::new(u, vk, points).map_err(|e| e.to_string())?;
    RationalSurface::new(net, weights).map_err(|e| e.to_string())
}

/// The surface turned (u and v exchanged) when its normal R_u × R_v does
/// not agree with the face's (the file's surface normal, which the reader
/// has turned for a face of opposite sense, reversed again for an oriented
/// face used backwards); when `converted`, first checked to lie on the
/// file's surface.
fn oriented_like(
    s: FaceSurface,
    face: &Face,
    edges: &[LoopEdge],
    converted: bool,
) -> std::result::Result<FaceSurface, String> {
    if !converted {
        return turned(s, face.orientation);
    }
    let tol = edge_tolerance(edges);
    let (ku, kv) = net(&s).knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    let mid = ((a + b) / 2.0, (c + d) / 2.0);
    let der = match &s {
        FaceSurface::Polynomial(p) => p.derivatives(mid.0, mid.1),
        FaceSurface::Rational(r) => r.derivatives(mid.0, mid.1),
    };
    let ours = fairsurf::vector::cross(der.du, der.dv);
    let file = &face.surface;
    // The file's nearest point: its own search, then Newton steps on
    // (S − p)·S_u = (S − p)·S_v = 0 to rounding.
    let on = |p: Vec3| -> Option<((f64, f64), f64)> {
        let q = Point3::new(p[0], p[1], p[2]);
        let found = SearchNearestParameter::<D2>::search_nearest_parameter(file, q, None, 100)
            .filter(|uv| uv.0.is_finite() && uv.1.is_finite());
        // Where truck's own search fails (its sphere's at the seam: NaN),
        // the nearest of a 33 × 33 grid of a bounded parameter range.
        let uv = match (found, file.try_range_tuple()) {
            (Some(uv), _) => uv,
            (None, (Some((u0, u1)), Some((v0, v1)))) => (0..=32)
                .flat_map(|i| (0..=32).map(move |j| (i, j)))
                .map(|(i, j)| {
                    (
                        u0 + (u1 - u0) * i as f64 / 32.0,
                        v0 + (v1 - v0) * j as f64 / 32.0,
                    )
                })
                .min_by(|x, y| {
                    dist(v3(file.subs(x.0, x.1)), p).total_cmp(&dist(v3(file.subs(y.0, y.1)), p))
                })?,
            (None, _) => return None,
        };
        let w = |x: Vector3| [x.x, x.y, x.z];
        let derivatives = |u: f64, v: f64| fairsurf::SurfaceDerivatives {
            point: v3(file.subs(u, v)),
            du: w(file.uder(u, v)),
            dv: w(file.vder(u, v)),
            duu: w(file.uuder(u, v)),
            duv: w(file.uvder(u, v)),
            dvv: w(file.vvder(u, v)),
        };
        let unbounded = ((f64::MIN, f64::MAX), (f64::MIN, f64::MAX));
        let start = dist(v3(file.subs(uv.0, uv.1)), p);
        Some(foot(&derivatives, p, uv, start, unbounded))
    };
    // Points of the converted surface lie on the file's.
    for i in 0..=4 {
        for j in 0..=4 {
            let (u, v) = (a + (b - a) * i as f64 / 4.0, c + (d - c) * j as f64 / 4.0);
            let p = eval(&s, u, v);
            match on(p) {
                Some((_, e)) if e <= tol => {}
                Some((_, e)) => {
                    return Err(format!(
                        "the face as a B-spline is off the file's surface by {e:e} at ({}, {}, {})",
                        p[0], p[1], p[2]
                    ))
                }
                None => {
                    return Err("the file's surface could not be evaluated near the face".into())
                }
            }
        }
    }
    let Some(((u, v), _)) = on(der.point) else {
        return Err("the file's surface could not be evaluated near the face".into());
    };
    let n = file.normal(u, v);
    let theirs = [n.x, n.y, n.z];
    let agree = fairsurf::vector::dot(ours, theirs) > 0.0;
    turned(s, agree == face.orientation)
}

/// `s`, or with u and v exchanged (its normal reversed) unless `keep`.
fn turned(s: FaceSurface, keep: bool) -> std::result::Result<FaceSurface, String> {
    Ok(if keep {
        s
    } else {
        match s {
            FaceSurface::Polynomial(p) => FaceSurface::Polynomial(p.transposed()),
            FaceSurface::Rational(r) => {
                let (cu, cv) = r.net().counts();
                let w = r.weights();
                let weights = (0..cv)
                    .flat_map(|j| (0..cu).map(move |i| w[i * cv + j]))
                    .collect();
                FaceSurface::Rational(
                    RationalSurface::new(r.net().transposed(), weights)
                        .map_err(|e| e.to_string())?,
                )
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::CadSurface;
    use fairsurf::TensorPatch;

    /// fairsurf's own STEP output reads back with the same surfaces.
    #[test]
    fn a_written_shell_reads_back() {
        let a = TensorPatch::from_fn(3, 2, |i, j| [i as f64, j as f64, 0.1 * (i * j) as f64]);
        let b = TensorPatch::from_fn(3, 2, |i, j| {
            [3.0 + i as f64, j as f64, 0.3 * (i * j) as f64]
        });
        let s = BSplineSurface::new(
            KnotVector::new(3, vec![0., 0., 0., 0., 0.5, 1., 1., 1., 1.]).unwrap(),
            KnotVector::bezier(2),
            (0..15)
                .map(|k| [(k / 3) as f64, (k % 3) as f64, -1.0])
                .collect(),
        )
        .unwrap();
        let surfaces: Vec<CadSurface> = vec![(&a).into(), (&b).into(), (&s).into()];
        let text = crate::step::step_text("x.step", &surfaces);
        let faces = read_step_faces(&text).unwrap();
        assert_eq!(faces.len(), 3);
        assert_eq!(faces[0], BSplineSurface::from_bezier(&a));
        assert_eq!(faces[1], BSplineSurface::from_bezier(&b));
        assert_eq!(faces[2], s);
    }

    /// A face with a side collapsed to a point (fairsurf writes no edge
    /// for it: a loop of three edges) and a face whose side is split in
    /// two read back whole; a face trimmed inside one side is refused.
    #[test]
    fn collapsed_and_split_sides_read_back_and_a_notch_does_not() {
        // A cone-like patch: row u = 0 all at the apex.
        let cone = TensorPatch::from_fn(3, 2, |i, j| {
            let r = i as f64 / 3.0;
            [r * (j as f64 - 1.0), r * 2.0, r * r]
        });
        let text = crate::step::step_text("x.step", &[(&cone).into()]);
        assert_eq!(text.matches("=ORIENTED_EDGE(").count(), 3, "{text}");
        let faces = read_step_faces(&text).unwrap();
        assert_eq!(faces, vec![BSplineSurface::from_bezier(&cone)]);
        // The unit square bounded by three lines and a fourth edge along
        // u = 0 that leaves the side at 3/8 of the way (a notch the edge's
        // midpoint does not see).
        use truck_stepio::r#in::alias::{BSplineCurve, KnotVec, Line};
        use truck_topology::compress::CompressedEdge;
        let square = BSplineSurface::new(
            KnotVector::bezier(1),
            KnotVector::bezier(1),
            vec![[0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
        )
        .unwrap();
        let pt = |x: f64, y: f64| Point3::new(x, y, 0.0);
        let corners = vec![pt(0.0, 0.0), pt(1.0, 0.0), pt(1.0, 1.0), pt(0.0, 1.0)];
        let line = |a: usize, b: usize| Curve3D::Line(Line(corners[a], corners[b]));
        let side = |notch: f64| {
            let pts: Vec<Point3> = (0..=8)
                .map(|k| pt(if k == 3 { notch } else { 0.0 }, 1.0 - k as f64 / 8.0))
                .collect();
            let mut knots = vec![0.0];
            knots.extend((0..=8).map(|k| k as f64 / 8.0));
            knots.push(1.0);
            Curve3D::BSplineCurve(BSplineCurve::new(KnotVec::from(knots), pts))
        };
        for (notch, accepted) in [(0.0, true), (0.1, false)] {
            let shell = Shell {
                vertices: corners.clone(),
                edges: vec![
                    CompressedEdge {
                        vertices: (0, 1),
                        curve: line(0, 1),
                    },
                    CompressedEdge {
                        vertices: (1, 2),
                        curve: line(1, 2),
                    },
                    CompressedEdge {
                        vertices: (2, 3),
                        curve: line(2, 3),
                    },
                    CompressedEdge {
                        vertices: (3, 0),
                        curve: side(notch),
                    },
                ],
                faces: vec![],
            };
            let edges: Vec<LoopEdge> = (0..4)
                .map(|k| LoopEdge::new(&shell, CompressedEdgeIndex::from((k, true))).unwrap())
                .collect();
            let got = restricted(FaceSurface::Polynomial(square.clone()), &edges);
            match got {
                Ok(FaceSurface::Polynomial(s)) => assert!(accepted && s == square),
                Err(e) => assert!(!accepted && e.contains("does not run along"), "{e}"),
                other => panic!("{other:?}"),
            }
        }
    }

    #[test]
    fn what_is_not_read_is_said() {
        let e = read_step_faces("not a step file").unwrap_err().to_string();
        assert!(e.contains("not a STEP file"), "{e}");
        let a = TensorPatch::from_fn(1, 1, |i, j| [i as f64, j as f64, 0.0]);
        let text = crate::step::step_text("x.step", &[(&a).into()]);
        let e = read_step_faces(&text.replace("OPEN_SHELL", "OPEN_SHELF"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no shell"), "{e}");
        // The surface made another through the file's own placement.
        let axes = text
            .lines()
            .find(|l| l.contains("=AXIS2_PLACEMENT_3D("))
            .and_then(|l| l.split('=').next())
            .unwrap();
        let with = |entity: &str| -> String {
            text.lines()
                .map(|l| match l.split_once("=B_SPLINE_SURFACE_WITH_KNOTS(") {
                    Some((id, _)) => format!("{id}={entity};\n"),
                    None => format!("{l}\n"),
                })
                .collect()
        };
        // A plane through the square's corners: read as the bilinear patch.
        let faces = read_step(&with(&format!("PLANE('',{axes})"))).unwrap();
        assert_eq!(faces[0].kind, "plane");
        let FaceSurface::Polynomial(s) = &faces[0].surface else {
            panic!("a plane is polynomial")
        };
        assert_eq!(
            s.points(),
            &[[0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]
        );
        let e = read_step(&with(&format!("SPHERICAL_SURFACE('',{axes},1.)")))
            .unwrap_err()
            .to_string();
        assert!(e.contains("a sphere face"), "{e}");
        // A plane the face's edges are not on.
        let tilted = text.replace("DIRECTION('',(0.,0.,1.))", "DIRECTION('',(0.,0.6,0.8))");
        let (id, _) = tilted
            .lines()
            .find_map(|l| l.split_once("=B_SPLINE_SURFACE_WITH_KNOTS("))
            .unwrap();
        let tilted: String = tilted
            .lines()
            .map(|l| {
                if l.starts_with(&format!("{id}=")) {
                    format!("{id}=PLANE('',{axes});\n")
                } else {
                    format!("{l}\n")
                }
            })
            .collect();
        let e = read_step(&tilted).unwrap_err().to_string();
        assert!(e.contains("off the file's surface"), "{e}");
    }

    /// An edge on a closed curve whose vertices lie on either side of the
    /// curve's seam runs through the seam (the short way its curve runs),
    /// not back across the whole curve; on an open curve that order is an
    /// error.
    #[test]
    fn an_edge_runs_through_its_closed_curve_s_seam() {
        use truck_stepio::r#in::alias::{BSplineCurve, KnotVec};
        use truck_topology::compress::CompressedEdge;
        // The unit square's outline, degree 1, from (0, 0) round to (0, 0).
        let square = [[0., 0.], [1., 0.], [1., 1.], [0., 1.], [0., 0.]]
            .map(|[x, y]| Point3::new(x, y, 0.0))
            .to_vec();
        let knots = KnotVec::from(vec![0., 0., 1., 2., 3., 4., 4.]);
        let curve = Curve3D::BSplineCurve(BSplineCurve::new(knots.clone(), square.clone()));
        let shell = |curve: Curve3D, [a, b]: [[f64; 2]; 2]| Shell {
            vertices: vec![Point3::new(a[0], a[1], 0.0), Point3::new(b[0], b[1], 0.0)],
            edges: vec![CompressedEdge {
                vertices: (0, 1),
                curve,
            }],
            faces: vec![],
        };
        let s = shell(curve, [[0.0, 0.5], [0.5, 0.0]]);
        for orientation in [true, false] {
            let e = LoopEdge::new(&s, CompressedEdgeIndex::from((0, orientation))).unwrap();
            let mid = e.at(0.5).0;
            assert!(dist(mid, [0.0; 3]) < 1e-15, "{mid:?}");
            assert!(e.distance([1.0, 1.0, 0.0]) > 0.7);
            assert!(e.distance([0.0, 0.25, 0.0]) < 1e-15);
            assert!(!e.straight(1e-9));
        }
        // Vertices in that order on the open curve that stops short of
        // closing.
        let open = Curve3D::BSplineCurve(BSplineCurve::new(
            KnotVec::from(vec![0., 0., 1., 2., 3., 3.]),
            square[..4].to_vec(),
        ));
        let s = shell(open, [[0.5, 1.0], [1.0, 0.5]]);
        let e = LoopEdge::new(&s, CompressedEdgeIndex::from((0, true))).err();
        assert!(e.unwrap().contains("from its end vertex to its start"));
    }

    /// A straight edge is straight whatever its parameterization.
    #[test]
    fn a_straight_edge_unevenly_parameterized_is_straight() {
        use truck_stepio::r#in::alias::{BSplineCurve, KnotVec};
        use truck_topology::compress::CompressedEdge;
        let pts = [0.0, 0.1, 0.2, 1.0]
            .map(|x| Point3::new(x, 2.0 * x, 0.0))
            .to_vec();
        let curve = BSplineCurve::new(KnotVec::bezier_knot(3), pts);
        let s = Shell {
            vertices: vec![Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 2.0, 0.0)],
            edges: vec![CompressedEdge {
                vertices: (0, 1),
                curve: Curve3D::BSplineCurve(curve),
            }],
            faces: vec![],
        };
        let e = LoopEdge::new(&s, CompressedEdgeIndex::from((0, true))).unwrap();
        assert!(e.straight(1e-12));
        // Its points are not at equal steps along it.
        let q = e.at(0.5).0;
        assert!(dist(q, [0.5, 1.0, 0.0]) > 0.1, "{q:?}");
    }

    /// A rational surface written reads back as the same rational surface,
    /// and as an error where only polynomial faces are taken.
    #[test]
    fn a_rational_face_reads_back() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let net = BSplineSurface::new(
            KnotVector::bezier(2),
            KnotVector::bezier(1),
            vec![
                [1.0, 0.0, 0.0],
                [1.0, 0.0, 1.0],
                [1.0, 1.0, 0.0],
                [1.0, 1.0, 1.0],
                [0.0, 1.0, 0.0],
                [0.0, 1.0, 1.0],
            ],
        )
        .unwrap();
        let r = RationalSurface::new(net, vec![1.0, 1.0, h, h, 1.0, 1.0]).unwrap();
        let text = crate::step::step_text("x.step", &[(&r).into()]);
        assert!(text.contains("RATIONAL_B_SPLINE_SURFACE("), "{text}");
        assert!(text.contains("RATIONAL_B_SPLINE_CURVE("), "{text}");
        let faces = read_step(&text).unwrap();
        assert_eq!(faces[0].kind, "rational B-spline");
        let FaceSurface::Rational(back) = &faces[0].surface else {
            panic!("rational")
        };
        assert_eq!(back.net(), r.net());
        for (a, b) in back.weights().iter().zip(r.weights()) {
            assert!((a - b).abs() < 1e-15);
        }
        let e = read_step_faces(&text).unwrap_err().to_string();
        assert!(e.contains("a rational B-spline face"), "{e}");
    }
}
