//! `fairsurf._fairsurf`: the native half of the Python module `fairsurf`.
//!
//! It wraps the Rust library and nothing else: scenes go in as JSON text
//! (the Python half turns paths and dicts into text), results come out as
//! numpy arrays and JSON text, errors as the exceptions of
//! `fairsurf/_errors.py` (a scene error carries its JSON path). Every solve,
//! evaluation, mesh, export and picture runs with the GIL released, so
//! Python threads overlap.

use fairsurf_io::{Error as IoError, MeshOptions, Scene, SolvedScene, Surface, SurfaceType};
use fairsurf_render::{render, ColourBy, Panel, Range, RenderOptions, View};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::PathBuf;

/// Raises `fairsurf._errors.<class>(message)` with the given attributes.
fn raise(py: Python<'_>, class: &str, message: String, attrs: &[(&str, &str)]) -> PyErr {
    let made = (|| -> PyResult<PyErr> {
        let cls = py.import("fairsurf._errors")?.getattr(class)?;
        let err = cls.call1((message.clone(),))?;
        for (k, v) in attrs {
            err.setattr(*k, *v)?;
        }
        Ok(PyErr::from_value(err))
    })();
    made.unwrap_or_else(|e| e)
}

/// The Python exception of an I/O-crate error: `SceneError` (with `.path`),
/// `OSError` for files, `ExportError`, `UnverifiedError` and `SolveError`.
fn to_py(py: Python<'_>, e: IoError) -> PyErr {
    let message = e.to_string();
    match &e {
        IoError::Scene { path, .. } => raise(py, "SceneError", message, &[("path", path)]),
        IoError::Read { source, .. } | IoError::Write { source, .. } => {
            let err = std::io::Error::new(source.kind(), message);
            PyErr::from(err)
        }
        IoError::Export { .. } => raise(py, "ExportError", message, &[]),
        IoError::Solve(fairsurf::Error::Unverified { .. } | fairsurf::Error::Unmet { .. }) => {
            raise(py, "UnverifiedError", message, &[])
        }
        IoError::Solve(_) => raise(py, "SolveError", message, &[]),
        _ => raise(py, "FairsurfError", message, &[]),
    }
}

/// Points as a numpy array of shape `shape` + (3,): the vector's buffer is
/// handed over to numpy (flattened in place, not copied).
fn points_array<'py>(
    py: Python<'py>,
    points: Vec<[f64; 3]>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = points.into_flattened();
    let mut dims = shape.to_vec();
    dims.push(3);
    Ok(PyArray1::from_vec(py, flat).reshape(dims)?.into_any())
}

/// The patch of each parameter of a triangular surface (`patch` given,
/// in range, and (u, v) in the triangle u + v ≤ 1); `None` for a tensor or
/// B-spline surface, which takes no `patch`.
fn triangle_parameters(
    surface: &Surface,
    us: &[f64],
    vs: &[f64],
    patch: Option<PyReadonlyArray1<'_, i64>>,
) -> PyResult<Option<Vec<usize>>> {
    let Surface::Triangular(t) = surface else {
        return match patch {
            None => Ok(None),
            Some(_) => Err(PyValueError::new_err(format!(
                "patch is for triangular surfaces; this one is {} (parameters (u, v) only)",
                surface.surface_type().name()
            ))),
        };
    };
    let Some(patch) = patch else {
        return Err(PyValueError::new_err(
            "a triangular surface is evaluated at (u, v) of a patch: give patch=… (the \
             barycentric point is (u, v, 1 − u − v))",
        ));
    };
    let k = patch.as_slice()?;
    if k.len() != us.len() {
        return Err(PyValueError::new_err(format!(
            "patch and u differ in length ({} and {})",
            k.len(),
            us.len()
        )));
    }
    let count = t.patch_count();
    if let Some(i) = k.iter().position(|&p| p < 0 || p as usize >= count) {
        return Err(PyValueError::new_err(format!(
            "patch[{i}] = {}: the surface has patches 0 to {}",
            k[i],
            count - 1
        )));
    }
    if let Some(i) = (0..us.len()).find(|&i| us[i] + vs[i] > 1.0 + 1e-12) {
        return Err(PyValueError::new_err(format!(
            "u[{i}] + v[{i}] = {}: a point of a triangular patch has u + v ≤ 1",
            us[i] + vs[i]
        )));
    }
    Ok(Some(k.iter().map(|&p| p as usize).collect()))
}

