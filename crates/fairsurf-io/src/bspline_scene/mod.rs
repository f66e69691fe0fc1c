//! Scene files of B-spline surfaces (`"surface": {"type": "bspline"}`):
//! clamped knot vectors, a net with `null` for free points, fixed rings or
//! free points as in tensor scenes, the membrane and thin-plate energies.
//!
//! Field docs here become the descriptions in `fairsurf schema --type bspline`.

use crate::tensor_scene::Net;
use crate::validate::{check_weight, free_mask, parse_net};
use crate::{Error, Result};
use fairsurf::bspline::{BSplineProblem, BSplineSolution, BSplineSurface, KnotVector};
use fairsurf::energy::{Integrand, NormalField, NormalGuide};
use fairsurf::{Bend, GuideSurface, Stretch};
use fairsurf::{SolveOptions, Vec3};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

mod result;
mod solve;

/// A B-spline scene: minimize stretch·membrane + bend·thin plate (Wu &
/// Yang eq. 1–2, exact over the knot domain) over the free control points.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BSplineScene {
    /// Free text: a title.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text: what the scene shows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The surface.
    pub surface: BSplineSpec,
    /// If k ≥ 1: the outer k rings of control points are fixed and every
    /// other point is free (k = 2: position and tangent plane along the
    /// boundary). Without it: given points are fixed, `null` ones free.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixed_rings: Option<usize>,
    /// Control points `[i, j]` that are free although given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub free_points: Option<Vec<[usize; 2]>>,
    /// The energy weights; without either, `bend: 1` when `fixed_rings` ≥ 2
    /// and `stretch: 1` otherwise.
    #[serde(default)]
    pub energy: BSplineEnergySpec,
    /// Linear constraints at points (u, v) of the knot domain (Veltkamp &
    /// Wesselink eq. 31, as in tensor scenes): point, normal, in_plane,
    /// on_line, met exactly (to rounding) through the solver core's KKT
    /// solve; the report gives each one's violation.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub constraints: Vec<crate::TensorConstraintSpec>,
    /// External energy operators (Veltkamp & Wesselink §5, as in tensor
    /// scenes) at `at` or over a convex `region` of the knot domain:
    /// directors and point, plane, line and surface attractors (a
    /// `surface` is a Bézier patch over the knot domain mapped onto
    /// [0, 1]²); regions are integrated exactly span by span; repellors by
    /// Newton's method; an edge-to-curve attractor's curve lies over the
    /// edge's parameter interval mapped onto [0, 1].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operators: Vec<crate::TensorOperatorSpec>,
    /// Knots to insert before solving (exact refinement: the surface as
    /// given is unchanged, it gains freedom); needs `fixed_rings`. Result
    /// files hold the refined knots and net instead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refine: Option<RefineSpec>,
    /// Written by `fairsurf solve` into result files; ignored on input.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(skip)]
    pub report: Option<Value>,
}

/// Exact refinement: degrees raised, knots inserted in u and in v, every
/// span split — in that order.
#[derive(Clone, Debug, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RefineSpec {
    /// `[a, b]`: raise the degree by a in u and b in v first (degree
    /// elevation: each knot's multiplicity rises with it, so the continuity
    /// at every knot is kept; the degrees stay at most 15).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elevate: Option<[usize; 2]>,
    /// Knots to insert in u, inside the domain (a knot may be repeated up
    /// to multiplicity p).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub u: Vec<f64>,
    /// Knots to insert in v.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub v: Vec<f64>,
    /// `[a, b]`: split every span into a equal parts in u and b in v (1 to 16),
    /// after inserting `u` and `v`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<[usize; 2]>,
}

impl RefineSpec {
    /// Whether it changes nothing (no elevation, no knots, no split into
    /// more than one part): then `fixed_rings` is not needed.
    pub fn is_noop(&self) -> bool {
        self.elevate.is_none_or(|e| e == [0, 0])
            && self.u.is_empty()
            && self.v.is_empty()
            && self.split.is_none_or(|s| s == [1, 1])
    }
}

