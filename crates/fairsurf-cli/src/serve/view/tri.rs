//! The view of a triangular surface.

use super::*;
use std::collections::BTreeSet;

/// The solved surface's point at a scene's domain point
/// (`{"triangle": t, "bary": [u, v, w]}`), if it is one.
fn domain_point(sol: &fairsurf::triangle::TriSolution, at: &Value) -> Option<Vec3> {
    sol.point_at(at["triangle"].as_u64()? as usize, vec3(&at["bary"])?)
}

pub(super) fn tri_view(solved: &SolvedTriScene) -> View<'_> {
    let scene = &solved.scene;
    let s = solved.surface();
    let r = &solved.solution.report;
    let size = size_of(s.points());
    let scene_json = entries_json(&scene.operators, &scene.constraints);
    let resolution = match s.patch_count() {
        0..=200 => 8,
        201..=2000 => 4,
        _ => 2,
    };
    let boundary: Vec<Vec<Vec3>> = s
        .boundary_edges()
        .into_iter()
        .map(|e| polyline(s.edge_points(e).iter().map(|&g| s.points()[g]).collect(), 8))
        .collect();

    let mut handles = Vec::new();
    let mut normals = Vec::new();
    if scene.fix_boundary {
        let boundary_vertices: BTreeSet<usize> = s.boundary_vertices().into_iter().collect();
        for (k, p) in scene.surface.vertices.iter().enumerate() {
            if boundary_vertices.contains(&k) {
                handles.push(Handle::point(
                    format!("/surface/vertices/{k}"),
                    *p,
                    format!("vertex {k}"),
                    "control_point",
                ));
            }
        }
    }
    // The initial net, for fixed points whose value the scene leaves to it
    // (built only if one does).
    let initial = std::cell::OnceCell::new();
    let at = |c: &Value| domain_point(&solved.solution, &c["at"]);
    constraint_controls(&scene_json, at, size, &mut handles, &mut normals);
    for field in Field::entries(&scene_json, "constraints", "constraint") {
        let c = field.entry;
        // A fixed control point: its value, or the net's when not given
        // (dragging writes `value`).
        if c["type"] == "fixed" {
            let position = if c["value"].is_array() {
                vec3(&c["value"])
            } else {
                c["index"].as_u64().and_then(|g| {
                    let net = initial.get_or_init(|| scene.surface().ok()).as_ref()?;
                    net.points().get(g as usize).copied()
                })
            };
            if let Some(position) = position {
                handles.push(Handle::point(
                    format!("{}/value", field.prefix),
                    position,
                    field.label.clone(),
                    "control_point",
                ));
            }
        }
    }
    let operators = operator_markers(&scene_json["operators"], &r.operators, size);
    let mut sliders = vec![
        slider(
            "/energy/stretch".into(),
            "α stretch".into(),
            scene.energy.stretch.unwrap_or(0.0),
            1e-4,
            1e3,
        ),
        slider(
            "/energy/bend".into(),
            "β bend".into(),
            scene.energy.bend.unwrap_or(1.0),
            1e-4,
            1e3,
        ),
    ];
    operator_controls(&scene_json, &operators, size, &mut handles, &mut sliders);
    let t = solved.solution.figures();
    let mut table = Vec::new();
    report_rows(&mut table, r, |table| {
        table.push(row(
            "max normal angle across edges (rad)",
            t.max_edge_normal_angle.map(|(a, _)| a),
        ));
        table.push(row("patches", t.patches as f64));
        table.push(row("continuity rows dropped", t.dropped.len() as f64));
    });
    View {
        kind: "triangular",
        table,
        result: Scene::Triangular(solved.result_scene()),
        mesh: surface_mesh_view(&SurfaceMesh::from_tri_surface(s, resolution)),
        net: Net {
            points: s.points(),
            edges: s.net_edges(),
        },
        boundary,
        normals,
        operators,
        handles,
        sliders,
        methods: None,
    }
}
