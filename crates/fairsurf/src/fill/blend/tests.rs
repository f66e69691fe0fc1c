//! Blends: a clamped blend of a ruled surface is the missing piece; a free
//! blend is G¹ and minimal; corners are paired and a flipped neighbour turned;
//! the default bulges give the least W; bad blends are refused.

use super::*;
use crate::bspline::BSplineProblem;
use crate::Bend;

/// S(u, v) = a(u) + v·b(u) on [0, 2] × [0, 3], a and b cubics
/// (knots inserted at 0.5 and 1.3: three uneven spans): ruled, and
/// biharmonic (Δ²S = 0, with no jumps of S_uuu at the knots).
fn ruled() -> BSplineSurface {
    let u = KnotVector::new(3, vec![0., 0., 0., 0., 2., 2., 2., 2.]).unwrap();
    let v = KnotVector::new(1, vec![0., 0., 3., 3.]).unwrap();
    let pts = (0..4)
        .flat_map(|i| {
            let x = i as f64 * 0.7;
            let a = [x, 0.1 * x * x, 0.3 * (1.7 * x).sin()];
            let b = [0.2 * x, 1.0 + 0.1 * x, 0.4 * (1.1 * x).cos()];
            [a, add(a, scale(b, 3.0))]
        })
        .collect();
    let s = BSplineSurface::new(u, v, pts).unwrap();
    s.insert_knot_u(0.5).unwrap().insert_knot_u(1.3).unwrap()
}

/// The ruled surface cut at v = 1 and v = 2: (A, middle, B).
fn ruled_in_three() -> (BSplineSurface, BSplineSurface, BSplineSurface) {
    let (a, rest) = ruled().split_v(1.0).unwrap();
    let (m, b) = rest.split_v(2.0).unwrap();
    (a, m, b)
}

fn plain() -> FillOptions {
    FillOptions {
        normal_weight: 0.0,
        willmore_steps: 0,
        descent_steps: 0,
        ..FillOptions::default()
    }
}

/// The blend's normal against a surface's at the same points,
/// evaluated afresh (not through the report's sampling).
fn largest_angle(blend: &Blend, k: usize, face: &BSplineSurface, flip: bool) -> f64 {
    let side = blend.sides[k / 2];
    (0..=40)
        .map(|i| {
            let t = i as f64 / 40.0;
            let (u, v) = super::super::fill_param(k, t);
            let d = blend.surface.derivatives(u, v);
            let tt = if side.reversed { 1.0 - t } else { t };
            let mut n = normal_at(face, side.edge, tt);
            if flip {
                n = scale(n, -1.0);
            }
            let p = super::super::edge_point(face, side.edge, tt);
            assert!(dist(p, d.point) < 1e-12, "gap at t = {t}");
            crate::vec3::angle(cross(d.du, d.dv), n)
        })
        .fold(0.0, f64::max)
}

/// Clamped on all four sides, the blend of a ruled bicubic cut in three
/// is the missing middle piece (α = 1 exactly, the made sides are its
/// straight sides), with the plain thin plate and with the Coons normal
/// field (the Hermite–Coons patch reproduces the piece, so its normals
/// are the piece's).
#[test]
fn a_clamped_blend_of_a_ruled_surface_is_the_missing_piece() {
    let (a, m, b) = ruled_in_three();
    for weight in [0.0, 100.0] {
        let options = BlendOptions {
            fill: FillOptions {
                normal_weight: weight,
                ..plain()
            },
            bulge: Bulge::Fixed([1.0, 1.0]),
            clamp_sides: true,
        };
        let bl = blend(&a, Edge::V1, &b, Edge::V0, &options).unwrap();
        assert!(!bl.report.flipped);
        assert!(!bl.sides[0].reversed);
        for x in bl.report.alpha {
            assert!((x - 1.0).abs() < 1e-13, "{x}");
        }
        for i in 0..=10 {
            for j in 0..=10 {
                let (u, v) = (i as f64 / 10.0, j as f64 / 10.0);
                let want = m.eval(2.0 * u, 1.0 + v);
                let got = bl.surface.eval(u, v);
                assert!(
                    dist(want, got) < 1e-11,
                    "λ {weight} ({u}, {v}): {got:?} {want:?}"
                );
            }
        }
    }
}

