//! What the editor draws and edits, from a solved scene: the mesh coloured
//! by mean curvature, the control net, boundary, normals, operators, the
//! draggable handles and sliders (as JSON pointers into the scene), and the
//! energy/area table (see `editor/API.md`), as typed structs that mirror it
//! (`View`, `Row`, `Handle`, `Edit`, `Slider`, `Arrow`, `Marker`), written
//! straight to JSON text.

use super::{ApiError, ApiResult, Limits};
use axum::http::StatusCode;
use fairsurf::colour::ColourMap;
use fairsurf::vector::{add, dot, normalize, scale, sub};
use fairsurf::{BezierCurve, ParamSurface, Vec3};
use fairsurf_io::{
    write_iges_surfaces, write_mesh, write_step_surfaces, Outcome, Scene, SolvedBSplineScene,
    SolvedScene, SolvedTensorScene, SolvedTriScene, SurfaceMesh,
};
use serde_json::{json, Value};
use std::time::Instant;

mod field;
mod tensor;
mod tri;

use field::Field;
use tensor::{bspline_view, tensor_view};
use tri::tri_view;

/// Solves the scene and describes the result for the page, as JSON text
/// (serialized straight from the typed view, no value tree). `quick` (while
/// the user drags) skips the analysis: area, functionals, the deviation from
/// the normal field and the distance to the guide surface. `seconds`
/// includes the serialization.
pub(crate) fn solve(
    text: &str,
    quick: bool,
    limits: &Limits,
    factors: &fairsurf::FactorCache,
) -> ApiResult<String> {
    let start = Instant::now();
    let scene = Scene::from_json(text)?;
    check_size(&scene, limits)?;
    let opts = fairsurf::SolveOptions::default().with_analyse(!quick);
    let solved = scene.solve_cached(&opts, factors)?;
    let view = match &solved {
        SolvedScene::Tensor(s) => tensor_view(s),
        SolvedScene::Triangular(s) => tri_view(s),
        SolvedScene::BSpline(s) => bspline_view(s),
    };
    let mut out = serde_json::to_string(&view).expect("a view serializes");
    // The object's last two members, after the rest is written.
    debug_assert!(out.ends_with('}'));
    out.pop();
    let seconds = start.elapsed().as_secs_f64();
    out.push_str(&format!(
        ",\"quick\":{quick},\"seconds\":{}}}",
        json!(seconds)
    ));
    Ok(out)
}

/// Measures the surface the scene gives, as it is, without solving: a
/// result file, or a scene whose control points are all given (a null one
/// is a 400 naming it). Tensor: area (adaptive Gauss–Legendre, with its
/// error estimate), the Dirichlet and biharmonic functionals (exact), |H|
/// on a grid. Triangular: the stretch and bend functionals (weights 1),
/// the largest normal angle across interior edges.
pub(crate) fn analyse(text: &str, limits: &Limits) -> ApiResult<Value> {
    let start = Instant::now();
    let scene = Scene::from_json(text)?;
    check_size(&scene, limits)?;
    let table: Vec<Row> = scene
        .analyse()?
        .into_iter()
        .map(|(l, v)| row(l, v))
        .collect();
    Ok(json!({
        "kind": scene.surface_type().name(),
        "table": table,
        "seconds": start.elapsed().as_secs_f64(),
    }))
}

/// The four surfaces of Monterde & Ugail §4 with the scene's boundary.
pub(crate) fn compare(text: &str, _limits: &Limits) -> ApiResult<Value> {
    let Scene::Tensor(scene) = Scene::from_json(text)? else {
        return Err(ApiError::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            "compare is for tensor-product scenes (Monterde & Ugail's four surfaces)",
        ));
    };
    let c = scene.compare()?;
    let rows: Vec<Value> = c
        .columns()
        .into_iter()
        .map(|(name, col)| {
            let m = &col.measures;
            json!([
                name.replace('_', " "),
                m.area,
                m.dirichlet,
                m.biharmonic,
                m.abs_mean_curvature.mean,
                if col.exact { "yes" } else { "least squares" },
            ])
        })
        .collect();
    Ok(json!({
        "columns": ["surface", "area", "Dirichlet", "biharmonic", "mean |H|", "exact"],
        "rows": rows,
    }))
}

