//! What the editor draws and edits, from a solved scene: the mesh coloured
//! by mean curvature, the control net, boundary, normals, operators, the
//! draggable handles and sliders (as JSON pointers into the scene), and the
//! energy/area table (see `editor/API.md`).

use super::{ApiError, ApiResult, Limits};
use axum::http::StatusCode;
use fairsurf::colour::ColourMap;
use fairsurf::triangle::{linear_index, multi_indices};
use fairsurf::vector::{add, dot, normalize, scale, sub};
use fairsurf::{BezierCurve, TriSurface, Vec3};
use fairsurf_io::{
    write_iges_surfaces, write_mesh, write_step_surfaces, Outcome, Scene, SolvedBSplineScene,
    SolvedScene, SolvedTensorScene, SolvedTriScene, SurfaceMesh,
};
use serde_json::{json, Value};
use std::collections::BTreeSet;
use std::time::Instant;

/// Solves the scene and describes the result for the page. `quick` (while
/// the user drags) skips the analysis: area, functionals, the deviation from
/// the normal field and the distance to the guide surface.
pub(crate) fn solve(
    text: &str,
    quick: bool,
    limits: &Limits,
    factors: &fairsurf::FactorCache,
) -> ApiResult<Value> {
    let start = Instant::now();
    let scene = Scene::from_json(text)?;
    check_size(&scene, limits)?;
    let opts = fairsurf::SolveOptions::default().with_analyse(!quick);
    let mut v = match scene.solve_cached(&opts, factors)? {
        SolvedScene::Tensor(s) => tensor_view(&s),
        SolvedScene::Triangular(s) => tri_view(&s),
        SolvedScene::BSpline(s) => bspline_view(&s),
    };
    v["quick"] = json!(quick);
    v["seconds"] = json!(start.elapsed().as_secs_f64());
    Ok(v)
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
    let table: Vec<Value> = scene
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

fn row(label: impl Into<String>, value: impl Into<Value>) -> Value {
    json!({"label": label.into(), "value": value.into()})
}

/// What the page draws and edits (`editor/API.md`, `POST /api/solve`),
/// the same fields for every kind of surface.
#[derive(serde::Serialize)]
struct View<'a> {
    /// "tensor", "triangular" or "bspline".
    kind: &'static str,
    /// Rows `{label, value}`.
    table: Vec<Value>,
    /// The result file's content.
    result: Value,
    /// Positions, indices, colours by mean curvature and their legend.
    mesh: Value,
    /// The control net.
    net: Net<'a>,
    /// Boundary curves as polylines.
    boundary: Vec<Vec<Vec3>>,
    /// Arrows of the guiding normals (`{at, dir}`).
    normals: Vec<Value>,
    /// Operator markers.
    operators: Vec<Value>,
    /// Draggable handles (JSON pointers into the scene).
    handles: Vec<Value>,
    /// Weight sliders (JSON pointers into the scene).
    sliders: Vec<Value>,
    /// The construction method's select (tensor scenes), else null.
    methods: Option<Value>,
}

/// Control points and the index pairs of the net's edges.
#[derive(serde::Serialize)]
struct Net<'a> {
    points: &'a [Vec3],
    edges: Vec<[usize; 2]>,
}

impl View<'_> {
    fn json(&self) -> Value {
        serde_json::to_value(self).expect("a view serializes")
    }
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

