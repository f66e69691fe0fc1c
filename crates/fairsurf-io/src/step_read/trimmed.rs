//! Trimmed faces: a face bounded otherwise than by four sides of its
//! surface (a B-spline, a plane, a cylinder, cone, sphere or torus), or
//! with holes. Kept as its surface (a surface of revolution as the exact
//! rational B-spline of the piece its loops lie on) and its loops, each
//! edge as it is ([`TrimEdge`]: the edge's curve and the face's normal at
//! its foot points), for fills to meet through strip stand-ins
//! ([`fairsurf::bspline::strip_stand_in`]).

use super::*;
use fairsurf::bspline::{Break, EdgeFrame, TrueEdge};
use truck_stepio::r#in::alias::{Matrix4, Transform};

/// An edge of a trimmed face's loop as the loop runs (the face on its left
/// seen from its normal's side).
#[derive(Clone, Debug, PartialEq)]
pub struct TrimEdge {
    /// The edge's point and tangent and the face's unit normal at
    /// t ∈ [0, 1] along it.
    pub edge: TrueEdge,
    /// Whether the edge is no other face's in the shell: a side of a hole
    /// (or of an open sheet's rim).
    pub free: bool,
    /// For a free edge whose ends each meet one other free edge: the
    /// directions a strip along it leaves its ends by — the other free
    /// edge there continued through the vertex, as a four-sided
    /// neighbour's cross derivative runs along the side it shares with the
    /// next neighbour ([`fairsurf::bspline::strip_stand_in_towards`]).
    pub ends: Option<[Vec3; 2]>,
    /// The length of a polygon through 33 points of the edge.
    pub length: f64,
    /// The largest distance of 33 points of the edge from the face's
    /// surface (CAD systems write a trimmed face's edges as curves that
    /// approximate its boundary: Open CASCADE's BuildCurves3d to 1e-5 by
    /// default); at most [`TRIM_TOLERANCE`] or 1e-7 of the loops' size.
    pub off_surface: f64,
    /// The larger distance of the file's vertices at its ends from the
    /// edge's curve (the file's precision there: Open CASCADE's loft 1000
    /// across had 1.6e-5).
    pub vertex_off: f64,
}

/// How far a trimmed face's edges may lie from its surface (at least).
pub const TRIM_TOLERANCE: f64 = 1e-5;

/// A trimmed face's surface (the file's B-spline, a bilinear patch of the
/// plane around the loops, or a surface of revolution's piece under them:
/// [`Revolution::around`]) and its loops' frames, or why not.
pub(super) fn trimmed(
    face: &Face,
    loops: &[Vec<LoopEdge>],
) -> std::result::Result<(&'static str, FaceSurface, Vec<Vec<Frames>>), String> {
    if let StepSurface::SweptCurve(_) = &face.surface {
        return Err(
            "a trimmed swept surface (extrusion or revolution of a curve): not filled around yet"
                .into(),
        );
    }
    // A B-spline evaluated by fairsurf (all derivatives from one pass over
    // the basis functions; truck's take one each); a surface of revolution
    // in closed form (truck's parameters are singular at a pole, where
    // Newton steps on them stall).
    let own = match &face.surface {
        StepSurface::BSplineSurface(_) | StepSurface::NurbsSurface(_) => {
            Some(spline(&face.surface)?)
        }
        _ => None,
    };
    let revolution = match &face.surface {
        StepSurface::ElementarySurface(e) if !matches!(e.as_ref(), ElementarySurface::Plane(_)) => {
            let (kind, axis) = Revolution::of(e)?;
            let sign = axis.sense_of(&face.surface, loops)?;
            Some((kind, axis, sign))
        }
        _ => None,
    };
    let eval = match (&own, &revolution) {
        (Some((_, s)), _) => Eval::Spline(std::sync::Arc::new(SeededSpline::new(s.clone()))),
        (_, Some((_, axis, sign))) => Eval::Revolution(axis.clone(), *sign),
        _ => Eval::File,
    };
    // The edges on the surface first: the surface written for them is
    // ranged by their points.
    let all: Vec<Vec3> = loops.iter().flatten().map(|e| e.start).collect();
    let tol = (1e-7 * fairsurf::vector::bounding_diagonal(&all)).max(TRIM_TOLERANCE);
    let frames = loops
        .iter()
        .map(|l| {
            l.iter()
                .map(|e| Frames::new(&face.surface, &eval, e, tol))
                .collect::<std::result::Result<Vec<_>, String>>()
        })
        .collect::<std::result::Result<Vec<_>, String>>()?;
    let (kind, surface) = match own {
        Some((kind, s)) => {
            let kind = if kind == "B-spline" {
                "trimmed B-spline"
            } else {
                "trimmed rational B-spline"
            };
            (kind, s)
        }
        None => match revolution {
            Some((kind, axis, _)) => (kind, axis.around(&face.surface, &frames, kind)?),
            None => ("trimmed plane", plane_around(&face.surface, loops)?),
        },
    };
    Ok((kind, surface, frames))
}

