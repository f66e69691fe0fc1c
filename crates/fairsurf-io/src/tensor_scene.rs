//! Scene files of tensor-product Bézier patches (`"surface": {"type":
//! "tensor"}`; Wu & Yang 2015, Monterde & Ugail 2004): one variational
//! problem or construction. Field docs here become the descriptions in
//! `fairsurf schema`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A control net as JSON: rows of points `[x, y, z]`; row i goes with u,
/// column j with v. `null` marks a free point with no initial value (only
/// allowed in `surface.control_points`).
pub type Net = Vec<Vec<Option<Vec<f64>>>>;

/// A tensor-product scene: the surface, which control points are fixed, and the
/// energy to minimize (Wu & Yang 2015, E1/E2 and their sampled form).
#[derive(Clone, Debug, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TensorScene {
    /// Free text: a title for the scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text: what the scene shows, where it comes from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The surface and its control points.
    pub surface: SurfaceSpec,
    /// How to fill the surface: `"minimize"` the energy (default), or build it
    /// from its boundary (Monterde & Ugail 2004): `"harmonic"` (Δx ≡ 0 from the
    /// first and last rows), `"biharmonic"` (Δ²x ≡ 0 from the boundary ring),
    /// `"harmonic_mask"` (the discrete Coons mask, boundary ring) or
    /// `"biharmonic_mask"` (the 13-point mask, two outer rings). The
    /// constructions use only those points; the others may be null.
    #[serde(default, skip_serializing_if = "Method::is_minimize")]
    pub method: Method,
    /// With a construction method: when no surface of that kind has the given
    /// boundary (e.g. biharmonic at some n ≠ m), return the least-squares net
    /// and its residual instead of an error (default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub least_squares: bool,
    /// If k ≥ 1: the outer k rings of control points are fixed and every other
    /// point is free, even when given (the given net is then the initial
    /// surface). k = 1 fixes the boundary curves; k = 2 also the
    /// cross-boundary derivatives (G1 hole filling and blending). Without it:
    /// given points are fixed and `null` points are free.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixed_rings: Option<usize>,
    /// Control points `[i, j]` that are free although given: their values are
    /// initial values. Result files list the solved points here so that they
    /// can be solved again.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub free_points: Option<Vec<[usize; 2]>>,
    /// The energy: a weighted sum of stretch, bend, normal-field and
    /// guide-surface terms (only with method `"minimize"`).
    #[serde(default, skip_serializing_if = "EnergySpec::is_empty")]
    pub energy: EnergySpec,
    /// External energy operators (Veltkamp & Wesselink §5 on the tensor
    /// patch): directors, attractors, repellors (only with method
    /// `"minimize"`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operators: Vec<crate::TensorOperatorSpec>,
    /// Linear constraints at points (u, v) of the patch (Veltkamp &
    /// Wesselink eq. 31): point, normal, in_plane, on_line; met exactly
    /// (only with method `"minimize"`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub constraints: Vec<crate::TensorConstraintSpec>,
    /// Written by `fairsurf solve` into result files; ignored on input.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(skip)]
    pub report: Option<serde_json::Value>,
}

/// How the surface is made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Minimize the energy over the free control points.
    #[default]
    Minimize,
    /// Harmonic Bézier surface (Theorem 1, Prop. 1).
    Harmonic,
    /// Biharmonic Bézier surface (Theorem 2, Prop. 2).
    Biharmonic,
    /// Harmonic mask (eq. 5–6).
    HarmonicMask,
    /// Biharmonic mask (eq. 7).
    BiharmonicMask,
}

impl Method {
    /// Whether this is the default, `"minimize"`.
    pub fn is_minimize(&self) -> bool {
        *self == Method::Minimize
    }

    /// The library's construction, `None` for `"minimize"`.
    pub fn construction(self) -> Option<fairsurf::harmonic::Method> {
        use fairsurf::harmonic::Method as M;
        match self {
            Method::Minimize => None,
            Method::Harmonic => Some(M::Harmonic),
            Method::Biharmonic => Some(M::Biharmonic),
            Method::HarmonicMask => Some(M::HarmonicMask),
            Method::BiharmonicMask => Some(M::BiharmonicMask),
        }
    }
}

/// The kind of surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TensorKind {
    /// A tensor-product Bézier patch of degree (n, m).
    #[default]
    Tensor,
}