/// The evaluate dict of derivatives: each column's vector handed to numpy.
fn derivatives_dict(
    py: Python<'_>,
    d: Vec<fairsurf::SurfaceDerivatives>,
) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
    let curv: Vec<_> = d.iter().map(fairsurf::analysis::curvature_from).collect();
    let out = pyo3::types::PyDict::new(py);
    let n = d.len();
    let column = |f: &dyn Fn(&fairsurf::SurfaceDerivatives) -> [f64; 3]| -> Vec<[f64; 3]> {
        d.iter().map(f).collect()
    };
    out.set_item("points", points_array(py, column(&|x| x.point), &[n])?)?;
    out.set_item("du", points_array(py, column(&|x| x.du), &[n])?)?;
    out.set_item("dv", points_array(py, column(&|x| x.dv), &[n])?)?;
    out.set_item("duu", points_array(py, column(&|x| x.duu), &[n])?)?;
    out.set_item("duv", points_array(py, column(&|x| x.duv), &[n])?)?;
    out.set_item("dvv", points_array(py, column(&|x| x.dvv), &[n])?)?;
    let normals = column(&|x| x.normal().unwrap_or([f64::NAN; 3]));
    out.set_item("normals", points_array(py, normals, &[n])?)?;
    let scalar = |f: &dyn Fn(&fairsurf::analysis::Curvature) -> f64| {
        let v: Vec<f64> = curv
            .iter()
            .map(|c| c.as_ref().map_or(f64::NAN, f))
            .collect();
        PyArray1::from_vec(py, v)
    };
    out.set_item("gaussian", scalar(&|c| c.gaussian))?;
    out.set_item("mean", scalar(&|c| c.mean))?;
    out.set_item("k1", scalar(&|c| c.principal.0))?;
    out.set_item("k2", scalar(&|c| c.principal.1))?;
    Ok(out)
}

/// The knot vectors U, V as numpy arrays.
type KnotArrays<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// A surface of any kind: what a result holds, or a scene whose control
/// points are all given.
#[pyclass(module = "fairsurf._fairsurf", frozen, name = "Surface")]
struct PySurface {
    surface: Surface,
}