/// A bilinear patch of a plane face's surface around its loops (their
/// points' bounding rectangle in the plane, 2% wider each way), its normal
/// the file's.
fn plane_around(
    file: &StepSurface,
    loops: &[Vec<LoopEdge>],
) -> std::result::Result<FaceSurface, String> {
    use fairsurf::vector::{add, cross, dot, norm, scale, sub};
    let points: Vec<Vec3> = loops
        .iter()
        .flatten()
        .flat_map(|e| (0..32).map(move |k| e.at(k as f64 / 32.0).0))
        .collect();
    let origin = points[0];
    let n = file.normal(0.0, 0.0);
    let n = [n.x, n.y, n.z];
    // An axis in the plane: the farthest point's direction.
    let far = points
        .iter()
        .map(|p| sub(*p, origin))
        .map(|d| sub(d, scale(n, dot(d, n))))
        .max_by(|a, b| norm(*a).total_cmp(&norm(*b)))
        .filter(|d| norm(*d) > 0.0)
        .ok_or("a plane face whose loop is one point")?;
    let e1 = scale(far, 1.0 / norm(far));
    let e2 = cross(n, e1);
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in &points {
        let d = sub(*p, origin);
        let x = [dot(d, e1), dot(d, e2)];
        for c in 0..2 {
            lo[c] = lo[c].min(x[c]);
            hi[c] = hi[c].max(x[c]);
        }
    }
    let margin = 0.02 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let at = |a: f64, b: f64| add(origin, add(scale(e1, a), scale(e2, b)));
    let (a0, a1, b0, b1) = (
        lo[0] - margin,
        hi[0] + margin,
        lo[1] - margin,
        hi[1] + margin,
    );
    let net = BSplineSurface::new(
        KnotVector::bezier(1),
        KnotVector::bezier(1),
        vec![at(a0, b0), at(a0, b1), at(a1, b0), at(a1, b1)],
    )
    .map_err(|e| e.to_string())?;
    Ok(FaceSurface::Polynomial(net))
}

/// A face's B-spline and the grids its nearest-point searches start
/// from, each made at its first use: the 17 × 17 one and, near a
/// collapsed side, a 65 × 65 one ([`foot_within`]).
pub(super) struct SeededSpline {
    surface: FaceSurface,
    coarse: std::sync::OnceLock<Seeds>,
    fine: std::sync::OnceLock<Seeds>,
}

impl SeededSpline {
    fn new(surface: FaceSurface) -> Self {
        Self {
            surface,
            coarse: std::sync::OnceLock::new(),
            fine: std::sync::OnceLock::new(),
        }
    }

    fn coarse(&self) -> &Seeds {
        self.coarse.get_or_init(|| Seeds::new(&self.surface))
    }

    fn fine(&self) -> &Seeds {
        self.fine.get_or_init(|| Seeds::of(&self.surface, 64))
    }
}

/// How [`Frames`] finds foot points and normals on a face's surface.
#[derive(Clone)]
pub(super) enum Eval {
    /// truck's evaluation of the file's surface (a plane).
    File,
    /// The file's B-spline as fairsurf's (the same parameters), with its
    /// seed grids (one per face: the face's edges share it).
    Spline(std::sync::Arc<SeededSpline>),
    /// A surface of revolution in closed form ([`Revolution::foot`]), its
    /// normal times the file's sense (±1).
    Revolution(Revolution, f64),
}

/// A cylinder, cone, sphere or torus as a surface of revolution: its axis
/// (through `o` along the unit vector `k`, angles θ counted from `e1`
/// towards k × e1) and its meridian in the half-plane (ρ, z) of distance
/// from the axis and height along it.
#[derive(Clone)]
pub(super) struct Revolution {
    o: Vec3,
    k: Vec3,
    e1: Vec3,
    meridian: Meridian,
}

/// The meridian of a [`Revolution`] in its (ρ, z) half-plane.
#[derive(Clone, Copy)]
enum Meridian {
    /// A cylinder's or cone's ruling, parameter t from `a` (t = 0) to `b`
    /// (t = 1).
    Line { a: [f64; 2], b: [f64; 2] },
    /// A sphere's (centre on the axis) or torus's circle, parameter the
    /// angle φ about the centre from the ρ direction towards z.
    Circle { centre: [f64; 2], radius: f64 },
}

