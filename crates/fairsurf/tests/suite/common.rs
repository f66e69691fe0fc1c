//! Shared helpers for the integration tests (a tiny deterministic RNG, nets).
#![allow(dead_code, missing_docs)]

use fairsurf::Bend;
use fairsurf::{TensorPatch, Vec3};

/// xorshift64*: deterministic, dependency-free pseudo-random numbers.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Uniform in [−1, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    pub fn vec3(&mut self) -> Vec3 {
        [self.uniform(), self.uniform(), self.uniform()]
    }
}

/// A wavy net over roughly the unit square with random perturbations.
pub fn random_net(n: usize, m: usize, seed: u64) -> TensorPatch {
    let mut r = Rng::new(seed);
    TensorPatch::from_fn(n, m, |i, j| {
        let (x, y) = (i as f64 / n as f64, j as f64 / m as f64);
        [
            x + 0.05 * r.uniform(),
            y + 0.05 * r.uniform(),
            0.3 * (3.0 * x).sin() * (2.0 * y + 0.5).cos() + 0.1 * r.uniform(),
        ]
    })
}

/// A smooth unit-ish normal field of degree (2, 2) tilting across the square.
pub fn tilted_field() -> TensorPatch {
    TensorPatch::from_fn(2, 2, |i, j| {
        [0.4 * (i as f64 - 1.0), 0.3 * (j as f64 - 1.0), 1.0]
    })
}

pub fn max_dist(a: &TensorPatch, b: &TensorPatch) -> f64 {
    a.points()
        .iter()
        .zip(b.points())
        .map(|(p, q)| fairsurf::vector::norm(fairsurf::vector::sub(*p, *q)))
        .fold(0.0, f64::max)
}

/// The unit square as an m × m grid of squares, each cut along its
/// diagonal into two counter-clockwise triangles: triangle 2(j·m + i) is
/// (i, j), (i+1, j), (i+1, j+1), the next one (i, j), (i+1, j+1), (i, j+1).
pub fn tri_grid(m: usize, n: usize) -> fairsurf::TriSurface {
    let id = |i: usize, j: usize| j * (m + 1) + i;
    let mut v = Vec::new();
    for j in 0..=m {
        for i in 0..=m {
            v.push([i as f64 / m as f64, j as f64 / m as f64, 0.0]);
        }
    }
    let mut t = Vec::new();
    for j in 0..m {
        for i in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    fairsurf::TriSurface::new(&v, &t, n)
}

/// One constraint of each kind (Veltkamp & Wesselink §4.1), at points of
/// [0, 1]².
pub fn four_constraints() -> Vec<(&'static str, fairsurf::TensorConstraint)> {
    use fairsurf::TensorConstraint as C;
    vec![
        (
            "peak",
            C::Point {
                at: [0.3, 0.4],
                target: [0.32, 0.41, 0.2],
            },
        ),
        (
            "tilt",
            C::Normal {
                at: [0.65, 0.6],
                normal: [0.3, -0.1, 1.0],
            },
        ),
        (
            "shelf",
            C::InPlane {
                at: [0.5, 0.2],
                normal: [0.1, 0.0, 1.0],
                offset: 0.12,
            },
        ),
        (
            "rail",
            C::OnLine {
                at: [0.25, 0.75],
                point: [0.25, 0.75, -0.1],
                direction: [0.0, 0.3, 1.0],
            },
        ),
    ]
}

/// How far a surface is from meeting the constraint, measured from its
/// point and first derivatives `(R, R_u, R_v)` at a parameter (not through
/// the constraint's rows).
pub fn constraint_miss(
    derivatives: impl Fn([f64; 2]) -> (Vec3, Vec3, Vec3),
    c: &fairsurf::TensorConstraint,
) -> f64 {
    use fairsurf::vector::{cross, dot, norm, normalize, sub};
    use fairsurf::TensorConstraint as C;
    match *c {
        C::Point { at, target } => norm(sub(derivatives(at).0, target)),
        C::Normal { at, normal } => {
            let (_, du, dv) = derivatives(at);
            let n = normalize(normal).unwrap();
            dot(n, du).abs().max(dot(n, dv).abs())
        }
        C::InPlane { at, normal, offset } => {
            (dot(normal, derivatives(at).0) - offset).abs() / norm(normal)
        }
        C::OnLine {
            at,
            point,
            direction,
        } => norm(cross(sub(derivatives(at).0, point), direction)) / norm(direction),
        C::Fixed { .. } => unreachable!("a fixed control point is no surface constraint"),
    }
}

/// Random directions over the free points' coordinates (3k + c), projected
/// on the null space of the rows (over all coordinates 3g + c): moves along
/// the constraints.
pub fn moves_along(
    rows: &[fairsurf::constraint::Row],
    free: &[usize],
    seed: u64,
    count: usize,
) -> Vec<Vec<f64>> {
    let n = 3 * free.len();
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for row in rows {
        let mut v = vec![0.0; n];
        for &(i, a) in &row.terms {
            if let Some(k) = free.iter().position(|&p| p == i / 3) {
                v[3 * k + i % 3] += a;
            }
        }
        for q in &basis {
            let d: f64 = v.iter().zip(q).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(q).for_each(|(a, b)| *a -= d * b);
        }
        let l = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        basis.push(v.iter().map(|a| a / l).collect());
    }
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|_| {
            let mut d: Vec<f64> = (0..n).map(|_| rng.uniform()).collect();
            for q in &basis {
                let p: f64 = d.iter().zip(q).map(|(a, b)| a * b).sum();
                d.iter_mut().zip(q).for_each(|(a, b)| *a -= p * b);
            }
            d
        })
        .collect()
}

