//! What every kind's view shares: the operators' markers, handles and
//! sliders, the constraints' handles and arrows, and the report's rows.

use super::*;

/// The scene's operators and constraints as JSON, what the markers and
/// handles read (`Field::entries`), without the rest of the scene (whose net
/// a drag would otherwise copy into a value tree at every step).
pub(super) fn entries_json(
    operators: &impl serde::Serialize,
    constraints: &impl serde::Serialize,
) -> Value {
    json!({"operators": operators, "constraints": constraints})
}

/// The operators' markers: each entry with its outcome's point.
pub(super) fn operator_markers(
    operators: &Value,
    outcomes: &[fairsurf::operator::OperatorOutcome],
    size: f64,
) -> Vec<Marker> {
    operators
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
        .map(|(k, o)| operator_json(o, outcomes.get(k).and_then(|r| r.at), size))
        .collect()
}

/// Where an operator's marker goes and what it points at, from its scene
/// entry and where it acts on the result (its outcome's `at`).
pub(super) fn operator_json(o: &Value, at: Option<Vec3>, size: f64) -> Marker {
    let kind = o["type"].as_str().unwrap_or("operator");
    let target = at.and_then(|s| match kind {
        "point_attractor" | "repellor" => vec3(&o["point"]),
        "plane_attractor" => {
            let n = vec3(&o["normal"])?;
            let d = (dot(n, s) - o["offset"].as_f64()?) / dot(n, n);
            Some(sub(s, scale(n, d)))
        }
        "line_attractor" => {
            let (p, q) = (vec3(&o["point"])?, vec3(&o["direction"])?);
            Some(add(p, scale(q, dot(sub(s, p), q) / dot(q, q))))
        }
        "director" => Some(add(
            s,
            scale(normalize(vec3(&o["direction"])?)?, ARROW * size),
        )),
        "curve_attractor" => {
            let pts: Option<Vec<Vec3>> = o["control_points"].as_array()?.iter().map(vec3).collect();
            Some(BezierCurve::try_new(pts?).ok()?.eval(0.5))
        }
        _ => None,
    });
    Marker {
        name: o["name"].as_str().unwrap_or(kind).into(),
        kind: if o["repel"].as_bool() == Some(true) {
            "repellor"
        } else {
            kind
        }
        .into(),
        at,
        target,
    }
}

/// Each operator's energy and how far its target is met.
pub(super) fn operator_rows(
    table: &mut Vec<Row>,
    operators: &[fairsurf::operator::OperatorOutcome],
) {
    for o in operators {
        let what = if o.kind == "director" {
            "angle (rad)"
        } else {
            "distance"
        };
        table.push(row(format!("{}: energy", o.name), o.energy));
        table.push(row(format!("{}: {what}", o.name), o.measure));
    }
}

/// A minimization's rows, the same for every tensor kind: the energy and
/// its terms, the operators, the measures (when analysed), then `extra`
/// (the kind's own figures) and how good the result is.
pub(super) fn report_rows(
    table: &mut Vec<Row>,
    r: &fairsurf::SolveReport,
    extra: impl FnOnce(&mut Vec<Row>),
) {
    table.push(row("energy", r.energy));
    for t in &r.terms {
        table.push(row(t.name.replace('_', " "), t.value));
    }
    operator_rows(table, &r.operators);
    measure_rows(table, r.measures.as_ref());
    extra(table);
    if !r.constraints.is_empty() {
        table.push(row("max constraint violation", r.max_violation));
    }
    table.push(row("gradient (relative)", r.relative_gradient));
    if let Some(c) = &r.check {
        table.push(row("checked: energy excess (relative)", c.excess));
    }
    table.push(row("residual", r.residual));
    table.push(row("condition estimate", r.condition_estimate));
    table.push(row("unknowns", r.unknowns as f64));
    table.push(row(
        "factorization",
        match (r.reused, r.reused_symbolic) {
            (true, _) => "reused",
            (false, true) => "refactored (ordering kept)",
            _ => "new",
        },
    ));
    table.push(row("solve (ms)", 1e3 * r.timings.total));
    if let Some(nr) = &r.newton {
        table.push(row("Newton iterations", nr.iterations as f64));
    }
}

/// Area, functionals and |H| of a tensor patch.
pub(super) fn measure_rows(table: &mut Vec<Row>, m: Option<&fairsurf::SurfaceMeasures>) {
    if let Some(m) = m {
        table.push(row("area", m.area));
        table.push(row("Dirichlet", m.dirichlet));
        table.push(row("biharmonic", m.biharmonic));
        table.push(row("mean |H|", m.abs_mean_curvature.mean));
        table.push(row("max |H|", m.abs_mean_curvature.max));
    }
}

/// Handles and sliders of the scene's operators; `markers` are their
/// [`operator_json`] entries (where each acts on the surface).
pub(super) fn operator_controls(
    scene: &Value,
    markers: &[Marker],
    size: f64,
    handles: &mut Vec<Handle>,
    sliders: &mut Vec<Slider>,
) {
    for (k, field) in Field::entries(scene, "operators", "operator").enumerate() {
        let o = field.entry;
        let at = markers.get(k).and_then(|m| m.at);
        field.point(handles, "point");
        match o["type"].as_str() {
            Some("director") => field.direction(handles, "direction", at, ARROW * size),
            Some("line_attractor") => {
                field.direction(handles, "direction", vec3(&o["point"]), ARROW * size)
            }
            Some("plane_attractor") => field.plane(handles, at, ARROW * size),
            _ => {}
        }
        let s = o["strength"].as_f64().unwrap_or(1.0);
        sliders.push(slider(
            format!("{}/strength", field.prefix),
            format!("{} strength", field.label),
            s,
            (s / 1000.0).clamp(1e-9, 1e-3),
            (s * 1000.0).max(1e3),
        ));
    }
}

/// Handles of the scene's point, normal, in-plane and on-line constraints
/// (the prescribed normals also drawn as arrows); `at` finds where a
/// constraint acts on the solved surface.
pub(super) fn constraint_controls(
    scene: &Value,
    at: impl Fn(&Value) -> Option<Vec3>,
    size: f64,
    handles: &mut Vec<Handle>,
    normals: &mut Vec<Arrow>,
) {
    for field in Field::entries(scene, "constraints", "constraint") {
        let c = field.entry;
        match c["type"].as_str() {
            Some("point") => field.point(handles, "target"),
            Some("normal") => {
                if let (Some(s), Some(n)) = (at(c), vec3(&c["normal"]).and_then(normalize)) {
                    normals.push(Arrow {
                        at: s,
                        dir: scale(n, ARROW * size),
                    });
                }
                field.direction(handles, "normal", at(c), ARROW * size);
            }
            Some("in_plane") => field.plane(handles, at(c), ARROW * size),
            Some("on_line") => {
                field.point(handles, "point");
                field.direction(handles, "direction", vec3(&c["point"]), ARROW * size);
            }
            _ => {}
        }
    }
}

/// (u, v) of a tensor constraint's `at`: `{"uv": [u, v]}` or `[u, v]`.
pub(super) fn uv_of(at: &Value) -> Option<[f64; 2]> {
    let a = at.get("uv").unwrap_or(at).as_array()?;
    match a.as_slice() {
        [u, v] => Some([u.as_f64()?, v.as_f64()?]),
        _ => None,
    }
}