/// The surface refined as `r` says (elevated, then knots inserted, then
/// spans split); errors name `refine.elevate[k]`, `refine.u[i]`,
/// `refine.v[i]` or `refine.split[k]`.
fn refined(surface: &BSplineSurface, r: &RefineSpec) -> Result<BSplineSurface> {
    let mut s = surface.clone();
    if let Some(by) = r.elevate {
        let (p, q) = s.degree();
        for (k, (&a, d)) in by.iter().zip([p, q]).enumerate() {
            if a > MAX_DEGREE.saturating_sub(d) {
                return Err(Error::scene(
                    format!("refine.elevate[{k}]"),
                    format!(
                        "degree {d} raised by {a} is above {MAX_DEGREE}: use more spans \
                         (refine.split) instead"
                    ),
                ));
            }
        }
        s = s
            .elevated(by[0], by[1])
            .map_err(|e| Error::scene("refine.elevate", e.to_string()))?;
    }
    for (k, (name, knots)) in [("u", &r.u), ("v", &r.v)].into_iter().enumerate() {
        for (i, &t) in knots.iter().enumerate() {
            let next = if k == 0 {
                s.insert_knot_u(t)
            } else {
                s.insert_knot_v(t)
            };
            s = next.map_err(|e| Error::scene(format!("refine.{name}[{i}]"), e.to_string()))?;
        }
    }
    if let Some(split) = r.split {
        for (k, &parts) in split.iter().enumerate() {
            if !(1..=16).contains(&parts) {
                return Err(Error::scene(
                    format!("refine.split[{k}]"),
                    format!("expected 1 to 16 parts per span, got {parts}"),
                ));
            }
            let knots = if k == 0 { s.knots().0 } else { s.knots().1 };
            let inner: Vec<f64> = knots
                .spans()
                .iter()
                .flat_map(|&(_, a, b)| {
                    (1..parts).map(move |m| a + (b - a) * m as f64 / parts as f64)
                })
                .collect();
            for t in inner {
                s = if k == 0 {
                    s.insert_knot_u(t)?
                } else {
                    s.insert_knot_v(t)?
                };
            }
        }
    }
    Ok(s)
}

/// Only `"bspline"` here.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum BSplineKind {
    /// A tensor-product B-spline surface.
    #[default]
    Bspline,
}

/// `R(u, v) = Σ N_i^p(u) N_j^q(v) P_ij` over clamped knot vectors.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BSplineSpec {
    /// `"bspline"`.
    #[serde(rename = "type")]
    pub kind: BSplineKind,
    /// `[p, q]`: degree in u and in v, each 1 to 15.
    pub degree: [usize; 2],
    /// `[U, V]`: full clamped knot vectors, nondecreasing, the first and
    /// last knot p + 1 (q + 1) times, interior knots at most p (q) times;
    /// U has (rows + p + 1) knots, V (columns + q + 1).
    pub knots: [Vec<f64>; 2],
    /// Rows (one per u-basis function) of points `[x, y, z]` or `null`.
    pub control_points: Net,
}

/// The energy over the knot domain (Wu & Yang eq. 1–2, exact):
/// stretch·½∫∫|R_u|²+|R_v|² plus bend·½∫∫|R_uu|²+2|R_uv|²+|R_vv|² plus
/// λ·½∫∫(R_u·N)²+(R_v·N)² plus γ·½∫∫|R−S|².
#[derive(Clone, Debug, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BSplineEnergySpec {
    /// Weight of the membrane energy, ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch: Option<f64>,
    /// Weight of the thin-plate energy, ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bend: Option<f64>,
    /// The normal-field term: a Bézier field N over the knot domain mapped
    /// onto [0, 1]², or with `knots` a B-spline field on its own knots over
    /// the knot domain, integrated exactly; with `sampling` the sampled sum
    /// (Wu & Yang eq. 5), as in tensor scenes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_field: Option<Box<BSplineNormalFieldSpec>>,
    /// The sampled normal field: a grid over the knot domain mapped onto
    /// [0, 1]², `normal_samples` (or N at the samples) and `normal_weights`,
    /// as in tensor scenes (`guide_weights` are refused: the guide is
    /// integrated exactly).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sampling: Option<crate::SamplingSpec>,
    /// The guide-surface term: S on the same knots.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guide_surface: Option<BSplineGuideSpec>,
}

/// The normal field N of a B-spline scene: a Bézier field as in tensor
/// scenes, or with `knots` a B-spline field on its own clamped knots over
/// the surface's knot domain (degrees from `degree`, else from the counts).
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BSplineNormalFieldSpec {
    /// λ ≥ 0 (default 1). With `sampling.normal_weights` the two multiply.
    #[serde(default = "crate::tensor_scene::one")]
    pub weight: f64,
    /// `[n1, m1]`: the field's degrees (a Bézier field: any, 0 for a
    /// constant; a B-spline field: 1 to 15).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub degree: Option<[usize; 2]>,
    /// The control points of N (rows along u). Required unless
    /// `sampling.normal_samples` gives the normals.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_points: Option<Net>,
    /// `[U, V]`: a B-spline field's knot vectors, over the surface's knot
    /// domain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub knots: Option<[Vec<f64>; 2]>,
}

impl BSplineNormalFieldSpec {
    /// The Bézier part, as tensor scenes read it.
    fn bezier(&self) -> crate::NormalFieldSpec {
        crate::NormalFieldSpec {
            weight: self.weight,
            degree: self.degree,
            control_points: self.control_points.clone(),
        }
    }

    /// The B-spline field, when `knots` are given, over the domain of
    /// `surface` (exact or sampled, it must lie there); errors name
    /// `energy.normal_field.…`.
    fn spline(&self, surface: &BSplineSurface) -> Result<Option<BSplineSurface>> {
        let Some(knots) = &self.knots else {
            return Ok(None);
        };
        let (u, v) = surface.knots();
        let field = own_spline(
            "energy.normal_field",
            self.control_points.as_ref(),
            self.degree,
            Some(knots),
            [u.domain(), v.domain()],
        )?;
        surface
            .check_domain(&field, "normal field")
            .map_err(|e| Error::scene("energy.normal_field", e.to_string()))?;
        Ok(Some(field))
    }
}

