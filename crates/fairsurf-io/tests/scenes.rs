//! The scene format: every documented error names its JSON path; results
//! round-trip; the bundled examples solve and show what the paper claims.

use fairsurf_io::{Error, Outcome, Scene};
use serde_json::{json, Value};

fn base() -> Value {
    json!({
        "surface": {"type": "tensor", "degree": [3, 3], "control_points": [
            [[0,0,0],[0,1,0],[0,2,0],[0,3,0]],
            [[1,0,0],null,null,[1,3,0]],
            [[2,0,0],null,null,[2,3,0.5]],
            [[3,0,0],[3,1,0],[3,2,0],[3,3,0]]]},
        "energy": {"stretch": 1}
    })
}

fn err(v: &Value) -> (String, String) {
    let r = Scene::from_json(&v.to_string()).and_then(|s| s.solve().map(|_| ()));
    match r {
        Err(Error::Scene { path, message }) => (path, message),
        Err(e) => (String::from("<not a scene error>"), e.to_string()),
        Ok(()) => panic!("expected an error for {v}"),
    }
}

fn with(mut v: Value, ptr: &str, x: Value) -> Value {
    *v.pointer_mut(ptr).unwrap_or_else(|| panic!("{ptr}")) = x;
    v
}

fn examples() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

#[test]
fn the_base_scene_solves() {
    let s = Scene::from_json(&base().to_string())
        .unwrap()
        .solve()
        .unwrap();
    let sol = s.outcome.solution().unwrap();
    assert_eq!(sol.report.free_points, 4);
    assert!(sol.report.relative_gradient < 1e-14);
}

#[test]
fn wrong_point_size_names_the_point() {
    let v = with(base(), "/surface/control_points/3/2", json!([3, 2]));
    assert_eq!(
        err(&v),
        (
            "surface.control_points[3][2]".into(),
            "expected 3 numbers, got 2".into()
        )
    );
}

#[test]
fn wrong_counts_name_the_row() {
    let v = with(
        base(),
        "/surface/control_points/1",
        json!([[1, 0, 0], null, [1, 3, 0]]),
    );
    assert_eq!(
        err(&v),
        (
            "surface.control_points[1]".into(),
            "expected 4 points, got 3".into()
        )
    );
    let v = with(base(), "/surface/degree", json!([4, 3]));
    assert_eq!(
        err(&v),
        (
            "surface.control_points".into(),
            "expected 5 rows, got 4".into()
        )
    );
}

#[test]
fn type_errors_name_the_path() {
    let v = with(base(), "/surface/control_points/0/1/2", json!("zero"));
    let (path, msg) = err(&v);
    assert_eq!(path, "surface.control_points[0][1][2]");
    assert!(msg.contains("invalid type"), "{msg}");
    let v = with(base(), "/energy/stretch", json!("much"));
    assert_eq!(err(&v).0, "energy.stretch");
    let mut v = base();
    v["energy"]["strech"] = json!(1);
    let (path, msg) = err(&v);
    assert_eq!(path, "energy.strech");
    assert!(msg.contains("unknown field `strech`"), "{msg}");
}

#[test]
fn infinite_numbers_are_rejected() {
    // JSON has no NaN or ∞ literal; an overflowing literal is the way to write one.
    let text = base().to_string().replacen("[3,0,0]", "[3,0,1e999]", 1);
    let e = Scene::from_json(&text).unwrap_err();
    assert!(
        matches!(&e, Error::Scene { path, .. } if path.starts_with("surface.control_points[3][0]")),
        "{e}"
    );
}

#[test]
fn negative_weights_are_rejected() {
    let v = with(base(), "/energy/stretch", json!(-1));
    assert_eq!(
        err(&v),
        (
            "energy.stretch".into(),
            "expected a weight ≥ 0, got -1".into()
        )
    );
    let mut v = base();
    v["energy"]["normal_field"] =
        json!({"weight": -2, "degree": [0, 0], "control_points": [[[0,0,1]]]});
    assert_eq!(err(&v).0, "energy.normal_field.weight");
}

#[test]
fn zero_normals_are_rejected() {
    let mut v = base();
    let mut samples = vec![vec![json!([0, 0, 1]); 3]; 3];
    samples[1][2] = json!([0, 0, 0]);
    v["energy"]["sampling"] = json!({"grid": [2, 2], "normal_samples": samples});
    assert_eq!(
        err(&v),
        (
            "energy.sampling.normal_samples[1][2]".into(),
            "is the zero vector and has no direction".into()
        )
    );
    // A Bézier field that vanishes at a sample.
    let mut v = base();
    v["energy"]["normal_field"] =
        json!({"degree": [1, 0], "control_points": [[[0,0,1]], [[0,0,-1]]]});
    v["energy"]["sampling"] = json!({"grid": [2, 2]});
    let (path, msg) = err(&v);
    assert_eq!(path, "energy.normal_field.control_points");
    assert!(msg.contains("vanishes at sample (u, v) = (0.5"), "{msg}");
}