impl Revolution {
    /// The file's elementary surface (not a plane) as a revolution, and the
    /// kind of trimmed face it makes.
    pub(super) fn of(e: &ElementarySurface) -> std::result::Result<(&'static str, Self), String> {
        use fairsurf::vector::{cross, dot, norm, normalize, scale, sub};
        let point = |m: &Matrix4, p: Point3| v3(m.transform_point(p));
        let along = |m: &Matrix4, x: f64, y: f64, z: f64| {
            let d = m.transform_vector(Vector3::new(x, y, z));
            [d.x, d.y, d.z]
        };
        // e1 ⟂ k: `hint` without its part along k, or any perpendicular.
        let across = |k: Vec3, hint: Vec3| {
            let w = sub(hint, scale(k, dot(hint, k)));
            normalize(w)
                .filter(|_| norm(w) > 1e-9 * norm(hint))
                .or_else(|| {
                    let x = if k[0].abs() < 0.9 {
                        [1.0, 0.0, 0.0]
                    } else {
                        [0.0, 1.0, 0.0]
                    };
                    normalize(cross(k, x))
                })
        };
        let bad = || "a surface of revolution with a degenerate axis".to_string();
        let (kind, o, k, hint, meridian_world) = match e {
            ElementarySurface::CylindricalSurface(p) | ElementarySurface::ConicalSurface(p) => {
                let kind = if matches!(e, ElementarySurface::CylindricalSurface(_)) {
                    "trimmed cylinder"
                } else {
                    "trimmed cone"
                };
                let (m, r) = (p.transform(), p.entity());
                let line = r.entity_curve();
                let axis = r.axis();
                let o = point(m, r.origin());
                let k = normalize(along(m, axis.x, axis.y, axis.z)).ok_or_else(bad)?;
                let (a, b) = (point(m, line.0), point(m, line.1));
                let hint = if dist(a, o) > dist(b, o) {
                    sub(a, o)
                } else {
                    sub(b, o)
                };
                (kind, o, k, hint, Ok((a, b)))
            }
            ElementarySurface::Sphere(p) => {
                let (m, s) = (p.transform(), &p.entity().0);
                let o = point(m, s.center());
                let rim = point(m, s.center() + Vector3::new(s.radius(), 0.0, 0.0));
                let k = normalize(along(m, 0.0, 0.0, 1.0)).ok_or_else(bad)?;
                let radius = dist(rim, o);
                (
                    "trimmed sphere",
                    o,
                    k,
                    sub(rim, o),
                    Err(([0.0, 0.0], radius)),
                )
            }
            ElementarySurface::ToroidalSurface(p) => {
                let (m, t) = (p.transform(), p.entity());
                let o = point(m, t.center());
                let k = normalize(along(m, 0.0, 0.0, 1.0)).ok_or_else(bad)?;
                let x = along(m, 1.0, 0.0, 0.0);
                let scale_x = norm(x);
                (
                    "trimmed torus",
                    o,
                    k,
                    x,
                    Err((
                        [t.large_radius() * scale_x, 0.0],
                        t.small_radius() * scale_x,
                    )),
                )
            }
            ElementarySurface::Plane(_) => return Err("a plane is not a revolution".into()),
        };
        let e1 = across(k, hint).ok_or_else(bad)?;
        let mut axis = Self {
            o,
            k,
            e1,
            meridian: Meridian::Circle {
                centre: [0.0, 0.0],
                radius: 0.0,
            },
        };
        axis.meridian = match meridian_world {
            Ok((a, b)) => {
                let (a, b) = (axis.rz(a), axis.rz(b));
                if a == b {
                    return Err(bad());
                }
                Meridian::Line { a, b }
            }
            Err((centre, radius)) if radius > 0.0 => Meridian::Circle { centre, radius },
            Err(_) => return Err("a sphere or torus of radius 0".into()),
        };
        Ok((kind, axis))
    }

    /// The distance of p from the surface and the surface's unit normal
    /// at its foot (the meridian's in p's half-plane, outward from a
    /// circle's centre; none at a circle's centre).
    pub(super) fn foot(&self, p: Vec3) -> (f64, Option<Vec3>) {
        use fairsurf::vector::{add, scale};
        let [rho, z] = self.rz(p);
        let out = self.radial(self.theta(p));
        let (off, n) = match self.meridian {
            Meridian::Line { a, b } => {
                let d = [b[0] - a[0], b[1] - a[1]];
                let l = d[0].hypot(d[1]);
                let (x, y) = (rho - a[0], z - a[1]);
                ((x * d[1] - y * d[0]).abs() / l, Some([d[1] / l, -d[0] / l]))
            }
            Meridian::Circle { centre, radius } => {
                let v = [rho - centre[0], z - centre[1]];
                let r = v[0].hypot(v[1]);
                ((r - radius).abs(), (r > 0.0).then(|| [v[0] / r, v[1] / r]))
            }
        };
        (off, n.map(|n| add(scale(out, n[0]), scale(self.k, n[1]))))
    }

    /// The file's sense against [`Revolution::foot`]'s normals (±1): at the
    /// loops' point farthest from the axis, by truck's normal there.
    fn sense_of(
        &self,
        file: &StepSurface,
        loops: &[Vec<LoopEdge>],
    ) -> std::result::Result<f64, String> {
        let p = loops
            .iter()
            .flatten()
            .flat_map(|e| (0..=8).map(move |k| e.at(k as f64 / 8.0).0))
            .max_by(|a, b| self.rz(*a)[0].total_cmp(&self.rz(*b)[0]))
            .ok_or("a face without edges")?;
        let unknown = || "the file's surface could not be evaluated near the face".to_string();
        let ((u, v), _) = file_foot(file, p, None).ok_or_else(unknown)?;
        let n = file.normal(u, v);
        let ours = self.foot(p).1.ok_or_else(unknown)?;
        let d = fairsurf::vector::dot(ours, [n.x, n.y, n.z]);
        if d.is_finite() && d != 0.0 {
            Ok(d.signum())
        } else {
            Err(unknown())
        }
    }

    /// (ρ, z) of a point.
    fn rz(&self, p: Vec3) -> [f64; 2] {
        use fairsurf::vector::{dot, norm, scale, sub};
        let d = sub(p, self.o);
        let z = dot(d, self.k);
        [norm(sub(d, scale(self.k, z))), z]
    }

