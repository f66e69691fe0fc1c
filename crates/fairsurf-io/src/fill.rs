//! Fill scenes and fill jobs ([`fairsurf::fill`]): the neighbour faces from
//! a JSON fill scene or a STEP file, their holes, which to fill, the fills,
//! the sewn STEP output (the input faces and the fills, sharing the hole's
//! edges) and the report.
//!
//! Field docs here become the descriptions in `fairsurf schema --type fill`.

use crate::step_read::FaceSurface;
use crate::tensor_scene::Net;
use crate::validate::parse_net;
use crate::{CadSurface, Error, Result};
use fairsurf::analysis::Edge;
use fairsurf::bspline::{BSplineSurface, FitTolerance, KnotVector, RationalSurface};
use fairsurf::fill::{
    find_holes_within, tolerance, CornerMismatch, FanFill, Fill, FillOptions, FillSeconds, Hole,
    HoleFill, SideFit, TotalCurvature,
};
use fairsurf::Vec3;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::path::Path;
use std::sync::Arc;

/// A fill scene: the faces around one or more holes, which holes to fill,
/// and how.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FillScene {
    /// Free text: a title.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text: what the scene shows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The faces: Bézier patches or B-spline surfaces, every control point
    /// given. Holes are the closed loops of boundaries no other face
    /// shares.
    pub faces: Vec<FaceSpec>,
    /// Which holes to fill, by their index in `fairsurf fill --list`
    /// (longest loop first). Default: every hole but the outer rim (the
    /// longest loop) when there are several, the one loop otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub holes: Option<Vec<usize>>,
    /// How to fill.
    #[serde(default)]
    pub fill: FillSpec,
}

/// `"tensor"` (a Bézier patch) or `"bspline"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum FaceKind {
    /// A tensor-product Bézier patch.
    Tensor,
    /// A tensor-product B-spline surface.
    Bspline,
}

/// One face.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FaceSpec {
    /// `"tensor"` or `"bspline"`.
    #[serde(rename = "type")]
    pub kind: FaceKind,
    /// `[p, q]`: degree in u and in v, 1 to 25.
    pub degree: [usize; 2],
    /// `[U, V]`: full clamped knot vectors (B-spline faces only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub knots: Option<[Vec<f64>; 2]>,
    /// Rows (one per u index) of points `[x, y, z]`.
    pub control_points: Net,
}

/// How to fill; every field optional ([`FillOptions::default`]).
#[derive(Clone, Debug, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FillSpec {
    /// Degrees the fill gets above its sides' largest (default 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elevate: Option<usize>,
    /// At least this many control points per direction (default 8, at
    /// least 5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_points: Option<usize>,
    /// Membrane weight (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch: Option<f64>,
    /// Thin-plate weight (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bend: Option<f64>,
    /// λ of the normal field from the boundary data, per unit area
    /// (default 100; 0: the plain thin plate).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_weight: Option<f64>,
    /// Normal samples per control point and direction (default 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<usize>,
    /// Linearized Willmore steps after the solve, each kept only if it
    /// lowers W (default 4; 0 to 50).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub willmore_steps: Option<usize>,
    /// Then at most this many steps lowering W itself (L-BFGS), stopping
    /// after three in a row that each gain less than 1e-8 of W (default 200;
    /// 0 to 10000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub descent_steps: Option<usize>,
}

/// The largest degree of a face (Open CASCADE reads up to 25).
const MAX_FACE_DEGREE: usize = 25;
/// The largest fill degree asked through `elevate`.
const MAX_ELEVATE: usize = 10;

