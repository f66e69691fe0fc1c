//! Planes, cylinders, cones, spheres and tori bounded by four edges, as
//! exact (rational) B-splines: bilinear patches, ruled surfaces between two
//! arcs, surfaces of revolution.

use super::*;

/// A plane face bounded by four straight edges: the bilinear patch of its
/// corners (exactly the face when the quadrilateral is convex).
pub(super) fn plane(edges: &[LoopEdge]) -> std::result::Result<FaceSurface, String> {
    let tol = loop_tolerance(edges);
    let straight = edges.iter().filter(|e| e.straight(tol)).count();
    if edges.len() != 4 || straight != 4 {
        let n = edges.len();
        return Err(format!(
            "a plane face bounded by {n} edge{}{}: only planes bounded by four straight edges \
             are filled around so far",
            if n == 1 { "" } else { "s" },
            match (n, straight) {
                (1, 0) => ", not straight".to_string(),
                (n, s) if s < n => format!(", {} not straight", n - s),
                _ => String::new(),
            }
        ));
    }
    let c: Vec<Vec3> = edges.iter().map(|e| e.start).collect();
    // A convex quadrilateral: the turn at every corner the same way.
    let turn = |k: usize| {
        let (a, b, d) = (c[(k + 3) % 4], c[k], c[(k + 1) % 4]);
        fairsurf::vector::cross(fairsurf::vector::sub(b, a), fairsurf::vector::sub(d, b))
    };
    let n0 = turn(0);
    if (1..4).any(|k| fairsurf::vector::dot(turn(k), n0) <= 0.0) {
        return Err("a plane face whose four corners are not a convex quadrilateral".into());
    }
    let net = BSplineSurface::new(
        KnotVector::bezier(1),
        KnotVector::bezier(1),
        vec![c[0], c[3], c[1], c[2]],
    )
    .map_err(|e| e.to_string())?;
    Ok(FaceSurface::Polynomial(net))
}

/// Control points, weights and full knot vector of a rational curve.
pub(super) type Arc = (Vec<Vec3>, Vec<f64>, Vec<f64>);

/// A circular arc as a rational quadratic B-spline (The NURBS Book
/// §7.5): pieces of at most 90°, each with its end points, the meeting
/// point of its end tangents, and weights 1, cos(φ/2), 1; double interior
/// knots. Control points, weights, full knot vector.
pub(super) fn arc(e: &LoopEdge) -> std::result::Result<Arc, String> {
    arc_along(|s| e.at(s), e.turning().1)
}

/// [`arc`] of the arc whose point and derivative at s ∈ [0, 1] are
/// `at(s)`, in `pieces` equal pieces (each of at most 90°).
pub(super) fn arc_along(
    at: impl Fn(f64) -> (Vec3, Vec3),
    pieces: usize,
) -> std::result::Result<Arc, String> {
    let (mut points, mut weights) = (vec![at(0.0).0], vec![1.0]);
    let mut knots = vec![0.0; 3];
    for k in 0..pieces {
        let (s0, s1) = (k as f64 / pieces as f64, (k + 1) as f64 / pieces as f64);
        let ((p0, t0), (p2, t2)) = (at(s0), at(s1));
        // p0 + a t0 = p2 - b t2, least squares in (a, b).
        let r = fairsurf::vector::sub(p2, p0);
        let dot = fairsurf::vector::dot;
        let (g11, g12, g22) = (dot(t0, t0), dot(t0, t2), dot(t2, t2));
        let (r1, r2) = (dot(t0, r), dot(t2, r));
        let det = g11 * g22 - g12 * g12;
        if det.abs() <= 1e-12 * g11 * g22 {
            return Err("an edge that is neither straight nor an arc of less than 360°".into());
        }
        let a = (r1 * g22 - r2 * g12) / det;
        let p1 = fairsurf::vector::add(p0, fairsurf::vector::scale(t0, a));
        let phi = fairsurf::vector::angle(t0, t2);
        points.extend([p1, p2]);
        weights.extend([(phi / 2.0).cos(), 1.0]);
        let t = s1;
        knots.extend(if k + 1 == pieces {
            vec![1.0; 3]
        } else {
            vec![t, t]
        });
    }
    Ok((points, weights, knots))
}