/// The solved surface as a file: (file name, content type, bytes).
pub(crate) fn export(
    text: &str,
    format: &str,
    limits: &Limits,
) -> ApiResult<(String, &'static str, Vec<u8>)> {
    let (ext, kind) = match format {
        "obj" => ("obj", "text/plain; charset=utf-8"),
        "stl" => ("stl", "model/stl"),
        "ply" => ("ply", "application/octet-stream"),
        "gltf" => ("glb", "model/gltf-binary"),
        "step" => ("step", "model/step"),
        "iges" => ("igs", "model/iges"),
        "json" => ("result.json", "application/json"),
        other => {
            return Err(ApiError {
                status: StatusCode::BAD_REQUEST,
                message: format!(
                    "format: expected obj, stl, ply, gltf, step, iges or json, got {other:?}"
                ),
                path: Some("format".into()),
            })
        }
    };
    // The surface: a result file as it is, any other scene solved.
    let scene = Scene::from_json(text)?;
    check_size(&scene, limits)?;
    let solved = scene.solve()?;
    let file = format!("{}.{ext}", file_stem(scene.name()));
    if format == "json" {
        return Ok((file, kind, solved.result_text().into_bytes()));
    }
    let dir = std::env::temp_dir().join(format!(
        "fairsurf-serve-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).map_err(|e| {
        ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("temporary file: {e}"),
        )
    })?;
    let path = dir.join(format!("surface.{ext}"));
    let written = match format {
        "step" => write_step_surfaces(&path, &solved.cad_surfaces()),
        "iges" => write_iges_surfaces(&path, &solved.cad_surfaces()),
        _ => write_mesh(&path, &solved.mesh(MESH_RESOLUTION)),
    };
    let bytes = written.map_err(ApiError::from).and_then(|()| {
        std::fs::read(&path).map_err(|e| {
            ApiError::new(
                StatusCode::INTERNAL_SERVER_ERROR,
                format!("temporary file: {e}"),
            )
        })
    });
    let _ = std::fs::remove_dir_all(&dir);
    Ok((file, kind, bytes?))
}

static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// A file name from the scene's name: letters, digits, `-` and `_`.
fn file_stem(name: Option<&str>) -> String {
    let s: String = name
        .unwrap_or("fairsurf")
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let s = s.trim_matches('_');
    let s: String = s.chars().take(48).collect();
    if s.is_empty() {
        "fairsurf".into()
    } else {
        s
    }
}

/// Quads per side of an exported tensor patch (a triangular surface gets a
/// quarter of it per patch edge, see [`fairsurf_io::SolvedScene::mesh`]).
const MESH_RESOLUTION: usize = 64;

/// Refuses a triangular scene with more unknowns than the limit (a tensor
/// scene's size is bounded by its degree, at most 40).
fn check_size(scene: &Scene, limits: &Limits) -> ApiResult<()> {
    let Scene::Triangular(scene) = scene else {
        return Ok(());
    };
    let s = scene.surface()?;
    let unknowns = 3 * s.point_count();
    if unknowns > limits.max_unknowns {
        return Err(ApiError {
            status: StatusCode::PAYLOAD_TOO_LARGE,
            message: format!(
                "surface: {unknowns} unknowns ({} patches of degree {}), more than the server's \
                 limit of {} (--max-unknowns)",
                s.patch_count(),
                s.degree(),
                limits.max_unknowns
            ),
            path: Some("surface".into()),
        });
    }
    Ok(())
}

