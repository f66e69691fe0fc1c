//! The `fairsurf` command as a user meets it: exit statuses, one-line errors
//! that name the file and JSON path, files written whole or not at all.

#[path = "../../fairsurf-io/tests/mutate/mod.rs"]
mod mutate;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fairsurf(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fairsurf"))
        .args(args)
        .output()
        .expect("runs")
}

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fairsurf-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The degree-n net of the flat unit square with its boundary given and
/// its interior free (null).
fn flat_square_net(n: usize) -> serde_json::Value {
    let rows: Vec<Vec<serde_json::Value>> = (0..=n)
        .map(|i| {
            (0..=n)
                .map(|j| match i == 0 || j == 0 || i == n || j == n {
                    true => serde_json::json!([i as f64 / n as f64, j as f64 / n as f64, 0.0]),
                    false => serde_json::Value::Null,
                })
                .collect()
        })
        .collect();
    serde_json::json!(rows)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn solve_writes_result_and_meshes() {
    let d = tmpdir("solve");
    let scene = examples().join("quickstart.json");
    for ext in ["obj", "ply", "stl"] {
        let out = d.join(format!("sub/r_{ext}.json"));
        let mesh = d.join(format!("sub/m.{ext}"));
        let o = fairsurf(&[
            "solve",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--mesh",
            mesh.to_str().unwrap(),
            "--resolution",
            "8",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        for key in ["area", "dirichlet", "biharmonic", "energy", "gradient_norm"] {
            assert!(v["report"][key].is_number(), "report.{key}");
        }
        assert!(
            v["surface"]["control_points"][1][1].is_array(),
            "free point filled"
        );
        let bytes = std::fs::read(&mesh).unwrap();
        match ext {
            "obj" => {
                let t = String::from_utf8(bytes).unwrap();
                assert_eq!(t.lines().filter(|l| l.starts_with("v ")).count(), 81);
                assert_eq!(t.lines().filter(|l| l.starts_with("vn ")).count(), 81);
                assert_eq!(t.lines().filter(|l| l.starts_with("f ")).count(), 128);
            }
            "ply" => {
                let header_end = bytes
                    .windows(11)
                    .position(|w| w == b"end_header\n")
                    .unwrap()
                    + 11;
                // 81 vertices × (3 doubles + 3 floats + 4 doubles of curvature)
                // + 128 faces × (1 + 3·4) bytes
                assert_eq!(bytes.len() - header_end, 81 * (36 + 32) + 128 * 13);
                let header = String::from_utf8_lossy(&bytes[..header_end]);
                assert!(header.contains("property double mean_curvature"));
            }
            _ => assert_eq!(bytes.len(), 84 + 128 * 50, "binary STL size"),
        }
    }
    let stl = std::fs::File::open(d.join("sub/m.stl")).unwrap();
    let mesh = stl_io_read(stl);
    assert_eq!(mesh, 128);
}

fn stl_io_read(f: std::fs::File) -> usize {
    // Count facets from the binary header: an independent reading of the file.
    use std::io::Read;
    let mut b = Vec::new();
    std::io::BufReader::new(f).read_to_end(&mut b).unwrap();
    u32::from_le_bytes([b[80], b[81], b[82], b[83]]) as usize
}

#[test]
fn bad_scene_exits_2_with_the_json_path_and_writes_nothing() {
    let d = tmpdir("bad");
    let scene = d.join("bad.json");
    let text = std::fs::read_to_string(examples().join("quickstart.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut v = v;
    v["surface"]["control_points"][3][2] = serde_json::json!([3, 2]);
    std::fs::write(&scene, v.to_string()).unwrap();
    let out = d.join("out.json");
    let o = fairsurf(&[
        "solve",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("surface.control_points[3][2]: expected 3 numbers, got 2"),
        "{e}"
    );
    assert_eq!(e.trim().lines().count(), 1, "one line: {e}");
    assert!(!out.exists());
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        1,
        "nothing but the scene"
    );
}

#[test]
fn unreadable_and_malformed_files_exit_2() {
    let o = fairsurf(&["solve", "/no/such/file.json"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("cannot read /no/such/file.json"),
        "{}",
        stderr(&o)
    );
    let d = tmpdir("malformed");
    let p = d.join("x.json");
    std::fs::write(&p, "{\"surface\": [").unwrap();
    let o = fairsurf(&["solve", p.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("line 1"), "{}", stderr(&o));
}

#[test]
fn singular_energy_exits_2_and_says_why() {
    let d = tmpdir("singular");
    let p = d.join("s.json");
    std::fs::write(
        &p,
        r#"{"surface": {"type": "tensor", "degree": [2, 2], "control_points": [
            [[0,0,0],[0,1,0],[0,2,0]], [[1,0,0],null,[1,2,0]], [[2,0,0],[2,1,0],[2,2,0]]]},
            "energy": {"stretch": 0, "normal_field": {"control_points": [[[0,0,1]]]}}}"#,
    )
    .unwrap();
    let o = fairsurf(&[
        "solve",
        p.to_str().unwrap(),
        "-o",
        d.join("r.json").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("stretch or bend"), "{}", stderr(&o));
    assert!(!d.join("r.json").exists());
}

#[test]
fn unwritable_output_exits_1_and_leaves_nothing() {
    let d = tmpdir("unwritable");
    let blocker = d.join("file");
    std::fs::write(&blocker, "x").unwrap();
    // A directory path through a regular file cannot be created.
    let out = blocker.join("r.json");
    let o = fairsurf(&[
        "solve",
        examples().join("quickstart.json").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
}

#[test]
fn bad_mesh_extension_exits_2_before_solving() {
    let o = fairsurf(&[
        "solve",
        examples().join("quickstart.json").to_str().unwrap(),
        "--mesh",
        "x.dxf",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains(".obj, .ply, .stl, .glb or .gltf"));
}

#[test]
fn several_scenes_go_to_a_directory() {
    let d = tmpdir("many");
    let a = examples().join("quickstart.json");
    let b = examples().join("wu_yang_fig1_l10_g0.json");
    let o = fairsurf(&[
        "solve",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "-o",
        d.join("res").to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.join("res/quickstart.result.json").exists());
    assert!(d.join("res/wu_yang_fig1_l10_g0.result.json").exists());
    assert!(o.stdout.is_empty(), "quiet");
}

/// Every command reads scenes through one entry point: an unknown
/// `surface.type` exits 2 naming the path and the known kinds; commands
/// made for tensor patches (eval at (u, v), compare, render --compare)
/// refuse a triangular scene by name, before any work.
#[test]
fn unknown_surface_types_and_kinds_a_command_does_not_take_exit_2() {
    let d = tmpdir("kinds");
    let nurbs = d.join("nurbs.json");
    std::fs::write(
        &nurbs,
        r#"{"surface": {"type": "nurbs", "degree": [1, 1], "control_points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,0]]]}}"#,
    )
    .unwrap();
    let out = d.join("r.json");
    for cmd in ["solve", "analyse", "eval", "compare", "export", "render"] {
        let mut args = vec![cmd, nurbs.to_str().unwrap()];
        match cmd {
            "solve" => args.extend(["-o", out.to_str().unwrap()]),
            "eval" => args.extend(["--uv", "0,0"]),
            "export" => args.extend(["-o", "never.step"]),
            "render" => args.extend(["-o", "never.png"]),
            _ => {}
        }
        let o = fairsurf(&args);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(
                r#"surface.type: unknown surface type "nurbs": expected "tensor", "triangular" or "bspline""#
            ),
            "{cmd}: {e}"
        );
        assert_eq!(e.lines().count(), 1, "{cmd}: {e}");
    }
    assert!(!out.exists() && !Path::new("never.step").exists() && !Path::new("never.png").exists());
    let tri = examples().join("vw_fig1_point_normal.json");
    let png = d.join("c.png");
    for args in [
        vec!["eval", tri.to_str().unwrap(), "--uv", "0,0"],
        vec!["compare", tri.to_str().unwrap()],
        vec![
            "render",
            tri.to_str().unwrap(),
            "--compare",
            "-o",
            png.to_str().unwrap(),
        ],
    ] {
        let o = fairsurf(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = stderr(&o);
        assert!(
            e.contains("works on tensor-product") && e.contains("this one is triangular"),
            "{args:?}: {e}"
        );
    }
    assert!(!png.exists());
}

/// Tensor and triangular reports say the common figures under the same
/// names with the same meaning: the energy is the sum of its terms and the
/// operators' share, the timings' total covers its phases, the accuracy
/// figures are numbers, and the check agrees with the energy.
#[test]
fn every_kind_reports_the_common_figures_under_one_name() {
    for name in [
        "wu_yang_fig4_l500",
        "tensor_operators",
        "vw_hexagon_hole",
        "vw_fig8_operators",
    ] {
        let scene = examples().join(format!("{name}.json"));
        let o = fairsurf(&["solve", scene.to_str().unwrap(), "--json"]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let num = |k: &str| {
            r[k].as_f64()
                .unwrap_or_else(|| panic!("{name}: {k} is {}", r[k]))
        };
        for k in [
            "energy",
            "gradient_norm",
            "relative_gradient",
            "residual",
            "max_violation",
        ] {
            assert!(
                num(k).is_finite() && num(k) >= 0.0 || k == "energy",
                "{name}: {k}"
            );
        }
        let cond = &r["condition_estimate"];
        assert!(cond.as_f64().is_some_and(|c| c >= 1.0), "{name}: {cond}");
        let terms: f64 = r["terms"]
            .as_object()
            .unwrap()
            .values()
            .map(|v| v.as_f64().unwrap())
            .sum();
        let external = r["external"].as_f64().unwrap_or(0.0);
        let energy = num("energy");
        assert!(
            (terms + external - energy).abs() <= 1e-12 * energy.abs().max(1e-300),
            "{name}: {terms} + {external} vs {energy}"
        );
        assert!(
            (r["check"]["energy"].as_f64().unwrap() - energy).abs() <= 1e-12 * energy.abs(),
            "{name}"
        );
        assert!(
            r["refinement_steps"].is_u64() && r["unknowns"].as_u64().unwrap() > 0,
            "{name}"
        );
        let t = r["timings_s"].as_object().unwrap();
        let total = t["total"].as_f64().unwrap();
        let phases: f64 = t
            .iter()
            .filter(|(k, _)| *k != "total")
            .map(|(_, v)| v.as_f64().unwrap())
            .sum();
        assert!(
            total > 0.0 && phases <= total * 1.01 + 1e-6,
            "{name}: {t:?}"
        );
        let turn = &r["max_normal_turn_deg"];
        assert!(
            turn["angle"].as_f64().unwrap() < 90.0 && turn["fold"] == false,
            "{name}: {turn}"
        );
        assert!(
            r["notes"].is_array() && r["fairsurf_version"].is_string(),
            "{name}"
        );
        assert!(
            r.get("seconds").is_none(),
            "{name}: one name for the timings"
        );
    }
}

/// `solve --refine A,B` splits a B-spline scene's spans before solving:
/// more unknowns, a lower thin-plate minimum, the refined knots in the
/// result; other kinds and bad counts exit 2 before any work.
#[test]
fn solve_refine_splits_bspline_spans_and_elevate_raises_degrees() {
    let d = tmpdir("refine");
    let scene = examples().join("bspline_hole.json");
    let report = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["solve", scene.to_str().unwrap(), "--json"];
        args.extend(extra);
        let o = fairsurf(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let (coarse, fine) = (report(&[]), report(&["--refine", "2,3"]));
    assert_eq!(coarse["spans"], serde_json::json!([11, 11]));
    assert_eq!(fine["spans"], serde_json::json!([22, 33]));
    assert!(
        fine["energy"].as_f64() < coarse["energy"].as_f64(),
        "{fine}"
    );
    let out = d.join("r.json");
    let o = fairsurf(&[
        "solve",
        scene.to_str().unwrap(),
        "--refine",
        "2,2",
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(
        r["surface"]["knots"][0].as_array().unwrap().len(),
        22 + 3 + 4
    );
    assert!(r.get("refine").is_none());
    let tensor = examples().join("quickstart.json");
    let o = fairsurf(&["solve", tensor.to_str().unwrap(), "--refine", "2,2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o)
            .contains("--refine splits the knot spans of B-spline scenes; this one is tensor"),
        "{}",
        stderr(&o)
    );
    let o = fairsurf(&["solve", scene.to_str().unwrap(), "--refine", "0,2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("from 1 to 16"), "{}", stderr(&o));
    // --elevate raises the degrees first, then --refine splits: bicubic
    // over 11 spans elevated by one in u (14 + 11 points), then 2 parts per
    // span in v (22 spans, 25 points); two rings fixed on each side.
    let both = report(&["--elevate", "1,0", "--refine", "1,2"]);
    assert_eq!(both["spans"], serde_json::json!([11, 22]));
    assert_eq!(both["free_points"], serde_json::json!(21 * 21), "{both}");
    assert!(both["energy"].as_f64() < coarse["energy"].as_f64());
    let o = fairsurf(&["solve", tensor.to_str().unwrap(), "--elevate", "1,1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--elevate raises the degrees of B-spline scenes; this one is tensor"),
        "{}",
        stderr(&o)
    );
    let o = fairsurf(&["solve", scene.to_str().unwrap(), "--elevate", "1,15"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("from 0 to 14"), "{}", stderr(&o));
    let o = fairsurf(&["solve", scene.to_str().unwrap(), "--elevate", "0,13"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("refine.elevate[1]"), "{}", stderr(&o));
}

#[test]
fn eval_reads_a_result_and_refuses_an_unsolved_scene() {
    let d = tmpdir("eval");
    let out = d.join("r.json");
    let scene = examples().join("quickstart.json");
    assert!(fairsurf(&[
        "solve",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q"
    ])
    .status
    .success());
    let o = fairsurf(&[
        "eval",
        out.to_str().unwrap(),
        "--uv",
        "0,0",
        "--uv",
        "1,1",
        "--grid",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v.as_array().unwrap().len(), 2 + 9);
    assert_eq!(
        v[0]["point"],
        serde_json::json!([0.0, 0.0, 0.0]),
        "corner interpolated"
    );
    assert_eq!(v[1]["point"], serde_json::json!([3.0, 3.0, 0.0]));
    let n = v[0]["normal"].as_array().unwrap();
    let len: f64 = n.iter().map(|c| c.as_f64().unwrap().powi(2)).sum::<f64>();
    assert!((len - 1.0).abs() < 1e-12);
    let o = fairsurf(&["eval", scene.to_str().unwrap(), "--uv", "0.5,0.5"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("surface.control_points[1][1]: is null"),
        "{}",
        stderr(&o)
    );
    let o = fairsurf(&["eval", out.to_str().unwrap(), "--uv", "1.5,0"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn schema_is_json_and_help_is_everywhere() {
    let o = fairsurf(&["schema"]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["properties"]["surface"].is_object());
    for sub in [
        &["--help"][..],
        &["solve", "--help"],
        &["eval", "--help"],
        &["schema", "--help"],
    ] {
        let o = fairsurf(sub);
        assert!(o.status.success() && !o.stdout.is_empty(), "{sub:?}");
    }
    assert_eq!(
        fairsurf(&["solve"]).status.code(),
        Some(2),
        "missing argument"
    );
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn compare_prints_the_table_with_the_smallest_marked() {
    let scene = examples().join("monterde_ugail_model.json");
    let o = fairsurf(&["compare", scene.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t = stdout(&o);
    // Table 1: the biharmonic surface has the least area, the harmonic
    // extremal the least Dirichlet value, the biharmonic extremal the least
    // biharmonic value.
    let row = |label: &str| {
        t.lines()
            .find(|l| l.starts_with(label))
            .unwrap()
            .to_string()
    };
    assert!(row("area").contains("2.515078431*"), "{t}");
    assert!(row("harmonic ").contains("2.781167271*"), "{t}");
    assert!(row("biharmonic ").contains("20.46342698*"), "{t}");
    assert_eq!(row("area").matches('*').count(), 1);

    let o = fairsurf(&["compare", "--json", scene.to_str().unwrap()]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let a = v["biharmonic_surface"]["area"].as_f64().unwrap();
    assert!((a - 2.51508).abs() < 5e-6);
}

#[test]
fn compare_errors_exit_2_naming_the_field() {
    let d = tmpdir("compare");
    let f = d.join("bad.json");
    std::fs::write(
        &f,
        r#"{"surface": {"type": "tensor", "degree": [2, 2], "control_points": [
            [[0,0,0], null, [0,2,0]], [[1,0,0], null, [1,2,0]], [[2,0,0], [2,1,0], [2,2,0]]]}}"#,
    )
    .unwrap();
    let o = fairsurf(&["compare", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("surface.control_points[0][1]"), "{e}");
    assert_eq!(e.lines().count(), 1);
}

#[test]
fn solve_by_method_reports_the_construction() {
    let scene = examples().join("monterde_ugail_model_harmonic.json");
    let o = fairsurf(&["solve", scene.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t = stdout(&o);
    assert!(t.contains("harmonic surface"), "{t}");
    assert!(t.contains("Bernstein coefficients of Δx"), "{t}");
    assert!(t.contains("|H| min"), "{t}");
    let o = fairsurf(&["solve", "--json", scene.to_str().unwrap()]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["method"], "harmonic");
    assert_eq!(v["exact"], true);
    assert!(v["residual"].as_f64().unwrap() < 1e-12);
    assert!(v["abs_mean_curvature"]["mean"].as_f64().unwrap() > 0.0);

    // No biharmonic surface of degree 4×6 for a generic boundary: exit 2.
    let d = tmpdir("method");
    let f = d.join("b46.json");
    let rows: Vec<String> = (0..=4)
        .map(|i| {
            let p: Vec<String> = (0..=6)
                .map(|j| format!("[{i}, {j}, {}]", ((i * 3 + j * 5) % 7) as f64 * 0.1))
                .collect();
            format!("[{}]", p.join(","))
        })
        .collect();
    std::fs::write(
        &f,
        format!(
            r#"{{"surface": {{"type": "tensor", "degree": [4, 6], "control_points": [{}]}}, "method": "biharmonic"}}"#,
            rows.join(",")
        ),
    )
    .unwrap();
    let o = fairsurf(&[
        "solve",
        f.to_str().unwrap(),
        "-o",
        d.join("r.json").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("no biharmonic Bézier surface"),
        "{}",
        stderr(&o)
    );
    assert!(!d.join("r.json").exists(), "no output on failure");
}

fn png_size(path: &Path) -> (u32, u32) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()))
        .read_info()
        .unwrap();
    (dec.info().width, dec.info().height)
}

/// `--normals` on B-spline scenes: the guide field's arrows are drawn (the
/// picture differs from the one without), for a solved scene with a field,
/// a sampled one, and the result file of the first (its field built from
/// the scene without solving).
#[test]
fn render_draws_bspline_normal_fields() {
    let d = tmpdir("render-bspline-normals");
    let png = |scene: &std::path::Path, name: &str, normals: bool| {
        let out = d.join(name);
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "240x180",
        ];
        if normals {
            args.push("--normals");
        }
        let o = fairsurf(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(&out).unwrap()
    };
    let field = examples().join("bspline_hole_guided.json");
    let sampled = examples().join("bspline_hole_sampled.json");
    let result = d.join("guided.result.json");
    let s = fairsurf(&[
        "solve",
        field.to_str().unwrap(),
        "-o",
        result.to_str().unwrap(),
    ]);
    assert!(s.status.success(), "{}", stderr(&s));
    for (k, scene) in [field, sampled, result].iter().enumerate() {
        let plain = png(scene, &format!("{k}-plain.png"), false);
        // Rendering is deterministic, so a difference is the arrows.
        assert_eq!(plain, png(scene, &format!("{k}-again.png"), false));
        let arrows = png(scene, &format!("{k}-arrows.png"), true);
        assert_ne!(plain, arrows, "{}: no arrows drawn", scene.display());
    }
}

#[test]
fn render_draws_scenes_results_and_comparisons() {
    let d = tmpdir("render");
    let scene = examples().join("wu_yang_fig4_l500.json");
    let out = d.join("pics/a.png");
    let o = fairsurf(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "320x240",
        "--net",
        "--normals",
        "--zebra",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(png_size(&out), (320, 240));
    assert!(stdout(&o).contains("covers"), "{}", stdout(&o));
    // A result file is drawn as it is, beside its scene.
    let result = d.join("r.json");
    let s = fairsurf(&[
        "solve",
        scene.to_str().unwrap(),
        "-o",
        result.to_str().unwrap(),
    ]);
    assert!(s.status.success());
    let two = d.join("two.png");
    let o = fairsurf(&[
        "render",
        scene.to_str().unwrap(),
        result.to_str().unwrap(),
        "-o",
        two.to_str().unwrap(),
        "--size",
        "400x200",
        "--colour",
        "mean",
        "--view",
        "-30,40",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let lines: Vec<String> = stdout(&o).lines().map(str::to_owned).collect();
    assert_eq!(lines.len(), 3, "{lines:?}");
    // The solved scene and its result file are the same surface: same range.
    let range = |l: &str| l.split_once(" in ").unwrap().1.to_owned();
    assert_eq!(range(&lines[1]), range(&lines[2]));
    let cmp = d.join("cmp.png");
    let model = examples().join("monterde_ugail_model.json");
    let o = fairsurf(&[
        "render",
        "--compare",
        model.to_str().unwrap(),
        "-o",
        cmp.to_str().unwrap(),
        "--range",
        "0,1",
        "--size",
        "640x200",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("biharmonic extremal"));
    assert_eq!(png_size(&cmp), (640, 200));
}

#[test]
fn render_errors_exit_2_and_write_nothing() {
    let d = tmpdir("render-bad");
    let scene = examples().join("quickstart.json");
    let out = d.join("x.png");
    for (args, needle) in [
        (vec!["--range", "1,0"], "range"),
        (vec!["--view", "sideways"], "view"),
        (vec!["--colour", "hue"], "colour"),
        (vec!["--size", "10x10"], "width"),
        (vec!["--size", "big"], "--size"),
        (vec!["--zebra", "0"], "zebra"),
    ] {
        let mut all = vec![
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        all.extend(args);
        let o = fairsurf(&all);
        assert_eq!(o.status.code(), Some(2), "{all:?}");
        assert!(stderr(&o).contains(needle), "{all:?}: {}", stderr(&o));
        assert!(!out.exists());
    }
    let o = fairsurf(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        d.join("x.jpg").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains(".png"));
    let o = fairsurf(&[
        "render",
        "--compare",
        scene.to_str().unwrap(),
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let bad = d.join("bad.json");
    std::fs::write(&bad, r#"{"surface": {"degree": [2, 2]}}"#).unwrap();
    let o = fairsurf(&["render", bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bad.json"), "{}", stderr(&o));
    assert!(!out.exists());
}

#[test]
fn export_writes_cad_and_meshes_and_refuses_unknown_formats() {
    let d = tmpdir("export");
    let scene = examples().join("monterde_ugail_model.json");
    let s = scene.to_str().unwrap();
    let out = |name: &str| d.join(name).to_str().unwrap().to_owned();
    let o = fairsurf(&["export", s, "-o", &out("m.step")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let step = std::fs::read_to_string(d.join("m.step")).unwrap();
    assert!(step.starts_with("ISO-10303-21;"));
    assert_eq!(step.matches("B_SPLINE_SURFACE_WITH_KNOTS").count(), 1);
    assert!(step.contains("B_SPLINE_SURFACE_WITH_KNOTS('',5,5,"));
    let o = fairsurf(&["export", s, "-o", &out("m.iges")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let iges = std::fs::read_to_string(d.join("m.iges")).unwrap();
    assert!(iges.lines().all(|l| l.len() == 80));
    assert!(iges.lines().any(|l| l.starts_with("     128")));
    let o = fairsurf(&[
        "export",
        s,
        "-o",
        &out("m.glb"),
        "--resolution",
        "4",
        "--colour-range",
        "0,1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("25 vertices, 32 triangles"),
        "{}",
        stdout(&o)
    );
    assert_eq!(&std::fs::read(d.join("m.glb")).unwrap()[..4], b"glTF");
    for (args, needle) in [
        (vec!["-o", out("m.dwg").as_str()], "cannot tell the format"),
        (
            vec!["-o", out("m.glb").as_str(), "--colour-range", "1,0"],
            "--colour-range",
        ),
    ] {
        let mut all = vec!["export", s];
        all.extend(args.iter().copied());
        let o = fairsurf(&all);
        assert_eq!(o.status.code(), Some(2), "{all:?}");
        assert!(stderr(&o).contains(needle), "{}", stderr(&o));
    }
    assert!(!d.join("m.dwg").exists());
}

#[test]
fn triangular_scenes_solve_write_results_that_solve_again_and_export() {
    let d = tmpdir("triangular");
    for name in ["vw_hexagon_hole", "vw_fig1_point_normal", "vw_fig2_curve"] {
        let scene = examples().join(format!("{name}.json"));
        let result = d.join(format!("{name}.result.json"));
        let mesh = d.join(format!("{name}.ply"));
        let o = fairsurf(&[
            "solve",
            scene.to_str().unwrap(),
            "-o",
            result.to_str().unwrap(),
            "--mesh",
            mesh.to_str().unwrap(),
            "--json",
        ]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert!(
            report["max_violation"].as_f64().unwrap() <= 1e-10,
            "{name}: {report}"
        );
        assert!(report["residual"].as_f64().unwrap() < 1e-12);
        assert!(std::fs::metadata(&mesh).unwrap().len() > 1000);
        // The result file solves to the same surface.
        let first: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&result).unwrap()).unwrap();
        let again = d.join(format!("{name}.again.json"));
        let o = fairsurf(&[
            "solve",
            result.to_str().unwrap(),
            "-o",
            again.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let second: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&again).unwrap()).unwrap();
        let pts = |v: &serde_json::Value| -> Vec<f64> {
            v["surface"]["control_points"]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|p| p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
                .collect()
        };
        let (a, b) = (pts(&first), pts(&second));
        assert_eq!(a.len(), b.len());
        let worst = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(
            worst < 1e-12,
            "{name}: re-solving moved a point by {worst:e}"
        );
    }
    // The hexagon: exact G1 inside, reported.
    let o = fairsurf(&[
        "solve",
        examples().join("vw_hexagon_hole.json").to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let angle: f64 = text
        .split("interior edges ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!(angle <= 1e-8, "{text}");
    // STEP of a triangular surface: one face per patch.
    let step = d.join("hex.step");
    let o = fairsurf(&[
        "export",
        d.join("vw_hexagon_hole.result.json").to_str().unwrap(),
        "-o",
        step.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&step).unwrap();
    assert_eq!(text.matches("ADVANCED_FACE").count(), 6);
}

#[test]
fn bad_triangular_scenes_exit_2_naming_the_field() {
    let d = tmpdir("triangular-bad");
    let base: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(examples().join("vw_fig1_point_normal.json")).unwrap(),
    )
    .unwrap();
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "degree",
            Box::new(|v| v["surface"]["degree"] = "x".into()),
            "surface.degree",
        ),
        (
            "zero degree",
            Box::new(|v| v["surface"]["degree"] = 0.into()),
            "surface.degree",
        ),
        (
            "triangle",
            Box::new(|v| v["surface"]["triangles"][3] = serde_json::json!([0, 0, 1])),
            "surface",
        ),
        (
            "target",
            Box::new(|v| {
                v["constraints"][0]
                    .as_object_mut()
                    .unwrap()
                    .remove("target")
                    .map(|_| ())
                    .unwrap()
            }),
            "constraints[0].target",
        ),
        (
            "kind",
            Box::new(|v| v["constraints"][1]["type"] = "magnet".into()),
            "constraints[1].type",
        ),
        (
            "operator field",
            Box::new(
                |v| v["operators"] = serde_json::json!([{"type": "director", "at": {"triangle": 0, "bary": [0.2, 0.3, 0.5]}}]),
            ),
            "operators[0].direction",
        ),
        (
            "operator place",
            Box::new(|v| {
                v["operators"] =
                    serde_json::json!([{"type": "point_attractor", "point": [0, 0, 1]}])
            }),
            "operators[0]",
        ),
        (
            "operator kind",
            Box::new(|v| v["operators"] = serde_json::json!([{"type": "magnet"}])),
            "operators[0].type",
        ),
        (
            "operator region",
            Box::new(|v| {
                v["operators"] = serde_json::json!([{"type": "point_attractor", "point": [0, 0, 1],
                    "region": [{"triangle": 0, "polygon": [[0.1, 0.1], [0.2, 0.2]]}]}])
            }),
            "operators[0] (point_attractor): region[0]",
        ),
        (
            "outside",
            Box::new(|v| v["constraints"][0]["at"]["bary"] = serde_json::json!([0.9, 0.9, -0.8])),
            "constraints[0].at: pull (triangle 18)",
        ),
        (
            "zero normal",
            Box::new(|v| v["constraints"][1]["normal"] = serde_json::json!([0, 0, 0])),
            "tilt",
        ),
        (
            "weight",
            Box::new(|v| v["energy"]["bend"] = serde_json::json!(-1.0)),
            "energy.bend",
        ),
        (
            "unknown",
            Box::new(|v| v["continuity"]["edge"] = "exact".into()),
            "continuity",
        ),
    ];
    for (what, change, field) in cases {
        let mut v = base.clone();
        change(&mut v);
        let path = d.join("bad.json");
        std::fs::write(&path, serde_json::to_string(&v).unwrap()).unwrap();
        let out = d.join("never.json");
        let o = fairsurf(&["solve", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{what}: {}", stderr(&o));
        assert!(stderr(&o).contains(field), "{what}: {}", stderr(&o));
        assert!(!out.exists(), "{what}: wrote a result");
    }
    let o = fairsurf(&["schema", "--triangular"]);
    let schema: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(schema.to_string().contains("triangular"));
}

/// `analyse` measures result files as they are: the tensor measures are the
/// ones the solve reported for the same surface; a file with a free point
/// exits 2 naming it.
#[test]
fn analyse_measures_result_files() {
    let d = tmpdir("analyse");
    let tensor = d.join("t.result.json");
    let tri = d.join("tri.result.json");
    for (scene, out) in [
        ("wu_yang_fig1_l10_g0.json", &tensor),
        ("vw_fig1_point_normal.json", &tri),
    ] {
        let o = fairsurf(&[
            "solve",
            examples().join(scene).to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let o = fairsurf(&[
        "analyse",
        "--json",
        tensor.to_str().unwrap(),
        tri.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&tensor).unwrap()).unwrap();
    let reported = &result["report"];
    let m = &v[0]["measures"];
    assert_eq!(v[0]["kind"], "tensor");
    for (label, key) in [
        ("area", "area"),
        ("Dirichlet", "dirichlet"),
        ("biharmonic", "biharmonic"),
    ] {
        let (a, b) = (m[label].as_f64().unwrap(), reported[key].as_f64().unwrap());
        assert!(
            (a - b).abs() <= 1e-12 * b.abs(),
            "{label}: {a} vs {b} in {reported}"
        );
    }
    assert_eq!(v[1]["kind"], "triangular");
    assert!(
        v[1]["measures"]["max normal angle across edges (rad)"]
            .as_f64()
            .unwrap()
            < 1e-12
    );

    // Text output names each file.
    let o = fairsurf(&["analyse", tensor.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("t.result.json: tensor") && text.contains("area error estimate"),
        "{text}"
    );

    // The scene before solving has free (null) points.
    let o = fairsurf(&[
        "analyse",
        examples().join("quickstart.json").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("surface.control_points["),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 17's silent non-solutions, each now an exit 2 that names the JSON
/// path or says what was reached, with no output file: trailing data after
/// the scene, a coordinate whose energy overflows, a NaN inside a
/// triangular scene (it was reported as an unknown surface type), and a
/// degree-34 flat square whose net double precision cannot hold (its
/// reported energy was −14.7).
#[test]
fn silent_non_solutions_are_refused() {
    let d = tmpdir("refused");
    let quick: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(examples().join("quickstart.json")).unwrap())
            .unwrap();
    let mut huge = quick.clone();
    huge["surface"]["control_points"][0][0] = serde_json::json!([1e154, 0, 0]);
    let tri = std::fs::read_to_string(examples().join("vw_fig1_point_normal.json")).unwrap();
    let at = tri.find("\"vertices\"").unwrap();
    let first = at + tri[at..].find("[").unwrap() + 1;
    let first = first + tri[first..].find('[').unwrap() + 1;
    let rest = &tri[first..];
    let tri_nan = format!(
        "{}NaN,{}",
        &tri[..first],
        &rest[rest.find(',').unwrap() + 1..]
    );
    let n = 34;
    let net = flat_square_net(n);
    let flat = serde_json::json!({"surface": {"type": "tensor", "degree": [n, n], "control_points": net}, "energy": {"stretch": 1.0}});
    for (name, text, expected) in [
        (
            "trailing",
            format!("{quick}\n{{\"x\": 1}}\n"),
            "a file holds one scene",
        ),
        (
            "huge",
            huge.to_string(),
            "surface.control_points[0][0][0]: 1e154 is too large",
        ),
        ("tri_nan", tri_nan, "surface.vertices[0][0]: expected value"),
        (
            "flat34",
            flat.to_string(),
            "cannot be verified in double precision",
        ),
    ] {
        let scene = d.join(format!("{name}.json"));
        std::fs::write(&scene, text).unwrap();
        let out = d.join(format!("{name}.result.json"));
        let o = fairsurf(&[
            "solve",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(expected), "{name}: {}", stderr(&o));
        assert!(!out.exists(), "{name}");
    }
}

/// A solve killed while it writes leaves the old result and mesh (a pair)
/// and no temporary file; SIGINT and SIGTERM alike.
#[cfg(unix)]
#[test]
fn an_interrupted_solve_leaves_the_old_pair_and_no_temporaries() {
    let d = tmpdir("interrupt");
    let scene = examples().join("quickstart.json");
    let (out, mesh) = (d.join("r.json"), d.join("m.obj"));
    std::fs::write(&out, "old result").unwrap();
    std::fs::write(&mesh, "old mesh").unwrap();
    for signal in ["-INT", "-TERM"] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_fairsurf"))
            .args([
                "solve",
                scene.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args(["--mesh", mesh.to_str().unwrap(), "--resolution", "1000"])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        // Wait until a temporary exists: the writes have begun.
        let start = std::time::Instant::now();
        let temporaries = || {
            std::fs::read_dir(&d)
                .unwrap()
                .filter(|e| {
                    e.as_ref()
                        .unwrap()
                        .file_name()
                        .to_string_lossy()
                        .ends_with(".tmp")
                })
                .count()
        };
        while temporaries() == 0 {
            assert!(start.elapsed().as_secs() < 60, "no temporary appeared");
            assert!(
                child.try_wait().unwrap().is_none(),
                "finished before it could be interrupted"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        let status = Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        let code = child.wait().unwrap();
        assert!(!code.success(), "{signal}: {code:?}");
        assert_eq!(temporaries(), 0, "{signal}: temporaries left");
        assert_eq!(
            std::fs::read_to_string(&out).unwrap(),
            "old result",
            "{signal}"
        );
        assert_eq!(
            std::fs::read_to_string(&mesh).unwrap(),
            "old mesh",
            "{signal}"
        );
    }
}

/// Two scenes with the same file name would write the same result in the
/// output directory: refused before anything is solved.
#[test]
fn colliding_result_names_are_refused() {
    let d = tmpdir("collide");
    std::fs::create_dir_all(d.join("b")).unwrap();
    let scene = std::fs::read_to_string(examples().join("quickstart.json")).unwrap();
    std::fs::write(d.join("a.json"), &scene).unwrap();
    std::fs::write(d.join("b/a.json"), &scene).unwrap();
    let out = d.join("out");
    let o = fairsurf(&[
        "solve",
        d.join("a.json").to_str().unwrap(),
        d.join("b/a.json").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("would both write"), "{}", stderr(&o));
    assert!(!out.join("a.result.json").exists());
}

/// Files are read with a size cap: /dev/zero is refused, not read until
/// memory runs out.
#[cfg(unix)]
#[test]
fn endless_input_is_refused() {
    let o = fairsurf(&["solve", "/dev/zero"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("larger than 256 MB"), "{}", stderr(&o));
}

/// Mutated example scenes through the command (issue 17): exit 0 or 2 only,
/// never a crash; on 2 no output file; on 0 the result file exists and a
/// minimized result (tensor or triangular) carries its passed check.
#[test]
fn mutated_scenes_exit_0_or_2_and_write_only_on_success() {
    let d = tmpdir("fuzz");
    let seeds = mutate::small_examples();
    let mut rng = mutate::Rng(0xD1B5_4A32_D192_ED03);
    let (mut ok, mut refused) = (0, 0);
    for round in 0..150 {
        let (name, seed) = &seeds[round % seeds.len()];
        let mut v = seed.clone();
        mutate::mutate(&mut v, &mut rng);
        if !mutate::small(&v) {
            continue;
        }
        let scene = d.join(format!("s{round}.json"));
        let out = d.join(format!("s{round}.result.json"));
        std::fs::write(&scene, v.to_string()).unwrap();
        let o = fairsurf(&[
            "solve",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ]);
        match o.status.code() {
            Some(0) => {
                ok += 1;
                let r: serde_json::Value =
                    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
                let minimized = match r["surface"]["type"].as_str() {
                    Some("tensor") => r["report"].get("method").is_none(),
                    _ => r["report"]["unknowns"].as_u64() > Some(0),
                };
                let c = &r["report"]["check"];
                if r["surface"]["type"] == "bspline" {
                    // Its check compares two roads to the energy.
                    let e = c["energy_error"].as_f64().unwrap();
                    assert!(e <= 1e-10, "round {round} ({name}): {c}");
                } else if minimized {
                    assert!(
                        c["excess"].as_f64().unwrap() <= 1e-10,
                        "round {round} ({name}): {c}"
                    );
                }
            }
            Some(2) => {
                refused += 1;
                assert!(
                    !out.exists(),
                    "round {round} ({name}): an output after an error"
                );
                assert!(stderr(&o).starts_with("error: "), "{}", stderr(&o));
            }
            other => panic!(
                "round {round} ({name}): exit {other:?}: {}\n{v}",
                stderr(&o)
            ),
        }
    }
    assert!(ok > 10 && refused > 10, "{ok} solved, {refused} refused");
}

/// Memory is estimated before the work: over `--max-memory-gb` the solve is
/// refused at once with the estimate, for tensor and triangular scenes.
#[test]
fn work_over_the_memory_limit_is_refused_with_the_estimate() {
    let d = tmpdir("memory");
    let n = 40;
    let net = flat_square_net(n);
    let field = serde_json::json!({"degree": [0, 0], "control_points": [[[0, 0, 1]]]});
    let scene = serde_json::json!({"surface": {"type": "tensor", "degree": [n, n], "control_points": net},
        "energy": {"stretch": 1, "normal_field": field}});
    let path = d.join("e1.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let t = std::time::Instant::now();
    let o = fairsurf(&["solve", path.to_str().unwrap(), "--max-memory-gb", "0.5"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("would need about 1.22 GB, more than the limit of 0.50 GB"),
        "{}",
        stderr(&o)
    );
    assert!(t.elapsed().as_secs_f64() < 2.0);
    // 200 degree-20 triangles: about 2 GB (measured 2.0-2.3 GB before).
    let k = 10;
    let vertices: Vec<[f64; 3]> = (0..=k)
        .flat_map(|i| (0..=k).map(move |j| [i as f64, j as f64, 0.0]))
        .collect();
    let mut triangles = Vec::new();
    for i in 0..k {
        for j in 0..k {
            let a = i * (k + 1) + j;
            triangles.push([a, a + k + 1, a + k + 2]);
            triangles.push([a, a + k + 2, a + 1]);
        }
    }
    let tri = serde_json::json!({"surface": {"type": "triangular", "degree": 20,
        "vertices": vertices, "triangles": triangles}, "fix_boundary": true});
    let path = d.join("tri.json");
    std::fs::write(&path, tri.to_string()).unwrap();
    let o = fairsurf(&["solve", path.to_str().unwrap(), "--max-memory-gb", "1"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("200 degree-20 patches would need about 2.05 GB"),
        "{}",
        stderr(&o)
    );
}

/// `fill` on the bundled network: the hole (not the rim) is filled, the
/// report says G1 to rounding, and the STEP file holds the 8 faces and the
/// fill sewn — 9 faces whose 24 edges are shared (12 rim edges stay free).
#[test]
fn fill_fills_the_hole_and_writes_a_sewn_shell() {
    let d = tmpdir("fill");
    let scene = examples().join("cad/fill_network.json");
    let out = d.join("sub/filled.step");
    let png = d.join("sub/filled.png");
    let o = fairsurf(&[
        "fill",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--render",
        png.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(report["faces"], 8);
    let fill = &report["fills"][0];
    assert_eq!(fill["hole"], 1);
    assert_eq!(report["holes"][0]["rim"], true);
    assert!(fill["max_angle_deg"].as_f64().unwrap() < 1e-9, "{fill}");
    assert!(fill["max_gap"].as_f64().unwrap() < 1e-12, "{fill}");
    assert!(fill["solve"]["check"]["energy_error"].as_f64().unwrap() < 1e-10);
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.matches("=ADVANCED_FACE(").count(), 9);
    // 3 × 3 faces of a sheet: 12 interior edges + 12 on the rim.
    assert_eq!(text.matches("=EDGE_CURVE(").count(), 24);
    assert_eq!(text.matches("=VERTEX_POINT(").count(), 16);
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);
    // The summary names the rim and the figures.
    let o = fairsurf(&["fill", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(
        s.contains("filled [1] (hole 0, taken as the outer rim)"),
        "{s}"
    );
    assert!(s.contains("largest normal angle"), "{s}");
    // A hole asked twice is filled once.
    let o = fairsurf(&[
        "fill",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--hole",
        "1",
        "--hole",
        "1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.matches("=ADVANCED_FACE(").count(), 9);
    let o = fairsurf(&["fill", scene.to_str().unwrap(), "--list"]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(s.contains("hole 1: 4 sides"), "{s}");
    assert!(s.contains("hole 0: 12 sides"), "{s}");
}

/// `fill` on the pentagonal hole: a fan of five triangular patches, G1 to
/// the neighbours to rounding and to each other as measured, written as
/// five collapsed tensor patches sewn to the faces (5 + 5 faces; edges: 5
/// rim, 5 radial, 5 hole sides, 5 spokes).
#[test]
fn fill_fills_a_pentagonal_hole_with_a_fan() {
    let d = tmpdir("fill-fan");
    let out = d.join("fan.step");
    let scene = examples().join("cad/fill_pentagon.json");
    let mesh = d.join("fan.ply");
    let o = fairsurf(&[
        "fill",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--json",
        "--mesh",
        mesh.to_str().unwrap(),
        "--resolution",
        "8",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The mesh: five bicubic faces at 9 × 9 vertices, the fan's five
    // triangles at 45 each.
    let ply = std::fs::read(&mesh).unwrap();
    let head = String::from_utf8_lossy(&ply[..200]);
    assert!(head.contains("element vertex 630"), "{head}");
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let fill = &r["fills"][0];
    assert_eq!(fill["kind"], "fan");
    assert_eq!(fill["patches"], 5);
    assert!(fill["max_angle_deg"].as_f64().unwrap() < 1e-9, "{fill}");
    assert!(fill["max_gap"].as_f64().unwrap() < 1e-12, "{fill}");
    assert!(fill["inner_angle_deg"].as_f64().unwrap() < 1e-8, "{fill}");
    assert_eq!(fill["solve"]["dropped_continuity"], serde_json::json!([]));
    assert!(fill["solve"]["check"]["energy_error"].as_f64().unwrap() < 1e-10);
    // The descent on W: the thin plate's W first, the last (lower) the W
    // reported.
    let history: Vec<f64> = fill["willmore_w"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_f64().unwrap())
        .collect();
    assert!(
        history.len() > 2 && history[history.len() - 1] < history[0],
        "{history:?}"
    );
    let w = fill["curvature_w"].as_f64().unwrap();
    assert!((history[history.len() - 1] - w).abs() <= 1e-12 * w);
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.matches("=ADVANCED_FACE(").count(), 10);
    assert_eq!(text.matches("=EDGE_CURVE(").count(), 20);
    let o = fairsurf(&["fill", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(
        s.contains("5 triangular patches of degree 7 around a centre"),
        "{s}"
    );
    let steps = history.len() - 1;
    assert!(
        s.contains(&format!("W-lowering steps kept: {steps}")),
        "{s}"
    );
    assert!(!s.contains("W still falling"), "{s}");
    // A budget of 2 steps (the descent took more) runs out, and says so.
    assert!(steps > 2, "{history:?}");
    let o = fairsurf(&[
        "fill",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--descent-steps",
        "2",
    ]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(s.contains("W-lowering steps kept: 2"), "{s}");
    let gain = (history[1] - history[2]) / history[2];
    assert!(
        s.contains(&format!(
            "W still falling when the descent's 2 steps ran out (the last lowered it by \
             {gain:.1e} of itself; from {:.6} at the thin plate)",
            history[0]
        )),
        "{s}"
    );
}

/// A fill measured beyond the tolerances is flagged, not passed off: the
/// lens with one face's hole edge bent near a corner (its control point
/// next to the corner lifted by 0.02; the faces still share their edges)
/// is filled, but 1.8° from the bent face along the two pieces next to
/// that corner. The summary says so and names the corner disagreement; the
/// JSON lists those sides; the output is written whole and the exit status
/// is 3 with a warning naming the hole and sides (a script must not take it
/// for a fill within the tolerances); a looser --angle-tolerance accepts
/// it (exit 0). The exact lens flags nothing.
#[test]
fn fill_flags_sides_beyond_the_tolerances() {
    let d = tmpdir("fill-beyond");
    let lens = examples().join("cad/fill_lens.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&lens).unwrap()).unwrap();
    let z = &mut v["faces"][0]["control_points"][3][4][2];
    *z = serde_json::json!(z.as_f64().unwrap() + 0.02);
    let bent = d.join("bent.json");
    std::fs::write(&bent, v.to_string()).unwrap();
    let out = d.join("bent.step");
    let run = |scene: &Path, json: bool| {
        let _ = std::fs::remove_file(&out);
        let mut args = vec!["fill", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
        if json {
            args.push("--json");
        }
        let o = fairsurf(&args);
        let beyond = scene == bent.as_path();
        assert_eq!(
            o.status.code(),
            Some(if beyond { 3 } else { 0 }),
            "{}",
            stderr(&o)
        );
        assert!(out.exists(), "the output is written");
        if beyond {
            assert_eq!(
                stderr(&o).trim(),
                "warning: written, but the fill is beyond the tolerances (gap 1e-6, angle \
                 1e-2°): hole 1 along sides (as cut for the fan) [1, 2] (--tolerance and --angle-tolerance set them)"
            );
        }
        o
    };
    let s = String::from_utf8_lossy(&run(&bent, false).stdout).into_owned();
    assert!(
        s.contains(
            "beyond the tolerances (gap 1e-6, angle 1e-2°) along sides (as cut for the fan) \
             [1, 2]: not G1 to the neighbours there to the tolerance (the sides disagree at a \
             corner, above)"
        ),
        "{s}"
    );
    let r: serde_json::Value = serde_json::from_slice(&run(&bent, true).stdout).unwrap();
    let fill = &r["fills"][0];
    assert_eq!(fill["sides_beyond_tolerances"], serde_json::json!([1, 2]));
    let worst = fill["max_angle_deg"].as_f64().unwrap();
    assert!(worst > 1.0 && worst < 3.0, "{worst}");
    let angle = r["tolerances"]["angle_deg"].as_f64().unwrap();
    assert!((angle - 0.01).abs() < 1e-15, "{angle}");
    let loose = format!("{}", 1.01 * worst);
    let o = fairsurf(&[
        "fill",
        bent.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--angle-tolerance",
        &loose,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = String::from_utf8_lossy(&run(&lens, false).stdout).into_owned();
    assert!(!s.contains("beyond the tolerances"), "{s}");
    let r: serde_json::Value = serde_json::from_slice(&run(&lens, true).stdout).unwrap();
    assert_eq!(
        r["fills"][0]["sides_beyond_tolerances"],
        serde_json::json!([])
    );
}

/// The corners of the rounded box: every one filled (a closed shell has no
/// rim), the stand-ins made one span along the corners; a tolerance one
/// span of degree 15 cannot reach is refused, naming the face and how far
/// it got, exit 2, nothing written.
#[test]
fn fill_fills_the_corners_of_a_rounded_box_or_says_why_not() {
    let d = tmpdir("fill-box");
    let out = d.join("box.step");
    let input = examples().join("cad/rounded_box.step");
    let o = fairsurf(&["fill", input.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(s.contains("filled [0, 1, 2, 3, 4, 5, 6, 7]\n"), "{s}");
    assert_eq!(
        s.matches("3 triangular patches of degree 12").count(),
        8,
        "{s}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.matches("=ADVANCED_FACE(").count(), 18 + 24);
    std::fs::remove_file(&out).unwrap();
    let e = exits_2(
        "fill",
        &out,
        &[
            input.to_str().unwrap(),
            "--tolerance",
            "1e-11",
            "--angle-tolerance",
            "1e-8",
        ],
    );
    assert!(e.contains("face 1: a cylinder:"), "{e}");
    assert!(e.contains("with one span of degree 15"), "{e}");
}

/// Runs `fairsurf <command> <args> -o <out>`, which must exit 2 and leave
/// no `out`; its standard error.
fn exits_2(command: &str, out: &std::path::Path, args: &[&str]) -> String {
    let mut all = vec![command];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", out.to_str().unwrap()]);
    let o = fairsurf(&all);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
    assert!(!out.exists());
    stderr(&o)
}

/// `v` written as `name` in `d`.
fn write_json(d: &std::path::Path, name: &str, v: &serde_json::Value) -> std::path::PathBuf {
    let p = d.join(name);
    std::fs::write(&p, v.to_string()).unwrap();
    p
}

/// Bad fill requests exit 2, say why, and write nothing.
#[test]
fn bad_fills_exit_2_and_write_nothing() {
    let d = tmpdir("fill-bad");
    let scene = examples().join("cad/fill_network.json");
    let out = d.join("x.step");
    let run = |args: &[&str]| exits_2("fill", &out, args);
    let s = scene.to_str().unwrap();
    assert!(
        run(&[s, "--hole", "7"]).contains("--hole: there is no hole 7: the faces have 2 (0 to 1)")
    );
    // The rim: 12 edges, 4 corners, the faces outside it.
    assert!(run(&[s, "--hole", "0"]).contains("hole 0: at the corner where side 0 starts"));
    assert!(run(&[s, "--lambda=-1"]).contains("--lambda: expected a number ≥ 0, got -1"));
    assert!(
        run(&[s, "--tolerance", "0"]).contains("--tolerance: expected a positive number, got 0")
    );
    assert!(run(&[s, "--angle-tolerance=-1"])
        .contains("--angle-tolerance: expected a positive number, got -1"));
    // A tolerance the stand-ins cannot reach (in double precision) is refused.
    let fillet = examples().join("cad/fillet_hole.step");
    assert!(run(&[fillet.to_str().unwrap(), "--tolerance", "1e-30"])
        .contains("could not be approximated by a polynomial one within 1e-30"));
    // A plane whose axis overflows (found by tests/suite/fill_fuzz.rs):
    // truck-geometry panics inside the reader; the error names the face and
    // what the panic said, and no panic message is printed.
    let step = std::fs::read_to_string(&fillet).unwrap();
    let axis = "#292 = DIRECTION('',(0.,0.,1.));";
    assert!(step.contains(axis));
    let broken = d.join("broken_plane.step");
    std::fs::write(
        &broken,
        step.replace(axis, "#292 = DIRECTION('',(0.,1.E300,1.));"),
    )
    .unwrap();
    let e = run(&[broken.to_str().unwrap()]);
    assert!(
        e.contains("face 5: the face's geometry could not be evaluated: called `Option::unwrap()`")
            && e.contains("truck-geometry"),
        "{e}"
    );
    assert!(!e.contains("panicked"), "{e}");
    let text: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    let write = |name: &str, v: &serde_json::Value| write_json(&d, name, v);
    let mut bad = text.clone();
    bad["faces"][3]["control_points"][2] = serde_json::json!([[0, 0, 0]]);
    let p = write("bad_net.json", &bad);
    assert!(run(&[p.to_str().unwrap()]).contains("faces[3].control_points[2]"));
    let mut bad = text.clone();
    bad["faces"][0]["knots"] = serde_json::json!([[0, 1], [0, 1]]);
    let p = write("tensor_knots.json", &bad);
    assert!(
        run(&[p.to_str().unwrap()]).contains("faces[0].knots: a tensor (Bézier) face has no knots")
    );
    let mut bad = text.clone();
    bad["fill"] = serde_json::json!({"elevate": 11});
    let p = write("elevate.json", &bad);
    assert!(run(&[p.to_str().unwrap()]).contains("fill.elevate: expected 0 to 10, got 11"));
    let mut bad = text.clone();
    bad["fill"] = serde_json::json!({"descent_steps": 10001});
    let p = write("descent.json", &bad);
    assert!(
        run(&[p.to_str().unwrap()]).contains("fill.descent_steps: expected 0 to 10000, got 10001")
    );
    let mut bad = text.clone();
    bad["fill"] = serde_json::json!({"bend": 0});
    let p = write("no_energy.json", &bad);
    assert!(run(&[p.to_str().unwrap()]).contains("stretch and bend are both 0"));
    // A closed cube of six bilinear faces has no free edge.
    let corners = |f: &dyn Fn(f64, f64) -> [f64; 3]| {
        serde_json::json!({"type": "tensor", "degree": [1, 1], "control_points":
            [[f(0.0, 0.0), f(0.0, 1.0)], [f(1.0, 0.0), f(1.0, 1.0)]]})
    };
    let cube = serde_json::json!({"faces": [
        corners(&|a, b| [a, b, 0.0]), corners(&|a, b| [a, b, 1.0]),
        corners(&|a, b| [a, 0.0, b]), corners(&|a, b| [a, 1.0, b]),
        corners(&|a, b| [0.0, a, b]), corners(&|a, b| [1.0, a, b]),
    ]});
    let p = write("cube.json", &cube);
    assert!(run(&[p.to_str().unwrap()]).contains("there is no hole: every face boundary is shared"));
    // One face alone: its rim is the only loop, which bounds the face
    // from outside: nothing to fill by default; asked for, the face's
    // cross derivatives point away from it: no G1 fill.
    let lone = serde_json::json!({"faces": [corners(&|a, b| [a, b, 0.0])]});
    let p = write("lone.json", &lone);
    let e = run(&[p.to_str().unwrap()]);
    assert!(
        e.contains("no hole to fill: every free loop is taken for an outer rim (hole 0:"),
        "{e}"
    );
    assert!(run(&[p.to_str().unwrap(), "--hole", "0"]).contains("does not point into the hole"));
    let p = write("empty.json", &serde_json::json!({"faces": []}));
    assert!(run(&[p.to_str().unwrap()]).contains("faces: no faces"));
    let p = write("not_json.json", &serde_json::json!(1));
    assert!(run(&[p.to_str().unwrap()]).contains("not_json.json"));
}

/// `blend` on the bundled sheets: G1 to both to rounding, and the STEP
/// file holds the two surfaces and the blend sewn — its two long edges
/// shared with the surfaces (8 + 4 + 4 - 2 = 10 edges, 8 vertices).
#[test]
fn blend_joins_two_surfaces_and_writes_them_sewn() {
    let d = tmpdir("blend");
    let scene = examples().join("cad/blend_sheets.json");
    let out = d.join("sub/blend.step");
    let png = d.join("sub/blend.png");
    let o = fairsurf(&[
        "blend",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--render",
        png.to_str().unwrap(),
        "--zebra",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(r["faces"], 2);
    assert!(r["max_angle_deg"].as_f64().unwrap() < 1e-9, "{r}");
    assert!(r["max_gap"].as_f64().unwrap() < 1e-12, "{r}");
    assert_eq!(r["sides"][0]["face"], 0);
    assert_eq!(r["sides"][1]["face"], 1);
    assert_eq!(r["sides"][0]["edge"], "u1");
    assert_eq!(r["sides"][1]["edge"], "u0");
    // The bulges were chosen by W: no higher than with both 1.
    let search = &r["bulge_search"];
    assert!(search["evaluations"].as_u64().unwrap() >= 4, "{r}");
    assert!(r["curvature_w"].as_f64().unwrap() <= search["curvature_w_at_one"].as_f64().unwrap());
    assert!(r["curvature_w"].as_f64().unwrap() > 0.0);
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.matches("=ADVANCED_FACE(").count(), 3);
    assert_eq!(text.matches("=EDGE_CURVE(").count(), 10);
    assert_eq!(text.matches("=VERTEX_POINT(").count(), 8);
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);
    // A mesh of the three surfaces: A has three spans in u.
    let obj = d.join("sub/blend.obj");
    let o = fairsurf(&[
        "blend",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--bulge",
        "1,1",
        "--mesh",
        obj.to_str().unwrap(),
        "--resolution",
        "4",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&obj).unwrap();
    assert_eq!(
        text.lines().filter(|l| l.starts_with("v ")).count(),
        13 * 5 + 25 + 25
    );
    // --bulge changes α by its factor; the summary says the figures.
    let with_bulge = |b: &str| {
        let o = fairsurf(&[
            "blend",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--bulge",
            b,
            "--json",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let (r, r2) = (with_bulge("1,1"), with_bulge("2,0.5"));
    assert_eq!(r["bulge"], serde_json::json!([1.0, 1.0]));
    assert_eq!(r["bulge_search"], serde_json::Value::Null);
    for (k, f) in [(0, 2.0), (1, 0.5)] {
        let (a, b) = (
            r["alpha"][k].as_f64().unwrap(),
            r2["alpha"][k].as_f64().unwrap(),
        );
        assert!((b - f * a).abs() < 1e-14 * a, "{a} {b}");
    }
    let o = fairsurf(&[
        "blend",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(s.contains("blend between face 0 and face 1"), "{s}");
    assert!(s.contains("against B: largest gap"), "{s}");
    let o = fairsurf(&["schema", "--type", "blend"]);
    assert!(o.status.success());
    let schema: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(schema["properties"]["surfaces"].is_object());
}

/// Bad blend requests exit 2, say why, and write nothing.
#[test]
fn bad_blends_exit_2_and_write_nothing() {
    let d = tmpdir("blend-bad");
    let scene = examples().join("cad/blend_sheets.json");
    let out = d.join("x.step");
    let run = |args: &[&str]| exits_2("blend", &out, args);
    let s = scene.to_str().unwrap();
    let mesh = d.join("x.xyz");
    let e = run(&[s, "--mesh", mesh.to_str().unwrap()]);
    assert!(e.contains("--mesh: cannot tell the mesh format"), "{e}");
    assert!(!mesh.exists());
    assert!(run(&[s, "--bulge", "1"]).contains("--bulge: expected two numbers > 0"));
    assert!(run(&[s, "--bulge", "1,-1"]).contains("--bulge: expected two numbers > 0"));
    assert!(run(&[s, "--lambda=-1"]).contains("--lambda: expected a number ≥ 0"));
    let text: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    let write = |name: &str, v: &serde_json::Value| write_json(&d, name, v);
    let mut bad = text.clone();
    bad["surfaces"][1] = serde_json::json!({"step": "missing.step", "index": 0, "edge": "u0"});
    let p = write("missing.json", &bad);
    let e = run(&[p.to_str().unwrap()]);
    assert!(
        e.contains("surfaces[1].step: cannot read") && e.contains("missing.step"),
        "{e}"
    );
    let mut bad = text.clone();
    bad["surfaces"][1]["edge"] = serde_json::json!("u2");
    let p = write("edge.json", &bad);
    assert!(run(&[p.to_str().unwrap()]).contains("surfaces[1].edge: unknown variant `u2`"));
    // Both edges of one surface that share a corner.
    let mut bad = text.clone();
    bad["surfaces"][1] = bad["surfaces"][0].clone();
    bad["surfaces"][1]["edge"] = serde_json::json!("v0");
    let p = write("touch.json", &bad);
    assert!(run(&[p.to_str().unwrap()]).contains("the two edges meet at their"));
    let p = write("fill.json", &serde_json::json!({"faces": []}));
    assert!(run(&[p.to_str().unwrap()]).contains("unknown field `faces`"));
}

/// One summary for every kind: the first line names the surface and its
/// free points, the report's lines are the same (energy = its terms, the
/// check of the written net, the solve's gradient), and the energy printed
/// is the JSON report's; then what only the kind has.
#[test]
fn the_summary_is_one_for_every_kind() {
    for (scene, kind, own) in [
        (
            "editor_degree10.json",
            "degree 10×10",
            "normal deviation from N",
        ),
        (
            "bspline_hole.json",
            "B-spline, degree 3×3",
            "largest normal turn between neighbouring samples",
        ),
        (
            "vw_hexagon_hole.json",
            "triangular, degree 4, 6 patches",
            "constraint rows 90: 81 independent, 9 dependent (reduced)",
        ),
    ] {
        let path = examples().join(scene);
        let o = fairsurf(&["solve", path.to_str().unwrap()]);
        assert!(o.status.success(), "{scene}: {}", stderr(&o));
        let t = stdout(&o);
        let lines: Vec<&str> = t.lines().collect();
        assert!(
            lines[0].contains(kind) && lines[0].contains("free points ("),
            "{t}"
        );
        let energy_line = lines[1].trim_start();
        assert!(energy_line.starts_with("energy "), "{t}");
        // energy E = t₁ + t₂ …: the printed terms add up to the printed total.
        let (total, terms) = energy_line["energy ".len()..].split_once(" = ").unwrap();
        let sum: f64 = terms
            .split(" + ")
            .map(|t| t.rsplit(' ').next().unwrap().parse::<f64>().unwrap())
            .sum();
        let total: f64 = total.parse().unwrap();
        assert!((sum - total).abs() <= 1e-9 * total.abs(), "{energy_line}");
        assert!(t.contains("  checked on the written net: energy "), "{t}");
        assert!(t.contains("  gradient "), "{t}");
        assert!(t.contains(own), "{scene}: {t}");
        assert!(lines.last().unwrap().contains("solved in"), "{t}");
        let o = fairsurf(&["solve", "--json", path.to_str().unwrap()]);
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let json = v["energy"].as_f64().unwrap();
        assert_eq!(format!("{total:.10e}"), format!("{json:.10e}"), "{scene}");
    }
}

/// A 4-sided hole that one patch cannot follow (the bundled
/// `fill_corners.json`: the faces' edges do not continue the hole's sides
/// at its corners) is filled by a fan, and the summary and the JSON say
/// why: the patch tried first, its angle to the neighbours and W, its time
/// in the fill's. With an angle tolerance of 5° that patch is within it
/// and kept, no fan tried.
#[test]
fn fill_says_why_a_4_sided_hole_took_a_fan() {
    let d = tmpdir("fill-corners");
    let scene = examples().join("cad/fill_corners.json");
    let out = d.join("corners.step");
    let run = |extra: &[&str]| {
        let mut args = vec!["fill", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = fairsurf(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        o
    };
    let s = String::from_utf8_lossy(&run(&[]).stdout).into_owned();
    assert!(s.contains("hole 1: 5 triangular patches"), "{s}");
    let r: serde_json::Value = serde_json::from_slice(&run(&["--json"]).stdout).unwrap();
    let fill = &r["fills"][0];
    assert_eq!(fill["kind"], "fan");
    let others = fill["others"].as_array().unwrap();
    assert_eq!(others.len(), 1);
    assert_eq!(others[0]["kind"], "patch");
    let angle = others[0]["max_angle_deg"].as_f64().unwrap();
    assert!((angle - 3.16).abs() < 0.01, "{angle}");
    // The patch's W: above the fan's (it was not kept for its angle, and
    // it is not fairer either), the summary's the JSON's.
    let w = others[0]["curvature_w"].as_f64().unwrap();
    assert!(w > fill["curvature_w"].as_f64().unwrap() && w < 0.36, "{w}");
    assert!(
        s.contains(&format!(
            "one patch missed its neighbours by 3.16° (W {w:.6}): a fan instead"
        )),
        "{s}"
    );
    let seconds = &fill["seconds"];
    let other = seconds["other_candidates"].as_f64().unwrap();
    assert_eq!(other, others[0]["seconds"].as_f64().unwrap());
    assert!(other > 0.0 && seconds["total"].as_f64().unwrap() > other);
    let r: serde_json::Value =
        serde_json::from_slice(&run(&["--json", "--angle-tolerance", "5"]).stdout).unwrap();
    let fill = &r["fills"][0];
    assert_eq!(fill["kind"], "patch");
    assert_eq!(fill["others"], serde_json::json!([]));
    // No candidate: 0 seconds, not "-0.0" (an empty f64 sum is −0).
    assert_eq!(fill["seconds"]["other_candidates"].to_string(), "0.0");
    assert_eq!(fill["sides_beyond_tolerances"], serde_json::json!([]));
}
