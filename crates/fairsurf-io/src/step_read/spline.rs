//! B-spline and NURBS faces: the file's surface, closest points on it, the
//! part of it the loop bounds, and its orientation against the face.

use super::*;

/// A B-spline or NURBS surface of the file.
pub(super) fn spline(s: &StepSurface) -> std::result::Result<(&'static str, FaceSurface), String> {
    type Net = Vec<Vec<Vec3>>;
    type Knots = (Vec<f64>, Vec<f64>);
    let (knots, points, weights): (Knots, Net, Option<Vec<f64>>) = match s {
        StepSurface::BSplineSurface(b) => (
            (b.uknot_vec().to_vec(), b.vknot_vec().to_vec()),
            b.control_points()
                .iter()
                .map(|row| row.iter().map(|p| v3(*p)).collect())
                .collect(),
            None,
        ),
        StepSurface::NurbsSurface(n) => {
            let b = n.non_rationalized();
            let cp = b.control_points();
            if cp.iter().flatten().any(|p| !(p.w.is_finite() && p.w > 0.0)) {
                return Err("a rational B-spline face with a weight that is not positive".into());
            }
            (
                (b.uknot_vec().to_vec(), b.vknot_vec().to_vec()),
                cp.iter()
                    .map(|row| {
                        row.iter()
                            .map(|p| [p.x / p.w, p.y / p.w, p.z / p.w])
                            .collect()
                    })
                    .collect(),
                Some(cp.iter().flatten().map(|p| p.w).collect()),
            )
        }
        _ => unreachable!("called for B-spline surfaces"),
    };
    let (cu, cv) = (points.len(), points.first().map_or(0, Vec::len));
    if points.iter().any(|r| r.len() != cv) {
        return Err(format!(
            "a control net of {cu} rows that are not all {cv} long"
        ));
    }
    if cu < 2 || cv < 2 {
        return Err(format!(
            "a control net of {cu} × {cv} points: a surface needs at least 2 × 2"
        ));
    }
    let (p, q) = (
        knots.0.len().saturating_sub(cu + 1),
        knots.1.len().saturating_sub(cv + 1),
    );
    let kv = |d: usize, k: Vec<f64>, name: &str| {
        KnotVector::new(d, k).map_err(|e| format!("its {name} knots: {e}"))
    };
    let u = kv(p, knots.0, "u")?;
    let v = kv(q, knots.1, "v")?;
    let net = BSplineSurface::new(u, v, points.into_iter().flatten().collect())
        .map_err(|e| e.to_string())?;
    match weights {
        None => Ok(("B-spline", FaceSurface::Polynomial(net))),
        Some(w) => {
            let r = RationalSurface::new(net, w).map_err(|e| e.to_string())?;
            Ok(if r.is_polynomial() {
                ("B-spline", FaceSurface::Polynomial(r.net().clone()))
            } else {
                ("rational B-spline", FaceSurface::Rational(r))
            })
        }
    }
}

pub(super) fn eval(s: &FaceSurface, u: f64, v: f64) -> Vec3 {
    match s {
        FaceSurface::Polynomial(b) => b.eval(u, v),
        FaceSurface::Rational(r) => r.eval(u, v),
    }
}

pub(super) fn net(s: &FaceSurface) -> &BSplineSurface {
    match s {
        FaceSurface::Polynomial(b) => b,
        FaceSurface::Rational(r) => r.net(),
    }
}

pub(super) fn derivatives(s: &FaceSurface, u: f64, v: f64) -> fairsurf::SurfaceDerivatives {
    match s {
        FaceSurface::Polynomial(b) => b.derivatives(u, v),
        FaceSurface::Rational(r) => r.derivatives(u, v),
    }
}

/// A 17 × 17 grid of a surface's domain and its points there: where every
/// nearest-point search on the face starts ([`nearest`]), evaluated once
/// per face.
pub(super) struct Seeds {
    us: Vec<f64>,
    vs: Vec<f64>,
    points: Vec<Vec3>,
}

impl Seeds {
    pub(super) fn new(s: &FaceSurface) -> Self {
        Self::of(s, 16)
    }

