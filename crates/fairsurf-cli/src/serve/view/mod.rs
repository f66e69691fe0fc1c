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

mod controls;
mod types;
use controls::*;
pub(crate) use types::MeshEncoding;
use types::*;

/// Solves the scene and describes the result for the page, as JSON text
/// (serialized straight from the typed view, no value tree). `quick` (while
/// the user drags) skips the analysis (area, functionals, the deviation from
/// the normal field and the distance to the guide surface) and the check's
/// polishing corrections where the net as solved meets the tolerance
/// ([`fairsurf::SolveOptions::polish`]). `encoding` is
/// how the mesh's arrays are written (JSON lists or base64). `seconds`
/// includes the serialization.
pub(crate) fn solve(
    text: &str,
    quick: bool,
    encoding: MeshEncoding,
    limits: &Limits,
    factors: &fairsurf::FactorCache,
) -> ApiResult<String> {
    let start = Instant::now();
    let scene = Scene::from_json(text)?;
    check_size(&scene, limits)?;
    let opts = fairsurf::SolveOptions::default()
        .with_analyse(!quick)
        .with_polish(!quick);
    let solved = scene.solve_cached(&opts, factors)?;
    let mut view = match &solved {
        SolvedScene::Tensor(s) => tensor_view(s),
        SolvedScene::Triangular(s) => tri_view(s),
        SolvedScene::BSpline(s) => bspline_view(s),
    };
    view.mesh.encoding = encoding;
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

/// Cells per side of a tensor surface's mesh for the page.
const GRID_CELLS: usize = 48;

/// [`mesh_view`] of a tensor surface on its GRID_CELLS × GRID_CELLS grid
/// (the positions and curvatures only: the page computes its own normals),
/// which a base64 answer sends as its size instead of the indices.
fn grid_mesh_view(surface: &impl ParamSurface) -> MeshView {
    let (us, vs) = surface.uniform_grid(GRID_CELLS, GRID_CELLS);
    let samples = surface.samples_on(&us, &vs);
    let n = GRID_CELLS + 1;
    mesh_view(
        samples.iter().map(|s| s.point).collect(),
        samples
            .iter()
            .map(|s| s.curvature.map(|c| c.mean))
            .collect(),
        fairsurf::TriMesh::grid_triangles(n, n),
        Some((n, n)),
    )
}

/// [`mesh_view`] of a mesh with its curvatures.
fn surface_mesh_view(m: &SurfaceMesh) -> MeshView {
    mesh_view(
        m.mesh().positions.clone(),
        m.curvature().iter().map(|c| c.map(|c| c.mean)).collect(),
        m.mesh().triangles.clone(),
        None,
    )
}

/// The mesh with per-vertex colours by signed mean curvature H (`means`,
/// `None` where the surface is singular; cool–warm, symmetric about 0 up
/// to the 98th percentile of |H|) and its legend.
fn mesh_view(
    positions: Vec<Vec3>,
    means: Vec<Option<f64>>,
    triangles: Vec<[u32; 3]>,
    grid: Option<(usize, usize)>,
) -> MeshView {
    debug_assert!(grid.is_none_or(|(rows, cols)| {
        positions.len() == rows * cols && triangles.len() == 2 * (rows - 1) * (cols - 1)
    }));
    let mut abs: Vec<f64> = means.iter().flatten().map(|h| h.abs()).collect();
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
    let colors: Vec<f32> = means
        .iter()
        .flat_map(|h| match h {
            Some(h) => map.at(0.5 + 0.5 * h / a),
            None => ColourMap::NAN,
        })
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
    // WebGL draws in) as the shortest decimals when written as JSON: a
    // third of the digits to write and to parse, nothing lost on the
    // screen.
    let extent = positions
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let digits = if extent > 0.0 && extent.is_finite() {
        extent.log10().floor() as i32 - 7
    } else {
        -7
    };
    MeshView {
        positions: positions.iter().flatten().copied().collect(),
        digits,
        indices: triangles.iter().flatten().copied().collect(),
        grid,
        colors,
        legend: Legend {
            name: "mean curvature H",
            min: -a,
            max: a,
            stops,
        },
        encoding: MeshEncoding::Json,
    }
}

/// `x` rounded to a multiple of 10^k, computed so that it prints as the
/// short decimal (a division by an exact power of ten for k < 0).
pub(super) fn decimal(x: f64, k: i32) -> f64 {
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
    use super::{Legend, MeshEncoding, MeshView};
    use fairsurf_io::base64;

    /// Past 65,536 vertices a base64 mesh's indices take four bytes each
    /// (and say so); below, two.
    #[test]
    fn base64_indices_widen_past_65536_vertices() {
        for (vertices, kind, width) in [(65_536, "uint16", 2), (65_537, "uint32", 4)] {
            let last = vertices as u32 - 1;
            let mesh = MeshView {
                positions: vec![0.5; 3 * vertices],
                digits: -7,
                indices: vec![0, 1, last],
                grid: None,
                colors: vec![1.0; 3 * vertices],
                legend: Legend {
                    name: "h",
                    min: -1.0,
                    max: 1.0,
                    stops: Vec::new(),
                },
                encoding: MeshEncoding::Base64,
            };
            let v = serde_json::to_value(&mesh).unwrap();
            assert_eq!(v["index_type"], kind);
            let mut bytes = Vec::new();
            for i in [0u32, 1, last] {
                bytes.extend_from_slice(&i.to_le_bytes()[..width]);
            }
            assert_eq!(v["indices"], base64(&bytes));
            assert_eq!(v["colors"], base64(&vec![255u8; 3 * vertices]));
            assert_eq!(
                v["positions"],
                base64(&0.5f32.to_le_bytes().repeat(3 * vertices))
            );
        }
    }

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
