//! Result files: the scene written back with every control point filled and
//! a `"report"`. A result file is itself a scene that solves to the same
//! surface: free points are listed in `free_points` (or implied by
//! `fixed_rings`) and a default guide surface is written out explicitly.

use crate::tensor_scene::{GuideSurfaceSpec, Net, SurfaceSpec, TensorKind, TensorScene};
use crate::validate::{Built, Plan};
use crate::Result;
use fairsurf::analysis::{normal_deviation, AbsMeanCurvature, NormalDeviation};
use fairsurf::harmonic::{Construction, ConstructionReport};
use fairsurf::{FactorCache, Solution, SolveOptions, SolveReport, SurfaceMeasures, TensorPatch};
use serde_json::{json, Map, Value};

/// A solved scene: what was asked, how it was read, and the answer.
#[derive(Debug)]
pub struct SolvedTensorScene {
    /// The scene as given.
    pub scene: TensorScene,
    /// The validated problem and what was assumed.
    pub built: Built,
    /// The surface and its report.
    pub outcome: Outcome,
    /// Angle between the result's normals and the guiding field (`None`
    /// without a field or without analysis).
    pub normal_deviation: Option<NormalDeviation>,
    /// max |R − S| over a 33×33 grid, for a guide surface S (`None` without
    /// one or without analysis).
    pub guide_distance: Option<f64>,
}

/// The answer: a minimized energy or a construction from the boundary.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// `method: "minimize"` (boxed: a solution's report is large).
    Minimized(Box<Solution>),
    /// A harmonic / biharmonic surface or mask.
    Constructed(Box<Construction>),
}

impl Outcome {
    /// The surface.
    pub fn patch(&self) -> &TensorPatch {
        match self {
            Outcome::Minimized(s) => &s.surface,
            Outcome::Constructed(c) => &c.patch,
        }
    }

    /// Area, functionals and curvature, when computed.
    pub fn measures(&self) -> Option<&SurfaceMeasures> {
        match self {
            Outcome::Minimized(s) => s.report.measures.as_ref(),
            Outcome::Constructed(c) => c.report.measures.as_ref(),
        }
    }

    /// The minimization's solution, if this was one.
    pub fn solution(&self) -> Option<&Solution> {
        match self {
            Outcome::Minimized(s) => Some(s.as_ref()),
            Outcome::Constructed(_) => None,
        }
    }

    /// The construction, if this was one.
    pub fn construction(&self) -> Option<&Construction> {
        match self {
            Outcome::Minimized(_) => None,
            Outcome::Constructed(c) => Some(c.as_ref()),
        }
    }
}

impl SolvedTensorScene {
    /// The surface.
    pub fn patch(&self) -> &TensorPatch {
        self.outcome.patch()
    }
}

impl TensorScene {
    /// Validates and solves with default options.
    pub fn solve(&self) -> Result<SolvedTensorScene> {
        self.solve_with(&SolveOptions::default())
    }

    /// Validates and solves.
    pub fn solve_with(&self, opts: &SolveOptions) -> Result<SolvedTensorScene> {
        self.solve_using(opts, None)
    }

    /// Validates and solves, reusing a factorization from `cache` when one
    /// fits (and keeping this one there): for a designer dragging points.
    pub fn solve_cached(
        &self,
        opts: &SolveOptions,
        cache: &FactorCache,
    ) -> Result<SolvedTensorScene> {
        self.solve_using(opts, Some(cache))
    }

    fn solve_using(
        &self,
        opts: &SolveOptions,
        cache: Option<&FactorCache>,
    ) -> Result<SolvedTensorScene> {
        let built = self.build()?;
        let outcome = match &built.plan {
            Plan::Minimize(problem) => Outcome::Minimized(Box::new(match cache {
                Some(c) => c.solve(problem, opts)?,
                None => problem.solve_with(opts)?,
            })),
            Plan::Construct(method, net) => {
                let copts = fairsurf::harmonic::ConstructOptions {
                    least_squares: self.least_squares,
                    analyse: opts.analyse,
                };
                Outcome::Constructed(Box::new(method.construct(net, &copts)?))
            }
        };
        let patch = outcome.patch();
        // Without analysis (`opts.analyse` false) the measures of the result
        // against the field and the guide are skipped too.
        let normal_deviation = built
            .normal_field
            .as_ref()
            .filter(|_| opts.analyse)
            .map(|f| normal_deviation(patch, f, built.deviation_grid));
        let guide_distance = built
            .guide
            .as_ref()
            .filter(|_| opts.analyse)
            .map(|s| max_distance(patch, s));
        Ok(SolvedTensorScene {
            scene: self.clone(),
            built,
            outcome,
            normal_deviation,
            guide_distance,
        })
    }
}