#[pymethods]
impl PySurface {
    /// "tensor", "triangular" or "bspline".
    #[getter]
    fn surface_type(&self) -> &'static str {
        self.surface.surface_type().name()
    }

    /// The control points: (n+1, m+1, 3) for a tensor patch, (count_u,
    /// count_v, 3) for a B-spline surface, (N, 3) for a triangular surface
    /// (its patches index them: `patch_indices`).
    #[getter]
    fn control_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match &self.surface {
            Surface::Tensor(p) => {
                let (n, m) = p.degree();
                points_array(py, p.points().to_vec(), &[n + 1, m + 1])
            }
            Surface::BSpline(s) => {
                let (cu, cv) = s.counts();
                points_array(py, s.points().to_vec(), &[cu, cv])
            }
            Surface::Triangular(t) => points_array(py, t.points().to_vec(), &[t.points().len()]),
        }
    }

    /// The surface as a scene's JSON text with every control point given
    /// (`{"surface": …}`): `load` reads it back as this surface exactly.
    fn scene_text(&self) -> String {
        serde_json::json!({ "surface": self.surface.scene_json() }).to_string()
    }

    /// The degree: (n, m) of a tensor or B-spline surface, (n, n) of a
    /// triangular one.
    #[getter]
    fn degree(&self) -> (usize, usize) {
        match &self.surface {
            Surface::Tensor(p) => p.degree(),
            Surface::BSpline(s) => s.degree(),
            Surface::Triangular(t) => (t.degree(), t.degree()),
        }
    }

    /// The knot vectors (U, V) of a B-spline surface, `None` otherwise.
    #[getter]
    fn knots<'py>(&self, py: Python<'py>) -> Option<KnotArrays<'py>> {
        match &self.surface {
            Surface::BSpline(s) => {
                let (u, v) = s.knots();
                Some((
                    PyArray1::from_slice(py, u.knots()),
                    PyArray1::from_slice(py, v.knots()),
                ))
            }
            _ => None,
        }
    }

    /// For a triangular surface: each patch's control-point indices into
    /// `control_points`, shape (patches, (n+1)(n+2)/2), in the order
    /// (i, j, k) with i descending, then j descending; `None` otherwise.
    #[getter]
    fn patch_indices<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Surface::Triangular(t) = &self.surface else {
            return Ok(None);
        };
        let per = t.patch_indices(0).len();
        let flat: Vec<u64> = (0..t.patch_count())
            .flat_map(|k| t.patch_indices(k).iter().map(|&g| g as u64))
            .collect();
        Ok(Some(
            PyArray1::from_vec(py, flat)
                .reshape([t.patch_count(), per])?
                .into_any(),
        ))
    }

    /// The surface as tensor Bézier patches, each an array (n+1, m+1, 3):
    /// the patch of a tensor surface, a B-spline surface's Bézier pieces, a
    /// triangular surface's patches as exact tensor patches with one side
    /// collapsed.
    fn tensor_patches<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        self.surface
            .tensor_patches()
            .iter()
            .map(|p| {
                let (n, m) = p.degree();
                points_array(py, p.points().to_vec(), &[n + 1, m + 1])
            })
            .collect()
    }

    /// Point, first and second derivatives, normal and curvatures at the
    /// parameters (u[i], v[i]) ∈ [0, 1]² of a tensor or B-spline surface, or
    /// of a triangular surface at the barycentric point (u[i], v[i],
    /// 1 − u[i] − v[i]) of patch `patch[i]` (derivatives along its first two
    /// barycentric directions): a dict of arrays (points, du, dv, duu, duv,
    /// dvv, normals: (N, 3); gaussian, mean, k1, k2: (N,); NaN where the
    /// surface is singular). The parameters are copied once: the GIL is
    /// released while they are read.
    #[pyo3(signature = (u, v, patch=None))]
    fn _evaluate<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray1<'py, f64>,
        v: PyReadonlyArray1<'py, f64>,
        patch: Option<PyReadonlyArray1<'py, i64>>,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let us = u.as_slice()?.to_vec();
        let vs = v.as_slice()?.to_vec();
        if us.len() != vs.len() {
            return Err(PyValueError::new_err(format!(
                "u and v differ in length ({} and {})",
                us.len(),
                vs.len()
            )));
        }
        for (name, t) in [("u", &us), ("v", &vs)] {
            if let Some(i) = t.iter().position(|x| !(0.0..=1.0).contains(x)) {
                return Err(PyValueError::new_err(format!(
                    "{name}[{i}] = {}: parameters lie in [0, 1]",
                    t[i]
                )));
            }
        }
        let surface = &self.surface;
        let patches = triangle_parameters(surface, &us, &vs, patch)?;
        let d: Vec<fairsurf::SurfaceDerivatives> = py.detach(|| match (surface, &patches) {
            (Surface::Triangular(t), Some(k)) => {
                let patches: Vec<_> = t.patches().collect();
                us.iter()
                    .zip(&vs)
                    .zip(k)
                    .map(|((&u, &v), &k)| patches[k].derivatives([u, v, (1.0 - u - v).max(0.0)]))
                    .collect()
            }
            _ => us
                .iter()
                .zip(&vs)
                .map(|(&u, &v)| surface.derivatives(u, v).expect("a tensor-product surface"))
                .collect(),
        });
        derivatives_dict(py, d)
    }

    /// A triangle mesh: a dict of vertices (V, 3), faces (F, 3) uint32,
    /// normals (V, 3), uvs (V, 2), mean and gaussian curvature (V,) (NaN
    /// where singular). `resolution` quads per direction of a tensor or
    /// B-spline surface, ⌈resolution/4⌉ subdivisions per triangular patch.
    fn _mesh<'py>(
        &self,
        py: Python<'py>,
        resolution: usize,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        check_resolution(resolution)?;
        check_mesh_size(&self.surface, resolution)?;
        let surface = &self.surface;
        let mesh = py.detach(|| surface.mesh(resolution));
        let c = mesh.curvature();
        let mean: Vec<f64> = c.iter().map(|c| c.map_or(f64::NAN, |c| c.mean)).collect();
        let gauss: Vec<f64> = c
            .iter()
            .map(|c| c.map_or(f64::NAN, |c| c.gaussian))
            .collect();
        let t = mesh.into_mesh();
        let out = pyo3::types::PyDict::new(py);
        let nv = t.positions.len();
        // A B-spline mesh's uvs are knot-domain values: mapped onto [0, 1]²
        // as evaluate takes them.
        let ((u0, u1), (v0, v1)) = match &self.surface {
            Surface::BSpline(s) => (s.knots().0.domain(), s.knots().1.domain()),
            _ => ((0.0, 1.0), (0.0, 1.0)),
        };
        let uvs: Vec<f64> = t
            .uvs
            .iter()
            .flat_map(|&[u, v]| [(u - u0) / (u1 - u0), (v - v0) / (v1 - v0)])
            .collect();
        // A triangular surface is meshed patch by patch, each patch's
        // vertices its own and in order: the patch of every vertex.
        let patches = match &self.surface {
            Surface::Triangular(s) if s.patch_count() > 0 => {
                let per = nv / s.patch_count();
                Some(PyArray1::from_vec(
                    py,
                    (0..nv).map(|i| (i / per) as i64).collect(),
                ))
            }
            _ => None,
        };
        out.set_item("vertices", points_array(py, t.positions, &[nv])?)?;
        out.set_item("normals", points_array(py, t.normals, &[nv])?)?;
        out.set_item("uvs", PyArray1::from_vec(py, uvs).reshape([nv, 2])?)?;
        let nf = t.triangles.len();
        let faces: Vec<u32> = t.triangles.into_flattened();
        out.set_item("faces", PyArray1::from_vec(py, faces).reshape([nf, 3])?)?;
        out.set_item("mean_curvature", PyArray1::from_vec(py, mean))?;
        out.set_item("gaussian_curvature", PyArray1::from_vec(py, gauss))?;
        out.set_item("patches", patches)?;
        Ok(out)
    }

    /// Writes the surface to `path` in the format its extension names
    /// (.step/.stp, .igs/.iges, .obj, .ply, .stl, .glb, .gltf); returns
    /// (summary, warning or None). Nothing is written on an error.
    #[pyo3(signature = (path, resolution = 64, colour_range = None))]
    fn export(
        &self,
        py: Python<'_>,
        path: PathBuf,
        resolution: usize,
        colour_range: Option<(f64, f64)>,
    ) -> PyResult<(String, Option<String>)> {
        check_resolution(resolution)?;
        check_mesh_size(&self.surface, resolution)?;
        let options = MeshOptions {
            colour_range: colour_range.map(|(lo, hi)| [lo, hi]),
        };
        let surface = &self.surface;
        let done = py
            .detach(|| surface.export(&path, resolution, &options))
            .map_err(|e| to_py(py, e))?;
        Ok((done.summary, done.warning))
    }

    /// A PNG picture (bytes) as `fairsurf render` draws it: colour by
    /// "abs-mean", "mean", "gaussian" or "none"; range "auto" or "lo,hi";
    /// view "iso", "top", "front", "side" or "azimuth,elevation".
    #[pyo3(signature = (width = 1200, height = 900, colour = "abs-mean", range = "auto",
        view = "iso", net = false, boundary = true, zebra = None, isophotes = None,
        resolution = 64, colour_bar = true))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        width: u32,
        height: u32,
        colour: &str,
        range: &str,
        view: &str,
        net: bool,
        boundary: bool,
        zebra: Option<u32>,
        isophotes: Option<u32>,
        resolution: usize,
        colour_bar: bool,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let bad = |e: fairsurf_render::Error| PyValueError::new_err(e.to_string());
        let opts = RenderOptions {
            width,
            height,
            colour: ColourBy::parse(colour).map_err(bad)?,
            range: Range::parse(range).map_err(bad)?,
            view: View::parse(view).map_err(bad)?,
            control_net: net,
            boundary,
            zebra,
            isophotes,
            resolution,
            colour_bar,
            ..RenderOptions::default()
        };
        opts.validate().map_err(bad)?;
        let panel = match &self.surface {
            Surface::Tensor(p) => Panel::new(p.clone()),
            Surface::BSpline(s) => Panel::bspline(s.clone()),
            Surface::Triangular(t) => Panel::triangular(t.patches().collect()),
        };
        let png = py.detach(|| -> Result<Vec<u8>, fairsurf_render::Error> {
            let picture = render(&[panel], &opts)?;
            let mut bytes = Vec::new();
            picture.encode_png(&mut bytes)?;
            Ok(bytes)
        });
        Ok(PyBytes::new(py, &png.map_err(bad)?))
    }
}

