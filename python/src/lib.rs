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

mod cad;
mod surface;
use cad::*;
use surface::*;

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
