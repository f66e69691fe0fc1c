//! STEP reading: fairsurf's own output and Open CASCADE's files read back
//! with the same surfaces; every refused entity is named.

use super::*;
use crate::CadSurface;
use fairsurf::TensorPatch;

/// fairsurf's own STEP output reads back with the same surfaces.
#[test]
fn a_written_shell_reads_back() {
    let a = TensorPatch::from_fn(3, 2, |i, j| [i as f64, j as f64, 0.1 * (i * j) as f64]);
    let b = TensorPatch::from_fn(3, 2, |i, j| {
        [3.0 + i as f64, j as f64, 0.3 * (i * j) as f64]
    });
    let s = BSplineSurface::new(
        KnotVector::new(3, vec![0., 0., 0., 0., 0.5, 1., 1., 1., 1.]).unwrap(),
        KnotVector::bezier(2),
        (0..15)
            .map(|k| [(k / 3) as f64, (k % 3) as f64, -1.0])
            .collect(),
    )
    .unwrap();
    let surfaces: Vec<CadSurface> = vec![(&a).into(), (&b).into(), (&s).into()];
    let text = crate::step::step_text("x.step", &surfaces);
    let faces = read_step_faces(&text).unwrap();
    assert_eq!(faces.len(), 3);
    assert_eq!(faces[0], BSplineSurface::from_bezier(&a));
    assert_eq!(faces[1], BSplineSurface::from_bezier(&b));
    assert_eq!(faces[2], s);
}