impl FillSpec {
    /// The options; errors name `fill.<field>`.
    pub fn options(&self) -> Result<FillOptions> {
        let d = FillOptions::default();
        let weight = |name: &str, w: Option<f64>, default: f64| -> Result<f64> {
            let w = w.unwrap_or(default);
            crate::validate::check_weight(&format!("fill.{name}"), w)?;
            Ok(w)
        };
        let elevate = self.elevate.unwrap_or(d.elevate);
        if elevate > MAX_ELEVATE {
            return Err(Error::scene(
                "fill.elevate",
                format!("expected 0 to {MAX_ELEVATE}, got {elevate}"),
            ));
        }
        let min_points = self.min_points.unwrap_or(d.min_points);
        if !(5..=64).contains(&min_points) {
            return Err(Error::scene(
                "fill.min_points",
                format!("expected 5 to 64, got {min_points}"),
            ));
        }
        let willmore_steps = self.willmore_steps.unwrap_or(d.willmore_steps);
        if willmore_steps > 50 {
            return Err(Error::scene(
                "fill.willmore_steps",
                format!("expected 0 to 50, got {willmore_steps}"),
            ));
        }
        let descent_steps = self.descent_steps.unwrap_or(d.descent_steps);
        if descent_steps > 10_000 {
            return Err(Error::scene(
                "fill.descent_steps",
                format!("expected 0 to 10000, got {descent_steps}"),
            ));
        }
        let samples = self.samples.unwrap_or(d.samples);
        if !(1..=16).contains(&samples) {
            return Err(Error::scene(
                "fill.samples",
                format!("expected 1 to 16, got {samples}"),
            ));
        }
        let options = FillOptions {
            elevate,
            min_points,
            stretch: weight("stretch", self.stretch, d.stretch)?,
            bend: weight("bend", self.bend, d.bend)?,
            normal_weight: weight("normal_weight", self.normal_weight, d.normal_weight)?,
            samples,
            willmore_steps,
            descent_steps,
            rational_faces: Vec::new(),
        };
        if options.stretch == 0.0 && options.bend == 0.0 {
            return Err(Error::scene(
                "fill",
                "stretch and bend are both 0: the fill needs a membrane or thin-plate energy",
            ));
        }
        Ok(options)
    }
}

impl FillScene {
    /// Parses a fill scene; errors name the JSON path.
    pub fn from_json(text: &str) -> Result<FillScene> {
        crate::scene::parse_with_path(text)
    }

    /// The JSON Schema of fill scenes.
    pub fn json_schema() -> Value {
        serde_json::to_value(schemars::schema_for!(FillScene)).expect("a schema serializes")
    }

    /// The faces as B-spline surfaces; errors name `faces[k].…`.
    pub fn faces(&self) -> Result<Vec<BSplineSurface>> {
        if self.faces.is_empty() {
            return Err(Error::scene("faces", "no faces: a hole needs neighbours"));
        }
        self.faces
            .iter()
            .enumerate()
            .map(|(k, f)| f.surface(&format!("faces[{k}]")))
            .collect()
    }
}

impl FaceSpec {
    /// The face; errors name `{path}.degree`, `.knots` or `.control_points`.
    pub fn surface(&self, path: &str) -> Result<BSplineSurface> {
        for (k, &d) in self.degree.iter().enumerate() {
            if !(1..=MAX_FACE_DEGREE).contains(&d) {
                return Err(Error::scene(
                    format!("{path}.degree[{k}]"),
                    format!("must be 1 to {MAX_FACE_DEGREE}, got {d}"),
                ));
            }
        }
        let (u, v) = match (self.kind, &self.knots) {
            (FaceKind::Tensor, None) => (
                KnotVector::bezier(self.degree[0]),
                KnotVector::bezier(self.degree[1]),
            ),
            (FaceKind::Tensor, Some(_)) => {
                return Err(Error::scene(
                    format!("{path}.knots"),
                    "a tensor (Bézier) face has no knots: use \"type\": \"bspline\"",
                ))
            }
            (FaceKind::Bspline, None) => {
                return Err(Error::scene(
                    format!("{path}.knots"),
                    "a bspline face needs its knot vectors [U, V]",
                ))
            }
            (FaceKind::Bspline, Some(k)) => {
                let one = |i: usize| {
                    KnotVector::new(self.degree[i], k[i].clone())
                        .map_err(|e| Error::scene(format!("{path}.knots[{i}]"), e.to_string()))
                };
                (one(0)?, one(1)?)
            }
        };
        let (cu, cv) = (u.count(), v.count());
        let net = parse_net(
            &self.control_points,
            &format!("{path}.control_points"),
            (cu - 1, cv - 1),
            false,
        )?;
        let points: Vec<Vec3> = net.into_iter().map(|p| p.expect("no null")).collect();
        Ok(BSplineSurface::new(u, v, points)?)
    }
}