/// Largest mesh made for Python: 50 million triangles (about 5 GB with the
/// curvature); beyond it the allocation would end the interpreter.
const MAX_TRIANGLES: usize = 50_000_000;

/// Refuses a mesh above [`MAX_TRIANGLES`].
fn check_mesh_size(surface: &Surface, resolution: usize) -> PyResult<()> {
    let n = surface.mesh_triangles(resolution);
    if n > MAX_TRIANGLES {
        return Err(PyValueError::new_err(format!(
            "resolution {resolution}: the mesh would have {n} triangles, more than \
             {MAX_TRIANGLES}; lower the resolution"
        )));
    }
    Ok(())
}

/// Mesh resolutions of `fairsurf export`: 1 to 4096.
fn check_resolution(r: usize) -> PyResult<()> {
    if !(1..=4096).contains(&r) {
        return Err(PyValueError::new_err(format!(
            "resolution {r}: expected 1 to 4096 quads per direction"
        )));
    }
    Ok(())
}

/// A solved scene: the surface, the report and the result file.
#[pyclass(module = "fairsurf._fairsurf", frozen, name = "Solved")]
struct PySolved {
    solved: SolvedScene,
}

#[pymethods]
impl PySolved {
    /// The solved surface.
    #[getter]
    fn surface(&self) -> PySurface {
        PySurface {
            surface: self.solved.surface(),
        }
    }