fn max_distance(r: &TensorPatch, s: &TensorPatch) -> f64 {
    let k = 32;
    let mut d: f64 = 0.0;
    for i in 0..=k {
        for j in 0..=k {
            let (u, v) = (i as f64 / k as f64, j as f64 / k as f64);
            d = d.max(fairsurf::vector::norm(fairsurf::vector::sub(
                r.eval(u, v),
                s.eval(u, v),
            )));
        }
    }
    d
}

/// A net as JSON rows.
pub(crate) fn net_json(p: &TensorPatch) -> Net {
    let (n, m) = p.degree();
    (0..=n)
        .map(|i| (0..=m).map(|j| Some(p.point(i, j).to_vec())).collect())
        .collect()
}

impl SolvedTensorScene {
    /// The result as a scene: every control point filled, the free ones
    /// listed, the guide written out, and the report attached.
    pub fn result_scene(&self) -> TensorScene {
        let mut out = self.scene.clone();
        let patch = self.patch();
        let (n, m) = patch.degree();
        out.surface = SurfaceSpec {
            kind: TensorKind::Tensor,
            degree: [n, m],
            control_points: net_json(patch),
        };
        if out.fixed_rings.is_none() && self.scene.method.is_minimize() {
            out.free_points = Some(
                self.built
                    .free
                    .iter()
                    .enumerate()
                    .filter(|(_, &f)| f)
                    .map(|(k, _)| [k / (m + 1), k % (m + 1)])
                    .collect(),
            );
        }
        if let (Some(g), Some(spec)) = (&self.built.guide, &self.scene.energy.guide_surface) {
            if spec.control_points.is_none() {
                let (a, b) = g.degree();
                out.energy.guide_surface = Some(GuideSurfaceSpec {
                    weight: spec.weight,
                    degree: Some([a, b]),
                    control_points: Some(net_json(g)),
                });
            }
        }
        out.report = Some(self.report_json());
        out
    }

    /// The `"report"` object.
    pub fn report_json(&self) -> Value {
        let mut r = match &self.outcome {
            Outcome::Minimized(s) => report_json(&s.report),
            Outcome::Constructed(c) => construction_report_json(&c.report),
        };
        let o = r.as_object_mut().expect("object");
        if let Some(d) = &self.normal_deviation {
            o.insert(
                "normal_deviation_deg".into(),
                json!({"max": d.max.to_degrees(), "mean": d.mean.to_degrees(), "rms": d.rms.to_degrees(), "samples": d.samples}),
            );
        }
        if let Some(d) = self.guide_distance {
            o.insert("guide_distance_max".into(), json!(d));
        }
        o.insert("notes".into(), json!(self.notes()));
        r
    }

    /// What the result's reader should know: the scene's notes, and a fold
    /// when the normal turns by more than 90° between neighbouring samples.
    pub fn notes(&self) -> Vec<String> {
        let mut notes = self.built.notes.clone();
        let fold = self
            .outcome
            .measures()
            .and_then(|m| m.normal_turn)
            .filter(|t| t.is_fold());
        if let Some(t) = fold {
            notes.push(format!(
                "the surface folds: its normal turns by {:.1}° between neighbouring samples \
                 near (u, v) = ({:.3}, {:.3}); lower λ or give a normal field the boundary can follow",
                t.angle.to_degrees(),
                t.at.0,
                t.at.1
            ));
        }
        notes
    }
}