/// A guide surface S: a net on the surface's knots, or any B-spline or
/// Bézier surface over the same domain (`knots` and/or `degree`: its L²
/// projection onto the surface's space is the guide, plus the constant
/// ∫|S − PS|²; exact, checked by quadrature of |R − S|²).
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BSplineGuideSpec {
    /// γ ≥ 0 (default 1).
    #[serde(default = "crate::tensor_scene::one")]
    pub weight: f64,
    /// The control points of S: as many as the surface's (on its knots),
    /// or as `knots` / `degree` give. Default: the initial net
    /// (`surface.control_points`, which must then have no null).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_points: Option<Net>,
    /// `[p, q]`: S's own degrees; without `knots`, S is a Bézier patch of
    /// this degree over the surface's knot domain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub degree: Option<[usize; 2]>,
    /// `[U, V]`: S's own clamped knot vectors over the surface's domain
    /// (degrees from `degree`, else from the counts).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub knots: Option<[Vec<f64>; 2]>,
}

impl BSplineGuideSpec {
    /// S on its own knots or degree, when the spec gives them; errors name
    /// `energy.guide_surface.…`.
    fn own_surface(&self, domain: [(f64, f64); 2]) -> Result<Option<BSplineSurface>> {
        if self.knots.is_none() && self.degree.is_none() {
            return Ok(None);
        }
        own_spline(
            "energy.guide_surface",
            self.control_points.as_ref(),
            self.degree,
            self.knots.as_ref(),
            domain,
        )
        .map(Some)
    }
}

/// A surface on its own knots (or a Bézier patch of `degree` over
/// `domain` without them) from a scene entry at `path`: `control_points`
/// required; the degrees from `degree`, else from the knot and point
/// counts; errors name `path.…`.
fn own_spline(
    path: &str,
    net: Option<&Net>,
    degree: Option<[usize; 2]>,
    own_knots: Option<&[Vec<f64>; 2]>,
    domain: [(f64, f64); 2],
) -> Result<BSplineSurface> {
    let net = net.ok_or_else(|| {
        Error::scene(
            format!("{path}.control_points"),
            "required with knots or degree (its own net)",
        )
    })?;
    let rows = net.len();
    let cols = net.first().map_or(0, Vec::len);
    let knots = |k: usize, count: usize| -> Result<KnotVector> {
        let degree = degree.map(|d| d[k]);
        let knots = match own_knots {
            Some(kn) => kn[k].clone(),
            None => {
                let p = degree.expect("degree or knots");
                let (a, b) = domain[k];
                let mut v = vec![a; p + 1];
                v.extend(std::iter::repeat_n(b, p + 1));
                v
            }
        };
        let p = match degree {
            Some(p) => p,
            None => (knots.len()).checked_sub(count + 1).ok_or_else(|| {
                Error::scene(
                    format!("{path}.knots[{k}]"),
                    format!("{} knots cannot carry {count} control points", knots.len()),
                )
            })?,
        };
        if !(1..=MAX_DEGREE).contains(&p) {
            return Err(match degree {
                Some(_) => Error::scene(
                    format!("{path}.degree[{k}]"),
                    format!("must be 1 to {MAX_DEGREE}, got {p}"),
                ),
                None => Error::scene(
                    format!("{path}.knots[{k}]"),
                    format!(
                        "{} knots and {count} control points make degree {p}; it must be 1 to \
                         {MAX_DEGREE}",
                        knots.len()
                    ),
                ),
            });
        }
        KnotVector::new(p, knots)
            .map_err(|e| Error::scene(format!("{path}.knots[{k}]"), e.to_string()))
    };
    let (u, v) = (knots(0, rows)?, knots(1, cols)?);
    let points: Vec<Vec3> = parse_net(
        net,
        &format!("{path}.control_points"),
        (u.count() - 1, v.count() - 1),
        false,
    )?
    .into_iter()
    .map(|p| p.expect("no null"))
    .collect();
    BSplineSurface::new(u, v, points)
        .map_err(|e| Error::scene(format!("{path}.control_points"), e.to_string()))
}

/// The highest degree a B-spline scene takes: beyond it use more spans.
const MAX_DEGREE: usize = 15;

/// A solved B-spline scene.
#[derive(Clone, Debug)]
pub struct SolvedBSplineScene {
    /// The scene as read.
    pub scene: BSplineScene,
    /// Which points were free (row-major).
    pub free: Vec<bool>,
    /// The surface and its report.
    pub solution: BSplineSolution,
    /// The largest turn of the normal between neighbouring samples, where.
    pub normal_turn: Option<fairsurf::analysis::NormalTurn>,
    /// The guide surface's net on the solved knots (empty without a guide,
    /// or for a guide on its own knots, which the result file keeps as
    /// given).
    pub guide_points: Vec<Vec3>,
    /// The normal field as solved (a Bézier field or samples over the knot
    /// domain mapped onto [0, 1]², or a B-spline field over the knot
    /// domain), when there is one.
    pub normal_field: Option<Box<NormalField>>,
}