    /// The report as JSON text (the result file's "report").
    fn report_json(&self) -> String {
        self.solved.report_json().to_string()
    }

    /// The result file's text: the scene with every control point and the
    /// report; solving it again gives the same surface.
    fn to_json(&self) -> String {
        self.solved.result_text()
    }
}

/// Writes `text` to `path` atomically (a result file kept as text, e.g. a
/// result that crossed a process boundary).
#[pyfunction]
fn write_text(py: Python<'_>, path: PathBuf, text: String) -> PyResult<()> {
    py.detach(|| {
        fairsurf_io::write_atomic(&path, |w| {
            w.write_all(text.as_bytes())?;
            w.write_all(b"\n")
        })
    })
    .map_err(|e| to_py(py, e))
}

/// Monterde & Ugail's comparison of a tensor scene's boundary (harmonic,
/// biharmonic, the two masks), as JSON text: what `fairsurf compare --json`
/// prints.
#[pyfunction]
fn compare(py: Python<'_>, text: String) -> PyResult<String> {
    let value = py
        .detach(|| match Scene::from_json(&text)? {
            Scene::Tensor(s) => s.compare().map(|c| fairsurf_io::comparison_json(&c)),
            other => Err(IoError::scene(
                "surface.type",
                format!(
                    "compare works on tensor-product scenes, this one is {}",
                    other.surface_type().name()
                ),
            )),
        })
        .map_err(|e| to_py(py, e))?;
    Ok(value.to_string())
}

/// The memory budget of a solve: `max_memory_gb` GB (the command line's
/// --max-memory-gb; default 8).
fn budget(max_memory_gb: f64) -> PyResult<fairsurf::budget::Budget> {
    if !(max_memory_gb > 0.0 && max_memory_gb <= 1e6) {
        return Err(PyValueError::new_err(format!(
            "max_memory_gb {max_memory_gb}: expected a positive number of GB"
        )));
    }
    Ok(fairsurf::budget::Budget {
        max_bytes: (max_memory_gb * 1e9) as usize,
        cancel: None,
    })
}

/// Parses and solves one scene (JSON text) within the memory budget.
fn solve_text(text: &str, budget: &fairsurf::budget::Budget) -> fairsurf_io::Result<SolvedScene> {
    fairsurf::budget::with_budget(budget.clone(), || {
        Scene::from_json(text).and_then(|s| s.solve())
    })
}