    /// θ of a point (its angle about the axis from e1).
    fn theta(&self, p: Vec3) -> f64 {
        use fairsurf::vector::{cross, dot, sub};
        let d = sub(p, self.o);
        dot(d, cross(self.k, self.e1)).atan2(dot(d, self.e1))
    }

    /// The meridian parameter of a point (t along the line, or φ).
    fn along(&self, p: Vec3) -> f64 {
        let [rho, z] = self.rz(p);
        match self.meridian {
            Meridian::Line { a, b } => {
                let d = [b[0] - a[0], b[1] - a[1]];
                ((rho - a[0]) * d[0] + (z - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1])
            }
            Meridian::Circle { centre, .. } => (z - centre[1]).atan2(rho - centre[0]),
        }
    }

    /// The unit vector away from the axis at angle θ.
    fn radial(&self, theta: f64) -> Vec3 {
        use fairsurf::vector::{add, cross, scale};
        let (s, c) = theta.sin_cos();
        add(scale(self.e1, c), scale(cross(self.k, self.e1), s))
    }

    /// The point at (θ, t) and its derivative by t.
    fn at(&self, theta: f64, t: f64) -> (Vec3, Vec3) {
        use fairsurf::vector::{add, scale};
        let out = self.radial(theta);
        let ([rho, z], [drho, dz]) = match self.meridian {
            Meridian::Line { a, b } => (
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
                [b[0] - a[0], b[1] - a[1]],
            ),
            Meridian::Circle { centre, radius } => {
                let (s, c) = t.sin_cos();
                (
                    [centre[0] + radius * c, centre[1] + radius * s],
                    [-radius * s, radius * c],
                )
            }
        };
        (
            add(self.o, add(scale(out, rho), scale(self.k, z))),
            add(scale(out, drho), scale(self.k, dz)),
        )
    }

