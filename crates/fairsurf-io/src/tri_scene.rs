//! Scene files of triangular surfaces (`"surface": {"type": "triangular"}`;
//! Veltkamp & Wesselink): a triangle mesh, the degree of its Bézier
//! patches, energy weights, default continuity and a list of constraints.
//!
//! Field docs here become the descriptions in `fairsurf schema --triangular`.

use crate::constraints::kind_name;
use crate::operators::OperatorKind;
use crate::tri_result::SolvedTriScene;
use crate::{Error, Result};
use fairsurf::triangle::{
    Constraint, Continuity, CurveConstraint, DomainPoint, EdgeContinuity, Operator, Place,
    RegionPiece, Target, TriProblem,
};
use fairsurf::{Bend, Stretch};
use fairsurf::{BezierCurve, TriPatch, TriSurface};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::Path;

/// A scene of a triangular Bézier surface: minimize α·stretch + β·bend
/// (eq. 6–7, exact over the equilateral domain triangle of side 1, eq.
/// 25–27) subject to the constraints (eq. 31–33).
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TriScene {
    /// Free text: a title.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text: what the scene shows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The mesh and its patches.
    pub surface: TriSurfaceSpec,
    /// Fix every boundary control point at its value (default true; the
    /// paper: "at least a number of boundary points should be interpolated").
    #[serde(default = "yes")]
    pub fix_boundary: bool,
    /// The energy weights.
    #[serde(default)]
    pub energy: TriEnergySpec,
    /// The default continuity conditions (§4.3); they give way to the
    /// constraints where they conflict.
    #[serde(default)]
    pub continuity: ContinuitySpec,
    /// Interpolation constraints, in priority order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub constraints: Vec<ConstraintSpec>,
    /// External energy operators (§5): directors, attractors, repellors.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operators: Vec<OperatorSpec>,
    /// Written by `fairsurf solve` into result files; ignored on input.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(skip)]
    pub report: Option<Value>,
}

fn yes() -> bool {
    true
}

/// Only `"triangular"` here (tensor scenes have their own format).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TriangularKind {
    /// Triangular Bézier patches over a triangle mesh.
    #[default]
    Triangular,
}

/// The surface: one degree-n triangular Bézier patch per mesh triangle,
/// sharing control points along common edges (C0).
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TriSurfaceSpec {
    /// `"triangular"`.
    #[serde(rename = "type")]
    pub kind: TriangularKind,
    /// Degree n of every patch, 1 to 20 (the paper uses 3; exact G1 across
    /// edges needs n ≥ 4 on most meshes).
    pub degree: usize,
    /// Mesh vertices `[x, y, z]`.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as vertex indices, counter-clockwise about the normal.
    pub triangles: Vec<[usize; 3]>,
    /// Every global control point (vertices, then n−1 per edge in sorted
    /// vertex-pair order from the smaller vertex, then the triangles'
    /// interiors). Without it: the flat triangles raised to degree n.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_points: Option<Vec<[f64; 3]>>,
}

impl From<&TriSurface> for TriSurfaceSpec {
    /// The surface with every control point given (its mesh: the vertices'
    /// points and the patches' corners).
    fn from(s: &TriSurface) -> Self {
        TriSurfaceSpec {
            kind: TriangularKind::Triangular,
            degree: s.degree(),
            vertices: s.points()[..s.vertex_count()].to_vec(),
            triangles: s.triangles().to_vec(),
            control_points: Some(s.points().to_vec()),
        }
    }
}

/// α·stretch + β·bend; without either, bend 1.
#[derive(Clone, Debug, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TriEnergySpec {
    /// α, weight of ½∫∫|T_x|²+|T_y|², ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch: Option<f64>,
    /// β, weight of ½∫∫|T_xx|²+2|T_xy|²+|T_yy|², ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bend: Option<f64>,
}