/// Parses and solves one scene (JSON text), the GIL released.
#[pyfunction]
#[pyo3(signature = (text, max_memory_gb = 8.0))]
fn solve(py: Python<'_>, text: String, max_memory_gb: f64) -> PyResult<PySolved> {
    let b = budget(max_memory_gb)?;
    py.detach(|| solve_text(&text, &b))
        .map(|solved| PySolved { solved })
        .map_err(|e| to_py(py, e))
}

/// Solves many scenes on `threads` threads (the GIL released); each entry
/// of the answer is a `Solved` or the exception its scene raised.
#[pyfunction]
#[pyo3(signature = (texts, threads, max_memory_gb = 8.0))]
fn solve_many(
    py: Python<'_>,
    texts: Vec<String>,
    threads: usize,
    max_memory_gb: f64,
) -> PyResult<Vec<Py<PyAny>>> {
    let b = budget(max_memory_gb)?;
    if threads == 0 {
        return Err(PyValueError::new_err("threads: expected at least 1"));
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    let slots: Vec<std::sync::Mutex<Option<fairsurf_io::Result<SolvedScene>>>> =
        texts.iter().map(|_| std::sync::Mutex::new(None)).collect();
    py.detach(|| {
        std::thread::scope(|s| {
            for _ in 0..threads.min(texts.len()) {
                s.spawn(|| loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(text) = texts.get(k) else { break };
                    // A panic in one solve is that scene's error, not the batch's.
                    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                        solve_text(text, &b)
                    }))
                    .unwrap_or_else(|panic| {
                        let why = panic
                            .downcast_ref::<&str>()
                            .map(|s| s.to_string())
                            .or_else(|| panic.downcast_ref::<String>().cloned())
                            .unwrap_or_default();
                        Err(IoError::Solve(fairsurf::Error::Mismatch {
                            what: "the solve".into(),
                            expected: "an answer".into(),
                            got: format!("an internal error ({why}); please report it"),
                        }))
                    });
                    *slots[k].lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
                });
            }
        })
    });
    slots
        .into_iter()
        .map(|slot| {
            let r = slot
                .into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .expect("every scene solved");
            Ok(match r {
                Ok(solved) => Py::new(py, PySolved { solved })?.into_any(),
                Err(e) => to_py(py, e).into_value(py).into_any(),
            })
        })
        .collect()
}

/// The surface a scene gives (every control point given, e.g. a result
/// file), without solving.
#[pyfunction]
fn load(py: Python<'_>, text: String) -> PyResult<PySurface> {
    py.detach(|| Scene::from_json(&text).and_then(|s| s.surface()))
        .map(|surface| PySurface { surface })
        .map_err(|e| to_py(py, e))
}

/// Measures of the surface a scene gives, as JSON text: an object of
/// label → value, as `fairsurf analyse --json` prints them.
#[pyfunction]
fn analyse(py: Python<'_>, text: String) -> PyResult<String> {
    let measures = py
        .detach(|| Scene::from_json(&text).and_then(|s| s.analyse()))
        .map_err(|e| to_py(py, e))?;
    let map: serde_json::Map<String, serde_json::Value> = measures.into_iter().collect();
    Ok(serde_json::Value::Object(map).to_string())
}

/// The JSON Schema of a scene kind ("tensor", "triangular", "bspline") or
/// of fill or blend scenes ("fill", "blend"), as JSON text.
#[pyfunction]
fn schema(py: Python<'_>, kind: &str) -> PyResult<String> {
    if kind == "fill" {
        return Ok(fairsurf_io::FillScene::json_schema().to_string());
    }
    if kind == "blend" {
        return Ok(fairsurf_io::BlendScene::json_schema().to_string());
    }
    let t = SurfaceType::ALL
        .into_iter()
        .find(|t| t.name() == kind)
        .ok_or_else(|| {
            let names: Vec<_> = SurfaceType::ALL.iter().map(|t| t.name()).collect();
            raise(
                py,
                "SceneError",
                format!("unknown surface type {kind:?}: expected one of {names:?}"),
                &[("path", "surface.type")],
            )
        })?;
    Ok(t.json_schema().to_string())
}

