//! `fill` and `blend` from Python: holes filled and surfaces blended from
//! STEP files or JSON scenes (`Filled`, `Blended`).

use super::*;

/// Filled holes: the input faces, the fills and the report.
#[pyclass(module = "fairsurf._fairsurf", frozen, name = "Filled")]
pub(super) struct PyFilled {
    pub(super) faces: Vec<fairsurf::bspline::BSplineSurface>,
    /// The faces and fills as written (a rational face as that, a trimmed
    /// one bounded by its loops).
    pub(super) surfaces: Vec<fairsurf_io::CadSurface>,
    /// Vertices and edges closer than this are shared in the STEP file.
    pub(super) sew_within: f64,
    pub(super) fills: Vec<fairsurf::fill::HoleFill>,
    pub(super) report: String,
}

#[pymethods]
impl PyFilled {
    /// The input faces (B-spline surfaces; a rational face such as a
    /// cylinder as its polynomial stand-in, see the report's `stand_ins`;
    /// a trimmed face as its whole surface, which runs beyond its loops —
    /// `write_step` writes it bounded by them).
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
        py.detach(|| fairsurf_io::write_step_sewn(&path, &self.surfaces, self.sew_within))
            .map_err(|e| to_py(py, e))
    }
}

/// Fills holes between faces given as a STEP file's text (`step`) or a
/// JSON fill scene's, the GIL released; `holes` and the options override
/// the scene's.
#[pyfunction]
#[pyo3(signature = (text, step, holes = None, normal_weight = None, elevate = None, willmore_steps = None, descent_steps = None))]
pub(super) fn fill(
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
        let mut input = fairsurf_io::FillInput::from_text(&text, step)?;
        let choice = input.choose(holes.as_deref())?;
        let mut options = input.options.clone();
        if let Some(w) = normal_weight {
            options.guide_with(w);
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
        let fills = choice
            .fill(&input.faces, &options)
            .map_err(|e| input.name_faces(e))?;
        let mut report = input.report_json(&choice, &fills, input.fit());
        report["stand_ins"] = input.stand_ins_json();
        let surfaces = input.surfaces(&fills);
        let (sew_within, n) = (input.hole_tolerance(), input.file_faces());
        let mut faces = input.faces;
        faces.truncate(n);
        Ok(PyFilled {
            sew_within,
            surfaces,
            faces,
            fills,
            report: report.to_string(),
        })
    })
    .map_err(|e| to_py(py, e))
}

/// A blend: every input face, the transition surface and the report.
#[pyclass(module = "fairsurf._fairsurf", frozen, name = "Blended")]
pub(super) struct PyBlended {
    pub(super) input: fairsurf_io::BlendInput,
    pub(super) blend: fairsurf::fill::Blend,
    pub(super) report: String,
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
pub(super) fn blend(
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
            o.fill.guide_with(w);
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