/// The faces to fill between, from a file: a JSON fill scene, or a STEP
/// file (`.step`, `.stp`).
#[derive(Clone, Debug)]
pub struct FillInput {
    /// The faces as polynomial B-splines: a rational face (a cylinder, …)
    /// by its polynomial stand-in (see `stand_ins`).
    pub faces: Vec<BSplineSurface>,
    /// What each face is in the file ("B-spline", "plane", "cylinder", …).
    pub kinds: Vec<&'static str>,
    /// Per face, for a rational one: how far its stand-in is from it along
    /// its sides (position, angle in radians).
    pub stand_ins: Vec<Option<(f64, f64)>>,
    /// The holes the scene chose, if it did.
    pub holes: Option<Vec<usize>>,
    /// The scene's fill options (the defaults for STEP), with the rational
    /// faces the stand-ins approximate (`rational_faces`).
    pub options: FillOptions,
}

impl FillInput {
    /// Reads `path`: STEP by its extension (`.step`, `.stp`, any case),
    /// else a JSON fill scene.
    pub fn read(path: &Path) -> Result<FillInput> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_text(&text, matches!(ext.as_deref(), Some("step" | "stp")))
    }

    /// From a STEP file's text (`step`) or a JSON fill scene's; rational
    /// faces get stand-ins within the default [`FitTolerance`].
    pub fn from_text(text: &str, step: bool) -> Result<FillInput> {
        if step {
            let read = crate::step_read::read_step(text)?;
            let mut input = FillInput {
                faces: Vec::with_capacity(read.len()),
                kinds: read.iter().map(|f| f.kind).collect(),
                stand_ins: vec![None; read.len()],
                holes: None,
                options: FillOptions::default(),
            };
            for f in read {
                match f.surface {
                    FaceSurface::Polynomial(s) => {
                        input.faces.push(s);
                        input.options.rational_faces.push(None);
                    }
                    FaceSurface::Rational(r) => {
                        // Refitted below.
                        input.faces.push(r.net().clone());
                        input.options.rational_faces.push(Some(Arc::new(r)));
                    }
                }
            }
            input.refit(FitTolerance::default())?;
            return Ok(input);
        }
        let scene = FillScene::from_json(text)?;
        let faces = scene.faces()?;
        Ok(FillInput {
            kinds: vec!["B-spline"; faces.len()],
            stand_ins: vec![None; faces.len()],
            faces,
            holes: scene.holes.clone(),
            options: scene.fill.options()?,
        })
    }

    /// Fits the rational faces' stand-ins anew within `fit`.
    pub fn refit(&mut self, fit: FitTolerance) -> Result<()> {
        for (k, r) in self.options.rational_faces.iter().enumerate() {
            if let Some(r) = r {
                let s = stand_in(r, fit, k, self.kinds[k])?;
                self.stand_ins[k] = Some((s.position, s.angle));
                self.faces[k] = s.surface;
            }
        }
        Ok(())
    }

    /// The distance under which boundary points are one when finding
    /// holes: [`tolerance`], or four times the largest stand-in's distance
    /// from its face when that is larger (two stand-ins of one edge may
    /// differ by twice that).
    pub fn hole_tolerance(&self) -> f64 {
        sew_tolerance(&self.faces, &self.stand_ins)
    }

    /// The rational faces and their stand-ins, as JSON: face, kind, and the
    /// stand-in's largest gap and angle along the face's sides.
    pub fn stand_ins_json(&self) -> Value {
        stand_ins_json(&self.kinds, &self.stand_ins)
    }
}