/// Filled holes: the input faces, the fills and the report.
#[pyclass(module = "fairsurf._fairsurf", frozen, name = "Filled")]
struct PyFilled {
    faces: Vec<fairsurf::bspline::BSplineSurface>,
    /// Per face, the rational surface it stands in for (written as that).
    rational: Vec<Option<std::sync::Arc<fairsurf::bspline::RationalSurface>>>,
    /// Vertices and edges closer than this are shared in the STEP file.
    sew_within: f64,
    fills: Vec<fairsurf::fill::HoleFill>,
    report: String,
}

#[pymethods]
impl PyFilled {
    /// The input faces (B-spline surfaces; a rational face such as a
    /// cylinder as its polynomial stand-in, see the report's `stand_ins`).
    fn faces(&self) -> Vec<PySurface> {
        self.faces
            .iter()
            .map(|f| PySurface {
                surface: Surface::BSpline(f.clone()),
            })
            .collect()
    }

    /// The fills, one per filled hole: a B-spline surface for a 4-sided
    /// hole, a triangular surface (a fan around a centre) otherwise.
    fn fills(&self) -> Vec<PySurface> {
        self.fills
            .iter()
            .map(|f| PySurface {
                surface: match f {
                    fairsurf::fill::HoleFill::Patch(p) => Surface::BSpline(p.surface.clone()),
                    fairsurf::fill::HoleFill::Fan(t) => Surface::Triangular(t.surface.clone()),
                },
            })
            .collect()
    }

    /// The report as JSON text (what `fairsurf fill --json` prints, without
    /// the file names).
    fn report_json(&self) -> String {
        self.report.clone()
    }

    /// Writes the faces and the fills as one sewn STEP shell.
    fn write_step(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let surfaces = fairsurf_io::fill_surfaces(&self.faces, &self.rational, &self.fills);
        py.detach(|| fairsurf_io::write_step_sewn(&path, &surfaces, self.sew_within))
            .map_err(|e| to_py(py, e))
    }
}

/// Fills holes between faces given as a STEP file's text (`step`) or a
/// JSON fill scene's, the GIL released; `holes` and the options override
/// the scene's.
#[pyfunction]
#[pyo3(signature = (text, step, holes = None, normal_weight = None, elevate = None, willmore_steps = None, descent_steps = None))]
fn fill(
    py: Python<'_>,
    text: String,
    step: bool,
    holes: Option<Vec<usize>>,
    normal_weight: Option<f64>,
    elevate: Option<usize>,
    willmore_steps: Option<usize>,
    descent_steps: Option<usize>,
) -> PyResult<PyFilled> {
    if let Some(w) = normal_weight {
        if !(w >= 0.0 && w.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "normal_weight {w}: expected a number ≥ 0"
            )));
        }
    }
    if elevate.is_some_and(|e| e > 10)
        || willmore_steps.is_some_and(|s| s > 50)
        || descent_steps.is_some_and(|s| s > 10_000)
    {
        return Err(PyValueError::new_err(
            "elevate is 0 to 10, willmore_steps 0 to 50 and descent_steps 0 to 10000",
        ));
    }
    py.detach(|| {
        let input = fairsurf_io::FillInput::from_text(&text, step)?;
        let mut options = input.options.clone();
        if let Some(w) = normal_weight {
            options.normal_weight = w;
        }
        if let Some(e) = elevate {
            options.elevate = e;
        }
        if let Some(s) = willmore_steps {
            options.willmore_steps = s;
        }
        if let Some(s) = descent_steps {
            options.descent_steps = s;
        }
        let asked = holes.or(input.holes.clone());
        let choice = fairsurf_io::HoleChoice::of(&input, asked.as_deref())?;
        let fills = choice.fill(&input.faces, &options)?;
        let mut report = fairsurf_io::fill_report_json(input.faces.len(), &choice, &fills);
        report["stand_ins"] = input.stand_ins_json();
        Ok(PyFilled {
            sew_within: input.hole_tolerance(),
            rational: options.rational_faces,
            faces: input.faces,
            fills,
            report: report.to_string(),
        })
    })
    .map_err(|e| to_py(py, e))
}

