//! STEP writing: one face with four edges per patch, collapsed and shared
//! sides, elevated copies of one boundary as one edge, escaped labels, sides
//! split at the corners of later faces.

use super::*;

fn count(text: &str, entity: &str) -> usize {
    text.matches(&format!("={entity}(")).count()
}

#[test]
fn a_patch_is_one_face_with_four_edges() {
    let p = TensorPatch::from_fn(3, 4, |i, j| [i as f64, j as f64, 0.1 * (i * j) as f64]);
    let t = step_text("x.step", &[(&p).into()]);
    assert_eq!(count(&t, "ADVANCED_FACE"), 1);
    assert_eq!(count(&t, "EDGE_CURVE"), 4);
    assert_eq!(count(&t, "VERTEX_POINT"), 4);
    assert_eq!(count(&t, "ORIENTED_EDGE"), 4);
    assert_eq!(count(&t, "CARTESIAN_POINT"), 20 + 1);
    assert!(t.contains(",(4,4),(5,5),(0.0,1.0),(0.0,1.0),.UNSPECIFIED.)"));
}

#[test]
fn a_collapsed_side_has_no_edge_and_shared_sides_are_shared() {
    // Side u = 0 (i = 0) collapsed to the origin.
    let p = TensorPatch::from_fn(2, 2, |i, j| {
        if i == 0 {
            [0.0; 3]
        } else {
            [i as f64, j as f64 - 1.0, 0.0]
        }
    });
    let t = step_text("x.step", &[(&p).into()]);
    assert_eq!(count(&t, "EDGE_CURVE"), 3);
    assert_eq!(count(&t, "VERTEX_POINT"), 3);
    // Two patches meeting along u = 1 of the first / u = 0 of the second.
    let a = TensorPatch::from_fn(2, 2, |i, j| [i as f64, j as f64, (i * j) as f64]);
    let b = TensorPatch::from_fn(2, 2, |i, j| [2.0 + i as f64, j as f64, (2 * j) as f64]);
    let t = step_text("x.step", &[(&a).into(), (&b).into()]);
    assert_eq!(count(&t, "ADVANCED_FACE"), 2);
    assert_eq!(count(&t, "EDGE_CURVE"), 7);
    assert_eq!(count(&t, "VERTEX_POINT"), 6);
    let shared = t
        .lines()
        .filter(|l| l.contains(",.F.);") && l.contains("ORIENTED_EDGE"));
    // Top and left of each run against their edges; the shared edge is
    // used once each way (a by its right side, b by its left).
    assert_eq!(shared.count(), 4);
}

/// A neighbour's boundary and the same curve degree-elevated (another
/// surface's boundary) are one edge.
#[test]
fn a_boundary_and_its_elevated_copy_are_one_edge() {
    let a = TensorPatch::from_fn(2, 2, |i, j| [i as f64, j as f64, (i * j) as f64]);
    let b = TensorPatch::from_fn(2, 2, |i, j| [2.0 + i as f64, j as f64, (2 * j) as f64]);
    let b = b.elevate(1, 1);
    let t = step_text("x.step", &[(&a).into(), (&b).into()]);
    assert_eq!(count(&t, "EDGE_CURVE"), 7);
    assert_eq!(count(&t, "VERTEX_POINT"), 6);
    // Moved off by 1e-6 of the size, it is not.
    let c = b.map(|p| [p[0], p[1], p[2] + 1e-6 * (p[0] - 2.0).abs().max(0.0) + 1e-6]);
    let t = step_text("x.step", &[(&a).into(), (&c).into()]);
    assert_eq!(count(&t, "EDGE_CURVE"), 8);
}

#[test]
fn labels_are_escaped() {
    assert_eq!(string("it's a\\b é"), "it''s a\\\\b _");
}

/// A side that two later faces each cover half of is split at their
/// common corner and shares its halves with them, whichever order the
/// faces come in.
#[test]
fn a_side_is_split_at_corners_of_faces_written_later() {
    let quad = |x0: f64, x1: f64, y0: f64, y1: f64| {
        TensorPatch::from_fn(1, 1, |i, j| {
            [
                if i == 0 { x0 } else { x1 },
                if j == 0 { y0 } else { y1 },
                0.0,
            ]
        })
    };
    let (a, b, c) = (
        quad(0.0, 2.0, -1.0, 0.0),
        quad(0.0, 1.0, 0.0, 1.0),
        quad(1.0, 2.0, 0.0, 1.0),
    );
    for order in [[&a, &b, &c], [&b, &c, &a], [&b, &a, &c]] {
        let surfaces: Vec<CadSurface> = order.iter().map(|p| CadSurface::from(*p)).collect();
        let t = step_text("x.step", &surfaces);
        assert_eq!(count(&t, "EDGE_CURVE"), 10, "{t}");
        assert_eq!(count(&t, "VERTEX_POINT"), 8, "{t}");
        assert_eq!(count(&t, "ORIENTED_EDGE"), 13, "{t}");
        // fairsurf reads its own split sides back: the faces as written.
        let back = crate::read_step_faces(&t).unwrap();
        let written: Vec<_> = order
            .iter()
            .map(|p| fairsurf::bspline::BSplineSurface::from_bezier(p))
            .collect();
        assert_eq!(back, written);
    }
}

/// An edge matched by its geometry takes its sense from the way its
/// points run along the written curve: a closed edge (a whole circle,
/// written as a rational quadratic) met by points on the circle spaced
/// otherwise, run one way or the other, or back and forth.
#[test]
fn a_closed_edge_matched_by_projection_gets_its_sense_from_its_run() {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let points = vec![
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [-1.0, -1.0, 0.0],
        [0.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 0.0, 0.0],
    ];
    let weights = vec![1.0, w, 1.0, w, 1.0, w, 1.0, w, 1.0];
    let knots = fairsurf::bspline::KnotVector::new(
        2,
        vec![
            0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
        ],
    )
    .unwrap();
    let circle = |theta: f64| [theta.cos(), theta.sin(), 0.0];
    let tau = std::f64::consts::TAU;
    let mut d = Data {
        tol: 1e-9,
        ..Data::default()
    };
    d.edge_samples.push(WrittenEdge {
        samples: std::array::from_fn(|k| circle(tau * k as f64 / 8.0)),
        edge: 7,
        knots,
        points,
        weights: Some(weights),
    });
    let run = |theta: &dyn Fn(f64) -> f64| -> [Vec3; EDGE_SAMPLES] {
        std::array::from_fn(|k| circle(theta(k as f64 / 8.0)))
    };
    assert_eq!(d.matching_edge(&run(&|s| tau * s * s)), Some((7, true)));
    assert_eq!(
        d.matching_edge(&run(&|s| tau * (1.0 - s * s))),
        Some((7, false))
    );
    // Out and back: not one run along the curve.
    let there_and_back = |s: f64| tau * if s <= 0.5 { s } else { 1.0 - s };
    assert_eq!(d.matching_edge(&run(&there_and_back)), None);
    // Off the circle by 1e-6: not this edge.
    let mut off = run(&|s| tau * s * s);
    off[4][2] += 1e-6;
    assert_eq!(d.matching_edge(&off), None);
}