/// A row of the table (`editor/API.md`, `table`).
#[derive(serde::Serialize)]
pub(super) struct Row {
    label: String,
    value: Cell,
}

/// A table cell: a number (null when absent or not finite) or text.
#[derive(serde::Serialize)]
#[serde(untagged)]
pub(super) enum Cell {
    Number(Option<f64>),
    Text(String),
}

impl From<f64> for Cell {
    fn from(x: f64) -> Self {
        Cell::Number(Some(x))
    }
}

impl From<Option<f64>> for Cell {
    fn from(x: Option<f64>) -> Self {
        Cell::Number(x)
    }
}

impl From<&str> for Cell {
    fn from(s: &str) -> Self {
        Cell::Text(s.into())
    }
}

impl From<String> for Cell {
    fn from(s: String) -> Self {
        Cell::Text(s)
    }
}

impl From<Value> for Cell {
    /// A measure of `analyse`: a number or its text.
    fn from(v: Value) -> Self {
        match v {
            Value::Number(n) => Cell::Number(n.as_f64()),
            Value::Null => Cell::Number(None),
            Value::String(s) => Cell::Text(s),
            other => Cell::Text(other.to_string()),
        }
    }
}

fn row(label: impl Into<String>, value: impl Into<Cell>) -> Row {
    Row {
        label: label.into(),
        value: value.into(),
    }
}

/// A draggable handle: a JSON pointer into the scene and where it is
/// (`editor/API.md`, `handles`).
#[derive(serde::Serialize)]
pub(super) struct Handle {
    pointer: String,
    position: Vec3,
    label: String,
    /// `control_point` or `operator` (its colour).
    kind: &'static str,
    /// How a drag edits the value when it is not the position itself.
    #[serde(skip_serializing_if = "Option::is_none")]
    edit: Option<Edit>,
}

impl Handle {
    /// A handle whose drag writes its position at `pointer`.
    fn point(pointer: String, position: Vec3, label: String, kind: &'static str) -> Self {
        Handle {
            pointer,
            position,
            label,
            kind,
            edit: None,
        }
    }
}

/// What dragging a handle edits (`editor/API.md`, `handles[].edit`).
#[derive(serde::Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub(super) enum Edit {
    /// A unit direction drawn `length` from `anchor`; with `offset`, the
    /// pointer of a plane's offset kept through the foot while it turns.
    Direction {
        anchor: Vec3,
        length: f64,
        #[serde(skip_serializing_if = "Option::is_none")]
        offset: Option<String>,
    },
    /// A plane's offset, moved along its normal from the surface point
    /// `anchor`.
    Offset { anchor: Vec3, normal: Vec3 },
}

/// A weight or strength slider (`editor/API.md`, `sliders`).
#[derive(serde::Serialize)]
pub(super) struct Slider {
    pointer: String,
    label: String,
    value: f64,
    min: f64,
    max: f64,
    scale: &'static str,
}

/// An arrow: a guiding or prescribed normal.
#[derive(serde::Serialize)]
pub(super) struct Arrow {
    at: Vec3,
    dir: Vec3,
}

/// An operator's marker: where it acts on the surface and what it pulls
/// toward.
#[derive(serde::Serialize)]
pub(super) struct Marker {
    name: String,
    kind: String,
    at: Option<Vec3>,
    target: Option<Vec3>,
}

/// What the page draws and edits (`editor/API.md`, `POST /api/solve`),
/// the same fields for every kind of surface.
#[derive(serde::Serialize)]
pub(super) struct View<'a> {
    /// "tensor", "triangular" or "bspline".
    kind: &'static str,
    /// Rows `{label, value}`.
    table: Vec<Row>,
    /// The result file's content.
    result: Scene,
    /// Positions, indices, colours by mean curvature and their legend.
    mesh: MeshView,
    /// The control net.
    net: Net<'a>,
    /// Boundary curves as polylines.
    boundary: Vec<Vec<Vec3>>,
    /// Arrows of the guiding normals (`{at, dir}`).
    normals: Vec<Arrow>,
    /// Operator markers.
    operators: Vec<Marker>,
    /// Draggable handles (JSON pointers into the scene).
    handles: Vec<Handle>,
    /// Weight sliders (JSON pointers into the scene).
    sliders: Vec<Slider>,
    /// The construction method's select (tensor scenes), else null.
    methods: Option<Methods>,
}