    /// The file's surface over the range of θ and of the meridian's
    /// parameter the face takes, as the exact rational B-spline of the
    /// revolution of that piece of the meridian (The NURBS Book §8.5),
    /// checked on the file's surface, its normal the file's. The ranges
    /// are the loops' points' (2% wider, never past a pole or a cone's
    /// apex), on the side the face lies: of an angle, the gap left out is
    /// one no edge runs through and away from which the edges at its ends
    /// turn the face ([`periodic_range`]); a face all the way round is
    /// taken from its seam edge once round; a face that runs on past its
    /// loops' last points along the meridian reaches a pole or apex.
    fn around(
        &self,
        file: &StepSurface,
        frames: &[Vec<Frames>],
        kind: &str,
    ) -> std::result::Result<FaceSurface, String> {
        use fairsurf::vector::{cross, dot, normalize};
        use std::f64::consts::{FRAC_PI_2, PI};
        // Points of the edges, with the direction into the face there (the
        // face lies on the loop's left seen from its normal).
        let mut samples: Vec<(Vec3, usize, Vec3)> = Vec::new();
        let edges: Vec<&Frames> = frames.iter().flatten().collect();
        for (e, f) in edges.iter().enumerate() {
            for k in 0..=32 {
                let fr = f.frame(k as f64 / 32.0);
                let into = normalize(cross(fr.normal, fr.tangent)).unwrap_or([0.0; 3]);
                samples.push((fr.point, e, into));
            }
        }
        let points: Vec<Vec3> = samples.iter().map(|s| s.0).collect();
        let size = fairsurf::vector::bounding_diagonal(&points);
        let refuse = |why: &str| format!("a {kind} face {why}: not filled around yet");
        // An angle's range: (angle, edge, rate into the face) per usable
        // point; without a gap the face goes round, from a seam edge: one
        // along which the angle stays put, which another of the face's edges
        // runs the other way.
        let turn = |name: &str,
                    usable: &dyn Fn(Vec3) -> bool,
                    angle: &dyn Fn(Vec3) -> f64,
                    ahead: &dyn Fn(Vec3) -> Vec3| {
            let at: Vec<(f64, usize, f64)> = samples
                .iter()
                .filter(|s| usable(s.0))
                .map(|&(p, e, into)| (angle(p), e, dot(into, ahead(p))))
                .collect();
            if let Some(range) = periodic_range(&at) {
                return Ok(range);
            }
            let seam = (0..edges.len()).find_map(|e| {
                let a: Vec<f64> = at.iter().filter(|x| x.1 == e).map(|x| x.0).collect();
                let still = a.len() > 1
                    && a.iter()
                        .all(|x| ((x - a[0] + PI).rem_euclid(2.0 * PI) - PI).abs() <= 1e-6);
                let (s, t) = (edges[e].start(), edges[e].end());
                let near = |x: Vec3, y: Vec3| dist(x, y) <= 1e-9 * size.max(1.0);
                let back = (0..edges.len()).any(|f| {
                    f != e
                        && near(edges[f].start(), t)
                        && near(edges[f].end(), s)
                        && near(edges[f].edge.at(0.5).0, edges[e].edge.at(0.5).0)
                });
                (still && back).then(|| a[0])
            });
            seam.map(|s| (s, s + 2.0 * PI))
                .ok_or_else(|| refuse(&format!("all the way round {name} without a seam edge")))
        };
        // θ where it is defined well (off the axis).
        let usable = |p: Vec3| self.rz(p)[0] > 1e-3 * size;
        let around_axis = |p: Vec3| {
            normalize(cross(self.k, fairsurf::vector::sub(p, self.o))).unwrap_or([0.0; 3])
        };
        let theta = turn("its axis", &usable, &|p| self.theta(p), &around_axis)?;
        // Along the meridian: the direction of increasing t (or φ).
        let along =
            |p: Vec3| normalize(self.at(self.theta(p), self.along(p)).1).unwrap_or([0.0; 3]);
        let t = match self.meridian {
            Meridian::Circle { centre, .. } if centre[0] != 0.0 => {
                turn("its tube", &|_| true, &|p| self.along(p), &along)?
            }
            meridian => {
                // From the lowest to the highest point, on to the bound
                // (a pole, an apex) where the face runs on past them.
                let bounds = match meridian {
                    Meridian::Line { a, b } if a[0] != b[0] => {
                        let apex = a[0] / (a[0] - b[0]);
                        let ts = samples.iter().map(|s| self.along(s.0));
                        if ts.clone().all(|t| t >= apex) {
                            (Some(apex), None)
                        } else {
                            (None, Some(apex))
                        }
                    }
                    Meridian::Line { .. } => (None, None),
                    Meridian::Circle { .. } => (Some(-FRAC_PI_2), Some(FRAC_PI_2)),
                };
                // A cone's apex on a loop: Open CASCADE read such a face,
                // written with its collapsed side, as faces of no area.
                if matches!(meridian, Meridian::Line { .. }) && bounds != (None, None) {
                    let apex = samples.iter().any(|s| self.rz(s.0)[0] <= 1e-6 * size);
                    if apex {
                        return Err(refuse("whose loops reach its apex"));
                    }
                }
                let ts: Vec<(f64, f64)> = samples
                    .iter()
                    .map(|&(p, _, into)| (self.along(p), dot(into, along(p))))
                    .collect();
                let (lo, hi) = ts
                    .iter()
                    .fold((f64::MAX, f64::MIN), |(l, h), x| (l.min(x.0), h.max(x.0)));
                let close = 1e-9 * (hi - lo).max(1e-300);
                let past_lo = ts.iter().any(|x| x.0 - lo <= close && x.1 < -1e-3);
                let past_hi = ts.iter().any(|x| hi - x.0 <= close && x.1 > 1e-3);
                let margin = 0.02 * (hi - lo);
                let cone = matches!(meridian, Meridian::Line { .. });
                if cone && ((past_lo && bounds.0.is_some()) || (past_hi && bounds.1.is_some())) {
                    return Err(refuse("that runs on to its apex"));
                }
                // Not onto a cone's apex (a collapsed side there was read
                // back as faces of no area): halfway to it at most.
                let (lo_bound, hi_bound) = match (cone, bounds) {
                    (true, (Some(b), _)) => (Some(0.5 * (b + lo)), None),
                    (true, (_, Some(b))) => (None, Some(0.5 * (b + hi))),
                    _ => bounds,
                };
                let lo = match (past_lo, lo_bound) {
                    (true, Some(b)) => b,
                    (true, None) => return Err(refuse("that runs on past its loops")),
                    (false, b) => (lo - margin).max(b.unwrap_or(f64::MIN)),
                };
                let hi = match (past_hi, hi_bound) {
                    (true, Some(b)) => b,
                    (true, None) => return Err(refuse("that runs on past its loops")),
                    (false, b) => (hi + margin).min(b.unwrap_or(f64::MAX)),
                };
                (lo, hi)
            }
        };
        if !(theta.1 > theta.0 && t.1 > t.0) {
            return Err(format!("a {kind} face whose loops enclose no area of it"));
        }
        let span = t.1 - t.0;
        let profile = match self.meridian {
            Meridian::Line { .. } => {
                let (p0, p1) = (self.at(theta.0, t.0).0, self.at(theta.0, t.1).0);
                (vec![p0, p1], vec![1.0, 1.0], vec![0.0, 0.0, 1.0, 1.0])
            }
            Meridian::Circle { .. } => {
                let pieces = ((span / FRAC_PI_2) - 1e-9).ceil().max(1.0) as usize;
                arc_along(
                    |s| {
                        let (p, d) = self.at(theta.0, t.0 + s * span);
                        (p, fairsurf::vector::scale(d, span))
                    },
                    pieces,
                )?
            }
        };
        let surface = revolve_arc(&profile, self.o, self.k, theta.1 - theta.0)?;
        let edges: Vec<LoopEdge> = edges.iter().map(|f| f.edge.clone()).collect();
        on_file_surface(FaceSurface::Rational(surface), file, &edges)
    }
}