    /// The (n + 1) × (n + 1) grid.
    pub(super) fn of(s: &FaceSurface, n: usize) -> Self {
        let (ku, kv) = net(s).knots();
        let ((a, b), (c, d)) = (ku.domain(), kv.domain());
        let us: Vec<f64> = (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect();
        let vs: Vec<f64> = (0..=n).map(|j| c + (d - c) * j as f64 / n as f64).collect();
        let grid = match s {
            FaceSurface::Polynomial(b) => b.derivatives_on(&us, &vs),
            FaceSurface::Rational(r) => r.derivatives_on(&us, &vs),
        };
        let points = grid.iter().map(|g| g.point).collect();
        Seeds { us, vs, points }
    }
}

/// The parameters of the point of `s` nearest to p, and the distance: the
/// best of the grid `seeds` (of `s`), then Newton steps on
/// (S − p)·S_u = (S − p)·S_v = 0 kept in the domain.
pub(super) fn nearest(s: &FaceSurface, seeds: &Seeds, p: Vec3) -> ((f64, f64), f64) {
    let (ku, kv) = net(s).knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    let (mut best, mut at) = (f64::MAX, (a, c));
    for (k, q) in seeds.points.iter().enumerate() {
        let e = dist(*q, p);
        if e < best {
            let n = seeds.vs.len();
            (best, at) = (e, (seeds.us[k / n], seeds.vs[k % n]));
        }
    }
    foot(&|u, v| derivatives(s, u, v), p, at, best, ((a, b), (c, d)))
}

/// Newton steps on (S − p)·S_u = (S − p)·S_v = 0 from `at` (at `best`
/// from p), kept in `domain`, while they bring the point closer and until
/// a step moves the parameters by at most 1e-12 (relative; the steps after
/// that only crept at rounding level: 1,275 → 875 surface evaluations on
/// the bench's bi-quintic network): the parameters of the foot of p and its
/// distance.
pub(super) fn foot(
    s: &dyn Fn(f64, f64) -> fairsurf::SurfaceDerivatives,
    p: Vec3,
    mut at: (f64, f64),
    mut best: f64,
    ((a, b), (c, d)): ((f64, f64), (f64, f64)),
) -> ((f64, f64), f64) {
    let dot = fairsurf::vector::dot;
    // The derivatives at `at`, kept from the step that found it.
    let mut x = s(at.0, at.1);
    // Where the steps started, kept if they end farther (a start on a
    // collapsed side, a pole, is moved a little inside once: no step can
    // leave it).
    let start = (at, best);
    let mut nudged = false;
    for _ in 0..40 {
        let (u, v) = at;
        let r = fairsurf::vector::sub(x.point, p);
        let (f1, f2) = (dot(r, x.du), dot(r, x.dv));
        let a11 = dot(x.du, x.du) + dot(r, x.duu);
        let a12 = dot(x.du, x.dv) + dot(r, x.duv);
        let a22 = dot(x.dv, x.dv) + dot(r, x.dvv);
        let det = a11 * a22 - a12 * a12;
        // Singular to rounding (at a pole S_u is 1e-16, not 0).
        let singular = det.is_nan() || det.abs() <= 1e-12 * (a11.abs() * a22.abs() + a12 * a12);
        if singular && !nudged {
            nudged = true;
            let inside = |t: f64, lo: f64, hi: f64| t + 1e-3 * ((lo + hi) / 2.0 - t);
            at = (inside(u, a, b), inside(v, c, d));
            x = s(at.0, at.1);
            best = dist(x.point, p);
            continue;
        }
        if det == 0.0 || det.is_nan() {
            break;
        }
        let next = (
            (u - (a22 * f1 - a12 * f2) / det).clamp(a, b),
            (v - (a11 * f2 - a12 * f1) / det).clamp(c, d),
        );
        let y = s(next.0, next.1);
        let e = dist(y.point, p);
        if e.is_nan() || e >= best {
            break;
        }
        let converged = (next.0 - u).abs() <= 1e-12 * (1.0 + u.abs())
            && (next.1 - v).abs() <= 1e-12 * (1.0 + v.abs());
        (best, at, x) = (e, next, y);
        if converged {
            break;
        }
    }
    if start.1 < best {
        start
    } else {
        (at, best)
    }
}

/// A surface's four sides as written: per side (v = c, v = d, u = a,
/// u = b) its knots mapped onto [0, 1] and its row of control points, and
/// the rounding under which two control points are one (1e-12 of the
/// net's largest coordinate, at least 1e-12).
pub(super) struct SideRows {
    rows: [(Vec<f64>, Vec<Vec3>); 4],
    rounding: f64,
}

impl SideRows {
    pub(super) fn of(p: &BSplineSurface) -> Self {
        let (ku, kv) = p.knots();
        let (nu, nv) = p.counts();
        let (u, v) = (unit(ku.knots()), unit(kv.knots()));
        let size = p
            .points()
            .iter()
            .flatten()
            .fold(1.0f64, |m, x| m.max(x.abs()));
        Self {
            rows: [
                (u.clone(), (0..nu).map(|i| p.point(i, 0)).collect()),
                (u, (0..nu).map(|i| p.point(i, nv - 1)).collect()),
                (v.clone(), (0..nv).map(|j| p.point(0, j)).collect()),
                (v, (0..nv).map(|j| p.point(nu - 1, j)).collect()),
            ],
            rounding: 1e-12 * size,
        }
    }
}

/// Knots mapped onto [0, 1] (empty when they do not rise).
fn unit(k: &[f64]) -> Vec<f64> {
    match (k.first(), k.last()) {
        (Some(&lo), Some(&hi)) if hi > lo => k.iter().map(|t| (t - lo) / (hi - lo)).collect(),
        _ => Vec::new(),
    }
}

/// Whether the edge is one of the surface's sides as its surface writes
/// it ([`SideRows`]), checked on the control points alone: its curve a
/// B-spline on the side's knots (up to t ↦ αt + β, either way round), its
/// control points the side's to rounding, and the edge running over the
/// curve's whole range. Then the edge is the side (the two curves'
/// difference is a B-spline whose control points are the differences). A
/// sufficient test, not a necessary one: a side written as another curve
/// (split, elevated, a line, moved within the tolerance) is left to
/// [`restricted`]'s foot points, which decide as before. Open CASCADE and
/// fairsurf write the boundary edges of a face that is not trimmed as its
/// surface's sides, so most faces are settled here without a Newton step.
pub(super) fn is_side(sides: &SideRows, e: &LoopEdge) -> bool {
    let Curve3D::BSplineCurve(c) = &e.curve else {
        return false;
    };
    let Some((r0, r1)) = c.try_range_tuple() else {
        return false;
    };
    let near = |x: f64, y: f64| (x - y).abs() <= 1e-12 * (r1 - r0).abs().max(f64::MIN_POSITIVE);
    let (a, b) = e.range;
    if e.seam.is_some() || !((near(a, r0) && near(b, r1)) || (near(a, r1) && near(b, r0))) {
        return false;
    }
    let points = c.control_points();
    let mine = unit(c.knot_vec());
    let one = |q: &Point3, r: &Vec3| dist(v3(*q), *r) <= sides.rounding;
    sides.rows.iter().any(|(theirs, row)| {
        let m = theirs.len();
        if m == 0 || mine.len() != m || row.len() != points.len() {
            return false;
        }
        let forward = (0..m).all(|i| (mine[i] - theirs[i]).abs() <= 1e-12)
            && points.iter().zip(row).all(|(q, r)| one(q, r));
        forward
            || ((0..m).all(|i| (mine[i] - (1.0 - theirs[m - 1 - i])).abs() <= 1e-12)
                && points.iter().zip(row.iter().rev()).all(|(q, r)| one(q, r)))
    })
}

/// The face's surface cut to the parameter rectangle its loop bounds: the
/// whole surface when the loop runs around its four sides, else (Open
/// CASCADE's `MakeFace(surface, u0, u1, v0, v1)`) the surface cut to the
/// rectangle exactly (knot insertion). A side may be made of several
/// edges (a writer splits a side where another face's corner lies on it).
/// Checked: every vertex and edge lies on the rectangle's sides, each of
/// its corners is a vertex, and its sides lie on the edges (by Newton foot
/// points, unless every edge is a side as written: [`is_side`]). Other
/// trimmed faces are refused.
pub(super) fn restricted(
    s: FaceSurface,
    edges: &[LoopEdge],
) -> std::result::Result<FaceSurface, String> {
    let tol = edge_tolerance(edges);
    if let FaceSurface::Polynomial(p) = &s {
        let sides = SideRows::of(p);
        if edges.iter().all(|e| is_side(&sides, e)) {
            return Ok(s);
        }
    }
    let trimmed = |why: &str| {
        format!(
            "the face is trimmed ({why}): only faces bounded by the four sides of a parameter \
             rectangle of their surface are filled around so far"
        )
    };
    // The parameters of every vertex and of seven points inside every edge
    // (each found by Newton steps from the point before it).
    let (ku, kv) = net(&s).knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    let mut vertices = Vec::with_capacity(edges.len());
    let mut inside = Vec::with_capacity(7 * edges.len());
    let seeds = Seeds::new(&s);
    for e in edges {
        let (mut uv, off) = nearest(&s, &seeds, e.start);
        if off > tol {
            return Err(trimmed(&format!("a vertex is {off:e} off its surface")));
        }
        vertices.push(uv);
        for k in 1..8 {
            let p = e.at(k as f64 / 8.0).0;
            let start = dist(eval(&s, uv.0, uv.1), p);
            let ders = |u: f64, v: f64| derivatives(&s, u, v);
            let (mut q, mut off) = foot(&ders, p, uv, start, ((a, b), (c, d)));
            if off > tol {
                (q, off) = nearest(&s, &seeds, p);
            }
            if off > tol {
                return Err(trimmed(&format!("an edge is {off:e} off its surface")));
            }
            inside.push(q);
            uv = q;
        }
    }
    let (eu, ev) = (1e-6 * (b - a), 1e-6 * (d - c));
    // Which sides of [u0, u1] × [v0, v1] a parameter pair lies on.
    let sides = |(u, v): (f64, f64), [u0, u1, v0, v1]: [f64; 4]| {
        [
            (u - u0).abs() <= eu,
            (u - u1).abs() <= eu,
            (v - v0).abs() <= ev,
            (v - v1).abs() <= ev,
        ]
    };
    // The whole surface: every vertex a corner of it in space (a side may
    // be collapsed to a point, and then has no edge) and every edge along
    // the domain's sides.
    let corners = [
        eval(&s, a, c),
        eval(&s, b, c),
        eval(&s, a, d),
        eval(&s, b, d),
    ];
    let whole = edges
        .iter()
        .all(|e| corners.iter().any(|k| dist(*k, e.start) <= tol))
        && inside
            .iter()
            .all(|&uv| sides(uv, [a, b, c, d]).iter().any(|&on| on));
    if whole {
        return Ok(s);
    }
    if edges.len() < 4 {
        return Err(trimmed(&format!("its loop has {} edges", edges.len())));
    }
    let range = |pick: fn(&(f64, f64)) -> f64| {
        let xs: Vec<f64> = vertices.iter().map(pick).collect();
        (
            xs.iter().copied().fold(f64::MAX, f64::min),
            xs.iter().copied().fold(f64::MIN, f64::max),
        )
    };
    let ((u0, u1), (v0, v1)) = (range(|p| p.0), range(|p| p.1));
    // Every vertex and edge point on a side of [u0, u1] × [v0, v1], each
    // corner a vertex once.
    let rect = [u0, u1, v0, v1];
    if inside
        .iter()
        .chain(&vertices)
        .any(|&uv| !sides(uv, rect).iter().any(|&on| on))
    {
        return Err(trimmed(
            "its boundary does not run along the sides of a parameter rectangle",
        ));
    }
    let mut corners = [0; 4];
    for &uv in &vertices {
        let [lo_u, hi_u, lo_v, hi_v] = sides(uv, rect);
        if (lo_u || hi_u) && (lo_v || hi_v) {
            corners[2 * usize::from(hi_u) + usize::from(hi_v)] += 1;
        }
    }
    if corners != [1; 4] || u1 - u0 <= eu || v1 - v0 <= ev {
        return Err(trimmed(
            "its vertices are not the corners of a parameter rectangle",
        ));
    }
    let snap = |x: f64, lo: f64, hi: f64, e: f64| {
        if (x - lo).abs() <= e {
            lo
        } else if (x - hi).abs() <= e {
            hi
        } else {
            x
        }
    };
    let (u0, u1) = (snap(u0, a, b, eu), snap(u1, a, b, eu));
    let (v0, v1) = (snap(v0, c, d, ev), snap(v1, c, d, ev));
    let cut = |x: &BSplineSurface| x.restricted_u(u0, u1)?.restricted_v(v0, v1);
    let sub = match &s {
        FaceSurface::Polynomial(p) => FaceSurface::Polynomial(cut(p).map_err(|e| e.to_string())?),
        FaceSurface::Rational(r) => {
            // The homogeneous surfaces w·P and w cut alike.
            let scaled = |f: &dyn Fn(usize) -> Vec3| {
                BSplineSurface::new(
                    r.net().knots().0.clone(),
                    r.net().knots().1.clone(),
                    (0..r.weights().len()).map(f).collect(),
                )
            };
            let w = r.weights();
            let pts = r.net().points();
            let num = scaled(&|k| fairsurf::vector::scale(pts[k], w[k]))
                .and_then(|x| cut(&x))
                .map_err(|e| e.to_string())?;
            let den = scaled(&|k| [w[k], 0.0, 0.0])
                .and_then(|x| cut(&x))
                .map_err(|e| e.to_string())?;
            let weights: Vec<f64> = den.points().iter().map(|p| p[0]).collect();
            let points = num
                .points()
                .iter()
                .zip(&weights)
                .map(|(p, w)| fairsurf::vector::scale(*p, 1.0 / w))
                .collect();
            let (nu, nv) = num.knots();
            let net =
                BSplineSurface::new(nu.clone(), nv.clone(), points).map_err(|e| e.to_string())?;
            FaceSurface::Rational(RationalSurface::new(net, weights).map_err(|e| e.to_string())?)
        }
    };
    // Its four sides lie on the face's edges.
    let (ku, kv) = net(&sub).knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    for k in 0..=8 {
        let t = k as f64 / 8.0;
        for (u, v) in [
            (a + (b - a) * t, c),
            (a + (b - a) * t, d),
            (a, c + (d - c) * t),
            (b, c + (d - c) * t),
        ] {
            let p = eval(&sub, u, v);
            let off = edges.iter().map(|e| e.distance(p)).fold(f64::MAX, f64::min);
            if off > tol {
                return Err(trimmed(&format!(
                    "its edges are not the sides of a parameter rectangle (off by {off:e})"
                )));
            }
        }
    }
    Ok(sub)
}

/// The surface turned (u and v exchanged) when its normal R_u × R_v does
/// not agree with the face's (the file's surface normal, which the reader
/// has turned for a face of opposite sense, reversed again for an oriented
/// face used backwards); when `converted`, first checked to lie on the
/// file's surface.
pub(super) fn oriented_like(
    s: FaceSurface,
    face: &Face,
    edges: &[LoopEdge],
    converted: bool,
) -> std::result::Result<FaceSurface, String> {
    if !converted {
        return turned(s, face.orientation);
    }
    turned(on_file_surface(s, &face.surface, edges)?, face.orientation)
}

/// `s` checked on the file's surface (at 5 × 5 points inside its domain,
/// within the edges' tolerance) and turned, if need be, so that its normal
/// is the file surface's (where both have one: not at a pole or apex).
pub(super) fn on_file_surface(
    s: FaceSurface,
    file: &StepSurface,
    edges: &[LoopEdge],
) -> std::result::Result<FaceSurface, String> {
    let tol = edge_tolerance(edges);
    let (ku, kv) = net(&s).knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    let (mut agree, mut votes) = (0.0, 0usize);
    // A surface of revolution, made once if a point needs it.
    let revolution = std::cell::OnceCell::new();
    for i in 0..5 {
        for j in 0..5 {
            let (u, v) = (
                a + (b - a) * (i as f64 + 0.5) / 5.0,
                c + (d - c) * (j as f64 + 0.5) / 5.0,
            );
            let der = derivatives(&s, u, v);
            let Some(((fu, fv), off)) = file_foot(file, der.point, None) else {
                return Err("the file's surface could not be evaluated near the face".into());
            };
            if off > tol {
                // truck's search can stop short near a sphere's pole (0.045
                // of the radius off, on spheres of some sizes but not
                // others): a surface of revolution tells its distance
                // itself, and a point on it has no vote on the sense (the
                // file's normal there is not known).
                let analytic = match file {
                    StepSurface::ElementarySurface(e) => revolution
                        .get_or_init(|| Revolution::of(e).ok().map(|(_, r)| r))
                        .as_ref()
                        .map(|r| r.foot(der.point).0),
                    _ => None,
                };
                if analytic.is_some_and(|d| d <= tol) {
                    continue;
                }
                return Err(format!(
                    "the face's surface as a B-spline is off the file's surface by {:e} at \
                     ({}, {}, {})",
                    analytic.unwrap_or(off),
                    der.point[0],
                    der.point[1],
                    der.point[2]
                ));
            }
            let n = file.normal(fu, fv);
            let x = fairsurf::vector::dot(fairsurf::vector::cross(der.du, der.dv), [n.x, n.y, n.z]);
            if x.is_finite() && x != 0.0 {
                agree += x;
                votes += 1;
            }
        }
    }
    if votes == 0 {
        return Err(
            "the face's sense against the file's surface could not be told (no point of it \
             where the file's surface has a normal was found)"
                .into(),
        );
    }
    turned(s, agree > 0.0)
}

/// `s`, or with u and v exchanged (its normal reversed) unless `keep`.
pub(super) fn turned(s: FaceSurface, keep: bool) -> std::result::Result<FaceSurface, String> {
    Ok(if keep {
        s
    } else {
        match s {
            FaceSurface::Polynomial(p) => FaceSurface::Polynomial(p.transposed()),
            FaceSurface::Rational(r) => {
                let (cu, cv) = r.net().counts();
                let w = r.weights();
                let weights = (0..cv)
                    .flat_map(|j| (0..cu).map(move |i| w[i * cv + j]))
                    .collect();
                FaceSurface::Rational(
                    RationalSurface::new(r.net().transposed(), weights)
                        .map_err(|e| e.to_string())?,
                )
            }
        }
    })
}