/// Continuity conditions (§4.3).
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContinuitySpec {
    /// G1 at the vertices (eq. 9–10), default true.
    #[serde(default = "yes")]
    pub vertices: bool,
    /// Across edges: `"exact"` (eq. 11–12, default), `"relaxed"` or `"off"`.
    #[serde(default)]
    pub edges: EdgesSpec,
    /// Angles at boundary vertices; elsewhere measured in the net.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub boundary_angles: Vec<BoundaryAngleSpec>,
}

impl Default for ContinuitySpec {
    fn default() -> Self {
        Self {
            vertices: true,
            edges: EdgesSpec::Exact,
            boundary_angles: Vec::new(),
        }
    }
}

/// G1 across edges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum EdgesSpec {
    /// Exact tangent-plane continuity along every interior edge.
    #[default]
    Exact,
    /// The paper's relaxed variant (approximate).
    Relaxed,
    /// None beyond the vertices.
    Off,
}

/// The angle α the surface makes at a boundary vertex.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BoundaryAngleSpec {
    /// The boundary vertex.
    pub vertex: usize,
    /// α in degrees, in (0, 360).
    pub degrees: f64,
}

/// What a constraint is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ConstraintKind {
    /// T(at) = target.
    Point,
    /// The normal at `at` is `normal` (eq. 8).
    Normal,
    /// normal·T(at) = offset.
    InPlane,
    /// T(at) on the line through `point` along `direction`.
    OnLine,
    /// Control point `index` keeps `value` (default: its value in the net).
    Fixed,
    /// Patch edges interpolate the Bézier curve `control_points` from
    /// `from` to `to` (§4.2): the mesh is refined along it.
    Curve,
}

/// A point of the domain: a triangle and barycentrics in it.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DomainPointSpec {
    /// Triangle index.
    pub triangle: usize,
    /// Barycentrics (u, v, w) ≥ 0 summing to 1, w.r.t. the triangle's
    /// corners in the order given in `triangles`.
    pub bary: [f64; 3],
}

/// One constraint. (A plain struct with a `type` field, so errors keep
/// their JSON path; the fields a kind needs are checked when solving.)
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConstraintSpec {
    /// The kind.
    #[serde(rename = "type")]
    pub kind: ConstraintKind,
    /// A name for reports (default `constraints[i] (kind)`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Where (point, normal, in_plane, on_line).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<DomainPointSpec>,
    /// The point to pass through (point).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<[f64; 3]>,
    /// The normal (normal, in_plane).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal: Option<[f64; 3]>,
    /// The plane's offset a in normal·x = a (in_plane).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<f64>,
    /// A point of the line (on_line).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<[f64; 3]>,
    /// The line's direction (on_line).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f64; 3]>,
    /// Global control point index (fixed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub index: Option<usize>,
    /// Its value (fixed; default its value in the net).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<[f64; 3]>,
    /// The curve's Bézier control points (curve), degree ≤ the surface's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_points: Option<Vec<[f64; 3]>>,
    /// Where the curve starts (curve).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<DomainPointSpec>,
    /// Where it ends (curve).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<DomainPointSpec>,
    /// The triangles it runs through (curve; default a shortest path).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub through: Option<Vec<usize>>,
}

/// A triangular patch as an attractor surface.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PatchSpec {
    /// Its degree n.
    pub degree: usize,
    /// Its (n+1)(n+2)/2 control points P_ijk, i descending, then j.
    pub control_points: Vec<[f64; 3]>,
}

/// A convex polygon in one patch's (u, v) plane (w = 1 − u − v).
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RegionPieceSpec {
    /// The patch (triangle) index.
    pub triangle: usize,
    /// The polygon's vertices (u, v).
    pub polygon: Vec<[f64; 2]>,
}