/// A rational face's stand-in within `fit`; errors name face `k` and its
/// kind.
pub(crate) fn stand_in(
    r: &RationalSurface,
    fit: FitTolerance,
    k: usize,
    kind: &str,
) -> Result<fairsurf::bspline::StandIn> {
    r.polynomial(fit)
        .map_err(|e| Error::scene(format!("face {k}"), format!("a {kind}: {e}")))
}

/// [`tolerance`] of `faces`, or four times the largest stand-in's
/// distance from its face when that is larger (two stand-ins of one edge
/// may differ by twice that): under it, points are one when finding holes
/// and sharing edges in the STEP file.
pub(crate) fn sew_tolerance(faces: &[BSplineSurface], stand_ins: &[Option<(f64, f64)>]) -> f64 {
    let fit = stand_ins.iter().flatten().map(|s| s.0).fold(0.0, f64::max);
    tolerance(faces).max(4.0 * fit)
}

/// The rational faces and their stand-ins, as JSON: face, kind, and the
/// stand-in's largest gap and angle along the face's sides.
pub(crate) fn stand_ins_json(kinds: &[&str], stand_ins: &[Option<(f64, f64)>]) -> Value {
    Value::Array(
        stand_ins
            .iter()
            .enumerate()
            .filter_map(|(k, s)| {
                s.map(|(gap, angle)| {
                    json!({
                        "face": k,
                        "kind": kinds[k],
                        "gap": gap,
                        "angle_deg": angle.to_degrees(),
                    })
                })
            })
            .collect(),
    )
}

/// The holes of a set of faces and which of them to fill.
#[derive(Clone, Debug)]
pub struct HoleChoice {
    /// Every hole, longest first.
    pub holes: Vec<Hole>,
    /// The indices to fill.
    pub chosen: Vec<usize>,
    /// The index taken for the outer rim of an open sheet (not filled
    /// unless asked), when there are several holes.
    pub rim: Option<usize>,
}

impl HoleChoice {
    /// The holes of `faces`; `asked` (indices) or, without it, every hole
    /// but the longest when there are several (the outer rim), the one
    /// hole otherwise. Errors: no hole, an index out of range (named as
    /// `holes[k]`).
    pub fn new(faces: &[BSplineSurface], asked: Option<&[usize]>) -> Result<HoleChoice> {
        Self::within(faces, asked, tolerance(faces))
    }

    /// [`new`](Self::new) for a read input (its stand-ins' tolerance).
    pub fn of(input: &FillInput, asked: Option<&[usize]>) -> Result<HoleChoice> {
        Self::within(&input.faces, asked, input.hole_tolerance())
    }

    /// [`new`](Self::new) with boundary points within `tol` taken as one.
    pub fn within(
        faces: &[BSplineSurface],
        asked: Option<&[usize]>,
        tol: f64,
    ) -> Result<HoleChoice> {
        let holes = find_holes_within(faces, tol)?;
        if holes.is_empty() {
            return Err(Error::Solve(fairsurf::Error::Fill {
                why: "there is no hole: every face boundary is shared by two faces".into(),
            }));
        }
        let rim = (holes.len() > 1).then_some(0);
        let chosen = match asked {
            Some(a) => {
                for (k, &h) in a.iter().enumerate() {
                    if h >= holes.len() {
                        return Err(Error::scene(
                            format!("holes[{k}]"),
                            format!(
                                "there is no hole {h}: the faces have {} (0 to {})",
                                holes.len(),
                                holes.len() - 1
                            ),
                        ));
                    }
                }
                // Each hole once, in the order first asked.
                let mut c: Vec<usize> = Vec::new();
                for &h in a {
                    if !c.contains(&h) {
                        c.push(h);
                    }
                }
                c
            }
            None if holes.len() == 1 => vec![0],
            None => (1..holes.len()).collect(),
        };
        Ok(HoleChoice { holes, chosen, rim })
    }

