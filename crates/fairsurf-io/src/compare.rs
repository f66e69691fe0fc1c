//! The comparison of Monterde & Ugail §4 for a scene's boundary.

use crate::result::curvature_json;
use crate::tensor_scene::TensorScene;
use crate::{Error, Result};
use fairsurf::harmonic::{compare, Comparison};
use fairsurf::TensorPatch;
use serde_json::{json, Map, Value};

impl TensorScene {
    /// The boundary ring of the scene's surface as a net (inner points
    /// zero): every boundary point must be given.
    pub fn boundary_net(&self) -> Result<TensorPatch> {
        let t = self.tensor();
        let [n, m] = t.degree;
        for (k, d) in [n, m].into_iter().enumerate() {
            if !(2..=crate::validate::MAX_DEGREE).contains(&d) {
                return Err(Error::scene(
                    format!("surface.degree[{k}]"),
                    format!(
                        "comparing needs degrees 2 to {}, got {d}",
                        crate::validate::MAX_DEGREE
                    ),
                ));
            }
        }
        let given =
            crate::validate::parse_net(&t.control_points, "surface.control_points", (n, m), true)?;
        let mut pts = Vec::with_capacity(given.len());
        for (k, p) in given.iter().enumerate() {
            let (i, j) = (k / (m + 1), k % (m + 1));
            let boundary = i == 0 || j == 0 || i == n || j == m;
            match (boundary, p) {
                (true, None) => return Err(Error::scene(
                    format!("surface.control_points[{i}][{j}]"),
                    "is null, but the comparison is built from the boundary ring: give its value",
                )),
                (true, Some(p)) => pts.push(*p),
                (false, _) => pts.push([0.0; 3]),
            }
        }
        Ok(TensorPatch::new(n, m, pts))
    }

    /// The four surfaces of Monterde & Ugail §4 for this scene's boundary.
    pub fn compare(&self) -> Result<Comparison> {
        Ok(compare(&self.boundary_net()?)?)
    }
}

/// `{"harmonic_extremal": {"area", "area_error", "dirichlet", "biharmonic",
/// "abs_mean_curvature", "exact", "residual"}, "harmonic_mask": …,
/// "biharmonic_surface": …, "biharmonic_extremal": …}`.
pub fn comparison_json(c: &Comparison) -> Value {
    let mut o = Map::new();
    for (name, col) in c.columns() {
        let m = &col.measures;
        o.insert(
            name.into(),
            json!({
                "area": m.area,
                "area_error": m.area_error,
                "dirichlet": m.dirichlet,
                "biharmonic": m.biharmonic,
                "abs_mean_curvature": curvature_json(&m.abs_mean_curvature),
                "exact": col.exact,
                "residual": col.residual,
            }),
        );
    }
    Value::Object(o)
}