/// One external energy operator. Give exactly one of `at`, `region`,
/// `domain_region` or `edge`.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OperatorSpec {
    /// The kind.
    #[serde(rename = "type")]
    pub kind: OperatorKind,
    /// A name for reports (default `operators[i] (kind)`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Its strength s ≥ 0 (default 1).
    #[serde(default = "crate::tensor_scene::one")]
    pub strength: f64,
    /// Make an attractor a repellor: s / E instead of s·E.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub repel: bool,
    /// Acts at one surface point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<DomainPointSpec>,
    /// Acts over convex polygons of single patches.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<Vec<RegionPieceSpec>>,
    /// Acts over a convex polygon in the (x, y) plane of the mesh as given,
    /// split across patches.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub domain_region: Option<Vec<[f64; 2]>>,
    /// The mesh edge [a, b] (curve_attractor).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge: Option<[usize; 2]>,
    /// Director or line direction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f64; 3]>,
    /// Attracting or repelling point, or a point of the line.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<[f64; 3]>,
    /// The plane's normal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal: Option<[f64; 3]>,
    /// The plane's offset a in normal·x = a.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<f64>,
    /// The attractor surface (surface_attractor).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<PatchSpec>,
    /// The attractor curve's Bézier control points (curve_attractor).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_points: Option<Vec<[f64; 3]>>,
}

const MAX_DEGREE: usize = 20;

impl TriScene {
    /// Parses a scene; errors name the JSON path.
    pub fn from_json(text: &str) -> Result<TriScene> {
        crate::scene::parse_with_path(text)
    }

    /// The problem the scene describes; errors name the field.
    pub fn problem(&self) -> Result<TriProblem> {
        let s = &self.surface;
        if s.degree == 0 || s.degree > MAX_DEGREE {
            return Err(Error::scene(
                "surface.degree",
                format!("must be 1 to {MAX_DEGREE}, got {}", s.degree),
            ));
        }
        check_domain(&s.vertices, &s.triangles)?;
        let mut surface = TriSurface::try_new(&s.vertices, &s.triangles, s.degree)
            .map_err(|e| Error::scene("surface", e.to_string()))?;
        if let Some(points) = &s.control_points {
            surface
                .set_points(points.clone())
                .map_err(|e| Error::scene("surface.control_points", e.to_string()))?;
        }
        let (stretch, bend) = match (self.energy.stretch, self.energy.bend) {
            (None, None) => (0.0, 1.0),
            (a, b) => (a.unwrap_or(0.0), b.unwrap_or(0.0)),
        };
        for (w, field) in [(stretch, "energy.stretch"), (bend, "energy.bend")] {
            if !(w.is_finite() && w >= 0.0) {
                return Err(Error::scene(
                    field,
                    format!("must be a number ≥ 0, got {w}"),
                ));
            }
        }
        let mut continuity = Continuity {
            vertices: self.continuity.vertices,
            edges: match self.continuity.edges {
                EdgesSpec::Exact => EdgeContinuity::Exact,
                EdgesSpec::Relaxed => EdgeContinuity::Relaxed,
                EdgesSpec::Off => EdgeContinuity::Off,
            },
            boundary_angles: Vec::new(),
            boundary_rules: Vec::new(),
        };
        for a in &self.continuity.boundary_angles {
            continuity
                .boundary_angles
                .push((a.vertex, a.degrees.to_radians()));
        }
        let mut problem = TriProblem::from_mesh(surface.clone())
            .with_term(Stretch::new(stretch))
            .with_term(Bend::new(bend))
            .with_continuity(continuity);
        if self.fix_boundary {
            problem = problem.with_fixed_boundary();
        }
        for (i, c) in self.constraints.iter().enumerate() {
            let path = format!("constraints[{i}]");
            let name = c
                .name
                .clone()
                .unwrap_or_else(|| format!("{path} ({})", kind_name(c.kind)));
            let need = |field: &str| {
                Error::scene(
                    format!("{path}.{field}"),
                    format!("required for a {} constraint", kind_name(c.kind)),
                )
            };
            let fields = crate::constraints::Fields {
                target: c.target,
                normal: c.normal,
                offset: c.offset,
                point: c.point,
                direction: c.direction,
            };
            let point = |p: Option<DomainPointSpec>, field: &str| {
                let p = p.ok_or_else(|| need(field))?;
                located_point(&surface, p, &format!("{path}.{field}"), &name)
            };
            let at = || point(c.at, "at");
            if let Some(constraint) = crate::constraints::located(c.kind, &path, &fields, at)? {
                problem = problem.with_constraint(name, constraint);
                continue;
            }
            let constraint = match c.kind {
                ConstraintKind::Fixed => {
                    let index = c.index.ok_or_else(|| need("index"))?;
                    let value = match c.value {
                        Some(v) => v,
                        None => *surface.points().get(index).ok_or_else(|| {
                            Error::scene(
                                format!("{path}.index"),
                                format!(
                                    "must be below {} (the control point count)",
                                    surface.point_count()
                                ),
                            )
                        })?,
                    };
                    Constraint::Fixed {
                        point: index,
                        value,
                    }
                }
                ConstraintKind::Curve => {
                    let points = c
                        .control_points
                        .clone()
                        .ok_or_else(|| need("control_points"))?;
                    if points.len() < 2 || points.iter().all(|p| *p == points[0]) {
                        return Err(Error::scene(
                            format!("{path}.control_points"),
                            "a curve needs at least two distinct control points \
                             (a single point is a \"point\" constraint)",
                        ));
                    }
                    let curve = BezierCurve::try_new(points).map_err(|e| {
                        Error::scene(format!("{path}.control_points"), e.to_string())
                    })?;
                    let (from, to) = (point(c.from, "from")?, point(c.to, "to")?);
                    problem = problem.with_curve(CurveConstraint {
                        name,
                        curve,
                        from,
                        to,
                        through: c.through.clone(),
                    });
                    continue;
                }
                // Built by `located` above.
                ConstraintKind::Point
                | ConstraintKind::Normal
                | ConstraintKind::InPlane
                | ConstraintKind::OnLine => continue,
            };
            problem = problem.with_constraint(name, constraint);
        }
        for (i, o) in self.operators.iter().enumerate() {
            let op = operator(o, i)?;
            if let Some(at) = o.at {
                located_point(&surface, at, &format!("operators[{i}].at"), &op.name)?;
            }
            problem = problem.with_operator(op);
        }
        Ok(problem)
    }