/// The select of a tensor scene's `method`.
#[derive(serde::Serialize)]
pub(super) struct Methods {
    pointer: &'static str,
    value: fairsurf_io::Method,
    options: [&'static str; 5],
}

impl Methods {
    const OPTIONS: [&'static str; 5] = [
        "minimize",
        "harmonic",
        "biharmonic",
        "harmonic_mask",
        "biharmonic_mask",
    ];
}

/// Control points and the index pairs of the net's edges.
#[derive(serde::Serialize)]
struct Net<'a> {
    points: &'a [Vec3],
    edges: Vec<[usize; 2]>,
}

/// The mesh as the page draws it (`editor/API.md`, `mesh`).
#[derive(serde::Serialize)]
struct MeshView {
    positions: Vec<f64>,
    indices: Vec<u32>,
    colors: Vec<f64>,
    legend: Legend,
}

/// The colour legend of the mesh.
#[derive(serde::Serialize)]
struct Legend {
    name: &'static str,
    min: f64,
    max: f64,
    /// `[t in 0..1, CSS colour]`.
    stops: Vec<(f64, String)>,
}

/// The edges of a rows × cols grid net, row-major.
fn grid_edges(rows: usize, cols: usize) -> Vec<[usize; 2]> {
    let mut edges = Vec::new();
    for i in 0..rows {
        for j in 0..cols {
            let k = i * cols + j;
            if j + 1 < cols {
                edges.push([k, k + 1]);
            }
            if i + 1 < rows {
                edges.push([k, k + cols]);
            }
        }
    }
    edges
}

/// Sliders for the energy's weights: stretch and bend (with the scenes'
/// default rule, [`fairsurf_io::default_weights`]), λ and γ when the scene
/// has those terms.
fn weight_sliders(
    (stretch, bend, rings): (Option<f64>, Option<f64>, Option<usize>),
    lambda: Option<f64>,
    gamma: Option<f64>,
) -> Vec<Slider> {
    let (stretch, bend, _) = fairsurf_io::default_weights(stretch, bend, rings);
    let mut out = vec![
        slider(
            "/energy/stretch".into(),
            "stretch (membrane)".into(),
            stretch.unwrap_or(0.0),
            1e-4,
            1e3,
        ),
        slider(
            "/energy/bend".into(),
            "bend (thin plate)".into(),
            bend.unwrap_or(0.0),
            1e-4,
            1e3,
        ),
    ];
    if let Some(l) = lambda {
        let p = "/energy/normal_field/weight".into();
        out.push(slider(p, "λ normal field".into(), l, 1e-3, 1e4));
    }
    if let Some(g) = gamma {
        let p = "/energy/guide_surface/weight".into();
        out.push(slider(p, "γ guide surface".into(), g, 1e-3, 1e4));
    }
    out
}

fn slider(pointer: String, label: String, value: f64, min: f64, max: f64) -> Slider {
    Slider {
        pointer,
        label,
        value,
        min,
        max,
        scale: "log",
    }
}

/// The diagonal of the points' bounding box (1 if degenerate).
fn size_of(points: &[Vec3]) -> f64 {
    let d = fairsurf::vector::bounding_diagonal(points);
    if d.is_finite() && d > 0.0 {
        d
    } else {
        1.0
    }
}

