//! The views of tensor (Bézier) and B-spline surfaces.

use super::*;

/// The view of a B-spline surface: its mesh over the knot domain, its own
/// control net and boundary, the held control points as handles (the
/// scene's own points, also when it is refined before solving), the normal
/// field's arrows, the operators' markers and the constraints' handles as
/// on a tensor patch, sliders for the energy weights and strengths, and the
/// report's table.
pub(super) fn bspline_view(solved: &SolvedBSplineScene) -> View<'_> {
    let scene = &solved.scene;
    let s = solved.surface();
    let size = size_of(s.points());
    let scene_json = entries_json(&scene.operators, &scene.constraints);
    let (cu, cv) = s.counts();
    // Handles: the scene's given points that are held. With "refine" the
    // solved net is finer; the held points are then the scene's rings.
    let rows = &scene.surface.control_points;
    let held = |i: usize, j: usize| match (scene.fixed_rings, &scene.refine) {
        (Some(k), _) => {
            let (r, c) = (rows.len(), rows.first().map_or(0, Vec::len));
            i.min(j).min(r - 1 - i).min(c - 1 - j) < k
        }
        (None, _) => !solved.free.get(i * cv + j).copied().unwrap_or(true),
    };
    let mut handles = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        for (j, p) in row.iter().enumerate() {
            let p = p.as_deref().and_then(|p| <[f64; 3]>::try_from(p).ok());
            if let (Some(p), true) = (p, held(i, j)) {
                handles.push(Handle::point(
                    format!("/surface/control_points/{i}/{j}"),
                    p,
                    format!("P({i},{j})"),
                    "control_point",
                ));
            }
        }
    }
    let e = &scene.energy;
    let sliders = weight_sliders(
        (e.stretch, e.bend, scene.fixed_rings),
        e.normal_field.as_ref().map(|f| f.weight),
        e.guide_surface.as_ref().map(|g| g.weight),
    );
    let r = &solved.solution.report;
    let mut table = Vec::new();
    report_rows(&mut table, r, |table| {
        let (su, sv) = (s.knots().0.spans().len(), s.knots().1.spans().len());
        table.push(row("spans", format!("{su} × {sv}")));
    });
    // The normal field's directions on a 9 × 9 grid of the knot domain
    // (the field lives on it mapped onto [0, 1]²).
    let mut normals = Vec::new();
    if let Some(f) = &solved.normal_field {
        let t: Vec<f64> = (0..=8).map(|k| k as f64 / 8.0).collect();
        for (k, d) in f.directions(&t, &t).into_iter().enumerate() {
            let (a, b) = (t[k / 9], t[k % 9]);
            if let Some(d) = d {
                let at = s.eval_unit(a, b);
                normals.push(Arrow {
                    at,
                    dir: scale(d, 0.08 * size),
                });
            }
        }
    }
    let operators = operator_markers(&scene_json["operators"], &r.operators, size);
    let mut sliders = sliders;
    operator_controls(&scene_json, &operators, size, &mut handles, &mut sliders);
    let at = |c: &Value| uv_of(&c["at"]).map(|[u, v]| s.eval(u, v));
    constraint_controls(&scene_json, at, size, &mut handles, &mut normals);
    View {
        kind: "bspline",
        table,
        result: Scene::BSpline(solved.result_scene()),
        mesh: grid_mesh_view(s),
        net: Net {
            points: s.points(),
            edges: grid_edges(cu, cv),
        },
        boundary: s.boundary(64).into(),
        normals,
        operators,
        handles,
        sliders,
        methods: None,
    }
}

pub(super) fn tensor_view(solved: &SolvedTensorScene) -> View<'_> {
    let scene = &solved.scene;
    let patch = solved.patch();
    let (n, m) = patch.degree();
    let size = size_of(patch.points());
    let scene_json = entries_json(&scene.operators, &scene.constraints);

    let boundary = patch.boundary(64).into();

    let mut normals = Vec::new();
    if let Some(f) = &solved.built.normal_field {
        let ts: Vec<f64> = (0..=8).map(|a| a as f64 / 8.0).collect();
        let at = patch.eval_on(&ts, &ts);
        for (k, &at) in at.iter().enumerate() {
            if let Some(d) = f.direction(ts[k / 9], ts[k % 9]) {
                normals.push(Arrow {
                    at,
                    dir: scale(d, 0.08 * size),
                });
            }
        }
    }

    // Operators: the marker at the surface point they act on (operators
    // come only with the minimizing method).
    let outcomes = match &solved.outcome {
        Outcome::Minimized(sol) => sol.report.operators.as_slice(),
        Outcome::Constructed(_) => &[],
    };
    let operators = operator_markers(&scene_json["operators"], outcomes, size);

    // Handles: the given control points that are held (not free).
    let mut handles = Vec::new();
    for (i, row) in scene.surface.control_points.iter().enumerate() {
        for (j, p) in row.iter().enumerate() {
            let k = i * (m + 1) + j;
            let p = p.as_deref().and_then(|p| <[f64; 3]>::try_from(p).ok());
            if let Some(p) = p {
                if !solved.built.free.get(k).copied().unwrap_or(true) {
                    handles.push(Handle::point(
                        format!("/surface/control_points/{i}/{j}"),
                        p,
                        format!("P({i},{j})"),
                        "control_point",
                    ));
                }
            }
        }
    }

    let mut sliders = Vec::new();
    let mut table = Vec::new();
    match &solved.outcome {
        Outcome::Minimized(sol) => {
            let e = &scene.energy;
            sliders = weight_sliders(
                (e.stretch, e.bend, scene.fixed_rings),
                e.normal_field.as_ref().map(|f| f.weight),
                e.guide_surface.as_ref().map(|g| g.weight),
            );
            report_rows(&mut table, &sol.report, |table| {
                if let Some(d) = &solved.normal_deviation {
                    table.push(row("normal deviation, mean (rad)", d.mean));
                }
                if let Some(g) = solved.guide_distance {
                    table.push(row("distance to guide", g));
                }
            });
            operator_controls(&scene_json, &operators, size, &mut handles, &mut sliders);
            let at = |c: &Value| uv_of(&c["at"]).map(|[u, v]| patch.eval(u, v));
            constraint_controls(&scene_json, at, size, &mut handles, &mut normals);
        }
        Outcome::Constructed(c) => {
            let r = &c.report;
            table.push(row("method", r.method.name()));
            table.push(row(
                "exact",
                if r.exact { "yes" } else { "no (least squares)" },
            ));
            table.push(row(
                format!("residual of {}", r.method.equations()),
                r.residual,
            ));
            table.push(row("backward error", r.backward_error));
            measure_rows(&mut table, r.measures.as_ref());
        }
    }
    View {
        kind: "tensor",
        table,
        result: Scene::Tensor(solved.result_scene()),
        mesh: grid_mesh_view(patch),
        net: Net {
            points: patch.points(),
            edges: grid_edges(n + 1, m + 1),
        },
        boundary,
        normals,
        operators,
        handles,
        sliders,
        methods: Some(Methods {
            pointer: "/method",
            value: scene.method,
            options: Methods::OPTIONS,
        }),
    }
}