    /// Fills the chosen holes: one patch for 4 sides, a fan of triangular
    /// patches otherwise.
    pub fn fill(&self, faces: &[BSplineSurface], options: &FillOptions) -> Result<Vec<HoleFill>> {
        self.chosen
            .iter()
            .map(|&h| {
                HoleFill::new(faces, &self.holes[h], options).map_err(|e| match e {
                    fairsurf::Error::Fill { why } => fairsurf::Error::Fill {
                        why: format!("hole {h}: {why}"),
                    },
                    e => e,
                })
            })
            .collect::<fairsurf::Result<_>>()
            .map_err(Error::Solve)
    }

    /// The `--list` table: index, sides, length, faces, and whether it is
    /// filled by default.
    pub fn list_json(&self) -> Value {
        Value::Array(
            self.holes
                .iter()
                .enumerate()
                .map(|(k, h)| {
                    json!({
                        "index": k,
                        "sides": h.sides.len(),
                        "length": h.length,
                        "faces": h.faces(),
                        "rim": self.rim == Some(k),
                        "chosen": self.chosen.contains(&k),
                    })
                })
                .collect(),
        )
    }
}

pub(crate) fn edge_name(e: Edge) -> &'static str {
    match e {
        Edge::U0 => "u0",
        Edge::U1 => "u1",
        Edge::V0 => "v0",
        Edge::V1 => "v1",
    }
}

/// One side's fit as JSON, `face` the neighbour's index in the output.
pub(crate) fn side_json(f: &SideFit, face: usize) -> Value {
    json!({
        "face": face,
        "edge": edge_name(f.side.edge),
        "reversed": f.side.reversed,
        "range": f.side.range,
        "gap": f.gap,
        "angle_deg": f.angle.to_degrees(),
        "samples": f.samples,
        "singular": f.singular,
        "exact": f.exact,
    })
}

/// The fields a fill and a blend report alike: size, sides, corners, W,
/// the solve and the time.
pub(crate) fn patch_json(
    surface: &BSplineSurface,
    sides: Vec<Value>,
    fits: &[SideFit],
    corners: &CornerMismatch,
    curvature: &TotalCurvature,
    willmore: &[f64],
    normal_weight: f64,
    s: &fairsurf::SolveReport,
    seconds: &FillSeconds,
) -> Value {
    let (ku, kv) = surface.knots();
    json!({
        "degree": surface.degree(),
        "control_points": surface.counts(),
        "spans": [ku.spans().len(), kv.spans().len()],
        "sides": sides,
        "max_gap": fits.iter().map(|f| f.gap).fold(0.0, f64::max),
        "max_angle_deg": fits.iter().map(|f| f.angle.to_degrees()).fold(0.0, f64::max),
        "corners": {
            "position": corners.position,
            "tangent": corners.tangent,
            "twist": corners.twist,
        },
        "curvature_w": curvature.value,
        "curvature_w_error": curvature.error,
        "willmore_w": willmore,
        "normal_weight": normal_weight,
        "solve": crate::result::report_json(s),
        "seconds": {
            "setup": seconds.setup,
            "solve": seconds.solve,
            "measure": seconds.measure,
            "total": seconds.setup + seconds.solve + seconds.measure,
        },
    })
}

/// One fill's report (`"kind"`: `"patch"` or `"fan"`): the surface's
/// size, per side the gap and normal angle measured on it, the corner
/// mismatches, W, the solve's figures and the time.
pub fn fill_json(hole: usize, fill: &HoleFill) -> Value {
    match fill {
        HoleFill::Patch(f) => patch_fill_json(hole, f),
        HoleFill::Fan(f) => fan_fill_json(hole, f),
    }
}