#[test]
fn too_few_free_points_and_too_low_degree_for_two_rings() {
    let mut v = base();
    for row in v["surface"]["control_points"].as_array_mut().unwrap() {
        for p in row.as_array_mut().unwrap() {
            if p.is_null() {
                *p = json!([1, 1, 1]);
            }
        }
    }
    assert_eq!(err(&v).0, "surface.control_points");
    let mut v2 = v.clone();
    v2["fixed_rings"] = json!(2);
    let (path, msg) = err(&v2);
    assert_eq!(path, "fixed_rings");
    assert!(msg.contains("both degrees must be at least 4"), "{msg}");
    // With one fixed ring the inner nulls are free, but a null on the boundary is an error.
    let mut v3 = with(base(), "/surface/control_points/0/1", Value::Null);
    v3["fixed_rings"] = json!(1);
    let (path, msg) = err(&v3);
    assert_eq!(path, "surface.control_points[0][1]");
    assert!(msg.contains("lies in the 1 fixed ring(s)"), "{msg}");
}

#[test]
fn sampling_sizes_are_checked() {
    let mut v = base();
    v["energy"]["normal_field"] = json!({"weight": 1});
    v["energy"]["sampling"] =
        json!({"grid": [2, 2], "normal_samples": vec![vec![json!([0,0,1]); 3]; 2]});
    assert_eq!(
        err(&v),
        (
            "energy.sampling.normal_samples".into(),
            "expected 3 rows, got 2".into()
        )
    );
    let mut v = base();
    v["energy"]["sampling"] = json!({"grid": [2, 0]});
    assert_eq!(err(&v).0, "energy.sampling.grid[1]");
    let mut v = base();
    v["energy"]["normal_field"] = json!({"degree": [0,0], "control_points": [[[0,0,1]]]});
    v["energy"]["sampling"] = json!({"grid": [2, 2], "normal_weights": [[1,1,1],[1,-1,1],[1,1,1]]});
    assert_eq!(
        err(&v),
        (
            "energy.sampling.normal_weights[1][1]".into(),
            "expected a weight ≥ 0, got -1".into()
        )
    );
    let mut v = base();
    v["energy"]["sampling"] = json!({"grid": [2, 2], "guide_weights": 2});
    assert_eq!(err(&v).0, "energy.sampling.guide_weights");
}

#[test]
fn guide_surface_needs_an_initial_net() {
    let mut v = base();
    v["energy"]["guide_surface"] = json!({"weight": 10});
    let (path, msg) = err(&v);
    assert_eq!(path, "energy.guide_surface.control_points");
    assert!(
        msg.contains("surface.control_points[1][1] is null"),
        "{msg}"
    );
}

#[test]
fn unsolvable_energy_is_a_solve_error_not_garbage() {
    let mut v = base();
    v["energy"] =
        json!({"stretch": 0, "normal_field": {"degree": [0,0], "control_points": [[[0,0,1]]]}});
    let e = Scene::from_json(&v.to_string())
        .unwrap()
        .solve()
        .unwrap_err();
    assert!(matches!(e, Error::Solve(_)), "{e}");
    assert!(
        e.to_string().contains("not positive definite") || e.to_string().contains("singular"),
        "{e}"
    );
}

#[test]
fn unreadable_file_is_a_read_error() {
    let e = Scene::read(std::path::Path::new("/no/such/scene.json")).unwrap_err();
    assert!(matches!(e, Error::Read { .. }));
    let e = Scene::from_json("{\"surface\": ").unwrap_err();
    assert!(e.to_string().contains("EOF"), "{e}");
}

/// A result file is a scene that solves to the same surface and energy.
#[test]
fn results_round_trip() {
    for name in [
        "quickstart.json",
        "wu_yang_fig1_l10_g100.json",
        "wu_yang_fig4_l500.json",
        "monterde_ugail_model.json",
        "monterde_ugail_model_harmonic.json",
        "monterde_ugail_fig7_harmonic_mask.json",
        "biharmonic_mask_bump.json",
    ] {
        let scene = Scene::read(&examples().join(name)).unwrap();
        let first = scene.solve().unwrap();
        let text = serde_json::to_string(&first.result_scene()).unwrap();
        let again = Scene::from_json(&text).unwrap().solve().unwrap();
        let d = first
            .patch()
            .points()
            .iter()
            .zip(again.patch().points())
            .map(|(a, b)| fairsurf::vector::norm(fairsurf::vector::sub(*a, *b)))
            .fold(0.0, f64::max);
        assert!(d < 1e-12, "{name}: moved by {d}");
        let rep = &first.result_scene().report.unwrap();
        for key in ["area", "dirichlet", "biharmonic"] {
            assert!(rep[key].is_number(), "{name}: report.{key}");
        }
        assert!(rep["abs_mean_curvature"]["mean"].is_number(), "{name}");
        if let (Some(a), Some(b)) = (first.outcome.solution(), again.outcome.solution()) {
            let (e1, e2) = (a.report.energy, b.report.energy);
            assert!((e1 - e2).abs() <= 1e-12 * e1, "{name}: {e1} vs {e2}");
            assert!(rep["energy"].is_number() && rep["gradient_norm"].is_number());
        } else {
            assert_eq!(
                rep["method"],
                first.scene.method.construction().unwrap().name()
            );
            assert_eq!(rep["exact"], true, "{name}");
        }
    }
}