/// The surface: a tensor-product Bézier patch `R(u,v) = Σ B_i^n(u) B_j^m(v) P_ij`.
///
/// (A plain struct with a `type` field rather than a tagged enum: serde's
/// tagged enums buffer their content and lose the JSON path of errors inside.)
#[derive(Clone, Debug, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    /// `"tensor"`.
    #[serde(rename = "type")]
    pub kind: TensorKind,
    /// `[n, m]`: degree in u and in v, each 1 to 40.
    pub degree: [usize; 2],
    /// (n+1) rows of (m+1) points `[x, y, z]` or `null` (free, no initial value).
    pub control_points: Net,
}

/// The tensor surface (the only kind so far).
pub type TensorSpec = SurfaceSpec;

/// The energy `E = w_s·stretch + w_b·bend + λ·normal_field + γ·guide_surface`.
/// Without `sampling` every term is an exact integral over [0, 1]²
/// (Wu & Yang eq. 1–2); with it every term is a sum over the sample grid
/// (eq. 5). If neither `stretch` nor `bend` is given, `bend: 1` is used when
/// `fixed_rings` ≥ 2 and `stretch: 1` otherwise.
#[derive(Clone, Debug, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EnergySpec {
    /// Weight of the membrane energy ½∫|R_u|²+|R_v|² (E1's fairness), ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch: Option<f64>,
    /// Weight of the thin-plate energy ½∫|R_uu|²+2|R_uv|²+|R_vv|² (E2's fairness), ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bend: Option<f64>,
    /// The normal-field term ½λ∫(R_u·N)²+(R_v·N)².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_field: Option<NormalFieldSpec>,
    /// The guide-surface term ½γ∫|R−S|².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guide_surface: Option<GuideSurfaceSpec>,
    /// Measure every term on a sample grid instead (Wu & Yang eq. 5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sampling: Option<SamplingSpec>,
}

impl EnergySpec {
    /// No term given.
    pub fn is_empty(&self) -> bool {
        self.stretch.is_none()
            && self.bend.is_none()
            && self.normal_field.is_none()
            && self.guide_surface.is_none()
            && self.sampling.is_none()
    }
}

/// A guiding normal field N.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NormalFieldSpec {
    /// λ ≥ 0 (default 1). With `sampling.normal_weights` the two multiply.
    #[serde(default = "one")]
    pub weight: f64,
    /// `[n1, m1]`: degree of the Bézier field N (any, 0 for a constant).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub degree: Option<[usize; 2]>,
    /// (n1+1) rows of (m1+1) vectors: the control points of N. Required
    /// unless `sampling.normal_samples` gives the normals.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_points: Option<Net>,
}

/// A guide surface S the result should stay close to.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GuideSurfaceSpec {
    /// γ ≥ 0 (default 1). With `sampling.guide_weights` the two multiply.
    #[serde(default = "one")]
    pub weight: f64,
    /// `[n, m]` of S: at most the surface's degree (S is degree-elevated).
    /// Default: the surface's degree.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub degree: Option<[usize; 2]>,
    /// The control points of S. Default: the initial net
    /// (`surface.control_points`, which must then have no null).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_points: Option<Net>,
}

/// The sample grid of Wu & Yang §4: u = ip/np, v = jp/mp.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SamplingSpec {
    /// `[np, mp]`, each 1 to 2000: (np+1)×(mp+1) samples.
    pub grid: [usize; 2],
    /// (np+1) rows of (mp+1) normals (normalized before use). Default: the
    /// normal field's N evaluated at the samples and normalized.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_samples: Option<Net>,
    /// λ_ij: one number for all samples or (np+1) rows of (mp+1) numbers, ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_weights: Option<NumberOrGrid>,
    /// γ_ij: one number for all samples or (np+1) rows of (mp+1) numbers, ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guide_weights: Option<NumberOrGrid>,
}

/// One number, or a grid of numbers.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum NumberOrGrid {
    /// The same value everywhere.
    Number(f64),
    /// One value per sample, rows of columns.
    Grid(Vec<Vec<f64>>),
}

/// The default weight and strength, 1.
pub(crate) fn one() -> f64 {
    1.0
}

impl TensorScene {
    /// Parses a scene; errors name the JSON path (`surface.degree[1]: invalid
    /// type: string "a", expected usize at line 3 column 20`).
    pub fn from_json(text: &str) -> crate::Result<TensorScene> {
        crate::scene::parse_with_path(text)
    }

    /// Reads and parses a scene file.
    pub fn read(path: &std::path::Path) -> crate::Result<TensorScene> {
        Self::from_json(&crate::scene::read_text(path)?)
    }

    /// The JSON Schema of scene files, generated from these types.
    pub fn json_schema() -> serde_json::Value {
        serde_json::to_value(schemars::schema_for!(TensorScene)).expect("a schema serializes")
    }

    /// The tensor part of the surface.
    pub fn tensor(&self) -> &TensorSpec {
        &self.surface
    }
}