/// A blend: every input face, the transition surface and the report.
#[pyclass(module = "fairsurf._fairsurf", frozen, name = "Blended")]
struct PyBlended {
    input: fairsurf_io::BlendInput,
    blend: fairsurf::fill::Blend,
    report: String,
}

#[pymethods]
impl PyBlended {
    /// The input faces (B-spline surfaces): the inline ones and every face
    /// of the STEP files named.
    fn faces(&self) -> Vec<PySurface> {
        self.input
            .faces
            .iter()
            .map(|f| PySurface {
                surface: Surface::BSpline(f.clone()),
            })
            .collect()
    }

    /// The transition surface.
    fn blend(&self) -> PySurface {
        PySurface {
            surface: Surface::BSpline(self.blend.surface.clone()),
        }
    }

    /// The report as JSON text (what `fairsurf blend --json` prints,
    /// without the file names).
    fn report_json(&self) -> String {
        self.report.clone()
    }

    /// Writes the faces and the blend as one sewn STEP shell.
    fn write_step(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let surfaces = self.input.surfaces(&self.blend);
        let within = self.input.sew_within();
        py.detach(|| fairsurf_io::write_step_sewn(&path, &surfaces, within))
            .map_err(|e| to_py(py, e))
    }
}

/// Blends two surfaces as a JSON blend scene's text says (STEP files it
/// names found in `folder`), the GIL released; the options override the
/// scene's.
#[pyfunction]
#[pyo3(signature = (text, folder, bulge = None, normal_weight = None, elevate = None, clamp_sides = None))]
fn blend(
    py: Python<'_>,
    text: String,
    folder: PathBuf,
    bulge: Option<[f64; 2]>,
    normal_weight: Option<f64>,
    elevate: Option<usize>,
    clamp_sides: Option<bool>,
) -> PyResult<PyBlended> {
    if let Some(w) = normal_weight {
        if !(w >= 0.0 && w.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "normal_weight {w}: expected a number ≥ 0"
            )));
        }
    }
    if let Some(b) = bulge {
        if let Err((k, why)) = fairsurf_io::check_bulge(b) {
            return Err(PyValueError::new_err(format!("bulge[{k}]: {why}")));
        }
    }
    if elevate.is_some_and(|e| e > 10) {
        return Err(PyValueError::new_err("elevate is 0 to 10"));
    }
    py.detach(|| {
        let mut input = fairsurf_io::BlendInput::from_text(&text, &folder)?;
        let o = &mut input.options;
        if let Some(b) = bulge {
            o.bulge = fairsurf::fill::Bulge::Fixed(b);
        }
        if let Some(w) = normal_weight {
            o.fill.normal_weight = w;
        }
        if let Some(e) = elevate {
            o.fill.elevate = e;
        }
        if let Some(c) = clamp_sides {
            o.clamp_sides = c;
        }
        let blend = input.blend()?;
        let report = fairsurf_io::blend_json(&input, &blend).to_string();
        Ok(PyBlended {
            input,
            blend,
            report,
        })
    })
    .map_err(|e| to_py(py, e))
}

/// Seconds of `repeats` parses and solves of one scene timed inside Rust
/// (the library's own cost, to measure what the Python call adds).
#[pyfunction]
fn _time_solve(py: Python<'_>, text: String, repeats: usize) -> PyResult<Vec<f64>> {
    let b = budget(8.0)?;
    py.detach(|| {
        (0..repeats)
            .map(|_| {
                let t = std::time::Instant::now();
                solve_text(&text, &b).map(|_| t.elapsed().as_secs_f64())
            })
            .collect::<fairsurf_io::Result<Vec<f64>>>()
    })
    .map_err(|e| to_py(py, e))
}

/// The native module.
#[pymodule]
fn _fairsurf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PySurface>()?;
    m.add_class::<PySolved>()?;
    m.add_class::<PyFilled>()?;
    m.add_function(wrap_pyfunction!(fill, m)?)?;
    m.add_class::<PyBlended>()?;
    m.add_function(wrap_pyfunction!(blend, m)?)?;
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    m.add_function(wrap_pyfunction!(solve_many, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(analyse, m)?)?;
    m.add_function(wrap_pyfunction!(schema, m)?)?;
    m.add_function(wrap_pyfunction!(_time_solve, m)?)?;
    m.add_function(wrap_pyfunction!(write_text, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