/// The mesh with per-vertex colours by signed mean curvature (cool–warm,
/// symmetric about 0 up to the 98th percentile of |H|) and its legend.
fn mesh_view(m: &SurfaceMesh) -> MeshView {
    let mesh = m.mesh();
    let mut abs: Vec<f64> = m
        .curvature()
        .iter()
        .flatten()
        .map(|c| c.mean.abs())
        .collect();
    abs.retain(|h| h.is_finite());
    // The 98th percentile (or the largest): one selection, not a sort.
    let k = ((abs.len() as f64 * 0.98) as usize).min(abs.len().saturating_sub(1));
    let a = if abs.is_empty() {
        1.0
    } else {
        *abs.select_nth_unstable_by(k, f64::total_cmp).1
    }
    .max(1e-12);
    let map = ColourMap::CoolWarm;
    // Colours to 1e-4 (a 255-level channel needs 4e-3).
    let colors: Vec<f64> = m
        .curvature()
        .iter()
        .flat_map(|c| match c {
            Some(c) => map.at(0.5 + 0.5 * c.mean / a),
            None => ColourMap::NAN,
        })
        .map(|x| decimal(x as f64, -4))
        .collect();
    let stops = (0..=4)
        .map(|k| {
            let t = k as f64 / 4.0;
            let [r, g, b] = map.at(t);
            let hex = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
            (t, format!("#{:02x}{:02x}{:02x}", hex(r), hex(g), hex(b)))
        })
        .collect();
    // Positions to 1e-7 of the mesh's extent (about the single precision
    // WebGL draws in) as the shortest decimals: a third of the digits to
    // write and to parse, nothing lost on the screen.
    let extent = mesh
        .positions
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let k = if extent > 0.0 && extent.is_finite() {
        extent.log10().floor() as i32 - 7
    } else {
        -7
    };
    MeshView {
        positions: mesh
            .positions
            .iter()
            .flatten()
            .map(|&x| decimal(x, k))
            .collect(),
        indices: mesh.triangles.iter().flatten().copied().collect(),
        colors,
        legend: Legend {
            name: "mean curvature H",
            min: -a,
            max: a,
            stops,
        },
    }
}

/// `x` rounded to a multiple of 10^k, computed so that it prints as the
/// short decimal (a division by an exact power of ten for k < 0).
fn decimal(x: f64, k: i32) -> f64 {
    if !x.is_finite() {
        return x;
    }
    let s = 10f64.powi(k.abs());
    if k < 0 {
        (x * s).round() / s
    } else {
        (x / s).round() * s
    }
}

/// Samples of a Bézier curve through `points`, as a polyline.
fn polyline(points: Vec<Vec3>, samples: usize) -> Vec<Vec3> {
    let c = BezierCurve::new(points);
    (0..=samples)
        .map(|k| c.eval(k as f64 / samples as f64))
        .collect()
}

/// The operators' markers: each entry with its outcome's point.
fn operator_markers(
    operators: &Value,
    outcomes: &[fairsurf::operator::OperatorOutcome],
    size: f64,
) -> Vec<Marker> {
    operators
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
        .map(|(k, o)| operator_json(o, outcomes.get(k).and_then(|r| r.at), size))
        .collect()
}

/// Where an operator's marker goes and what it points at, from its scene
/// entry and where it acts on the result (its outcome's `at`).
fn operator_json(o: &Value, at: Option<Vec3>, size: f64) -> Marker {
    let kind = o["type"].as_str().unwrap_or("operator");
    let target = at.and_then(|s| match kind {
        "point_attractor" | "repellor" => vec3(&o["point"]),
        "plane_attractor" => {
            let n = vec3(&o["normal"])?;
            let d = (dot(n, s) - o["offset"].as_f64()?) / dot(n, n);
            Some(sub(s, scale(n, d)))
        }
        "line_attractor" => {
            let (p, q) = (vec3(&o["point"])?, vec3(&o["direction"])?);
            Some(add(p, scale(q, dot(sub(s, p), q) / dot(q, q))))
        }
        "director" => Some(add(
            s,
            scale(normalize(vec3(&o["direction"])?)?, ARROW * size),
        )),
        "curve_attractor" => {
            let pts: Option<Vec<Vec3>> = o["control_points"].as_array()?.iter().map(vec3).collect();
            Some(BezierCurve::try_new(pts?).ok()?.eval(0.5))
        }
        _ => None,
    });
    Marker {
        name: o["name"].as_str().unwrap_or(kind).into(),
        kind: if o["repel"].as_bool() == Some(true) {
            "repellor"
        } else {
            kind
        }
        .into(),
        at,
        target,
    }
}

