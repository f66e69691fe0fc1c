//! Faces on a torus and on a sphere (TOROIDAL_SURFACE, SPHERICAL_SURFACE
//! bounded by two parallels and two meridians, written by Open CASCADE:
//! `tests/data/revolved.py`) read as exact rational surfaces of
//! revolution: every point on the analytic surface to rounding, the
//! angles they cover exactly the face's parameter rectangle.

use fairsurf_io::{read_step, FaceSurface};
use std::f64::consts::PI;

fn faces() -> Vec<fairsurf_io::StepFace> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/revolved.step");
    read_step(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// On a 41 × 41 grid of the face: the largest distance from the analytic
/// surface (`off`), and the range of its two angles (`angles`).
fn measure(
    f: &fairsurf_io::StepFace,
    off: impl Fn([f64; 3]) -> f64,
    angles: impl Fn([f64; 3]) -> (f64, f64),
) -> (f64, [f64; 4]) {
    let FaceSurface::Rational(r) = &f.surface else {
        panic!("a rational face")
    };
    let ((a, b), (c, d)) = (r.net().knots().0.domain(), r.net().knots().1.domain());
    let (mut worst, mut range) = (0.0f64, [f64::MAX, f64::MIN, f64::MAX, f64::MIN]);
    for i in 0..=40 {
        for j in 0..=40 {
            let (u, v) = (a + (b - a) * i as f64 / 40.0, c + (d - c) * j as f64 / 40.0);
            let p = r.eval(u, v);
            worst = worst.max(off(p));
            let (s, t) = angles(p);
            range = [
                range[0].min(s),
                range[1].max(s),
                range[2].min(t),
                range[3].max(t),
            ];
        }
    }
    (worst, range)
}

#[test]
fn a_torus_face_is_read_exactly() {
    let faces = faces();
    let torus = faces
        .iter()
        .find(|f| f.kind == "torus")
        .expect("a torus face");
    // Axis z through (1, 2, 3), radii 2 and 0.5; u about the axis, v about
    // the tube.
    let (worst, [u0, u1, v0, v1]) = measure(
        torus,
        |p| {
            let rho = (p[0] - 1.0).hypot(p[1] - 2.0);
            ((rho - 2.0).hypot(p[2] - 3.0) - 0.5).abs()
        },
        |p| {
            let rho = (p[0] - 1.0).hypot(p[1] - 2.0);
            (
                (p[1] - 2.0).atan2(p[0] - 1.0),
                (p[2] - 3.0).atan2(rho - 2.0),
            )
        },
    );
    assert!(worst < 1e-11, "{worst}");
    for (got, want) in [(u0, 0.3), (u1, 1.9), (v0, -0.4), (v1, 1.2)] {
        assert!((got - want).abs() < 1e-9, "{got} vs {want}");
    }
}

#[test]
fn a_sphere_face_is_read_exactly() {
    let faces = faces();
    let sphere = faces
        .iter()
        .find(|f| f.kind == "sphere")
        .expect("a sphere face");
    assert_eq!(faces.iter().filter(|f| f.kind == "sphere").count(), 2);
    // Centre (-3, 0, 1), radius 1.5; u the longitude, v the latitude.
    let (worst, [u0, u1, v0, v1]) = measure(
        sphere,
        |p| ((p[0] + 3.0).hypot(p[1]).hypot(p[2] - 1.0) - 1.5).abs(),
        |p| {
            let rho = (p[0] + 3.0).hypot(p[1]);
            (p[1].atan2(p[0] + 3.0), (p[2] - 1.0).atan2(rho))
        },
    );
    assert!(worst < 1e-11, "{worst}");
    for (got, want) in [(u0, 0.2), (u1, 2.2), (v0, -0.6), (v1, 0.9)] {
        assert!((got - want).abs() < 1e-9, "{got} vs {want}");
    }
    assert!(u1 - u0 < PI);
}

/// An octant of the unit sphere about (0, −4, 0) up to its north pole
/// (three edges: the equator's quarter and two meridians meeting at the
/// pole): read with a side collapsed to the pole.
#[test]
fn a_sphere_octant_reaching_its_pole_is_read_exactly() {
    let faces = faces();
    let octant = faces
        .iter()
        .filter(|f| f.kind == "sphere")
        .nth(1)
        .expect("the octant");
    let (worst, [u0, u1, v0, v1]) = measure(
        octant,
        |p| (p[0].hypot(p[1] + 4.0).hypot(p[2]) - 1.0).abs(),
        |p| {
            let rho = p[0].hypot(p[1] + 4.0);
            ((p[1] + 4.0).atan2(p[0]), p[2].atan2(rho))
        },
    );
    assert!(worst < 1e-11, "{worst}");
    for (got, want) in [(u0, 0.0), (u1, PI / 2.0), (v0, 0.0), (v1, PI / 2.0)] {
        assert!((got - want).abs() < 1e-9, "{got} vs {want}");
    }
}

/// The same file with every edge written the other way (EDGE_CURVE from
/// its second vertex to its first with same_sense .F., each ORIENTED_EDGE
/// turned: the same model by ISO 10303-42) reads to the same faces.
#[test]
fn edges_of_either_sense_read_alike() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/revolved.step");
    let text = std::fs::read_to_string(path).unwrap();
    let mut edges = Vec::new();
    let turned: String = text
        .lines()
        .map(|line| {
            let Some((id, rest)) = line.split_once(" = EDGE_CURVE('") else {
                return format!("{line}\n");
            };
            let fields: Vec<&str> = rest.trim_end_matches(");").split(',').collect();
            assert_eq!(fields[4], ".T.", "{line}");
            edges.push(id.trim().to_string());
            format!(
                "{id} = EDGE_CURVE('{},{},{},{},.F.);\n",
                fields[0], fields[2], fields[1], fields[3]
            )
        })
        .collect();
    let turned: String = turned
        .lines()
        .map(|line| match line.split_once("ORIENTED_EDGE('',*,*,") {
            Some((head, rest)) => {
                let (edge, sense) = rest.split_once(',').unwrap();
                assert!(edges.iter().any(|e| e == edge), "{line}");
                let flipped = if sense.starts_with(".T.") {
                    ".F.);"
                } else {
                    ".T.);"
                };
                format!("{head}ORIENTED_EDGE('',*,*,{edge},{flipped}\n")
            }
            None => format!("{line}\n"),
        })
        .collect();
    assert!(turned.contains(",.F.);") && edges.len() >= 10);
    assert_eq!(read_step(&turned).unwrap(), read_step(&text).unwrap());
}