/// Sliders for the energy's weights: stretch and bend (with the default
/// rule: bend 1 with two fixed rings, else stretch 1, when neither is
/// given), λ and γ when the scene has those terms.
fn weight_sliders(
    (stretch, bend, rings): (Option<f64>, Option<f64>, Option<usize>),
    lambda: Option<f64>,
    gamma: Option<f64>,
) -> Vec<Value> {
    let none = stretch.is_none() && bend.is_none();
    let default_bend = none && rings >= Some(2);
    let w = |given: Option<f64>, default: bool| given.unwrap_or(if default { 1.0 } else { 0.0 });
    let mut out = vec![
        slider(
            "/energy/stretch".into(),
            "stretch (membrane)".into(),
            w(stretch, none && !default_bend),
            1e-4,
            1e3,
        ),
        slider(
            "/energy/bend".into(),
            "bend (thin plate)".into(),
            w(bend, default_bend),
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

fn slider(pointer: String, label: String, value: f64, min: f64, max: f64) -> Value {
    json!({"pointer": pointer, "label": label, "value": value, "min": min, "max": max, "scale": "log"})
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
fn mesh_json(m: &SurfaceMesh) -> Value {
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
    let colors: Vec<f32> = m
        .curvature()
        .iter()
        .flat_map(|c| match c {
            Some(c) => map.at(0.5 + 0.5 * c.mean / a),
            None => ColourMap::NAN,
        })
        .collect();
    let stops: Vec<Value> = (0..=4)
        .map(|k| {
            let t = k as f64 / 4.0;
            let [r, g, b] = map.at(t);
            let hex = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
            json!([t, format!("#{:02x}{:02x}{:02x}", hex(r), hex(g), hex(b))])
        })
        .collect();
    json!({
        "positions": mesh.positions.iter().flatten().collect::<Vec<_>>(),
        "indices": mesh.triangles.iter().flatten().collect::<Vec<_>>(),
        "colors": colors,
        "legend": {"name": "mean curvature H", "min": -a, "max": a, "stops": stops},
    })
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
) -> Vec<Value> {
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
fn operator_json(o: &Value, at: Option<Vec3>, size: f64) -> Value {
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
    json!({
        "name": o["name"].as_str().unwrap_or(kind),
        "kind": if o["repel"].as_bool() == Some(true) { "repellor" } else { kind },
        "at": at,
        "target": target,
    })
}

/// Each operator's energy and how far its target is met.
fn operator_rows(table: &mut Vec<Value>, operators: &[fairsurf::operator::OperatorOutcome]) {
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

/// Area, functionals and |H| of a tensor patch.
fn measure_rows(table: &mut Vec<Value>, m: Option<&fairsurf::SurfaceMeasures>) {
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
    markers: &[Value],
    size: f64,
    handles: &mut Vec<Value>,
    sliders: &mut Vec<Value>,
) {
    for (k, field) in Field::entries(scene, "operators", "operator").enumerate() {
        let o = field.entry;
        let at = markers.get(k).and_then(|m| vec3(&m["at"]));
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
    handles: &mut Vec<Value>,
    normals: &mut Vec<Value>,
) {
    for field in Field::entries(scene, "constraints", "constraint") {
        let c = field.entry;
        match c["type"].as_str() {
            Some("point") => field.point(handles, "target"),
            Some("normal") => {
                if let (Some(s), Some(n)) = (at(c), vec3(&c["normal"]).and_then(normalize)) {
                    normals.push(json!({"at": s, "dir": scale(n, ARROW * size)}));
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

/// An entry of the scene (an operator or a constraint) whose fields become
/// handles (see `editor/API.md`, `handles[].edit`).
struct Field<'a> {
    /// The entry's JSON pointer (`/operators/2`).
    prefix: String,
    entry: &'a Value,
    /// Its name, or `operator 2`.
    label: String,
    /// `operator` or `control_point` (the handle's colour).
    kind: &'static str,
}

impl<'a> Field<'a> {
    /// The entries of the scene's list `list` (`operators`,
    /// `constraints`), unnamed ones called `noun k`.
    fn entries(
        scene: &'a Value,
        list: &'static str,
        noun: &'static str,
    ) -> impl Iterator<Item = Field<'a>> {
        let kind = if list == "operators" {
            "operator"
        } else {
            "control_point"
        };
        scene[list]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate()
            .map(move |(k, entry)| Field {
                prefix: format!("/{list}/{k}"),
                entry,
                label: entry["name"]
                    .as_str()
                    .map_or(format!("{noun} {k}"), str::to_string),
                kind,
            })
    }

    fn handle(&self, field: &str, position: Vec3, edit: Option<Value>) -> Value {
        let mut h = json!({
            "pointer": format!("{}/{field}", self.prefix),
            "position": position,
            "label": format!("{}: {field}", self.label),
            "kind": self.kind,
        });
        if let Some(e) = edit {
            h["edit"] = e;
        }
        h
    }

    /// The point `field`: the handle is where the value is.
    fn point(&self, handles: &mut Vec<Value>, field: &str) {
        if let Some(p) = vec3(&self.entry[field]) {
            handles.push(self.handle(field, p, None));
        }
    }

    /// The direction `field`, drawn `length` from `anchor` along it.
    fn direction(&self, handles: &mut Vec<Value>, field: &str, anchor: Option<Vec3>, length: f64) {
        if let Some(h) = self.direction_handle(field, anchor, length) {
            handles.push(h);
        }
    }

    fn direction_handle(&self, field: &str, anchor: Option<Vec3>, length: f64) -> Option<Value> {
        let (anchor, d) = (anchor?, normalize(vec3(&self.entry[field])?)?);
        Some(self.handle(
            field,
            add(anchor, scale(d, length)),
            Some(json!({"type": "direction", "anchor": anchor, "length": length})),
        ))
    }

    /// The plane `normal`·x = `offset` as seen from the surface point `at`:
    /// a handle at the foot of `at` on the plane that moves the plane along
    /// its normal, and one for the normal that turns the plane about that
    /// foot.
    fn plane(&self, handles: &mut Vec<Value>, at: Option<Vec3>, length: f64) {
        let (Some(s), Some(n), Some(a)) = (
            at,
            vec3(&self.entry["normal"]),
            self.entry["offset"].as_f64(),
        ) else {
            return;
        };
        let nn = dot(n, n);
        if !(nn > 0.0 && nn.is_finite()) {
            return;
        }
        let foot = add(s, scale(n, (a - dot(n, s)) / nn));
        handles.push(self.handle(
            "offset",
            foot,
            Some(json!({"type": "offset", "anchor": s, "normal": n})),
        ));
        if let Some(mut h) = self.direction_handle("normal", Some(foot), length) {
            h["edit"]["offset"] = json!(format!("{}/offset", self.prefix));
            handles.push(h);
        }
    }
}

/// The view of a B-spline surface: its mesh over the knot domain, its own
/// control net and boundary, the held control points as handles (the
/// scene's own points, also when it is refined before solving), sliders
/// for the energy weights and the report's table.
fn bspline_view(solved: &SolvedBSplineScene) -> Value {
    let scene = &solved.scene;
    let s = solved.surface();
    let (cu, cv) = s.counts();
    let ((u0, u1), (v0, v1)) = (s.knots().0.domain(), s.knots().1.domain());
    let side = |f: &dyn Fn(f64) -> (f64, f64)| -> Vec<Vec3> {
        (0..=64)
            .map(|k| {
                let (u, v) = f(k as f64 / 64.0);
                s.eval(u, v)
            })
            .collect()
    };
    let boundary = vec![
        side(&|t| (u0, v0 + t * (v1 - v0))),
        side(&|t| (u0 + t * (u1 - u0), v1)),
        side(&|t| (u1, v1 - t * (v1 - v0))),
        side(&|t| (u1 - t * (u1 - u0), v0)),
    ];
    // Handles: the scene's given points that are held. With "refine" the
    // solved net is finer; the held points are then the scene's rings.
    let rows = &scene.surface.control_points;
    let held = |i: usize, j: usize| match (scene.fixed_rings, &scene.refine) {
        (Some(k), _) => {
            let (r, c) = (rows.len(), rows.first().map_or(0, Vec::len));
            i.min(j).min(r - 1 - i).min(c - 1 - j) < k
        }
        (None, _) => !solved.free.get(i * cv + j).copied().unwrap_or(true),
    };
    let mut handles = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        for (j, p) in row.iter().enumerate() {
            if let (Some(p), true) = (p, held(i, j)) {
                handles.push(json!({
                    "pointer": format!("/surface/control_points/{i}/{j}"),
                    "position": p,
                    "label": format!("P({i},{j})"),
                    "kind": "control_point",
                }));
            }
        }
    }
    let e = &scene.energy;
    let sliders = weight_sliders(
        (e.stretch, e.bend, scene.fixed_rings),
        e.normal_field.as_ref().map(|f| f.weight),
        e.guide_surface.as_ref().map(|g| g.weight),
    );
    let r = &solved.solution.report;
    let mut table = vec![row("energy", r.energy)];
    for (name, v, given) in [
        ("stretch", r.stretch, true),
        ("bend", r.bend, true),
        ("normal field", r.normal_field, e.normal_field.is_some()),
        ("guide surface", r.guide_surface, e.guide_surface.is_some()),
    ] {
        if given {
            table.push(row(name, v));
        }
    }
    table.push(row("checked: energy difference (relative)", r.energy_error));
    table.push(row("checked: above the minimum (relative)", r.excess));
    table.push(row("gradient (relative)", r.relative_gradient));
    table.push(row("residual", r.residual));
    table.push(row("condition estimate", r.condition_estimate));
    table.push(row("unknowns", r.unknowns as f64));
    let (su, sv) = (s.knots().0.spans().len(), s.knots().1.spans().len());
    table.push(row("spans", format!("{su} × {sv}")));
    table.push(row("solve (ms)", 1e3 * r.timings.total));
    View {
        kind: "bspline",
        table,
        result: json!(solved.result_scene()),
        mesh: mesh_json(&SurfaceMesh::from_bspline(s, 48, 48)),
        net: Net {
            points: s.points(),
            edges: grid_edges(cu, cv),
        },
        boundary,
        normals: Vec::new(),
        operators: Vec::new(),
        handles,
        sliders,
        methods: None,
    }
    .json()
}

fn tensor_view(solved: &SolvedTensorScene) -> Value {
    let scene = &solved.scene;
    let patch = solved.patch();
    let (n, m) = patch.degree();
    let size = size_of(patch.points());
    let scene_json = serde_json::to_value(scene).expect("json");

    let boundary: Vec<Vec<Vec3>> = [
        (0..=m).map(|j| patch.point(0, j)).collect::<Vec<_>>(),
        (0..=n).map(|i| patch.point(i, m)).collect(),
        (0..=m).rev().map(|j| patch.point(n, j)).collect(),
        (0..=n).rev().map(|i| patch.point(i, 0)).collect(),
    ]
    .into_iter()
    .map(|pts| polyline(pts, 48))
    .collect();

    let mut normals = Vec::new();
    if let Some(f) = &solved.built.normal_field {
        for a in 0..=8 {
            for b in 0..=8 {
                let (u, v) = (a as f64 / 8.0, b as f64 / 8.0);
                if let Some(d) = f.direction(u, v) {
                    normals.push(json!({"at": patch.eval(u, v), "dir": scale(d, 0.08 * size)}));
                }
            }
        }
    }

    // Operators: the marker at the surface point they act on (operators
    // come only with the minimizing method).
    let outcomes = match &solved.outcome {
        Outcome::Minimized(sol) => sol.report.operators.as_slice(),
        Outcome::Constructed(_) => &[],
    };
    let operators = operator_markers(&scene_json["operators"], outcomes, size);

    // Handles: the given control points that are held (not free).
    let mut handles = Vec::new();
    for (i, row) in scene.surface.control_points.iter().enumerate() {
        for (j, p) in row.iter().enumerate() {
            let k = i * (m + 1) + j;
            if let Some(p) = p {
                if !solved.built.free.get(k).copied().unwrap_or(true) {
                    handles.push(json!({
                        "pointer": format!("/surface/control_points/{i}/{j}"),
                        "position": p,
                        "label": format!("P({i},{j})"),
                        "kind": "control_point",
                    }));
                }
            }
        }
    }

    let mut sliders = Vec::new();
    let mut table = Vec::new();
    match &solved.outcome {
        Outcome::Minimized(sol) => {
            let e = &scene.energy;
            sliders = weight_sliders(
                (e.stretch, e.bend, scene.fixed_rings),
                e.normal_field.as_ref().map(|f| f.weight),
                e.guide_surface.as_ref().map(|g| g.weight),
            );
            let r = &sol.report;
            table.push(row("energy", r.energy));
            for t in &r.terms {
                table.push(row(t.name.replace('_', " "), t.value));
            }
            operator_rows(&mut table, &r.operators);
            measure_rows(&mut table, r.measures.as_ref());
            if let Some(d) = &solved.normal_deviation {
                table.push(row("normal deviation, mean (rad)", d.mean));
            }
            if let Some(g) = solved.guide_distance {
                table.push(row("distance to guide", g));
            }
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
            operator_controls(&scene_json, &operators, size, &mut handles, &mut sliders);
            let at = |c: &Value| uv_of(&c["at"]).map(|[u, v]| patch.eval(u, v));
            constraint_controls(&scene_json, at, size, &mut handles, &mut normals);
        }
        Outcome::Constructed(c) => {
            let r = &c.report;
            table.push(row("method", r.method.name()));
            table.push(row(
                "exact",
                if r.exact { "yes" } else { "no (least squares)" },
            ));
            table.push(row(
                format!("residual of {}", r.method.equations()),
                r.residual,
            ));
            table.push(row("backward error", r.backward_error));
            measure_rows(&mut table, r.measures.as_ref());
        }
    }
    View {
        kind: "tensor",
        table,
        result: json!(solved.result_scene()),
        mesh: mesh_json(&SurfaceMesh::from_patch(patch, 48, 48)),
        net: Net {
            points: patch.points(),
            edges: grid_edges(n + 1, m + 1),
        },
        boundary,
        normals,
        operators,
        handles,
        sliders,
        methods: Some(json!({
            "pointer": "/method",
            "value": scene_json.get("method").and_then(Value::as_str).unwrap_or("minimize"),
            "options": ["minimize", "harmonic", "biharmonic", "harmonic_mask", "biharmonic_mask"],
        })),
    }
    .json()
}

/// The control net of a triangular surface as line segments.
fn tri_net_edges(s: &TriSurface) -> Vec<[usize; 2]> {
    let n = s.degree();
    let mut edges = BTreeSet::new();
    for t in 0..s.patch_count() {
        let idx = s.patch_indices(t);
        for [i, j, k] in multi_indices(n) {
            let at = |i: usize, j: usize, k: usize| idx[linear_index(n, i, j, k)];
            let a = at(i, j, k);
            let mut add = |b: usize| {
                edges.insert([a.min(b), a.max(b)]);
            };
            if i > 0 {
                add(at(i - 1, j + 1, k));
                add(at(i - 1, j, k + 1));
            }
            if j > 0 {
                add(at(i, j - 1, k + 1));
            }
        }
    }
    edges.into_iter().collect()
}

/// The solved surface's point at a scene's domain point
/// (`{"triangle": t, "bary": [u, v, w]}`), if it is one.
fn domain_point(sol: &fairsurf::triangle::TriSolution, at: &Value) -> Option<Vec3> {
    tri_point(sol, at["triangle"].as_u64()? as usize, vec3(&at["bary"])?)
}

/// The solved surface's point at (t, bary) of the scene's mesh: found in
/// the result patch that came from triangle t (curves split patches) and
/// contains the point, evaluated there.
fn tri_point(sol: &fairsurf::triangle::TriSolution, t: usize, bary: [f64; 3]) -> Option<Vec3> {
    sol.origin
        .iter()
        .enumerate()
        .filter(|(_, (from, _))| *from == t)
        .find_map(|(k, (_, [a, b, c]))| {
            // bary = c₀a + c₁b + c₂c with c₀ + c₁ + c₂ = 1, in the first two
            // coordinates of the original triangle.
            let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            if det.abs() < 1e-14 {
                return None;
            }
            let (px, py) = (bary[0] - a[0], bary[1] - a[1]);
            let c1 = (px * (c[1] - a[1]) - (c[0] - a[0]) * py) / det;
            let c2 = ((b[0] - a[0]) * py - px * (b[1] - a[1])) / det;
            let child = [1.0 - c1 - c2, c1, c2];
            (child.iter().all(|&x| x >= -1e-12) && k < sol.surface.patch_count())
                .then(|| sol.surface.patch(k).eval(child))
        })
}

fn tri_view(solved: &SolvedTriScene) -> Value {
    let scene = &solved.scene;
    let s = solved.surface();
    let r = &solved.solution.report;
    let size = size_of(s.points());
    let scene_json = serde_json::to_value(scene).expect("json");
    let resolution = match s.patch_count() {
        0..=200 => 8,
        201..=2000 => 4,
        _ => 2,
    };
    let boundary: Vec<Vec<Vec3>> = s
        .boundary_edges()
        .into_iter()
        .map(|e| polyline(s.edge_points(e).iter().map(|&g| s.points()[g]).collect(), 8))
        .collect();

    let mut handles = Vec::new();
    let mut normals = Vec::new();
    if scene.fix_boundary {
        let boundary_vertices: BTreeSet<usize> = s.boundary_vertices().into_iter().collect();
        for (k, p) in scene.surface.vertices.iter().enumerate() {
            if boundary_vertices.contains(&k) {
                handles.push(json!({
                    "pointer": format!("/surface/vertices/{k}"),
                    "position": p,
                    "label": format!("vertex {k}"),
                    "kind": "control_point",
                }));
            }
        }
    }
    // The initial net, for fixed points whose value the scene leaves to it
    // (built only if one does).
    let initial = std::cell::OnceCell::new();
    let at = |c: &Value| domain_point(&solved.solution, &c["at"]);
    constraint_controls(&scene_json, at, size, &mut handles, &mut normals);
    for field in Field::entries(&scene_json, "constraints", "constraint") {
        let c = field.entry;
        // A fixed control point: its value, or the net's when not given
        // (dragging writes `value`).
        if c["type"] == "fixed" {
            let position = if c["value"].is_array() {
                Some(c["value"].clone())
            } else {
                c["index"]
                    .as_u64()
                    .and_then(|g| {
                        let net = initial.get_or_init(|| scene.surface().ok()).as_ref()?;
                        net.points().get(g as usize).copied()
                    })
                    .map(|p| json!(p))
            };
            if let Some(position) = position {
                handles.push(json!({
                    "pointer": format!("{}/value", field.prefix),
                    "position": position,
                    "label": field.label,
                    "kind": "control_point",
                }));
            }
        }
    }
    let operators = operator_markers(&scene_json["operators"], &r.operators, size);
    let mut sliders = vec![
        slider(
            "/energy/stretch".into(),
            "α stretch".into(),
            scene.energy.stretch.unwrap_or(0.0),
            1e-4,
            1e3,
        ),
        slider(
            "/energy/bend".into(),
            "β bend".into(),
            scene.energy.bend.unwrap_or(1.0),
            1e-4,
            1e3,
        ),
    ];
    operator_controls(&scene_json, &operators, size, &mut handles, &mut sliders);
    let mut table = vec![
        row("energy", r.total),
        row("stretch", r.stretch),
        row("bend", r.bend),
    ];
    operator_rows(&mut table, &r.operators);
    table.extend([
        row("max constraint violation", r.max_violation),
        row("gradient (relative)", r.relative_gradient),
        row(
            "checked: energy excess (relative)",
            r.check.as_ref().map(|c| c.excess),
        ),
        row(
            "max normal angle across edges (rad)",
            r.max_edge_normal_angle.map(|(a, _)| a),
        ),
        row("patches", r.patches as f64),
        row("unknowns", r.unknowns as f64),
        row("continuity rows dropped", r.dropped.len() as f64),
        row(
            "factorization",
            match (r.reused, r.kkt.is_some_and(|k| k.reused_symbolic)) {
                (true, _) => "reused",
                (false, true) => "refactored (ordering kept)",
                _ => "new",
            },
        ),
        row("solve (ms)", 1e3 * r.seconds.total),
    ]);
    View {
        kind: "triangular",
        table,
        result: json!(solved.result_scene()),
        mesh: mesh_json(&SurfaceMesh::from_tri_surface(s, resolution)),
        net: Net {
            points: s.points(),
            edges: tri_net_edges(s),
        },
        boundary,
        normals,
        operators,
        handles,
        sliders,
        methods: None,
    }
    .json()
}
