//! External energy operators in scene files (Veltkamp & Wesselink §5): the
//! kinds and target fields shared by triangular and tensor-product scenes,
//! the tensor scenes' operator entries, and the operators' report JSON.

use crate::{Error, Result};
use fairsurf::operator::{
    NewtonReport, Operator, OperatorOutcome, PatchEdge, Target, TensorOperator, TensorPlace,
};
use fairsurf::{BezierCurve, TensorPatch};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

/// What an operator pulls toward.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum OperatorKind {
    /// The normal toward `direction` (eq. 13–14).
    Director,
    /// Toward `point` (eq. 15–16).
    PointAttractor,
    /// Toward the plane `normal`·x = `offset` (eq. 17–18).
    PlaneAttractor,
    /// Toward the line through `point` along `direction` (eq. 20–21).
    LineAttractor,
    /// A triangular `region` toward the triangular patch `surface`
    /// (eq. 19), corner to corner.
    SurfaceAttractor,
    /// The mesh `edge` toward the Bézier curve `control_points` (eq. 22).
    CurveAttractor,
    /// Away from `point`: 1/‖S − P‖² (eq. 23); any attractor can also be
    /// made a repellor with `"repel": true`.
    Repellor,
}

/// The target's fields of an operator entry, as given.
pub(crate) struct TargetFields<'a> {
    pub direction: Option<[f64; 3]>,
    pub point: Option<[f64; 3]>,
    pub normal: Option<[f64; 3]>,
    pub offset: Option<f64>,
    pub control_points: Option<&'a [[f64; 3]]>,
}

/// The kind as reports and messages name it.
pub(crate) fn kind_name(k: OperatorKind) -> &'static str {
    match k {
        OperatorKind::Director => "director",
        OperatorKind::PointAttractor => "point_attractor",
        OperatorKind::PlaneAttractor => "plane_attractor",
        OperatorKind::LineAttractor => "line_attractor",
        OperatorKind::SurfaceAttractor => "surface_attractor",
        OperatorKind::CurveAttractor => "curve_attractor",
        OperatorKind::Repellor => "repellor",
    }
}

/// The operator's name: given, or `operators[i] (kind)`.
pub(crate) fn name(given: Option<&str>, path: &str, kind: OperatorKind) -> String {
    given.map_or_else(|| format!("{path} ({})", kind_name(kind)), str::to_string)
}

/// The library target of the entry at `path`; `surface` builds a
/// surface attractor's (its form differs by scene kind). Errors name the
/// JSON path of the missing or bad field.
pub(crate) fn target(
    kind: OperatorKind,
    path: &str,
    f: TargetFields<'_>,
    surface: impl FnOnce() -> Result<Target>,
) -> Result<Target> {
    let need = |field: &str| {
        Error::scene(
            format!("{path}.{field}"),
            format!("required for a {}", kind_name(kind)),
        )
    };
    Ok(match kind {
        OperatorKind::Director => Target::Direction(f.direction.ok_or_else(|| need("direction"))?),
        OperatorKind::PointAttractor | OperatorKind::Repellor => {
            Target::Point(f.point.ok_or_else(|| need("point"))?)
        }
        OperatorKind::PlaneAttractor => Target::Plane {
            normal: f.normal.ok_or_else(|| need("normal"))?,
            offset: f.offset.ok_or_else(|| need("offset"))?,
        },
        OperatorKind::LineAttractor => Target::Line {
            point: f.point.ok_or_else(|| need("point"))?,
            direction: f.direction.ok_or_else(|| need("direction"))?,
        },
        OperatorKind::SurfaceAttractor => surface()?,
        OperatorKind::CurveAttractor => {
            let points = f.control_points.ok_or_else(|| need("control_points"))?;
            Target::Curve(
                BezierCurve::try_new(points.to_vec())
                    .map_err(|e| Error::scene(format!("{path}.control_points"), e.to_string()))?,
            )
        }
    })
}

/// A boundary curve of a tensor patch in scene files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum EdgeSpec {
    /// u = 0: the control points of row 0, the curve's t = v.
    U0,
    /// u = 1: the last row, t = v.
    U1,
    /// v = 0: column 0, t = u.
    V0,
    /// v = 1: the last column, t = u.
    V1,
}

/// A tensor-product patch as an attractor surface.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TensorPatchSpec {
    /// `[n, m]`: its degree (any, independent of the surface's).
    pub degree: [usize; 2],
    /// (n+1) rows of (m+1) points `[x, y, z]`.
    pub control_points: Vec<Vec<[f64; 3]>>,
}