    /// Reads and parses a scene file.
    pub fn read(path: &Path) -> Result<TriScene> {
        Self::from_json(&crate::scene::read_text(path)?)
    }

    /// The JSON Schema of triangular scene files.
    pub fn json_schema() -> Value {
        serde_json::to_value(schemars::schema_for!(TriScene)).expect("a schema serializes")
    }

    /// Solves the scene.
    pub fn solve(&self) -> Result<SolvedTriScene> {
        self.solve_using(None)
    }

    /// Solves, reusing a KKT factorization the cache kept when only fixed
    /// values, targets, plane offsets or operator targets differ (the
    /// editor's drags); the same answer as [`Self::solve`] to rounding.
    pub fn solve_cached(&self, cache: &fairsurf::FactorCache) -> Result<SolvedTriScene> {
        self.solve_using(Some(cache))
    }

    fn solve_using(&self, cache: Option<&fairsurf::FactorCache>) -> Result<SolvedTriScene> {
        let problem = self.problem()?;
        let solution = match cache {
            Some(c) => c.solve_triangular(&problem)?,
            None => problem.solve()?,
        };
        Ok(SolvedTriScene {
            scene: self.clone(),
            solution,
        })
    }

    /// The surface as written in the file (a result file's solved points).
    pub fn surface(&self) -> Result<TriSurface> {
        Ok(self.problem()?.surface().clone())
    }
}