/// A fan's report (one triangular patch for a 3-sided hole when that is
/// fairer: `"patches": 1`): as a patch's, with the fan's own G¹ (the largest
/// normal angle between its patches, the conditions kept and dropped) and
/// the triangular solve's check.
fn fan_fill_json(hole: usize, fan: &FanFill) -> Value {
    let r = &fan.report;
    let s = &r.solve;
    let sides: Vec<Value> = r.sides.iter().map(|f| side_json(f, f.side.face)).collect();
    json!({
        "hole": hole,
        "kind": "fan",
        "patches": fan.surface.patch_count(),
        "degree": fan.surface.degree(),
        "control_points": fan.surface.point_count(),
        "sides": sides,
        "max_gap": r.sides.iter().map(|f| f.gap).fold(0.0, f64::max),
        "max_angle_deg": r.sides.iter().map(|f| f.angle.to_degrees()).fold(0.0, f64::max),
        "inner_angle_deg": r.inner_angle.to_degrees(),
        "corners": {
            "position": r.corners.position,
            "tangent": r.corners.tangent,
            "twist": r.corners.twist,
        },
        "curvature_w": r.curvature.value,
        "curvature_w_error": r.curvature.error,
        "solve": {
            "energy": s.total,
            "terms": {"stretch": s.stretch, "bend": s.bend},
            "relative_gradient": s.relative_gradient,
            "free_coordinates": s.unknowns,
            "conditions": s.rows,
            "conditions_kept": s.independent_rows,
            "conditions_implied": s.dependent_rows,
            "conditions_dropped": s.dropped.iter().map(|d| json!({"name": d.name, "residual": d.residual})).collect::<Vec<_>>(),
            "row_tolerance": s.row_tolerance,
            "check": s.check.as_ref().map(|c| json!({
                "energy": c.energy,
                "energy_error": c.energy_error,
                "excess": c.excess,
                "tolerance": fairsurf::CHECK_TOLERANCE,
            })),
        },
        "seconds": {
            "setup": r.seconds.setup,
            "solve": r.seconds.solve,
            "measure": r.seconds.measure,
            "other_candidate": r.other_seconds,
            "total": r.seconds.setup + r.seconds.solve + r.seconds.measure + r.other_seconds,
        },
    })
}

/// A 4-sided fill's report.
fn patch_fill_json(hole: usize, fill: &Fill) -> Value {
    let r = &fill.report;
    let sides = r.sides.iter().map(|f| side_json(f, f.side.face)).collect();
    let mut out = patch_json(
        &fill.surface,
        sides,
        &r.sides,
        &r.corners,
        &r.curvature,
        &r.willmore,
        r.normal_weight,
        &r.solve,
        &r.seconds,
    );
    out["hole"] = json!(hole);
    out["kind"] = json!("patch");
    out["alpha"] = json!(r.alpha);
    out
}

/// The whole report of a fill job: the number of faces, every hole (as
/// `--list` gives them) and each fill's report ([`fill_json`]).
pub fn fill_report_json(faces: usize, choice: &HoleChoice, fills: &[HoleFill]) -> Value {
    json!({
        "faces": faces,
        "holes": choice.list_json(),
        "fills": choice
            .chosen
            .iter()
            .zip(fills)
            .map(|(&h, f)| fill_json(h, f))
            .collect::<Vec<_>>(),
        "fairsurf_version": env!("CARGO_PKG_VERSION"),
    })
}

