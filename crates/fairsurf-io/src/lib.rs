//! # fairsurf-io
//!
//! Files for fairsurf: the JSON scene format (with a JSON Schema generated
//! from its types), validation of a scene into a [`fairsurf::Problem`] with
//! errors that name the JSON path, result files that can be solved again,
//! mesh writers (OBJ, PLY with per-vertex curvature, STL, glTF 2.0 with
//! curvature colours) and the exact surfaces for CAD (STEP AP214, IGES 5.3).
//! Every file is written to a temporary name and renamed, so a failure
//! never leaves a partial file.
//!
//! ```
//! let text = r#"{
//!   "surface": {"type": "tensor", "degree": [2, 2], "control_points": [
//!     [[0,0,0], [0,1,0], [0,2,0]],
//!     [[1,0,0], null,    [1,2,0]],
//!     [[2,0,0], [2,1,0], [2,2,0]]]},
//!   "energy": {"stretch": 1}
//! }"#;
//! let scene = fairsurf_io::TensorScene::from_json(text).unwrap();
//! let solved = scene.solve().unwrap();
//! assert!((solved.patch().point(1, 1)[0] - 1.0).abs() < 1e-14);
//! ```

mod analysis;
mod atomic;
mod blend;
mod bspline_scene;
mod cad;
mod compare;
mod constraints;
mod error;
mod fill;
mod gltf;
mod iges;
mod mesh;
mod operators;
mod result;
mod scene;
mod step;
mod step_read;
mod surface;
mod surface_mesh;
mod tensor_scene;
mod tri_result;
mod tri_scene;
mod validate;

pub use analysis::Measures;
pub use atomic::{remove_temporaries, write_atomic, Batch};
pub use blend::{blend_json, check_bulge, BlendInput, BlendScene, BlendSurfaceSpec, EdgeName};
pub use bspline_scene::{
    BSplineEnergySpec, BSplineGuideSpec, BSplineKind, BSplineNormalFieldSpec, BSplineScene,
    BSplineSpec, SolvedBSplineScene,
};
pub use cad::{CadCurve, CadSurface};
pub use compare::comparison_json;
pub use constraints::{TensorConstraintSpec, UvSpec};
pub use error::{Error, Result};
pub use fill::{
    fill_json, fill_report_json, fill_surfaces, sides_beyond, FaceKind, FaceSpec, FillInput,
    FillScene, FillSpec, HoleChoice, StripOf,
};
pub use gltf::base64;
pub use iges::{write_iges, write_iges_surfaces};
pub use mesh::{write_mesh, write_mesh_with, MeshFormat, MeshOptions};
pub use operators::{EdgeSpec, OperatorKind, TensorOperatorSpec, TensorPatchSpec};
pub use result::{construction_report_json, report_json, Outcome, SolvedTensorScene};
pub use scene::{Scene, SolvedScene, SurfaceType};
pub use step::{write_step, write_step_sewn, write_step_surfaces};
pub use step_read::{read_step, read_step_faces, FaceSurface, StepFace, TrimEdge, TRIM_TOLERANCE};
pub use surface::{Exported, Surface, OCC_MAX_DEGREE};
pub use surface_mesh::SurfaceMesh;
pub use tensor_scene::{
    EnergySpec, GuideSurfaceSpec, Method, Net, NormalFieldSpec, NumberOrGrid, SamplingSpec,
    SurfaceSpec, TensorScene, TensorSpec,
};
pub use tri_result::{tri_report_json, SolvedTriScene};
pub use tri_scene::{
    BoundaryAngleSpec, ConstraintKind, ConstraintSpec, ContinuitySpec, DomainPointSpec, EdgesSpec,
    TriEnergySpec, TriScene, TriSurfaceSpec, TriangularKind,
};
pub use validate::{default_weights, Built, Plan};