/// Free sides: the blend is G¹ to both surfaces to rounding — checked
/// by fresh evaluation — and the thin plate's minimizer: any free
/// point moved raises the energy.
#[test]
fn a_free_blend_is_g1_and_minimal() {
    let (a, _, b) = ruled_in_three();
    let options = BlendOptions {
        fill: plain(),
        bulge: Bulge::Fixed([1.0, 1.0]),
        ..BlendOptions::default()
    };
    let bl = blend(&a, Edge::V1, &b, Edge::V0, &options).unwrap();
    for (k, face) in [(0, &a), (2, &b)] {
        assert!(largest_angle(&bl, k, face, false).to_degrees() < 1e-9);
    }
    for f in &bl.report.sides {
        assert!(f.gap < 1e-12 && f.angle.to_degrees() < 1e-9, "{f:?}");
    }
    let c = bl.report.corners;
    assert!(c.position < 1e-13 && c.tangent < 1e-13, "{c:?}");
    let (cu, cv) = bl.surface.counts();
    let free: Vec<bool> = (0..cu * cv)
        .map(|k| {
            let (i, j) = (k / cv, k % cv);
            i > 0 && i + 1 < cu && j > 1 && j + 2 < cv
        })
        .collect();
    let problem = BSplineProblem::from_surface(bl.surface.clone())
        .with_free(free.clone())
        .unwrap()
        .with_term(Bend::new(1.0));
    let e0 = problem.energy_at(&bl.surface).unwrap();
    let mut raised = 0;
    for k in (0..cu * cv).filter(|&k| free[k]) {
        for c in 0..3 {
            for h in [1e-4, -1e-4] {
                let mut pts = bl.surface.points().to_vec();
                pts[k][c] += h;
                let (ku, kv) = bl.surface.knots();
                let moved = BSplineSurface::new(ku.clone(), kv.clone(), pts).unwrap();
                assert!(
                    problem.energy_at(&moved).unwrap() > e0,
                    "point {k} coordinate {c} by {h}"
                );
                raised += 1;
            }
        }
    }
    assert!(raised >= 6 * 2 * 4, "{raised}");
    // Free sides are fairer than clamped ones.
    let clamped = blend(
        &a,
        Edge::V1,
        &b,
        Edge::V0,
        &BlendOptions {
            clamp_sides: true,
            ..options
        },
    )
    .unwrap();
    assert!(e0 < problem.energy_at(&clamped.surface).unwrap());
}

/// Between faces of other degrees and knots, B given with its edge
/// the other way round and its normal facing the other way: corners
/// still pair, G¹ holds to rounding with B's turned normal, W falls
/// with the default steps.
#[test]
fn a_blend_pairs_corners_and_turns_a_flipped_neighbour() {
    let (a, _, b) = ruled_in_three();
    // B with u reversed: its V0 edge runs the other way and its
    // normal S_u × S_v turns.
    let (ku, kv) = b.knots();
    let (cu, cv) = b.counts();
    let mirrored: Vec<f64> = ku.knots().iter().rev().map(|&t| 2.0 - t).collect();
    let pts = (0..cu * cv)
        .map(|k| b.point(cu - 1 - k / cv, k % cv))
        .collect();
    let b2 = BSplineSurface::new(KnotVector::new(3, mirrored).unwrap(), kv.clone(), pts)
        .unwrap()
        .elevated(1, 2)
        .unwrap();
    let one = BlendOptions {
        bulge: Bulge::Fixed([1.0, 1.0]),
        ..BlendOptions::default()
    };
    let bl = blend(&a, Edge::V1, &b2, Edge::V0, &one).unwrap();
    assert!(bl.report.flipped);
    // B's edge runs along A's now: traversed along u (not against it,
    // a hole's convention for side 2) where the unmirrored one is not.
    assert_eq!((bl.sides[0].reversed, bl.sides[1].reversed), (false, false));
    assert!(largest_angle(&bl, 0, &a, false).to_degrees() < 1e-9);
    assert!(largest_angle(&bl, 2, &b2, true).to_degrees() < 1e-9);
    let w = &bl.report.willmore;
    // The steps lowered W, each kept one by itself.
    assert!(
        w.len() >= 2
            && w.iter().cloned().fold(f64::MAX, f64::min) < w[0]
            && w.windows(2).take(w.len() - 2).all(|x| x[1] < x[0]),
        "{w:?}"
    );
    assert!((bl.report.curvature.value - w.iter().cloned().fold(f64::MAX, f64::min)).abs() < 1e-15);
    // B unmirrored: not flipped, its edge traversed against u.
    let same = blend(&a, Edge::V1, &b, Edge::V0, &one).unwrap();
    assert!(!same.report.flipped);
    assert_eq!(
        (same.sides[0].reversed, same.sides[1].reversed),
        (false, true)
    );
}