/// A cylinder or cone face bounded by two circular arcs and two straight
/// rulings: the rational ruled surface between the two arcs (exact when
/// the arcs are coaxial circles, checked against the face's edges).
pub(super) fn ruled(edges: &[LoopEdge]) -> std::result::Result<FaceSurface, String> {
    let tol = loop_tolerance(edges);
    let straight: Vec<bool> = edges.iter().map(|e| e.straight(tol)).collect();
    let refuse = || {
        format!(
            "a cylinder or cone face bounded by {} edges that are not two arcs and two rulings, \
             alternating: only such faces are filled around so far",
            edges.len()
        )
    };
    if edges.len() != 4 {
        return Err(refuse());
    }
    let Some(first) = (0..4).find(|&k| !straight[k] && straight[(k + 1) % 4]) else {
        return Err(refuse());
    };
    if straight[(first + 2) % 4] || !straight[(first + 3) % 4] {
        return Err(refuse());
    }
    let a = &edges[first];
    let b = &edges[(first + 2) % 4];
    let (pa, wa, knots) = arc(a)?;
    // B runs against A in the loop: its arc from its end to its start.
    let (pb, wb, kb) = arc(&b.reversed())?;
    if pa.len() != pb.len() || kb != knots || wa.iter().zip(&wb).any(|(x, y)| (x - y).abs() > 1e-9)
    {
        return Err("a cylinder or cone face whose two arcs do not turn by the same angle".into());
    }
    let points: Vec<Vec3> = pa.iter().zip(&pb).flat_map(|(p, q)| [*p, *q]).collect();
    let weights: Vec<f64> = wa.iter().flat_map(|&w| [w, w]).collect();
    let u = KnotVector::new(2, knots).map_err(|e| e.to_string())?;
    let net = BSplineSurface::new(u, KnotVector::bezier(1), points).map_err(|e| e.to_string())?;
    let r = RationalSurface::new(net, weights).map_err(|e| e.to_string())?;
    // The arcs as built lie on the file's edges.
    for k in 0..=16 {
        let u = k as f64 / 16.0;
        for (v, e) in [(0.0, a), (1.0, b)] {
            let d = e.distance(r.eval(u, v));
            if d > tol {
                return Err(format!(
                    "a face edge that is not a circular arc (off the arc through its ends and \
                     tangents by {d:e})"
                ));
            }
        }
    }
    Ok(FaceSurface::Rational(r))
}

/// The circle an arc edge lies on: centre, unit normal (the arc's turning
/// sense), radius — through its ends and middle.
pub(super) fn circle_of(e: &LoopEdge) -> Option<(Vec3, Vec3, f64)> {
    use fairsurf::vector::{add, cross, dot, normalize, scale, sub};
    let (a, b, c) = (e.start, e.at(0.5).0, e.end);
    let (ab, ac) = (sub(b, a), sub(c, a));
    let n = cross(ab, ac);
    let nn = dot(n, n);
    if nn.is_nan() || nn <= 1e-24 * dot(ab, ab) * dot(ac, ac) {
        return None;
    }
    // Circumcentre: a + (|ab|² (ac × n) + |ac|² (n × ab)) / (2|n|²).
    let centre = add(
        a,
        scale(
            add(
                scale(cross(ac, n), dot(ab, ab)),
                scale(cross(n, ab), dot(ac, ac)),
            ),
            0.5 / nn,
        ),
    );
    Some((centre, normalize(n)?, dist(centre, a)))
}

/// p turned by `angle` about the axis through `o` along the unit vector
/// `k` (Rodrigues).
pub(super) fn rotated(p: Vec3, o: Vec3, k: Vec3, angle: f64) -> Vec3 {
    use fairsurf::vector::{add, cross, dot, scale, sub};
    let v = sub(p, o);
    let (s, c) = angle.sin_cos();
    add(
        o,
        add(
            add(scale(v, c), scale(cross(k, v), s)),
            scale(k, dot(k, v) * (1.0 - c)),
        ),
    )
}

