//! Monterde & Ugail 2004 through scene files: Tables 1, 2 and 4 from the
//! example boundaries, the `method` field, and its errors.

use fairsurf::harmonic::Comparison;
use fairsurf_io::{comparison_json, Error, Outcome, TensorScene};
use std::path::PathBuf;

fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn table(name: &str) -> Comparison {
    TensorScene::read(&examples().join(name))
        .unwrap()
        .compare()
        .unwrap()
}

/// Rows (area, harmonic, biharmonic) × the four columns, as printed.
type Printed = [[&'static str; 4]; 3];

/// Our values against the printed ones: `|ours − printed| ≤ k` units of
/// the printed last digit, per row.
fn check(c: &Comparison, printed: &Printed, units: [f64; 3], what: &str) {
    let cols = c.columns();
    for (r, row) in printed.iter().enumerate() {
        for (k, text) in row.iter().enumerate() {
            let m = &cols[k].1.measures;
            let ours = [m.area, m.dirichlet, m.biharmonic][r];
            let p: f64 = text.parse().unwrap();
            let decimals = text.split('.').nth(1).map_or(0, str::len);
            let unit = 10f64.powi(-(decimals as i32));
            assert!(
                (ours - p).abs() <= units[r] * unit,
                "{what}: row {r} column {k}: ours {ours:.8} vs printed {text}"
            );
        }
    }
}

fn argmin(c: &Comparison, row: usize) -> usize {
    let v: Vec<f64> = c
        .columns()
        .iter()
        .map(|(_, k)| [k.measures.area, k.measures.dirichlet, k.measures.biharmonic][row])
        .collect();
    (0..4).min_by(|&a, &b| v[a].total_cmp(&v[b])).unwrap()
}

/// Table 1 (model problem, boundary printed in §2.1). The functionals match
/// every printed digit; two areas differ by one unit in the last digit
/// (27.68557 → ours 27.685557, 2.51679 → ours 2.516781); our areas are
/// accurate to 1e-13 (independently checked quadrature).
#[test]
fn table1_model_problem() {
    let c = table("monterde_ugail_model.json");
    let printed: Printed = [
        ["2.57882", "2.53203", "2.51508", "2.51679"],
        ["2.78117", "2.83688", "2.95473", "2.96027"],
        ["27.68557", "22.91089", "21.37350", "20.46343"],
    ];
    check(&c, &printed, [1.5, 0.5, 1.5], "Table 1");
    // The printed digits of the functionals: all but 27.68557 exactly.
    assert_eq!((argmin(&c, 0), argmin(&c, 1), argmin(&c, 2)), (2, 0, 3));
}

/// Table 4 (Fig. 7, four semicircles of radius 1). The functionals match
/// every printed digit. Areas: 4.41579 and 5.00357 are one unit low (ours
/// 4.4157954, 5.0035773: truncated, not rounded), and the printed "4.5887"
/// has lost a digit (ours 4.5888687).
#[test]
fn table4_four_semicircles() {
    let c = table("monterde_ugail_fig7.json");
    let printed: Printed = [
        ["4.5887", "4.41579", "5.00357", "5.03371"],
        ["5.15927", "5.4736", "6.25076", "6.30423"],
        ["84.1009", "58.1741", "51.6785", "49.5086"],
    ];
    // "4.5887" is our 4.58887 with its fourth decimal dropped.
    let ours = format!("{:.5}", c.harmonic_extremal.measures.area);
    assert_eq!(format!("{}{}", &ours[..5], &ours[6..]), "4.5887");
    let mut rest = printed;
    rest[0][0] = "4.58887";
    check(&c, &rest, [1.0, 0.5, 0.5], "Table 4");
    assert_eq!((argmin(&c, 0), argmin(&c, 1), argmin(&c, 2)), (1, 0, 3));
}

/// Table 2 (catenoid). The paper does not say how it approximated the side
/// catenaries by degree-5 curves; interpolation at six equally spaced
/// parameters gives every entry to within 1e-5 relative and the same
/// winners in every row.
#[test]
fn table2_catenoid_boundary() {
    let c = table("monterde_ugail_catenoid.json");
    let printed = [
        [8.31778, 8.00677, 7.77847, 7.79836],
        [9.18563, 9.38326, 9.82239, 9.88235],
        [113.941, 96.5717, 89.2635, 86.1143],
    ];
    for (r, row) in printed.iter().enumerate() {
        for (k, &p) in row.iter().enumerate() {
            let m = &c.columns()[k].1.measures;
            let ours = [m.area, m.dirichlet, m.biharmonic][r];
            assert!(
                (ours - p).abs() <= 1e-5 * p,
                "row {r} column {k}: {ours} vs {p}"
            );
        }
    }
    assert_eq!((argmin(&c, 0), argmin(&c, 1), argmin(&c, 2)), (2, 0, 3));
}

#[test]
fn comparison_json_has_the_documented_shape() {
    let v = comparison_json(&table("monterde_ugail_model.json"));
    for col in [
        "harmonic_extremal",
        "harmonic_mask",
        "biharmonic_surface",
        "biharmonic_extremal",
    ] {
        for key in ["area", "dirichlet", "biharmonic"] {
            assert!(v[col][key].is_number(), "{col}.{key}");
        }
        assert!(v[col]["abs_mean_curvature"]["max"].is_number());
    }
}

fn scene_with(
    method: &str,
    extra: &str,
    degree: (usize, usize),
    null_at: Option<(usize, usize)>,
) -> String {
    let (n, m) = degree;
    let rows: Vec<String> = (0..=n)
        .map(|i| {
            let pts: Vec<String> = (0..=m)
                .map(|j| {
                    if Some((i, j)) == null_at {
                        "null".into()
                    } else {
                        let z = ((i * 7 + j * 3) % 5) as f64 * 0.1;
                        format!("[{i}, {j}, {z}]")
                    }
                })
                .collect();
            format!("[{}]", pts.join(", "))
        })
        .collect();
    format!(
        r#"{{"surface": {{"type": "tensor", "degree": [{n}, {m}], "control_points": [{}]}}, "method": "{method}"{extra}}}"#,
        rows.join(", ")
    )
}

fn scene_error(text: &str) -> (String, String) {
    match TensorScene::from_json(text).and_then(|s| s.solve()) {
        Err(Error::Scene { path, message }) => (path, message),
        other => panic!(
            "expected a scene error, got {:?}",
            other.map(|s| s.patch().clone())
        ),
    }
}

#[test]
fn construction_methods_solve_scenes_with_free_insides() {
    // Inner points may be null: the constructions do not read them.
    for method in ["harmonic", "biharmonic", "harmonic_mask"] {
        let text = scene_with(method, "", (4, 4), Some((2, 2)));
        let s = TensorScene::from_json(&text).unwrap().solve().unwrap();
        let c = s.outcome.construction().unwrap();
        assert_eq!(c.report.method.name(), method);
        assert!(c.report.exact);
        // The result is a scene that builds the same surface again.
        let again = TensorScene::from_json(&serde_json::to_string(&s.result_scene()).unwrap())
            .unwrap()
            .solve()
            .unwrap();
        let moved = s
            .patch()
            .points()
            .iter()
            .zip(again.patch().points())
            .map(|(a, b)| fairsurf::vector::norm(fairsurf::vector::sub(*a, *b)))
            .fold(0.0, f64::max);
        assert!(moved < 1e-12, "{method}: {moved}");
    }
    let s = TensorScene::from_json(&scene_with("biharmonic_mask", "", (5, 5), Some((2, 2))))
        .unwrap()
        .solve()
        .unwrap();
    assert!(matches!(s.outcome, Outcome::Constructed(_)));
}

#[test]
fn construction_method_errors_name_the_field() {
    let (p, m) = scene_error(&scene_with("harmonic", "", (4, 4), Some((0, 2))));
    assert_eq!(p, "surface.control_points[0][2]");
    assert!(m.contains("first and last rows"), "{m}");
    let (p, _) = scene_error(&scene_with("biharmonic", "", (4, 4), Some((2, 0))));
    assert_eq!(p, "surface.control_points[2][0]");
    let (p, m) = scene_error(&scene_with("biharmonic_mask", "", (5, 5), Some((1, 2))));
    assert_eq!(p, "surface.control_points[1][2]");
    assert!(m.contains("two outer rings"), "{m}");
    let (p, _) = scene_error(&scene_with("biharmonic_mask", "", (3, 5), None));
    assert_eq!(p, "surface.degree[0]");
    let (p, m) = scene_error(&scene_with(
        "harmonic",
        r#", "energy": {"bend": 1}"#,
        (4, 4),
        None,
    ));
    assert_eq!(p, "energy");
    assert!(m.contains("not used by method"), "{m}");
    let (p, _) = scene_error(&scene_with(
        "biharmonic",
        r#", "fixed_rings": 1"#,
        (4, 4),
        None,
    ));
    assert_eq!(p, "fixed_rings");
    let (p, _) = scene_error(&scene_with(
        "minimize",
        r#", "least_squares": true, "fixed_rings": 1"#,
        (4, 4),
        None,
    ));
    assert_eq!(p, "least_squares");
    let (p, _) = scene_error(&scene_with(
        "harmonic_mask",
        r#", "least_squares": true"#,
        (4, 4),
        None,
    ));
    assert_eq!(p, "least_squares");
    // An unknown method is a parse error at the field.
    let (p, m) = scene_error(&scene_with("coons", "", (4, 4), None));
    assert_eq!(p, "method");
    assert!(m.contains("unknown variant"), "{m}");
}

#[test]
fn inconsistent_biharmonic_is_an_error_unless_least_squares_is_asked() {
    let text = scene_with("biharmonic", "", (4, 6), None);
    match TensorScene::from_json(&text).unwrap().solve() {
        Err(Error::Solve(fairsurf::Error::Inconsistent { residual, .. })) => {
            assert!(residual > 1e-6)
        }
        other => panic!("{:?}", other.map(|s| s.patch().clone())),
    }
    let text = scene_with("biharmonic", r#", "least_squares": true"#, (4, 6), None);
    let s = TensorScene::from_json(&text).unwrap().solve().unwrap();
    let rep = s.report_json();
    assert_eq!(rep["exact"], false);
    assert!(rep["residual"].as_f64().unwrap() > 1e-6);
}
