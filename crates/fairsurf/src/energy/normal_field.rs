//! The normal-field term of Wu & Yang 2015:
//! `½ λ ∫∫ (R_u·N)² + (R_v·N)² du dv` (eq. 1–2) with N a tensor Bézier field of
//! any degree (n1, m1), or its sampled form
//! `½ Σ λ_ij [(R_u(u_i,v_j)·N_ij)² + (R_v(u_i,v_j)·N_ij)²]` (eq. 5) with unit
//! normals N_ij on a grid. It pulls the surface's tangent planes toward the
//! planes orthogonal to N, and couples x, y and z. On B-spline surfaces N
//! may also be a B-spline field on its own knots ([`NormalGuide::Spline`]).

use super::{
    check_weight, check_weights, coupled_form, derivative_net, pairs, Axis, EnergyTerm, Hessian,
    HessianKey, Integrand, PatternForm, SampleGrid, Space, TermForm, STRETCH_PATTERNS,
};
use crate::basis::binomial;
use crate::vec3::{is_finite, normalize, Vec3};
use crate::{Error, Result, TensorPatch};
use faer::Mat;

/// Where the guiding normals come from.
#[derive(Clone, Debug, PartialEq)]
pub enum NormalGuide {
    /// A tensor Bézier field N(u, v) = Σ B_i^{n1}(u) B_j^{m1}(v) N_ij, integrated
    /// exactly. N need not be unit length: Wu & Yang's continuous functional
    /// uses the field as given.
    Field(TensorPatch),
    /// Normals at the samples of a grid (eq. 5), row-major over (ip, jp); they
    /// are normalized before use. `weights` are the per-sample λ_ij, multiplied
    /// with the term's weight (all 1 when `None`).
    Samples {
        /// The sample grid.
        grid: SampleGrid,
        /// One normal per sample.
        normals: Vec<Vec3>,
        /// Optional per-sample weights.
        weights: Option<Vec<f64>>,
    },
    /// A B-spline field N(u, v) = Σ N_i^{n1}(u) N_j^{m1}(v) N_ij on its own
    /// knots over the surface's knot domain, integrated exactly (Gauss rules
    /// between both surfaces' knot lines). For B-spline surfaces only
    /// ([`NormalField::spline`]); a Bézier patch's problem
    /// refuses it. N as given, not normalized.
    Spline(crate::bspline::BSplineSurface),
}

impl NormalGuide {
    /// Samples a Bézier field on a grid: N(u_i, v_j) normalized, with optional
    /// per-sample weights. A zero normal at a sample is an error.
    pub fn sample_field(
        field: &TensorPatch,
        grid: SampleGrid,
        weights: Option<Vec<f64>>,
    ) -> Result<Self> {
        let normals = (0..grid.len())
            .map(|k| {
                let (u, v) = grid.param(k);
                field.eval(u, v)
            })
            .collect();
        Ok(NormalGuide::Samples {
            grid,
            normals,
            weights,
        })
    }
}

/// The samples' normals normalized, after checking the lists against the
/// grid: a wrong count, a negative or non-finite weight, a zero or
/// non-finite normal is an error naming the sample.
pub(crate) fn unit_samples(
    grid: SampleGrid,
    normals: &[Vec3],
    weights: Option<&[f64]>,
) -> Result<Vec<Vec3>> {
    grid.check_len("normal_field samples", normals.len())?;
    if let Some(w) = weights {
        grid.check_len("normal_field sample weights", w.len())?;
        check_weights("normal_field sample weight", w)?;
    }
    normals
        .iter()
        .enumerate()
        .map(|(k, &nrm)| {
            if !is_finite(nrm) {
                return Err(Error::NotFinite {
                    what: format!("normal sample {k}"),
                });
            }
            normalize(nrm).ok_or(Error::ZeroNormal {
                what: format!("normal sample {k}"),
            })
        })
        .collect()
}

/// The normal-field term with weight λ (≥ 0).
#[derive(Clone, Debug, PartialEq)]
pub struct NormalField {
    /// λ.
    pub weight: f64,
    /// The guiding normals.
    pub guide: NormalGuide,
}

impl NormalField {
    /// The exact term with a Bézier normal field.
    pub fn new(weight: f64, field: TensorPatch) -> Self {
        Self {
            weight,
            guide: NormalGuide::Field(field),
        }
    }

    /// The exact term with a B-spline field over the surface's knot domain
    /// (B-spline surfaces only).
    pub fn spline(weight: f64, field: crate::bspline::BSplineSurface) -> Self {
        Self {
            weight,
            guide: NormalGuide::Spline(field),
        }
    }

    /// The sampled term (eq. 5).
    pub fn sampled(
        weight: f64,
        grid: SampleGrid,
        normals: Vec<Vec3>,
        weights: Option<Vec<f64>>,
    ) -> Self {
        Self {
            weight,
            guide: NormalGuide::Samples {
                grid,
                normals,
                weights,
            },
        }
    }

    /// The unit guiding normal at (u, v) ∈ [0, 1]² (a B-spline field's
    /// domain mapped onto it): the field normalized, or for samples the
    /// normal of the nearest sample. `None` where the field vanishes.
    pub fn direction(&self, u: f64, v: f64) -> Option<Vec3> {
        match &self.guide {
            NormalGuide::Field(f) => normalize(f.eval(u, v)),
            NormalGuide::Spline(f) => normalize(crate::ParamSurface::eval_unit(f, u, v)),
            NormalGuide::Samples { grid, normals, .. } => {
                let (np, mp) = grid.size();
                let i = (u * np as f64).round().clamp(0.0, np as f64) as usize;
                let j = (v * mp as f64).round().clamp(0.0, mp as f64) as usize;
                normalize(normals[i * (mp + 1) + j])
            }
        }
    }