/// Vertices within the coordinate limit, and triangles with three corners
/// not on a line: area above 1e-12 of the squared bounding diagonal (a
/// zero-area triangle has no tangent plane; its curvature was 2e31).
fn check_domain(vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> Result<()> {
    let limit = crate::validate::MAX_COORDINATE;
    for (k, v) in vertices.iter().enumerate() {
        if let Some(c) = v.iter().position(|x| !x.is_finite() || x.abs() > limit) {
            return Err(Error::scene(
                format!("surface.vertices[{k}][{c}]"),
                format!(
                    "expected a finite number of magnitude at most {limit:e}, got {:e}",
                    v[c]
                ),
            ));
        }
    }
    let diagonal = fairsurf::vector::bounding_diagonal(vertices);
    for (k, t) in triangles.iter().enumerate() {
        let Some(p) = t
            .iter()
            .map(|&i| vertices.get(i))
            .collect::<Option<Vec<_>>>()
        else {
            continue; // an index out of range: TriSurface::try_new names it
        };
        use fairsurf::vector::{cross, norm, sub};
        let area = 0.5 * norm(cross(sub(*p[1], *p[0]), sub(*p[2], *p[0])));
        if area.is_nan() || area <= 1e-12 * diagonal * diagonal {
            return Err(Error::scene(
                format!("surface.triangles[{k}]"),
                format!(
                    "its corners {t:?} are equal or on a line (area {area:.1e}): a triangle \
                     needs three corners that span a plane"
                ),
            ));
        }
    }
    Ok(())
}

/// The domain point at `path`, checked against the surface's mesh (a
/// triangle index, barycentrics of a point of it); errors name the path
/// and `what` (the constraint or operator).
fn located_point(
    surface: &TriSurface,
    p: DomainPointSpec,
    path: &str,
    what: &str,
) -> Result<DomainPoint> {
    let d = domain_point(p);
    surface
        .check_point(d, what)
        .map_err(|e| Error::scene(path, e.to_string()))?;
    Ok(d)
}

pub(crate) fn domain_point(p: DomainPointSpec) -> DomainPoint {
    DomainPoint {
        triangle: p.triangle,
        bary: p.bary,
    }
}

/// The library operator of `operators[i]`; errors name the JSON path.
pub(crate) fn operator(o: &OperatorSpec, i: usize) -> Result<Operator> {
    let path = format!("operators[{i}]");
    let target = crate::operators::target(
        o.kind,
        &path,
        crate::operators::TargetFields {
            direction: o.direction,
            point: o.point,
            normal: o.normal,
            offset: o.offset,
            control_points: o.control_points.as_deref(),
        },
        || {
            let p = o.surface.as_ref().ok_or_else(|| {
                Error::scene(
                    format!("{path}.surface"),
                    "required for a surface_attractor",
                )
            })?;
            let patch = TriPatch::try_new(p.degree, p.control_points.clone()).map_err(|e| {
                Error::scene(format!("{path}.surface.control_points"), e.to_string())
            })?;
            Ok(Target::Surface(patch))
        },
    )?;
    let places = [
        o.at.is_some(),
        o.region.is_some(),
        o.domain_region.is_some(),
        o.edge.is_some(),
    ];
    if places.iter().filter(|&&p| p).count() != 1 {
        return Err(Error::scene(
            path,
            "give exactly one of `at`, `region`, `domain_region` and `edge`".to_string(),
        ));
    }
    let place = if let Some(at) = o.at {
        Place::Point(domain_point(at))
    } else if let Some(r) = &o.region {
        Place::Patches(
            r.iter()
                .map(|p| RegionPiece {
                    triangle: p.triangle,
                    polygon: p.polygon.clone(),
                })
                .collect(),
        )
    } else if let Some(d) = &o.domain_region {
        Place::Domain(d.clone())
    } else {
        Place::Edge(o.edge.expect("one place"))
    };
    Ok(Operator {
        name: crate::operators::name(o.name.as_deref(), &path, o.kind),
        target,
        place,
        strength: o.strength,
        repel: o.repel || o.kind == OperatorKind::Repellor,
    })
}

/// Gives an operator entry its region as per-patch pieces.
pub(crate) fn set_region(o: &mut OperatorSpec, pieces: Vec<RegionPiece>) {
    o.domain_region = None;
    o.region = Some(
        pieces
            .into_iter()
            .map(|p| RegionPieceSpec {
                triangle: p.triangle,
                polygon: p.polygon,
            })
            .collect(),
    );
}