#[test]
fn every_example_solves_to_a_true_minimizer_or_exact_construction() {
    let mut n = 0;
    for entry in std::fs::read_dir(examples()).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "json") {
            let text = std::fs::read_to_string(&p).unwrap();
            if fairsurf_io::is_triangular(&text) {
                let s = fairsurf_io::TriScene::from_json(&text)
                    .unwrap()
                    .solve()
                    .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                let r = &s.solution.report;
                assert!(r.max_violation <= 1e-10, "{}", p.display());
                match r.newton {
                    // Repellors: Newton's method to its tolerance, downhill.
                    Some(nr) => assert!(
                        r.relative_gradient <= 1e-10 && nr.energy <= nr.start_energy,
                        "{}: {nr:?}",
                        p.display()
                    ),
                    None => assert!(r.relative_gradient < 1e-12, "{}", p.display()),
                }
                assert!(r.kkt.unwrap().relative_residual < 1e-12, "{}", p.display());
                if !s.scene.operators.is_empty() {
                    // The result file solves again to the same surface, its
                    // operators' regions now given per patch.
                    let again = fairsurf_io::TriScene::from_json(
                        &serde_json::to_string(&s.result_scene()).unwrap(),
                    )
                    .unwrap()
                    .solve()
                    .unwrap();
                    let (a, b) = (s.surface().points(), again.surface().points());
                    let d = a
                        .iter()
                        .zip(b)
                        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max))
                        .fold(0.0, f64::max);
                    assert!(d < 1e-9, "{}: result re-solves {d:e} away", p.display());
                    let (ea, eb) = (r.external, again.solution.report.external);
                    assert!(
                        (ea - eb).abs() <= 1e-9 * ea.abs(),
                        "{}: {ea} vs {eb}",
                        p.display()
                    );
                }
                n += 1;
                continue;
            }
            let s = Scene::read(&p)
                .unwrap()
                .solve()
                .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            match &s.outcome {
                Outcome::Minimized(sol) => {
                    assert!(sol.report.relative_gradient < 1e-12, "{}", p.display())
                }
                Outcome::Constructed(c) => {
                    assert!(
                        c.report.exact && c.report.residual < 1e-11,
                        "{}",
                        p.display()
                    )
                }
            }
            n += 1;
        }
    }
    assert!(n >= 16);
}

/// Wu & Yang Fig. 4: the guiding normals help restore the salient feature:
/// with λ = 500 the filling is closer to the ground truth than the plain
/// thin plate.
#[test]
fn fig4_normals_restore_the_ground_truth() {
    let truth = Scene::read(&examples().join("data/wu_yang_fig4_ground_truth.json"))
        .unwrap()
        .surface_patch()
        .unwrap();
    let dist = |name: &str| {
        let p = Scene::read(&examples().join(name))
            .unwrap()
            .solve()
            .unwrap()
            .patch()
            .clone();
        let mut d: f64 = 0.0;
        for i in 0..=40 {
            for j in 0..=40 {
                let (u, v) = (i as f64 / 40.0, j as f64 / 40.0);
                d = d.max(fairsurf::vector::norm(fairsurf::vector::sub(
                    p.eval(u, v),
                    truth.eval(u, v),
                )));
            }
        }
        d
    };
    let (plain, guided) = (dist("wu_yang_fig4_l0.json"), dist("wu_yang_fig4_l500.json"));
    assert!(
        guided < 0.5 * plain,
        "λ=500: {guided} vs thin plate {plain}"
    );
}

#[test]
fn schema_describes_the_format() {
    let s = Scene::json_schema();
    let text = s.to_string();
    for key in [
        "surface",
        "fixed_rings",
        "normal_field",
        "guide_surface",
        "sampling",
        "normal_samples",
        "guide_weights",
    ] {
        assert!(text.contains(key), "schema lacks {key}");
    }
}