/// The range [a, b] (b − a < 2π) of angles a face takes, from its edges'
/// points: per point (angle in radians, any turn; edge; the rate at which
/// the direction into the face turns the angle, of a unit vector), each
/// edge's points in order along it. The gap left out is the widest one
/// that no edge runs through (between two of its consecutive points) and
/// away from which the edges at its ends turn into the face (rates above
/// 1e-3 into it refuse it: of points inside their edges where there are
/// any, else of the edges' ends there); the range is widened by 2% of its length each
/// way (at most a quarter of the gap). None when no gap is left out: the
/// face goes all the way round.
pub(super) fn periodic_range(points: &[(f64, usize, f64)]) -> Option<(f64, f64)> {
    use std::f64::consts::{PI, TAU};
    let wrap = |x: f64| (x + PI).rem_euclid(TAU) - PI;
    let mut order: Vec<(f64, usize)> = points
        .iter()
        .enumerate()
        .map(|(k, p)| (p.0.rem_euclid(TAU), k))
        .collect();
    order.sort_by(|x, y| x.0.total_cmp(&y.0));
    let n = order.len();
    // Does an edge run through angle m (between two of its consecutive
    // points, the short way)?
    let crossed = |m: f64| {
        points.windows(2).any(|w| {
            let (a, b) = (w[0], w[1]);
            if a.1 != b.1 {
                return false;
            }
            let d = wrap(b.0 - a.0);
            let x = wrap(m - a.0);
            (d > 0.0 && x > 0.0 && x < d) || (d < 0.0 && x < 0.0 && x > d)
        })
    };
    // The rates at an angle: of points inside their edges where there
    // are any — at an edge's end the direction into the face is the
    // edge's alone, not the corner's: an edge leaving a parallel at an
    // acute corner points across it, into the gap the face does not reach
    // (a torus cut by planes across its tube was taken as going all the
    // way round it) — else of the edges' ends there (a corner that is the
    // extreme: a hole's corner turns the face into the gap beyond it).
    let inside = |k: usize| {
        k > 0
            && k + 1 < points.len()
            && points[k - 1].1 == points[k].1
            && points[k + 1].1 == points[k].1
    };
    let at = |angle: f64| -> Vec<f64> {
        let here: Vec<usize> = (0..points.len())
            .filter(|&k| wrap(points[k].0 - angle).abs() <= 1e-7)
            .collect();
        let within: Vec<f64> = here
            .iter()
            .filter(|&&k| inside(k))
            .map(|&k| points[k].2)
            .collect();
        if within.is_empty() {
            here.iter().map(|&k| points[k].2).collect()
        } else {
            within
        }
    };
    // The gaps, widest first; the first one left out (the edges are
    // searched for each, so the widest is usually the only one tried).
    let mut gaps: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let b = if k + 1 < n {
                order[k + 1].0
            } else {
                order[0].0 + TAU
            };
            (order[k].0, b)
        })
        .filter(|(a, b)| b - a > 1e-9)
        .collect();
    gaps.sort_by(|x, y| (y.1 - y.0).total_cmp(&(x.1 - x.0)));
    let (start, gap) = gaps.into_iter().find_map(|(a, b)| {
        let open = !crossed((a + b) / 2.0)
            && !at(a).iter().any(|&r| r > 1e-3)
            && !at(b).iter().any(|&r| r < -1e-3);
        open.then_some((b, b - a))
    })?;
    let length = TAU - gap;
    let margin = (0.02 * length).min(0.25 * gap);
    Some((start - margin, start + length + margin))
}

/// Foot points on a file's surface along one edge (33 parameters), where
/// the edge's frames start their Newton steps.
#[derive(Clone)]
pub(super) struct Frames {
    edge: LoopEdge,
    surface: StepSurface,
    /// How the surface is evaluated.
    eval: Eval,
    hints: Vec<(f64, f64)>,
    /// The largest distance of the points from the surface.
    off: f64,
    /// How far they may be.
    tol: f64,
    /// Where along the edge (s ∈ (0, 1)) its curve has a knot or its foot
    /// points cross a knot line of the surface, and how smooth it is there.
    breaks: Vec<Break>,
}

/// Parameters at which [`Frames`] keeps foot points.
const HINTS: usize = 32;

impl Frames {
    fn new(
        surface: &StepSurface,
        eval: &Eval,
        edge: &LoopEdge,
        tol: f64,
    ) -> std::result::Result<Self, String> {
        let spline = match eval {
            Eval::Spline(s) => Some(&**s),
            _ => None,
        };
        let mut hints = Vec::with_capacity(HINTS + 1);
        let mut largest = 0.0f64;
        for k in 0..=HINTS {
            let p = edge.at(k as f64 / HINTS as f64).0;
            let ((u, v), off) = match eval {
                Eval::Revolution(r, _) => ((0.0, 0.0), r.foot(p).0),
                _ => foot_within((surface, spline), p, hints.last().copied(), tol)
                    .ok_or("the file's surface could not be evaluated near an edge of the face")?,
            };
            if off > tol {
                return Err(format!(
                    "an edge of the face is {off:e} off its surface at ({}, {}, {}) (a trimmed \
                     face's edges are taken within {tol:e})",
                    p[0], p[1], p[2]
                ));
            }
            hints.push((u, v));
            largest = largest.max(off);
        }
        let mut frames = Self {
            edge: edge.clone(),
            surface: surface.clone(),
            eval: eval.clone(),
            hints,
            off: largest,
            tol,
            breaks: Vec::new(),
        };
        frames.breaks = frames.find_breaks();
        Ok(frames)
    }

