//! Measures of a surface as a scene gives it (a result file, or a scene
//! with every control point given), without solving: what `fairsurf
//! analyse` prints and the editor's `POST /api/analyse` answers.

use crate::{Result, TensorScene, TriScene};
use fairsurf::triangle::{max_edge_normal_angle, InternalEnergy};
use serde_json::{json, Value};

/// Labelled measures, in order: a number, or a string for what is not one.
pub type Measures = Vec<(String, Value)>;

impl TensorScene {
    /// Area (adaptive Gauss–Legendre, with its error estimate), the
    /// Dirichlet and biharmonic functionals (exact), |H| on a 65×65 grid,
    /// and the degree of the surface as given; a `null` control point is
    /// an error naming it (there is no surface to measure).
    pub fn analyse(&self) -> Result<Measures> {
        let patch = self.surface_patch()?;
        let m = fairsurf::analysis::measures(&patch);
        let (n, k) = patch.degree();
        Ok(vec![
            ("area".into(), json!(m.area)),
            ("area error estimate".into(), json!(m.area_error)),
            ("Dirichlet".into(), json!(m.dirichlet)),
            ("biharmonic".into(), json!(m.biharmonic)),
            ("mean |H|".into(), json!(m.abs_mean_curvature.mean)),
            ("max |H|".into(), json!(m.abs_mean_curvature.max)),
            ("degree".into(), json!(format!("{n} × {k}"))),
        ])
    }
}

impl TriScene {
    /// The stretch and bend functionals (weights 1; Veltkamp & Wesselink
    /// eq. 25–27), the largest normal angle across interior edges (65
    /// samples an edge), patches and control points of the surface as
    /// given (a result file's solved net).
    pub fn analyse(&self) -> Result<Measures> {
        let s = self.surface()?;
        let functional = |stretch: f64, bend: f64| -> Result<Value> {
            Ok(json!(InternalEnergy::new(stretch, bend).surface_value(&s)?))
        };
        let angle = max_edge_normal_angle(&s, 65).map_or(Value::Null, |(a, _)| json!(a));
        Ok(vec![
            ("stretch functional (α = 1)".into(), functional(1.0, 0.0)?),
            ("bend functional (β = 1)".into(), functional(0.0, 1.0)?),
            ("max normal angle across edges (rad)".into(), angle),
            ("patches".into(), json!(s.patch_count())),
            ("control points".into(), json!(s.point_count())),
        ])
    }
}