/// A sphere or torus face bounded by four circular arcs — two parallels
/// (circles about the surface's axis) and two meridians — or a sphere
/// face bounded by one parallel and two meridians meeting at a pole, as
/// the rational biquadratic surface of revolution of one meridian (The
/// NURBS Book §8.5, algorithm A8.1; at a pole a side collapsed to a
/// point). The axis is the parallel's normal through its centre; the
/// result is checked against the face's edges (and, by the caller,
/// against the file's surface).
pub(super) fn revolved(edges: &[LoopEdge], kind: &str) -> std::result::Result<FaceSurface, String> {
    use fairsurf::vector::{cross, norm, sub};
    let tol = edge_tolerance(edges);
    let refuse = |why: &str| {
        format!(
            "a {kind} face {why}: only {kind} faces bounded by two parallels and two meridians \
             (four circular arcs), or by a parallel and two meridians through a pole, are \
             filled around so far"
        )
    };
    let circles: Vec<(Vec3, Vec3, f64)> = edges
        .iter()
        .map(circle_of)
        .collect::<Option<_>>()
        .ok_or_else(|| refuse("with a straight edge"))?;
    // The parallels to try, each with the meridian that ends at its start
    // as the profile. Four arcs: opposite ones with parallel normals whose
    // centres lie on one line along them, apart or of different radii.
    let candidates: Vec<usize> = match edges.len() {
        3 => vec![0, 1, 2],
        4 => {
            let parallel = |a: usize, b: usize| {
                let ((ca, na, ra), (cb, nb, rb)) = (circles[a], circles[b]);
                let d = sub(cb, ca);
                norm(cross(na, nb)) <= 1e-9
                    && norm(cross(d, na)) <= tol
                    && (norm(d) > tol || (ra - rb).abs() > tol)
            };
            match (parallel(0, 2), parallel(1, 3)) {
                (true, _) => vec![2],
                (_, true) => vec![1],
                _ => return Err(refuse("whose arcs are not two parallels and two meridians")),
            }
        }
        n => return Err(refuse(&format!("bounded by {n} edges"))),
    };
    let n = edges.len();
    let mut missed = f64::INFINITY;
    for along in candidates {
        let profile = &edges[(along + n - 1) % n];
        let Ok(r) = revolve(profile, &edges[along], circles[along]) else {
            continue;
        };
        // Its four sides lie on the face's edges.
        let off = (0..=16)
            .flat_map(|i| {
                let t = i as f64 / 16.0;
                [(t, 0.0), (t, 1.0), (0.0, t), (1.0, t)]
            })
            .map(|(a, b)| {
                let p = r.eval(a, b);
                edges.iter().map(|e| e.distance(p)).fold(f64::MAX, f64::min)
            })
            .fold(0.0, f64::max);
        if off <= tol {
            return Ok(FaceSurface::Rational(r));
        }
        missed = missed.min(off);
    }
    Err(refuse(&format!(
        "whose edges the surface of revolution misses by {missed:e}"
    )))
}

/// The surface swept by the arc `profile` about the axis of the arc
/// `along` (its circle: centre, unit normal, radius), which starts at the
/// profile's end, through `along`'s angle ([`revolve_arc`]).
pub(super) fn revolve(
    profile: &LoopEdge,
    along: &LoopEdge,
    (o, k, _): (Vec3, Vec3, f64),
) -> std::result::Result<RationalSurface, String> {
    // The circle's normal turns with the arc (circle_of): a positive turn.
    revolve_arc(&arc(profile)?, o, k, along.turning().0)
}

/// The surface swept by a rational profile curve (control points,
/// weights, full knot vector; its degree what their counts say) turned
/// about the axis through `o` along the unit vector `k` by `turning`
/// radians (right-handed about k): control points and weights of the
/// profile swept in pieces of at most 90° (the middle points pushed out by
/// 1/cos(φ/2), weights multiplied), u about the axis, v along the
/// profile (The NURBS Book §8.5, algorithm A8.1).
pub(super) fn revolve_arc(
    (q, v, kv): &Arc,
    o: Vec3,
    k: Vec3,
    turning: f64,
) -> std::result::Result<RationalSurface, String> {
    use fairsurf::vector::{add, dot, scale, sub};
    let pieces = ((turning / std::f64::consts::FRAC_PI_2) - 1e-9)
        .ceil()
        .max(1.0) as usize;
    let step = turning / pieces as f64;
    let half = (step / 2.0).cos();
    let (mut points, mut weights) = (Vec::new(), Vec::new());
    let mut ku = vec![0.0; 3];
    for i in 0..=2 * pieces {
        let middle = i % 2 == 1;
        for (qj, vj) in q.iter().zip(v) {
            // The control point about the axis at its own height, pushed to
            // the tangents' meeting point in the middle of a piece.
            let foot = add(o, scale(k, dot(sub(*qj, o), k)));
            let mut p = rotated(*qj, o, k, step * i as f64 / 2.0);
            if middle {
                p = add(foot, scale(sub(p, foot), 1.0 / half));
            }
            points.push(p);
            weights.push(vj * if middle { half } else { 1.0 });
        }
        if i % 2 == 0 && i > 0 && i < 2 * pieces {
            let t = i as f64 / (2 * pieces) as f64;
            ku.extend([t, t]);
        }
    }
    ku.extend([1.0; 3]);
    let degree = kv
        .len()
        .checked_sub(q.len() + 1)
        .ok_or("a profile with fewer knots than its points need")?;
    let u = KnotVector::new(2, ku).map_err(|e| e.to_string())?;
    let vk = KnotVector::new(degree, kv.clone()).map_err(|e| e.to_string())?;
    let net = BSplineSurface::new(u, vk, points).map_err(|e| e.to_string())?;
    RationalSurface::new(net, weights).map_err(|e| e.to_string())
}