/// A [`SolveReport`] as JSON: energies, accuracy, measures, timings.
pub fn report_json(r: &SolveReport) -> Value {
    let mut terms = Map::new();
    for t in &r.terms {
        // Two terms of one kind (possible through the library) are summed.
        let prev = terms.get(&t.name).and_then(Value::as_f64).unwrap_or(0.0);
        terms.insert(t.name.clone(), json!(prev + t.value));
    }
    let mut o = json!({
        "energy": r.energy,
        "terms": terms,
        "gradient_norm": r.gradient_norm,
        "relative_gradient": r.relative_gradient,
        "residual": r.residual,
        "condition_estimate": finite(r.condition_estimate),
        "refinement_steps": r.refinement_steps,
        "unknowns": r.unknowns,
        "free_points": r.free_points,
        "coupled": r.coupled,
        "reused_factorization": r.reused,
        "reused_symbolic": r.reused_symbolic,
        "timings_s": {
            "assemble": r.timings.assemble, "factor": r.timings.factor, "solve": r.timings.solve,
            "analyse": r.timings.analyse, "total": r.timings.total,
        },
        "fairsurf_version": env!("CARGO_PKG_VERSION"),
    });
    o["external"] = json!(r.external);
    o["operators"] = crate::operators::outcomes_json(&r.operators);
    o["newton"] = crate::operators::newton_json(r.newton.as_ref());
    o["constraints"] = crate::constraints::outcomes_json(&r.constraints);
    o["max_violation"] = json!(r.max_violation);
    if let Some(c) = &r.check {
        o["check"] = check_json(c);
    }
    if let Some(n) = r.factor_nonzeros {
        o["factor_nonzeros"] = json!(n);
    }
    if let Some(k) = &r.kkt {
        o["kkt"] = crate::tri_result::kkt_json(k);
    }
    insert_measures(&mut o, r.measures.as_ref());
    o
}

/// The independent check of a solve ([`fairsurf::Check`]) as JSON.
pub fn check_json(c: &fairsurf::Check) -> Value {
    json!({
        "energy": c.energy,
        "energy_error": c.energy_error,
        "excess": c.excess,
        "scale": c.scale,
        "corrections": c.corrections,
        "tolerance": c.tolerance,
        "seconds": c.seconds,
    })
}

/// A [`ConstructionReport`] as JSON: how well the defining equations hold,
/// overridden points, measures, timings.
pub fn construction_report_json(r: &ConstructionReport) -> Value {
    let overridden: Vec<Value> = r
        .overridden
        .iter()
        .map(|o| json!({"index": [o.index.0, o.index.1], "given": o.given, "determined": o.determined}))
        .collect();
    let mut o = json!({
        "method": r.method.name(),
        "equations_kind": r.method.equations(),
        "exact": r.exact,
        "residual": r.residual,
        "backward_error": r.backward_error,
        "condition_estimate": finite(r.condition_estimate),
        "refinement_steps": r.refinement_steps,
        "equations": r.equations,
        "free_points": r.unknowns,
        "overridden": overridden,
        "timings_s": {
            "assemble": r.timings.assemble, "factor": r.timings.factor, "solve": r.timings.solve,
            "analyse": r.timings.analyse, "total": r.timings.total,
        },
        "fairsurf_version": env!("CARGO_PKG_VERSION"),
    });
    insert_measures(&mut o, r.measures.as_ref());
    o
}

/// A number, or `null` for NaN and ±∞ (JSON has neither).
pub(crate) fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// The largest turn of the normal between neighbouring samples, where, and
/// whether it folds (above 90°): `{"angle": degrees, "at": …, "fold": …}`.
pub(crate) fn normal_turn_json(angle: f64, at: Value, fold: bool) -> Value {
    json!({"angle": angle.to_degrees(), "at": at, "fold": fold})
}

/// |H| statistics as JSON.
pub(crate) fn curvature_json(c: &AbsMeanCurvature) -> Value {
    json!({
        "min": finite(c.min), "max": finite(c.max), "mean": finite(c.mean),
        "samples": c.samples, "singular": c.singular,
    })
}

fn insert_measures(o: &mut Value, m: Option<&SurfaceMeasures>) {
    let Some(m) = m else { return };
    let obj = o.as_object_mut().expect("object");
    obj.insert("area".into(), json!(m.area));
    obj.insert("area_error".into(), json!(m.area_error));
    obj.insert("dirichlet".into(), json!(m.dirichlet));
    obj.insert("biharmonic".into(), json!(m.biharmonic));
    obj.insert(
        "abs_mean_curvature".into(),
        curvature_json(&m.abs_mean_curvature),
    );
    if let Some(t) = m.normal_turn {
        obj.insert(
            "max_normal_turn_deg".into(),
            normal_turn_json(t.angle, json!([t.at.0, t.at.1]), t.is_fold()),
        );
    }
}