/// Each operator's energy and how far its target is met.
fn operator_rows(table: &mut Vec<Row>, operators: &[fairsurf::operator::OperatorOutcome]) {
    for o in operators {
        let what = if o.kind == "director" {
            "angle (rad)"
        } else {
            "distance"
        };
        table.push(row(format!("{}: energy", o.name), o.energy));
        table.push(row(format!("{}: {what}", o.name), o.measure));
    }
}

/// A minimization's rows, the same for every tensor kind: the energy and
/// its terms, the operators, the measures (when analysed), then `extra`
/// (the kind's own figures) and how good the result is.
fn report_rows(table: &mut Vec<Row>, r: &fairsurf::SolveReport, extra: impl FnOnce(&mut Vec<Row>)) {
    table.push(row("energy", r.energy));
    for t in &r.terms {
        table.push(row(t.name.replace('_', " "), t.value));
    }
    operator_rows(table, &r.operators);
    measure_rows(table, r.measures.as_ref());
    extra(table);
    if !r.constraints.is_empty() {
        table.push(row("max constraint violation", r.max_violation));
    }
    table.push(row("gradient (relative)", r.relative_gradient));
    if let Some(c) = &r.check {
        table.push(row("checked: energy excess (relative)", c.excess));
    }
    table.push(row("residual", r.residual));
    table.push(row("condition estimate", r.condition_estimate));
    table.push(row("unknowns", r.unknowns as f64));
    table.push(row(
        "factorization",
        if r.reused { "reused" } else { "new" },
    ));
    table.push(row("solve (ms)", 1e3 * r.timings.total));
    if let Some(nr) = &r.newton {
        table.push(row("Newton iterations", nr.iterations as f64));
    }
}

/// Area, functionals and |H| of a tensor patch.
fn measure_rows(table: &mut Vec<Row>, m: Option<&fairsurf::SurfaceMeasures>) {
    if let Some(m) = m {
        table.push(row("area", m.area));
        table.push(row("Dirichlet", m.dirichlet));
        table.push(row("biharmonic", m.biharmonic));
        table.push(row("mean |H|", m.abs_mean_curvature.mean));
        table.push(row("max |H|", m.abs_mean_curvature.max));
    }
}

/// Handles and sliders of the scene's operators; `markers` are their
/// [`operator_json`] entries (where each acts on the surface).
fn operator_controls(
    scene: &Value,
    markers: &[Marker],
    size: f64,
    handles: &mut Vec<Handle>,
    sliders: &mut Vec<Slider>,
) {
    for (k, field) in Field::entries(scene, "operators", "operator").enumerate() {
        let o = field.entry;
        let at = markers.get(k).and_then(|m| m.at);
        field.point(handles, "point");
        match o["type"].as_str() {
            Some("director") => field.direction(handles, "direction", at, ARROW * size),
            Some("line_attractor") => {
                field.direction(handles, "direction", vec3(&o["point"]), ARROW * size)
            }
            Some("plane_attractor") => field.plane(handles, at, ARROW * size),
            _ => {}
        }
        let s = o["strength"].as_f64().unwrap_or(1.0);
        sliders.push(slider(
            format!("{}/strength", field.prefix),
            format!("{} strength", field.label),
            s,
            (s / 1000.0).clamp(1e-9, 1e-3),
            (s * 1000.0).max(1e3),
        ));
    }
}

