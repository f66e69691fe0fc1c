//! Results of triangular scenes: the solved surface written back as a
//! scene that solves again to it (the mesh refined by curve constraints,
//! the constraints and operators moved onto it), and its report.

use crate::tri_scene::{domain_point, operator, set_region};
use crate::{
    ConstraintKind, ConstraintSpec, DomainPointSpec, Error, OperatorKind, TriScene, TriSurfaceSpec,
};
use fairsurf::triangle::{Refinement, TriSolution};
use fairsurf::SolveReport;
use fairsurf::TriSurface;
use serde_json::{json, Value};

/// A solved triangular scene.
#[derive(Clone, Debug)]
pub struct SolvedTriScene {
    /// The scene as read.
    pub scene: TriScene,
    /// The solution.
    pub solution: TriSolution,
}

impl SolvedTriScene {
    /// The solved surface.
    pub fn surface(&self) -> &TriSurface {
        &self.solution.surface
    }

    /// The result as a scene: the (refined) mesh with every control point,
    /// the constraints moved onto the refined mesh (a curve becomes the
    /// fixed control points of its chain edges, which is what it
    /// amounts to), and the report. Solving it again gives the same surface.
    pub fn result_scene(&self) -> TriScene {
        let s = self.surface();
        let mut out = self.scene.clone();
        out.surface = TriSurfaceSpec::from(s);
        let refined = self
            .scene
            .constraints
            .iter()
            .any(|c| c.kind == ConstraintKind::Curve);
        // Regions in the mesh's (x, y) become the per-patch pieces they were
        // split into (the solved vertices have other (x, y)).
        if let Ok(original) = self.scene.surface() {
            for (i, o) in out.operators.iter_mut().enumerate() {
                if let Ok(Some(pieces)) = operator(o, i).and_then(|op| {
                    op.domain_pieces(&original)
                        .map_err(|e| Error::scene(format!("operators[{i}]"), e.to_string()))
                }) {
                    set_region(o, pieces);
                }
            }
        }
        if refined {
            let r = Refinement {
                surface: s.clone(),
                origin: self.solution.figures().origin.clone(),
            };
            // Regions are clipped to the split patches; points move with
            // the mesh. Edge and surface attractors are not carried over: a
            // split edge is no longer one edge, and a split region no longer
            // one triangle matching the attractor surface's corners.
            let original = self.scene.surface().ok();
            let mut kept = Vec::new();
            for (i, mut o) in self.scene.operators.iter().cloned().enumerate() {
                if o.edge.is_some() || o.kind == OperatorKind::SurfaceAttractor {
                    continue;
                }
                if o.region.is_some() || o.domain_region.is_some() {
                    let pieces = match (&original, operator(&o, i)) {
                        (Some(orig), Ok(op)) => op.refined_region(orig, &r).ok().flatten(),
                        _ => None,
                    };
                    let Some(pieces) = pieces else { continue };
                    set_region(&mut o, pieces);
                }
                kept.push(o);
            }
            out.operators = kept;
            for o in &mut out.operators {
                if let Some(at) = o.at {
                    o.at = r.locate(domain_point(at)).map(|p| DomainPointSpec {
                        triangle: p.triangle,
                        bary: p.bary,
                    });
                }
            }
            let mut constraints = Vec::new();
            for c in &self.scene.constraints {
                let mut c = c.clone();
                match c.kind {
                    ConstraintKind::Curve => continue,
                    ConstraintKind::Fixed => {
                        // Fixed points are stated by value: after refinement
                        // their indices change; the boundary fix and the
                        // curves' chains below keep the values.
                        continue;
                    }
                    _ => {
                        if let Some(at) = c.at {
                            c.at = r.locate(domain_point(at)).map(|p| DomainPointSpec {
                                triangle: p.triangle,
                                bary: p.bary,
                            });
                        }
                    }
                }
                constraints.push(c);
            }
            // Every point the solve held fixed keeps its value (the
            // boundary is fixed again by `fix_boundary`).
            let boundary = if self.scene.fix_boundary {
                s.boundary_points()
            } else {
                Vec::new()
            };
            for (g, p) in fixed_points(&self.solution) {
                if boundary.binary_search(&g).is_ok() {
                    continue;
                }
                constraints.push(ConstraintSpec {
                    kind: ConstraintKind::Fixed,
                    name: Some(format!("fixed point {g}")),
                    index: Some(g),
                    value: Some(p),
                    ..blank(ConstraintKind::Fixed)
                });
            }
            out.constraints = constraints;
        }
        out.report = Some(self.report_json());
        out
    }

