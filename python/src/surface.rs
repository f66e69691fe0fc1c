//! `Surface`: a surface of any kind in Python — evaluation, derivatives,
//! meshes, pictures and exports, each with the GIL released.

use super::*;

/// The knot vectors U, V as numpy arrays.
pub(super) type KnotArrays<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// A surface of any kind: what a result holds, or a scene whose control
/// points are all given.
#[pyclass(module = "fairsurf._fairsurf", frozen, name = "Surface")]
pub(super) struct PySurface {
    pub(super) surface: Surface,
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
pub(super) const MAX_TRIANGLES: usize = 50_000_000;

/// Refuses a mesh above [`MAX_TRIANGLES`].
pub(super) fn check_mesh_size(surface: &Surface, resolution: usize) -> PyResult<()> {
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
pub(super) fn check_resolution(r: usize) -> PyResult<()> {
    if !(1..=4096).contains(&r) {
        return Err(PyValueError::new_err(format!(
            "resolution {r}: expected 1 to 4096 quads per direction"
        )));
    }
    Ok(())
}