/// Handles of the scene's point, normal, in-plane and on-line constraints
/// (the prescribed normals also drawn as arrows); `at` finds where a
/// constraint acts on the solved surface.
fn constraint_controls(
    scene: &Value,
    at: impl Fn(&Value) -> Option<Vec3>,
    size: f64,
    handles: &mut Vec<Handle>,
    normals: &mut Vec<Arrow>,
) {
    for field in Field::entries(scene, "constraints", "constraint") {
        let c = field.entry;
        match c["type"].as_str() {
            Some("point") => field.point(handles, "target"),
            Some("normal") => {
                if let (Some(s), Some(n)) = (at(c), vec3(&c["normal"]).and_then(normalize)) {
                    normals.push(Arrow {
                        at: s,
                        dir: scale(n, ARROW * size),
                    });
                }
                field.direction(handles, "normal", at(c), ARROW * size);
            }
            Some("in_plane") => field.plane(handles, at(c), ARROW * size),
            Some("on_line") => {
                field.point(handles, "point");
                field.direction(handles, "direction", vec3(&c["point"]), ARROW * size);
            }
            _ => {}
        }
    }
}

/// (u, v) of a tensor constraint's `at`: `{"uv": [u, v]}` or `[u, v]`.
fn uv_of(at: &Value) -> Option<[f64; 2]> {
    let a = at.get("uv").unwrap_or(at).as_array()?;
    match a.as_slice() {
        [u, v] => Some([u.as_f64()?, v.as_f64()?]),
        _ => None,
    }
}

/// Length of director markers and direction handles, over the scene size.
const ARROW: f64 = 0.15;

/// A 3-vector in the scene JSON.
fn vec3(v: &Value) -> Option<Vec3> {
    let a = v.as_array()?;
    if a.len() != 3 {
        return None;
    }
    Some([a[0].as_f64()?, a[1].as_f64()?, a[2].as_f64()?])
}

#[cfg(test)]
mod tests {
    use super::{decimal, Methods};

    /// The method select's options are methods of the scene format, each
    /// once, named as scenes write them.
    #[test]
    fn the_method_select_offers_every_scene_method() {
        let mut seen = std::collections::BTreeSet::new();
        for o in Methods::OPTIONS {
            let m: fairsurf_io::Method = serde_json::from_value(serde_json::json!(o)).unwrap();
            assert_eq!(serde_json::to_value(m).unwrap(), o);
            assert!(seen.insert(o));
        }
        // And every method the scene format's schema names is offered.
        let schema = fairsurf_io::TensorScene::json_schema();
        let defs = schema.get("$defs").or(schema.get("definitions")).unwrap();
        let named: std::collections::BTreeSet<&str> = defs["Method"]["oneOf"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["const"].as_str().unwrap())
            .collect();
        assert_eq!(named, seen);
    }

    /// Rounded to 10^k and printed as the short decimal, within half a
    /// step of the value; signs, steps above one and non-finite values.
    #[test]
    fn decimals_print_short_and_stay_within_half_a_step() {
        for (x, k, want) in [
            (0.020833333333333332, -7, "0.0208333"),
            (-0.041666666666666664, -7, "-0.0416667"),
            (0.34028154611587524, -4, "0.3403"),
            (123456.7, 1, "123460"),
            (1.0 / 3.0, -12, "0.333333333333"),
        ] {
            let d = decimal(x, k);
            assert_eq!(
                serde_json::to_string(&d).unwrap().trim_end_matches(".0"),
                want
            );
            assert!(
                (d - x).abs() <= 0.5 * 10f64.powi(k) * (1.0 + 1e-12),
                "{x} {k}"
            );
        }
        assert!(decimal(f64::NAN, -3).is_nan());
        assert_eq!(decimal(f64::INFINITY, -3), f64::INFINITY);
    }
}
