//! Constraints in scene files, shared by both surface kinds: the kinds'
//! fields become [`fairsurf::constraint::Constraint`]s (at a triangle's
//! barycentrics or at a tensor patch's (u, v)), and their outcomes JSON.

use crate::tri_scene::ConstraintKind;
use crate::{Error, Result};
use fairsurf::constraint::{Constraint, ConstraintOutcome};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

/// The fields of a point, normal, in_plane or on_line constraint.
pub(crate) struct Fields {
    pub target: Option<[f64; 3]>,
    pub normal: Option<[f64; 3]>,
    pub offset: Option<f64>,
    pub point: Option<[f64; 3]>,
    pub direction: Option<[f64; 3]>,
}

/// The constraint of kind `kind` at `at()` from its fields (`None` for
/// fixed and curve constraints, which each kind handles itself); a
/// missing field is an error naming `path.field`.
pub(crate) fn located<A>(
    kind: ConstraintKind,
    path: &str,
    f: &Fields,
    at: impl FnOnce() -> Result<A>,
) -> Result<Option<Constraint<A>>> {
    let need = |field: &str| {
        Error::scene(
            format!("{path}.{field}"),
            format!("required for a {} constraint", kind_name(kind)),
        )
    };
    Ok(Some(match kind {
        ConstraintKind::Point => Constraint::Point {
            at: at()?,
            target: f.target.ok_or_else(|| need("target"))?,
        },
        ConstraintKind::Normal => Constraint::Normal {
            at: at()?,
            normal: f.normal.ok_or_else(|| need("normal"))?,
        },
        ConstraintKind::InPlane => Constraint::InPlane {
            at: at()?,
            normal: f.normal.ok_or_else(|| need("normal"))?,
            offset: f.offset.ok_or_else(|| need("offset"))?,
        },
        ConstraintKind::OnLine => Constraint::OnLine {
            at: at()?,
            point: f.point.ok_or_else(|| need("point"))?,
            direction: f.direction.ok_or_else(|| need("direction"))?,
        },
        ConstraintKind::Fixed | ConstraintKind::Curve => return Ok(None),
    }))
}

/// The kind as scene files write it.
pub(crate) fn kind_name(k: ConstraintKind) -> &'static str {
    match k {
        ConstraintKind::Point => "point",
        ConstraintKind::Normal => "normal",
        ConstraintKind::InPlane => "in_plane",
        ConstraintKind::OnLine => "on_line",
        ConstraintKind::Fixed => "fixed",
        ConstraintKind::Curve => "curve",
    }
}

/// Each constraint's name, kind and violation, as reports list them.
pub(crate) fn outcomes_json(outcomes: &[ConstraintOutcome]) -> Value {
    outcomes
        .iter()
        .map(|c| json!({"name": c.name, "kind": c.kind, "violation": c.violation}))
        .collect()
}

/// Where a tensor patch's constraint acts: `{"uv": [u, v]}`, or `[u, v]`
/// as the operators write it.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum UvSpec {
    /// `{"uv": [u, v]}`.
    Named(NamedUv),
    /// `[u, v]`.
    Pair([f64; 2]),
}

/// `{"uv": [u, v]}`.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NamedUv {
    /// (u, v) in [0, 1]².
    pub uv: [f64; 2],
}

impl UvSpec {
    /// (u, v).
    pub fn uv(self) -> [f64; 2] {
        match self {
            UvSpec::Named(NamedUv { uv }) | UvSpec::Pair(uv) => uv,
        }
    }
}

/// One constraint of a tensor patch (Veltkamp & Wesselink eq. 31 at a
/// point (u, v) of the patch): the surface passes through `target`, has
/// the normal `normal`, lies in the plane normal·x = offset or on the line
/// through `point` along `direction` there. Met exactly (to rounding);
/// the report gives each one's violation.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TensorConstraintSpec {
    /// The kind: point, normal, in_plane or on_line.
    #[serde(rename = "type")]
    pub kind: ConstraintKind,
    /// A name for reports (default `constraints[i] (kind)`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Where: `{"uv": [u, v]}` (or `[u, v]`), (u, v) in [0, 1]².
    pub at: UvSpec,
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
}

impl TensorConstraintSpec {
    /// The name and the library constraint of `constraints[i]` of a tensor
    /// patch ((u, v) in [0, 1]²).
    pub(crate) fn build(&self, i: usize) -> Result<(String, fairsurf::TensorConstraint)> {
        self.build_in(i, [(0.0, 1.0), (0.0, 1.0)], "[0, 1]²")
    }

    /// The name and the library constraint of `constraints[i]`, (u, v) in
    /// the parameter rectangle `domain` (a B-spline's knot domain), which
    /// errors call `described`.
    pub(crate) fn build_in(
        &self,
        i: usize,
        domain: [(f64, f64); 2],
        described: &str,
    ) -> Result<(String, fairsurf::TensorConstraint)> {
        let path = format!("constraints[{i}]");
        let name = self
            .name
            .clone()
            .unwrap_or_else(|| format!("{path} ({})", kind_name(self.kind)));
        let fields = Fields {
            target: self.target,
            normal: self.normal,
            offset: self.offset,
            point: self.point,
            direction: self.direction,
        };
        let uv = self.at.uv();
        let at = || {
            if uv.iter().zip(domain).all(|(t, (a, b))| (a..=b).contains(t)) {
                return Ok(uv);
            }
            Err(Error::scene(
                format!("{path}.at"),
                format!("expected (u, v) in {described}, got {uv:?}"),
            ))
        };
        let constraint = located(self.kind, &path, &fields, at)?.ok_or_else(|| {
            Error::scene(
                format!("{path}.type"),
                format!(
                    "a tensor or B-spline surface takes point, normal, in_plane or on_line constraints, not {} \
                     (a fixed control point is a given one in surface.control_points)",
                    kind_name(self.kind)
                ),
            )
        })?;
        Ok((name, constraint))
    }
}