    /// The `"report"` object, with the [`Self::notes`].
    pub fn report_json(&self) -> Value {
        let mut r = tri_report_json(&self.solution.report);
        r["notes"] = json!(self.notes());
        r
    }

    /// What the result's reader should know: a fold inside a patch, when
    /// the normal turns by more than 90° between neighbouring samples.
    pub fn notes(&self) -> Vec<String> {
        let fold = (self.solution.report.triangular.as_ref())
            .and_then(|t| t.normal_turn)
            .filter(|t| t.is_fold());
        fold.map(|t| {
            format!(
                "the surface folds: its normal turns by {:.1}° between neighbouring samples \
                 of patch {} near barycentric ({:.3}, {:.3}, {:.3}); lower the operators' \
                 strengths or move their targets",
                t.angle.to_degrees(),
                t.patch,
                t.at[0],
                t.at[1],
                t.at[2]
            )
        })
        .into_iter()
        .collect()
    }
}

/// The points the solve held fixed, with their values.
fn fixed_points(solution: &TriSolution) -> Vec<(usize, [f64; 3])> {
    solution
        .figures()
        .fixed
        .iter()
        .map(|&g| (g, solution.surface.points()[g]))
        .collect()
}

fn blank(kind: ConstraintKind) -> ConstraintSpec {
    ConstraintSpec {
        kind,
        name: None,
        at: None,
        target: None,
        normal: None,
        offset: None,
        point: None,
        direction: None,
        index: None,
        value: None,
        control_points: None,
        from: None,
        to: None,
        through: None,
    }
}

/// The solver core's KKT solve ([`fairsurf::triangle::KktInfo`]) as JSON.
pub(crate) fn kkt_json(k: &fairsurf::triangle::KktInfo) -> Value {
    json!({
        "size": k.size,
        "factorization": k.factorization.name(),
        "per_coordinate": k.per_coordinate,
        "reused_symbolic": k.reused_symbolic,
        "factor_nonzeros": k.factor_nonzeros,
        "delta": k.delta,
    })
}

/// A triangular surface's report as JSON: every kind's keys
/// ([`crate::result::report_json`]) and the triangular figures (mesh,
/// constraint rows, continuity residuals, edge angles, normal turn; the
/// refine and classify phases in `timings_s`).
pub fn tri_report_json(r: &SolveReport) -> Value {
    let mut o = crate::result::report_json(r);
    let Some(t) = &r.triangular else {
        return o;
    };
    let rows = |d: &[fairsurf::triangle::DroppedRow]| -> Vec<Value> {
        d.iter()
            .map(|x| json!({"name": x.name, "residual": x.residual}))
            .collect()
    };
    let extra = json!({
        "mesh": {"patches": t.patches, "vertices": t.vertices, "control_points": t.points},
        "fixed_coordinates": t.fixed_coordinates,
        "constraint_rows": {
            "total": t.rows,
            "independent": t.independent_rows,
            "dependent": t.dependent_rows,
        },
        "dropped_continuity": rows(&t.dropped),
        "inconsistent": rows(&t.inconsistent),
        "continuity_residual": t.continuity_residual,
        "unenforced_continuity_residual": t.unenforced_residual,
        "row_tolerance": t.row_tolerance,
        "row_classifications": t.classifications,
        "kkt_factorizations": t.factorizations,
        "max_edge_normal_angle_rad": t.max_edge_normal_angle.map(|(a, _)| a),
        "max_edge_normal_angle_at": t.max_edge_normal_angle.map(|(_, e)| e),
        "max_normal_turn_deg": t.normal_turn.map(|n| crate::result::normal_turn_json(
            n.angle, json!({"patch": n.patch, "bary": n.at}), n.is_fold())),
    });
    let map = o.as_object_mut().expect("an object");
    for (k, v) in extra.as_object().expect("an object") {
        map.insert(k.clone(), v.clone());
    }
    o["timings_s"]["refine"] = json!(t.refine_seconds);
    o["timings_s"]["classify"] = json!(t.classify_seconds);
    o
}