    /// Where the edge is less smooth: its curve's interior knots (a
    /// B-spline curve's, mapped onto s ∈ (0, 1); none through a seam),
    /// and where its foot points cross an interior knot line of a
    /// B-spline surface (bisection between the samples that straddle it);
    /// each C^(p − m) there (degree p, the knot's multiplicity m).
    fn find_breaks(&self) -> Vec<Break> {
        let mut out = Vec::new();
        let (a, b) = self.edge.range;
        let knots: Option<(Vec<f64>, usize)> = match &self.edge.curve {
            Curve3D::BSplineCurve(c) => Some((c.knot_vec().to_vec(), c.degree())),
            Curve3D::NurbsCurve(c) => Some((c.knot_vec().to_vec(), c.degree())),
            _ => None,
        };
        if let (Some((k, p)), None) = (knots, self.edge.seam) {
            out.extend(k.iter().map(|&t| Break {
                at: (t - a) / (b - a),
                continuity: p.saturating_sub(multiplicity(&k, t)),
            }));
        }
        let lines: [(Vec<f64>, usize); 2] = match &self.surface {
            StepSurface::BSplineSurface(s) => [
                (s.uknot_vec().to_vec(), s.udegree()),
                (s.vknot_vec().to_vec(), s.vdegree()),
            ],
            StepSurface::NurbsSurface(s) => {
                let s = s.non_rationalized();
                [
                    (s.uknot_vec().to_vec(), s.udegree()),
                    (s.vknot_vec().to_vec(), s.vdegree()),
                ]
            }
            _ => return out,
        };
        let foot = |s: f64, hint: (f64, f64)| {
            let p = self.edge.at(s).0;
            file_foot_on((&self.surface, self.spline()), p, Some(hint)).map_or(hint, |f| f.0)
        };
        for (c, (knots, degree)) in lines.iter().enumerate() {
            let (lo, hi) = (knots[0], knots[knots.len() - 1]);
            let inner: Vec<f64> = knots
                .iter()
                .copied()
                .filter(|&k| k > lo && k < hi)
                .collect();
            let at = |uv: (f64, f64)| if c == 0 { uv.0 } else { uv.1 };
            for k in 0..HINTS {
                let (h0, h1) = (self.hints[k], self.hints[k + 1]);
                let (x0, x1) = (at(h0), at(h1));
                for &kn in &inner {
                    if (x0 - kn) * (x1 - kn) >= 0.0 {
                        continue;
                    }
                    let (mut s0, mut s1) = (k as f64 / HINTS as f64, (k + 1) as f64 / HINTS as f64);
                    let mut hint = h0;
                    for _ in 0..40 {
                        let m = 0.5 * (s0 + s1);
                        let uv = foot(m, hint);
                        if (at(uv) - kn) * (x0 - kn) > 0.0 {
                            s0 = m;
                            hint = uv;
                        } else {
                            s1 = m;
                        }
                    }
                    out.push(Break {
                        at: 0.5 * (s0 + s1),
                        continuity: degree.saturating_sub(multiplicity(knots, kn)),
                    });
                }
            }
        }
        out
    }

    /// The edge's point and tangent at s ∈ [0, 1] and the surface's unit
    /// normal at its foot point.
    fn frame(&self, s: f64) -> EdgeFrame {
        let (point, tangent) = self.edge.at(s);
        if let Eval::Revolution(r, sign) = &self.eval {
            let normal = r
                .foot(point)
                .1
                .map_or([f64::NAN; 3], |n| fairsurf::vector::scale(n, *sign));
            return EdgeFrame {
                point,
                tangent,
                normal,
            };
        }
        let hint = self.hints[((s.clamp(0.0, 1.0) * HINTS as f64).round()) as usize];
        let file = (&self.surface, self.spline());
        let (u, v) = foot_within(file, point, Some(hint), self.tol).map_or(hint, |f| f.0);
        let normal = match self.spline() {
            Some(s) => {
                let d = derivatives(&s.surface, u, v);
                fairsurf::vector::normalize(fairsurf::vector::cross(d.du, d.dv))
                    .unwrap_or([f64::NAN; 3])
            }
            None => {
                let n = self.surface.normal(u, v);
                [n.x, n.y, n.z]
            }
        };
        EdgeFrame {
            point,
            tangent,
            normal,
        }
    }

    /// The surface as fairsurf's B-spline, when it is one.
    fn spline(&self) -> Option<&SeededSpline> {
        match &self.eval {
            Eval::Spline(s) => Some(s),
            _ => None,
        }
    }

    pub(super) fn start(&self) -> Vec3 {
        self.edge.start
    }

    pub(super) fn end(&self) -> Vec3 {
        self.edge.end
    }

    /// The direction the edge leaves its start (`at_start`) or end by.
    pub(super) fn leaving(&self, at_start: bool) -> Vec3 {
        if at_start {
            self.edge.at(0.0).1
        } else {
            let d = self.edge.at(1.0).1;
            [-d[0], -d[1], -d[2]]
        }
    }