/// The input faces followed by the fills (a fan as its patches), for the
/// CAD writers; a face that stands in for a rational one (`rational`, per
/// face, as [`FillOptions::rational_faces`]) is written as that.
pub fn fill_surfaces(
    faces: &[BSplineSurface],
    rational: &[Option<Arc<RationalSurface>>],
    fills: &[HoleFill],
) -> Vec<CadSurface> {
    let patches: Vec<BSplineSurface> = fills.iter().flat_map(HoleFill::patches).collect();
    let own =
        faces
            .iter()
            .enumerate()
            .map(|(k, f)| match rational.get(k).and_then(Option::as_deref) {
                Some(r) => CadSurface::from(r),
                None => CadSurface::from(f),
            });
    own.chain(patches.iter().map(CadSurface::from)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn network() -> Vec<BSplineSurface> {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cad/fill_network.json");
        FillInput::read(&p).unwrap().faces
    }

    /// The default choice leaves out the rim; an asked hole is filled once,
    /// in the order first asked; a hole that does not exist names its index.
    #[test]
    fn holes_are_chosen_once() {
        let faces = network();
        let c = HoleChoice::new(&faces, None).unwrap();
        assert_eq!((c.chosen.clone(), c.rim), (vec![1], Some(0)));
        let c = HoleChoice::new(&faces, Some(&[1, 0, 1])).unwrap();
        assert_eq!(c.chosen, vec![1, 0]);
        let e = HoleChoice::new(&faces, Some(&[0, 2]))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("holes[1]: there is no hole 2"), "{e}");
    }

    /// The approximate case (the bundled `fillet_hole.step`, written by
    /// Open CASCADE): planes read as exact bilinear faces, cylinders as
    /// rational faces met through stand-ins; the fill is exact along the
    /// planes and within the stand-ins' tolerance along the cylinders, as
    /// measured against the cylinders themselves, and close to the missing
    /// quarter cylinder; a tighter tolerance brings it closer.
    #[test]
    fn a_hole_between_planes_and_cylinders_is_filled_within_tolerance() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cad/fillet_hole.step");
        let mut input = FillInput::read(&p).unwrap();
        let mut kinds = input.kinds.clone();
        kinds.sort_unstable();
        assert_eq!(
            kinds,
            ["cylinder", "cylinder", "plane", "plane", "plane", "plane", "plane", "plane"]
        );
        let fill = |input: &FillInput| {
            let choice = HoleChoice::of(input, None).unwrap();
            assert_eq!((choice.holes.len(), choice.chosen.clone()), (2, vec![1]));
            let mut fills = choice.fill(&input.faces, &input.options).unwrap();
            let Some(HoleFill::Patch(f)) = fills.pop() else {
                panic!("one patch")
            };
            f
        };
        // On the cylinder x² + (z − 1)² = 1 within `tol` at 21 × 21 points.
        let off = |f: &Fill| {
            (0..=20)
                .flat_map(|i| (0..=20).map(move |j| (i as f64 / 20.0, j as f64 / 20.0)))
                .map(|(u, v)| {
                    let p = f.surface.eval(u, v);
                    (p[0].hypot(p[2] - 1.0) - 1.0).abs()
                })
                .fold(0.0, f64::max)
        };
        for (fit, gap, angle) in [
            (FitTolerance::default(), 1e-6, 0.01),
            (
                FitTolerance {
                    position: 1e-10,
                    angle: 1e-8,
                },
                1e-10,
                1e-8f64.to_degrees(),
            ),
        ] {
            input.refit(fit).unwrap();
            let f = fill(&input);
            for s in &f.report.sides {
                let cylinder = input.kinds[s.side.face] == "cylinder";
                assert_eq!(s.exact, !cylinder);
                assert!(s.gap <= gap && s.angle.to_degrees() <= angle, "{s:?}");
                if !cylinder {
                    assert!(s.gap < 1e-14, "{s:?}");
                }
            }
            // Fairer than the quarter cylinder it replaces (W = area/r² = π/2:
            // the descent on W takes it 0.02% below), and near it.
            let w = f.report.curvature.value;
            assert!(
                w < std::f64::consts::FRAC_PI_2 && w > 0.999 * std::f64::consts::FRAC_PI_2,
                "{w}"
            );
            assert!(off(&f) < 5e-3, "{}", off(&f));
        }
    }
}