/// An attractor or director named `name` (not a repellor).
pub fn attractor<P>(
    name: &str,
    target: fairsurf::operator::Target,
    place: P,
    strength: f64,
) -> fairsurf::operator::Operator<P> {
    fairsurf::operator::Operator {
        name: name.into(),
        target,
        place,
        strength,
        repel: false,
    }
}

/// A B-spline surface over the knots `u`, `v` whose control points lie on
/// the graph of `f` over the Greville abscissae.
pub fn graph_bspline(
    u: fairsurf::bspline::KnotVector,
    v: fairsurf::bspline::KnotVector,
    f: impl Fn(f64, f64) -> f64,
) -> fairsurf::bspline::BSplineSurface {
    let (gu, gv) = (u.greville(), v.greville());
    let points = gu
        .iter()
        .flat_map(|&x| gv.iter().map(|&y| [x, y, f(x, y)]).collect::<Vec<_>>())
        .collect();
    fairsurf::bspline::BSplineSurface::new(u, v, points).unwrap()
}

/// The largest distance between corresponding points of two nets.
pub fn max_distance(a: &[Vec3], b: &[Vec3]) -> f64 {
    assert_eq!(a.len(), b.len(), "nets of different sizes");
    a.iter()
        .zip(b)
        .map(|(x, y)| fairsurf::vector::norm(fairsurf::vector::sub(*x, *y)))
        .fold(0.0, f64::max)
}

/// A bicubic B-spline of 6 × 5 uniform spans over the unit square, a wavy
/// sheet (the guidance tests' surface).
#[allow(dead_code)]
pub fn wavy_sheet() -> fairsurf::bspline::BSplineSurface {
    use fairsurf::bspline::KnotVector;
    graph_bspline(
        KnotVector::uniform(3, 6),
        KnotVector::uniform(3, 5),
        |x, y| 0.15 * (3.0 * x).sin() * (2.0 * y).cos(),
    )
}

/// Asserts that `s` (on the problem's knots) is the problem's minimum: its
/// energy is the report's `energy` (to 1e-12) and six random moves of the
/// free points by up to 1e-4 each raise it.
#[allow(dead_code)]
pub fn assert_bspline_minimal(
    problem: &fairsurf::bspline::BSplineProblem,
    s: &fairsurf::bspline::BSplineSurface,
    energy: f64,
    seed: u64,
) {
    let e0 = problem.energy_at(s).unwrap();
    assert!((e0 - energy).abs() < 1e-12 * energy, "{e0} vs {energy}");
    let free: Vec<usize> = (0..problem.free().len())
        .filter(|&k| problem.free()[k])
        .collect();
    let (ku, kv) = s.knots();
    let mut rng = Rng::new(seed);
    for trial in 0..6 {
        let mut points = s.points().to_vec();
        for &g in &free {
            for c in 0..3 {
                points[g][c] += 1e-4 * rng.uniform();
            }
        }
        let moved = fairsurf::bspline::BSplineSurface::new(ku.clone(), kv.clone(), points).unwrap();
        assert!(problem.energy_at(&moved).unwrap() > e0, "trial {trial}");
    }
}

/// The thin plate on [`wavy_sheet`] with two rings fixed.
#[allow(dead_code)]
pub fn wavy_problem() -> fairsurf::bspline::BSplineProblem {
    fairsurf::bspline::BSplineProblem::from_surface(wavy_sheet())
        .with_fixed_rings(2)
        .with_term(Bend::new(1.0))
}