    /// The edge as a [`TrimEdge`] (`free`, `ends` as the shell says).
    pub(super) fn into_edge(self, free: bool, ends: Option<[Vec3; 2]>) -> TrimEdge {
        let pts: Vec<Vec3> = (0..=32).map(|k| self.edge.at(k as f64 / 32.0).0).collect();
        let length = pts.windows(2).map(|w| dist(w[0], w[1])).sum();
        let off_surface = self.off;
        let vertex_off = self.edge.vertex_off;
        let breaks = self.breaks.clone();
        TrimEdge {
            edge: TrueEdge::new(move |t| self.frame(t)).with_breaks(breaks),
            free,
            ends,
            length,
            off_surface,
            vertex_off,
        }
    }
}

/// How many of `knots` are t.
fn multiplicity(knots: &[f64], t: f64) -> usize {
    knots.iter().filter(|&&k| k == t).count()
}

/// [`file_foot`] from `hint`, or from the surface's own search where that
/// lands farther than `tol` (Newton steps from a hint stay in a B-spline's
/// domain: a closed surface's point across its seam is reached from the
/// other end).
fn foot_within(
    file: (&StepSurface, Option<&SeededSpline>),
    p: Vec3,
    hint: Option<(f64, f64)>,
    tol: f64,
) -> Option<((f64, f64), f64)> {
    let better = |a: Option<((f64, f64), f64)>, b: Option<((f64, f64), f64)>| match (a, b) {
        (Some(a), Some(b)) => Some(if b.1 < a.1 { b } else { a }),
        (a, b) => a.or(b),
    };
    let mut near = file_foot_on(file, p, hint);
    if hint.is_some() && near.is_none_or(|n| n.1 > tol) {
        near = better(near, file_foot_on(file, p, None));
    }
    // Near a B-spline's collapsed side (a pole) the 17 × 17 seeds can all
    // be too far round for Newton steps: a finer grid.
    if let (Some(s), true) = (file.1, near.is_none_or(|n| n.1 > tol)) {
        near = better(near, Some(nearest(&s.surface, s.fine(), p)));
    }
    near
}

/// The parameters of the point of a file's surface nearest to p, and the
/// distance: Newton steps on (S − p)·S_u = (S − p)·S_v = 0 from `hint`, or
/// from the surface's own search (a 33 × 33 grid of a bounded parameter
/// range where that fails: its sphere's at the seam gives NaN).
pub(super) fn file_foot(
    file: &StepSurface,
    p: Vec3,
    hint: Option<(f64, f64)>,
) -> Option<((f64, f64), f64)> {
    file_foot_on((file, None), p, hint)
}

/// [`file_foot`], its Newton steps on `spline` (the file's B-spline as
/// fairsurf's, the same parameters) when given.
fn file_foot_on(
    (file, spline): (&StepSurface, Option<&SeededSpline>),
    p: Vec3,
    hint: Option<(f64, f64)>,
) -> Option<((f64, f64), f64)> {
    // Without a hint: the nearest of a B-spline's 17 × 17 grid, by
    // fairsurf's evaluation (truck's search evaluates its own grid by its
    // evaluation, one pass over the basis functions per derivative).
    if let (Some(s), None) = (spline, hint) {
        return Some(nearest(&s.surface, s.coarse(), p));
    }
    let q = Point3::new(p[0], p[1], p[2]);
    let uv = match hint {
        Some(uv) => uv,
        None => {
            let found = SearchNearestParameter::<D2>::search_nearest_parameter(file, q, None, 100)
                .filter(|uv| uv.0.is_finite() && uv.1.is_finite());
            match (found, file.try_range_tuple()) {
                (Some(uv), _) => uv,
                (None, (Some((u0, u1)), Some((v0, v1)))) => (0..=32)
                    .flat_map(|i| (0..=32).map(move |j| (i, j)))
                    .map(|(i, j)| {
                        (
                            u0 + (u1 - u0) * i as f64 / 32.0,
                            v0 + (v1 - v0) * j as f64 / 32.0,
                        )
                    })
                    .min_by(|x, y| {
                        dist(v3(file.subs(x.0, x.1)), p)
                            .total_cmp(&dist(v3(file.subs(y.0, y.1)), p))
                    })?,
                (None, _) => return None,
            }
        }
    };
    let w = |x: Vector3| [x.x, x.y, x.z];
    let truck = |u: f64, v: f64| fairsurf::SurfaceDerivatives {
        point: v3(file.subs(u, v)),
        du: w(file.uder(u, v)),
        dv: w(file.vder(u, v)),
        duu: w(file.uuder(u, v)),
        duv: w(file.uvder(u, v)),
        dvv: w(file.vvder(u, v)),
    };
    // A B-spline's parameters stay in its knot domain; an elementary
    // surface's run on (truck gives a plane the range [0, 1]² "as a
    // square").
    let all = (f64::MIN, f64::MAX);
    let domain = match (file, file.try_range_tuple()) {
        (StepSurface::BSplineSurface(_) | StepSurface::NurbsSurface(_), (Some(u), Some(v))) => {
            (u, v)
        }
        _ => (all, all),
    };
    Some(match spline {
        Some(s) => {
            let s = &s.surface;
            let start = dist(eval(s, uv.0, uv.1), p);
            foot(&|u, v| derivatives(s, u, v), p, uv, start, domain)
        }
        None => {
            let start = dist(v3(file.subs(uv.0, uv.1)), p);
            foot(&truck, p, uv, start, domain)
        }
    })
}