/// The default bulges are W's least: no lower than at (1, 1), and
/// moving either by 5% does not lower W by more than the search's
/// tolerance.
#[test]
fn the_default_bulges_have_the_least_w() {
    let (a, _, b) = ruled_in_three();
    // A bent B: the blend must turn, and W depends on the bulges.
    let (ku, kv) = b.knots();
    let pts = b
        .points()
        .iter()
        .map(|p| [p[0], p[1], p[2] + 0.6 * (p[1] - 2.0)])
        .collect();
    let b = BSplineSurface::new(ku.clone(), kv.clone(), pts).unwrap();
    // The search compares thin-plate blends: so do these.
    let opts = |bulge| BlendOptions {
        fill: FillOptions {
            willmore_steps: 0,
            descent_steps: 0,
            ..FillOptions::default()
        },
        bulge,
        clamp_sides: false,
    };
    let least = blend(&a, Edge::V1, &b, Edge::V0, &opts(Bulge::Least)).unwrap();
    let r = &least.report;
    let search = r.bulge_search.unwrap();
    let w = r.curvature.value;
    assert!(search.evaluations >= 4 && search.evaluations <= BULGE_EVALUATIONS);
    assert!(w <= search.w_at_one, "{w} {}", search.w_at_one);
    assert!(
        w < 0.999 * search.w_at_one,
        "the search found nothing: {w} {search:?}"
    );
    for (k, f) in [(0, 1.05), (0, 0.95), (1, 1.05), (1, 0.95)] {
        let mut moved = r.bulge;
        moved[k] *= f;
        let other = blend(&a, Edge::V1, &b, Edge::V0, &opts(Bulge::Fixed(moved))).unwrap();
        let wo = other.report.curvature.value;
        assert!(wo >= w * (1.0 - 1e-6), "bulge {moved:?}: W {wo} < {w}");
    }
    // G1 holds whatever the bulges.
    for f in &r.sides {
        assert!(f.gap < 1e-12 && f.angle.to_degrees() < 1e-9, "{f:?}");
    }
}

#[test]
fn bad_blends_are_refused() {
    let (a, m, b) = ruled_in_three();
    let bad_bulge = BlendOptions {
        bulge: Bulge::Fixed([1.0, 0.0]),
        ..BlendOptions::default()
    };
    let e = blend(&a, Edge::V1, &b, Edge::V0, &bad_bulge).unwrap_err();
    assert!(e.to_string().contains("bulge 1 is 0"), "{e}");
    // A and the middle piece touch along the whole edge.
    let e = blend(&a, Edge::V1, &m, Edge::V0, &BlendOptions::default()).unwrap_err();
    assert!(e.to_string().contains("meet at their first corner"), "{e}");
    // An edge collapsed to a point (a cone's apex row) is no edge.
    let u = KnotVector::bezier(2);
    let pts = (0..9)
        .map(|k| {
            let (i, j) = ((k / 3) as f64, (k % 3) as f64);
            if i == 0.0 {
                [0.0, 0.0, 5.0]
            } else {
                [i, j, 5.0]
            }
        })
        .collect();
    let cone = BSplineSurface::new(u.clone(), u, pts).unwrap();
    let e = blend(&cone, Edge::U0, &b, Edge::V0, &BlendOptions::default()).unwrap_err();
    assert!(
        e.to_string().contains("surface A's edge U0 is collapsed"),
        "{e}"
    );
    let e = blend(&b, Edge::V0, &cone, Edge::U0, &BlendOptions::default()).unwrap_err();
    assert!(
        e.to_string().contains("surface B's edge U0 is collapsed"),
        "{e}"
    );
}