    /// [`Self::direction`] at every (u, v) of a tensor grid, u-major
    /// (`out[a·vs.len() + b]` at `(us[a], vs[b])`); a field patch is
    /// evaluated by [`TensorPatch::derivatives_on`].
    pub fn directions(&self, us: &[f64], vs: &[f64]) -> Vec<Option<Vec3>> {
        match &self.guide {
            NormalGuide::Field(f) => f
                .derivatives_on(us, vs)
                .iter()
                .map(|d| normalize(d.point))
                .collect(),
            NormalGuide::Samples { .. } | NormalGuide::Spline(_) => us
                .iter()
                .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
                .map(|(u, v)| self.direction(u, v))
                .collect(),
        }
    }

    /// The (a, b) weight tables and axes: ω_ab = λ N_a N_b as Bernstein
    /// coefficients (exact) or per-sample values.
    fn weight_tables(&self) -> Result<WeightTables> {
        let lam = self.weight;
        match &self.guide {
            NormalGuide::Field(f) => {
                let (n1, m1) = f.degree();
                let tables = pairs()
                    .map(|(a, b)| {
                        let mut t = product_table(f, a, b);
                        t *= faer::Scale(lam);
                        t
                    })
                    .collect();
                Ok(((Axis::Bernstein(2 * n1), Axis::Bernstein(2 * m1)), tables))
            }
            NormalGuide::Samples {
                grid,
                normals,
                weights,
            } => {
                let units = unit_samples(*grid, normals, weights.as_deref())?;
                let base = grid.weight_table(weights.as_deref());
                let (_, mp) = grid.size();
                let tables = pairs()
                    .map(|(a, b)| {
                        Mat::from_fn(base.nrows(), base.ncols(), |i, j| {
                            let nk = units[i * (mp + 1) + j];
                            lam * base[(i, j)] * nk[a] * nk[b]
                        })
                    })
                    .collect();
                Ok((grid.axes(), tables))
            }
            NormalGuide::Spline(_) => Err(Error::Mismatch {
                what: "normal field".into(),
                expected: "a Bézier field or samples on a Bézier patch (a B-spline field is for \
                           B-spline surfaces: BSplineSurface::from_bezier converts the patch)"
                    .into(),
                got: "a B-spline field".into(),
            }),
        }
    }
}

/// Axes and the six weight tables of the coordinate pairs (a, b), a ≤ b.
type WeightTables = ((Axis, Axis), Vec<Mat<f64>>);

/// Bernstein coefficients, degree (2n1, 2m1), of N_a · N_b.
fn product_table(f: &TensorPatch, a: usize, b: usize) -> Mat<f64> {
    let (n1, m1) = f.degree();
    let mut t = Mat::<f64>::zeros(2 * n1 + 1, 2 * m1 + 1);
    for r in 0..=n1 {
        for s in 0..=m1 {
            let x = f.point(r, s)[a] * binomial(n1, r) * binomial(m1, s);
            if x == 0.0 {
                continue;
            }
            for r2 in 0..=n1 {
                for s2 in 0..=m1 {
                    let y = f.point(r2, s2)[b] * binomial(n1, r2) * binomial(m1, s2);
                    t[(r + r2, s + s2)] += x * y;
                }
            }
        }
    }
    Mat::from_fn(2 * n1 + 1, 2 * m1 + 1, |p, q| {
        t[(p, q)] / (binomial(2 * n1, p) * binomial(2 * m1, q))
    })
}

impl EnergyTerm for NormalField {
    fn name(&self) -> &'static str {
        "normal_field"
    }

    fn hessian_key(&self) -> Option<u64> {
        let key = HessianKey::new(self.name()).number(self.weight);
        Some(match &self.guide {
            NormalGuide::Field(f) => key.with(&f.degree()).points(f.points()).finish(),
            NormalGuide::Spline(f) => key
                .with(&f.degree())
                .numbers(f.knots().0.knots())
                .numbers(f.knots().1.knots())
                .points(f.points())
                .finish(),
            NormalGuide::Samples {
                grid,
                normals,
                weights,
            } => key
                .with(grid)
                .points(normals)
                .with(&weights.is_some())
                .numbers(weights.as_deref().unwrap_or(&[]))
                .finish(),
        })
    }

    fn integrand(&self) -> Option<Integrand<'_>> {
        Some(Integrand::NormalField {
            weight: self.weight,
            guide: &self.guide,
        })
    }

    fn value(&self, patch: &TensorPatch) -> Result<f64> {
        check_weight("normal_field weight", self.weight)?;
        let ((au, av), tables) = self.weight_tables()?;
        let degree = patch.degree();
        let mut total = 0.0;
        for pattern in [(1, 0), (0, 1)] {
            let nets: Vec<Mat<f64>> = (0..3)
                .map(|c| derivative_net(patch.points(), degree, pattern, c))
                .collect();
            let pf = PatternForm::new(degree, pattern, (&au, &av));
            let values = pf.pair_values(&tables, [&nets[0], &nets[1], &nets[2]]);
            for ((a, b), v) in pairs().zip(values) {
                let twice = if a == b { 1.0 } else { 2.0 };
                total += twice * v;
            }
        }
        Ok(0.5 * total)
    }

    fn form_in(&self, space: &Space) -> Result<TermForm> {
        check_weight("normal_field weight", self.weight)?;
        let ((au, av), tables) = self.weight_tables()?;
        let h = coupled_form(space, STRETCH_PATTERNS, (&au, &av), &tables)?;
        Ok(TermForm {
            hessian: Hessian::Coupled(h),
            center: None,
        })
    }
}