/// One external energy operator on a tensor-product patch (Veltkamp &
/// Wesselink §5 with the tensor basis). Give exactly one of `at`, `region`
/// and `edge`.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TensorOperatorSpec {
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
    /// Acts at one surface point `[u, v]` in [0, 1]².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<[f64; 2]>,
    /// Acts over a convex polygon of `[u, v]` vertices in [0, 1]²
    /// (dA = du dv, integrated exactly).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<Vec<[f64; 2]>>,
    /// A boundary curve of the patch (curve_attractor).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge: Option<EdgeSpec>,
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
    /// The attractor surface T (surface_attractor): S(u, v) toward T(u, v).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<TensorPatchSpec>,
    /// The attractor curve's Bézier control points (curve_attractor).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_points: Option<Vec<[f64; 3]>>,
}

/// The highest degree of a surface attractor's target patch.
const MAX_TARGET_DEGREE: usize = 30;

/// The library operator of a tensor scene's `operators[i]`, validated on
/// the parameter square.
pub(crate) fn tensor_operator(o: &TensorOperatorSpec, i: usize) -> Result<TensorOperator> {
    let op = unchecked_operator(o, i)?;
    op.validate()
        .map_err(|e| Error::scene(format!("operators[{i}]"), e.to_string()))?;
    Ok(op)
}

/// The library operator of `operators[i]` as written (its place checked
/// by the surface it acts on).
pub(crate) fn unchecked_operator(o: &TensorOperatorSpec, i: usize) -> Result<TensorOperator> {
    let path = format!("operators[{i}]");
    let target = target(
        o.kind,
        &path,
        TargetFields {
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
            let [n, m] = p.degree;
            // The region rules grow with T's degree (their node count with
            // its square): beyond this a scene could ask for minutes.
            if let Some(k) = [n, m].iter().position(|&d| d > MAX_TARGET_DEGREE) {
                return Err(Error::scene(
                    format!("{path}.surface.degree[{k}]"),
                    format!("must be at most {MAX_TARGET_DEGREE}, got {}", [n, m][k]),
                ));
            }
            let rows = &p.control_points;
            let bad = |what: String| Error::scene(format!("{path}.surface.control_points"), what);
            if rows.len() != n.saturating_add(1)
                || rows.iter().any(|r| r.len() != m.saturating_add(1))
            {
                return Err(bad(format!(
                    "expected {} rows of {} points for degree [{n}, {m}]",
                    n + 1,
                    m + 1
                )));
            }
            let patch = TensorPatch::try_new(n, m, rows.iter().flatten().copied().collect())
                .map_err(|e| bad(e.to_string()))?;
            Ok(Target::TensorSurface(patch))
        },
    )?;
    let places = [o.at.is_some(), o.region.is_some(), o.edge.is_some()];
    if places.iter().filter(|&&p| p).count() != 1 {
        return Err(Error::scene(
            path,
            "give exactly one of `at`, `region` and `edge`",
        ));
    }
    let place = if let Some(at) = o.at {
        TensorPlace::Point(at)
    } else if let Some(r) = &o.region {
        TensorPlace::Region(r.clone())
    } else {
        TensorPlace::Edge(match o.edge.expect("one place") {
            EdgeSpec::U0 => PatchEdge::U0,
            EdgeSpec::U1 => PatchEdge::U1,
            EdgeSpec::V0 => PatchEdge::V0,
            EdgeSpec::V1 => PatchEdge::V1,
        })
    };
    Ok(Operator {
        name: name(o.name.as_deref(), &path, o.kind),
        target,
        place,
        strength: o.strength,
        repel: o.repel || o.kind == OperatorKind::Repellor,
    })
}

/// Operators' outcomes as report JSON.
pub(crate) fn outcomes_json(outcomes: &[OperatorOutcome]) -> Value {
    outcomes
        .iter()
        .map(|o| {
            json!({
                "name": o.name,
                "kind": o.kind,
                "strength": o.strength,
                "energy": o.energy,
                "measure": o.measure,
                "max": o.max,
                "at": o.at,
                "measure_is": if o.kind == "director" { "mean angle to the direction (rad)" } else { "root-mean-square distance to the target" },
            })
        })
        .collect()
}

/// A Newton report as JSON (null without repellors).
pub(crate) fn newton_json(n: Option<&NewtonReport>) -> Value {
    n.map_or(Value::Null, |n| {
        json!({
            "iterations": n.iterations,
            "convex_steps": n.convex_steps,
            "start_objective": n.start_energy,
            "objective": n.energy,
            "gradient_norm": n.gradient_norm,
            "relative_gradient": n.relative_gradient,
            "reused_orderings": n.reused_orderings,
        })
    })
}