/// A face with a side collapsed to a point (fairsurf writes no edge
/// for it: a loop of three edges) and a face whose side is split in
/// two read back whole; a face trimmed inside one side is refused.
#[test]
fn collapsed_and_split_sides_read_back_and_a_notch_does_not() {
    // A cone-like patch: row u = 0 all at the apex.
    let cone = TensorPatch::from_fn(3, 2, |i, j| {
        let r = i as f64 / 3.0;
        [r * (j as f64 - 1.0), r * 2.0, r * r]
    });
    let text = crate::step::step_text("x.step", &[(&cone).into()]);
    assert_eq!(text.matches("=ORIENTED_EDGE(").count(), 3, "{text}");
    let faces = read_step_faces(&text).unwrap();
    assert_eq!(faces, vec![BSplineSurface::from_bezier(&cone)]);
    // The unit square bounded by three lines and a fourth edge along
    // u = 0 that leaves the side at 3/8 of the way (a notch the edge's
    // midpoint does not see).
    use truck_stepio::r#in::alias::{BSplineCurve, KnotVec, Line};
    use truck_topology::compress::CompressedEdge;
    let square = BSplineSurface::new(
        KnotVector::bezier(1),
        KnotVector::bezier(1),
        vec![[0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
    )
    .unwrap();
    let pt = |x: f64, y: f64| Point3::new(x, y, 0.0);
    let corners = vec![pt(0.0, 0.0), pt(1.0, 0.0), pt(1.0, 1.0), pt(0.0, 1.0)];
    let line = |a: usize, b: usize| Curve3D::Line(Line(corners[a], corners[b]));
    let side = |notch: f64| {
        let pts: Vec<Point3> = (0..=8)
            .map(|k| pt(if k == 3 { notch } else { 0.0 }, 1.0 - k as f64 / 8.0))
            .collect();
        let mut knots = vec![0.0];
        knots.extend((0..=8).map(|k| k as f64 / 8.0));
        knots.push(1.0);
        Curve3D::BSplineCurve(BSplineCurve::new(KnotVec::from(knots), pts))
    };
    for (notch, accepted) in [(0.0, true), (0.1, false)] {
        let shell = Shell {
            vertices: corners.clone(),
            edges: vec![
                CompressedEdge {
                    vertices: (0, 1),
                    curve: line(0, 1),
                },
                CompressedEdge {
                    vertices: (1, 2),
                    curve: line(1, 2),
                },
                CompressedEdge {
                    vertices: (2, 3),
                    curve: line(2, 3),
                },
                CompressedEdge {
                    vertices: (3, 0),
                    curve: side(notch),
                },
            ],
            faces: vec![],
        };
        let edges: Vec<LoopEdge> = (0..4)
            .map(|k| LoopEdge::new(&shell, CompressedEdgeIndex::from((k, true))).unwrap())
            .collect();
        let got = restricted(FaceSurface::Polynomial(square.clone()), &edges);
        match got {
            Ok(FaceSurface::Polynomial(s)) => assert!(accepted && s == square),
            Err(e) => assert!(!accepted && e.contains("does not run along"), "{e}"),
            other => panic!("{other:?}"),
        }
    }
}

/// An edge written as its face's own side (the side's degree, knots up to
/// t ↦ αt + β, control points) is recognised from the control points
/// (`is_side`), either way round; a point moved past the tolerance, the
/// points reversed on uneven knots, part of the curve, or the side written
/// one degree higher are not — and `restricted` still reads the elevated
/// side as the whole surface's (Newton's foot points) and refuses the
/// moved one, so the quick test changes no decision.
#[test]
fn edges_that_are_their_surfaces_sides_are_recognised_on_their_points() {
    use truck_stepio::r#in::alias::{BSplineCurve, KnotVec};
    let uk = vec![0., 0., 0., 0.3, 1., 1., 1.];
    let s = BSplineSurface::new(
        KnotVector::new(2, uk.clone()).unwrap(),
        KnotVector::bezier(2),
        (0..12)
            .map(|k| {
                let (i, j) = ((k / 3) as f64, (k % 3) as f64);
                [i, j + 0.2 * i, 0.3 * (i * j).sin()]
            })
            .collect(),
    )
    .unwrap();
    let tol = EDGE_TOLERANCE;
    let edge = |knots: Vec<f64>, pts: &[Vec3], range: (f64, f64)| {
        let pts = pts.iter().map(|p| Point3::new(p[0], p[1], p[2])).collect();
        let mut e = LoopEdge {
            curve: Curve3D::BSplineCurve(BSplineCurve::new(KnotVec::from(knots), pts)),
            range,
            seam: None,
            start: [0.0; 3],
            end: [0.0; 3],
            vertex_off: 0.0,
        };
        (e.start, e.end) = (e.point(range.0), e.point(range.1));
        e
    };
    let bottom: Vec<Vec3> = (0..4).map(|i| s.point(i, 0)).collect();
    let reversed: Vec<Vec3> = bottom.iter().rev().copied().collect();
    let scaled: Vec<f64> = uk.iter().map(|t| 2.0 + 2.0 * t).collect();
    let flipped: Vec<f64> = uk.iter().rev().map(|t| 1.0 - t).collect();
    let moved = |by: f64| {
        let mut p = bottom.clone();
        p[1][2] += by;
        p
    };
    let bezier = vec![0., 0., 0., 1., 1., 1.];
    let right: Vec<Vec3> = (0..3).map(|j| s.point(3, j)).collect();
    for (what, e, expected) in [
        (
            "v = 0 on scaled knots",
            edge(scaled, &bottom, (2.0, 4.0)),
            true,
        ),
        (
            "v = 0 reversed",
            edge(flipped.clone(), &reversed, (1.0, 0.0)),
            true,
        ),
        ("u = 1", edge(bezier, &right, (0.0, 1.0)), true),
        (
            "a point moved 1e-13",
            edge(uk.clone(), &moved(1e-13), (0.0, 1.0)),
            true,
        ),
        (
            "a point moved 0.5 tol",
            edge(uk.clone(), &moved(0.5 * tol), (0.0, 1.0)),
            false,
        ),
        (
            "reversed points, knots not",
            edge(uk.clone(), &reversed, (0.0, 1.0)),
            false,
        ),
        (
            "part of the curve",
            edge(uk.clone(), &bottom, (0.0, 0.5)),
            false,
        ),
    ] {
        assert_eq!(is_side(&SideRows::of(&s), &e), expected, "{what}");
    }
    // The loop around the four sides, its first side as given.
    let ring = |first: LoopEdge| -> Vec<LoopEdge> {
        let row = |f: &dyn Fn(usize) -> Vec3, n: usize| (0..n).map(f).collect::<Vec<_>>();
        vec![
            first,
            edge(vec![0., 0., 0., 1., 1., 1.], &right, (0.0, 1.0)),
            edge(flipped.clone(), &row(&|i| s.point(3 - i, 2), 4), (0.0, 1.0)),
            edge(
                vec![0., 0., 0., 1., 1., 1.],
                &row(&|j| s.point(0, 2 - j), 3),
                (0.0, 1.0),
            ),
        ]
    };
    let flat: Vec<f64> = bottom.iter().flatten().copied().collect();
    let (k3, c3) = KnotVector::new(2, uk.clone())
        .unwrap()
        .elevate(&flat, 3)
        .unwrap();
    let elevated: Vec<Vec3> = c3.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    let elevated = edge(k3.knots().to_vec(), &elevated, (0.0, 1.0));
    assert!(!is_side(&SideRows::of(&s), &elevated));
    for (what, first, whole) in [
        ("exact sides", edge(uk.clone(), &bottom, (0.0, 1.0)), true),
        ("the first side elevated", elevated, true),
        (
            "a point moved 0.5 tol",
            edge(uk.clone(), &moved(0.5 * tol), (0.0, 1.0)),
            true,
        ),
        (
            "a point moved 1e-2",
            edge(uk.clone(), &moved(1e-2), (0.0, 1.0)),
            false,
        ),
    ] {
        let edges = ring(first);
        for w in edges.windows(2) {
            assert!(dist(w[0].end, w[1].start) < 1e-12, "{what}: a closed loop");
        }
        match restricted(FaceSurface::Polynomial(s.clone()), &edges) {
            Ok(FaceSurface::Polynomial(got)) => assert!(whole && got == s, "{what}"),
            Err(e) => assert!(!whole && e.contains("trimmed"), "{what}: {e}"),
            Ok(other) => panic!("{what}: {other:?}"),
        }
    }
}

#[test]
fn what_is_not_read_is_said() {
    let e = read_step_faces("not a step file").unwrap_err().to_string();
    assert!(e.contains("not a STEP file"), "{e}");
    let a = TensorPatch::from_fn(1, 1, |i, j| [i as f64, j as f64, 0.0]);
    let text = crate::step::step_text("x.step", &[(&a).into()]);
    let e = read_step_faces(&text.replace("OPEN_SHELL", "OPEN_SHELF"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("no shell"), "{e}");
    // The surface made another through the file's own placement.
    let axes = text
        .lines()
        .find(|l| l.contains("=AXIS2_PLACEMENT_3D("))
        .and_then(|l| l.split('=').next())
        .unwrap();
    let with = |entity: &str| -> String {
        text.lines()
            .map(|l| match l.split_once("=B_SPLINE_SURFACE_WITH_KNOTS(") {
                Some((id, _)) => format!("{id}={entity};\n"),
                None => format!("{l}\n"),
            })
            .collect()
    };
    // A plane through the square's corners: read as the bilinear patch.
    let faces = read_step(&with(&format!("PLANE('',{axes})"))).unwrap();
    assert_eq!(faces[0].kind, "plane");
    let FaceSurface::Polynomial(s) = &faces[0].surface else {
        panic!("a plane is polynomial")
    };
    assert_eq!(
        s.points(),
        &[[0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]
    );
    // A sphere the square's edges are not on (not a four-sided face of it,
    // nor a trimmed one).
    let e = read_step(&with(&format!("SPHERICAL_SURFACE('',{axes},1.)")))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("an edge of the face is") && e.contains("off its surface"),
        "{e}"
    );
    // A plane the face's edges are not on.
    let tilted = text.replace("DIRECTION('',(0.,0.,1.))", "DIRECTION('',(0.,0.6,0.8))");
    let (id, _) = tilted
        .lines()
        .find_map(|l| l.split_once("=B_SPLINE_SURFACE_WITH_KNOTS("))
        .unwrap();
    let tilted: String = tilted
        .lines()
        .map(|l| {
            if l.starts_with(&format!("{id}=")) {
                format!("{id}=PLANE('',{axes});\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    // (Not four sides of it, so not a trimmed face of it either.)
    let e = read_step(&tilted).unwrap_err().to_string();
    assert!(
        e.contains("an edge of the face is") && e.contains("off its surface"),
        "{e}"
    );
}

/// An edge on a closed curve whose vertices lie on either side of the
/// curve's seam runs through the seam (the short way its curve runs),
/// not back across the whole curve; on an open curve that order is an
/// error.
#[test]
fn an_edge_runs_through_its_closed_curve_s_seam() {
    use truck_stepio::r#in::alias::{BSplineCurve, KnotVec};
    use truck_topology::compress::CompressedEdge;
    // The unit square's outline, degree 1, from (0, 0) round to (0, 0).
    let square = [[0., 0.], [1., 0.], [1., 1.], [0., 1.], [0., 0.]]
        .map(|[x, y]| Point3::new(x, y, 0.0))
        .to_vec();
    let knots = KnotVec::from(vec![0., 0., 1., 2., 3., 4., 4.]);
    let curve = Curve3D::BSplineCurve(BSplineCurve::new(knots.clone(), square.clone()));
    let shell = |curve: Curve3D, [a, b]: [[f64; 2]; 2]| Shell {
        vertices: vec![Point3::new(a[0], a[1], 0.0), Point3::new(b[0], b[1], 0.0)],
        edges: vec![CompressedEdge {
            vertices: (0, 1),
            curve,
        }],
        faces: vec![],
    };
    let s = shell(curve, [[0.0, 0.5], [0.5, 0.0]]);
    for orientation in [true, false] {
        let e = LoopEdge::new(&s, CompressedEdgeIndex::from((0, orientation))).unwrap();
        let mid = e.at(0.5).0;
        assert!(dist(mid, [0.0; 3]) < 1e-15, "{mid:?}");
        assert!(e.distance([1.0, 1.0, 0.0]) > 0.7);
        assert!(e.distance([0.0, 0.25, 0.0]) < 1e-15);
        assert!(!e.straight(1e-9));
    }
    // Vertices in that order on the open curve that stops short of
    // closing.
    let open = Curve3D::BSplineCurve(BSplineCurve::new(
        KnotVec::from(vec![0., 0., 1., 2., 3., 3.]),
        square[..4].to_vec(),
    ));
    let s = shell(open, [[0.5, 1.0], [1.0, 0.5]]);
    let e = LoopEdge::new(&s, CompressedEdgeIndex::from((0, true))).err();
    assert!(e.unwrap().contains("from its end vertex to its start"));
}

/// A straight edge is straight whatever its parameterization.
#[test]
fn a_straight_edge_unevenly_parameterized_is_straight() {
    use truck_stepio::r#in::alias::{BSplineCurve, KnotVec};
    use truck_topology::compress::CompressedEdge;
    let pts = [0.0, 0.1, 0.2, 1.0]
        .map(|x| Point3::new(x, 2.0 * x, 0.0))
        .to_vec();
    let curve = BSplineCurve::new(KnotVec::bezier_knot(3), pts);
    let s = Shell {
        vertices: vec![Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 2.0, 0.0)],
        edges: vec![CompressedEdge {
            vertices: (0, 1),
            curve: Curve3D::BSplineCurve(curve),
        }],
        faces: vec![],
    };
    let e = LoopEdge::new(&s, CompressedEdgeIndex::from((0, true))).unwrap();
    assert!(e.straight(1e-12));
    // Its points are not at equal steps along it.
    let q = e.at(0.5).0;
    assert!(dist(q, [0.5, 1.0, 0.0]) > 0.1, "{q:?}");
}

/// A rational surface written reads back as the same rational surface,
/// and as an error where only polynomial faces are taken.
#[test]
fn a_rational_face_reads_back() {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let net = BSplineSurface::new(
        KnotVector::bezier(2),
        KnotVector::bezier(1),
        vec![
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 0.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 0.0],
            [0.0, 1.0, 1.0],
        ],
    )
    .unwrap();
    let r = RationalSurface::new(net, vec![1.0, 1.0, h, h, 1.0, 1.0]).unwrap();
    let text = crate::step::step_text("x.step", &[(&r).into()]);
    assert!(text.contains("RATIONAL_B_SPLINE_SURFACE("), "{text}");
    assert!(text.contains("RATIONAL_B_SPLINE_CURVE("), "{text}");
    let faces = read_step(&text).unwrap();
    assert_eq!(faces[0].kind, "rational B-spline");
    let FaceSurface::Rational(back) = &faces[0].surface else {
        panic!("rational")
    };
    assert_eq!(back.net(), r.net());
    for (a, b) in back.weights().iter().zip(r.weights()) {
        assert!((a - b).abs() < 1e-15);
    }
    let e = read_step_faces(&text).unwrap_err().to_string();
    assert!(e.contains("a rational B-spline face"), "{e}");
}

/// `guarded` returns the value, or what a panic said and where (this
/// file's name, not a local path), and guards nest: an inner panic is the
/// inner guard's, and the outer one still reports its own after it.
#[test]
fn guarded_reports_a_panic_as_its_message_and_place() {
    assert_eq!(super::guarded(|| 5), Ok(5));
    let e = super::guarded(|| -> u8 { panic!("the axis is {}", "zero") }).unwrap_err();
    assert!(e.starts_with("the axis is zero ("), "{e}");
    assert!(e.contains("step_read/tests.rs:"), "{e}");
    let e = super::guarded(|| {
        let inner = super::guarded(|| -> u8 { panic!("inner") }).unwrap_err();
        assert!(inner.starts_with("inner ("), "{inner}");
        panic!("outer")
    })
    .unwrap_err();
    assert!(e.starts_with("outer ("), "{e}");
}

/// The range of angles a trimmed surface of revolution is written over
/// (`periodic_range`): the widest gap between its edges' points that no
/// edge runs through and that the edges at its ends turn the face away
/// from is left out, across the turn from 2π to 0 too, and the rest widened
/// by 2% each way; none when no gap is left out (all the way round).
#[test]
fn angles_are_ranged_on_the_face_s_side() {
    use std::f64::consts::TAU;
    // Equal ranges, up to whole turns.
    let close = |a: (f64, f64), b: (f64, f64)| {
        let turns = ((a.0 - b.0) / TAU).round() * TAU;
        let a = (a.0 - turns, a.1 - turns);
        assert!(
            (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12,
            "{a:?} vs {b:?}"
        );
    };
    // An edge's points from `a` to `b` (9 of them), the face turned by
    // `rate` from it.
    let edge = |e: usize, a: f64, b: f64, rate: f64| -> Vec<(f64, usize, f64)> {
        (0..=8)
            .map(|k| (a + (b - a) * k as f64 / 8.0, e, rate))
            .collect()
    };
    // Two meridians at 1 and 2 rad (any turn), the face between them.
    let between = [edge(0, 1.0, 1.0, 1.0), edge(1, 2.0 + TAU, 2.0 + TAU, -1.0)].concat();
    close(periodic_range(&between).unwrap(), (1.0 - 0.02, 2.0 + 0.02));
    // The same meridians with the face outside them: the 1 rad between is
    // left out, the other 2π − 1 taken (its margin at most a quarter gap).
    let outside = [edge(0, 1.0, 1.0, -1.0), edge(1, 2.0, 2.0, 1.0)].concat();
    let most = TAU - 1.0;
    close(
        periodic_range(&outside).unwrap(),
        (2.0 - 0.02 * most, 2.0 + 1.02 * most),
    );
    // Across 0: an arc from 2π − 0.5 to 2π + 0.5 along the face (rate 0).
    let arc = edge(0, TAU - 0.5, TAU + 0.5, 0.0);
    close(periodic_range(&arc).unwrap(), (TAU - 0.52, TAU + 0.52));
    // A whole circle in 8 steps: every gap is run through: none.
    assert_eq!(periodic_range(&edge(0, 0.0, TAU, 0.0)), None);
    // A seam's two sides (the face turned away from it both ways) and a
    // hole from 2 to 3 rad (arcs along it, its meridians turning the face
    // away from it): no gap the face does not reach.
    let seam = [edge(0, 0.0, 0.0, 1.0), edge(1, 0.0, 0.0, -1.0)].concat();
    let hole = [
        edge(2, 2.0, 3.0, 0.0),
        edge(3, 3.0, 3.0, 1.0),
        edge(4, 3.0, 2.0, 0.0),
        edge(5, 2.0, 2.0, -1.0),
    ]
    .concat();
    assert_eq!(periodic_range(&[seam, hole.clone()].concat()), None);
    // The hole alone (a face all round but for it, no seam): none either.
    assert_eq!(periodic_range(&hole), None);
    // A face between 1 and 2 rad whose side edge meets the meridian at 2
    // at an acute corner: its direction into the face points across the
    // meridian there (rate 0.3), the meridian's inside away from the gap.
    let acute = [
        edge(0, 1.0, 1.0, 1.0),
        edge(1, 1.0, 2.0, 0.3),
        edge(2, 2.0, 2.0, -1.0),
        edge(3, 2.0, 1.0, 0.0),
    ]
    .concat();
    close(periodic_range(&acute).unwrap(), (1.0 - 0.02, 2.0 + 0.02));
}
