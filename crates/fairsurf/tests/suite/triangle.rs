//! Triangular Bézier patches (Veltkamp & Wesselink §2): the Bernstein basis,
//! evaluation, derivatives, degree elevation and subdivision, checked against
//! closed forms, finite differences and each other.

use crate::common::Rng;
use fairsurf::analysis::curvature_from;
use fairsurf::triangle::{multi_indices, tri_bernstein_all, Bary};
use fairsurf::vector::{add, cross, norm, normalize, scale, sub};
use fairsurf::{Error, TriPatch, Vec3};
use proptest::prelude::*;

const V1: Bary = [1.0, 0.0, 0.0];
const V2: Bary = [0.0, 1.0, 0.0];
const V3: Bary = [0.0, 0.0, 1.0];

/// A patch of degree n with control points uniform in [−1, 1)³.
fn random_patch(n: usize, seed: u64) -> TriPatch {
    let mut r = Rng::new(seed);
    TriPatch::from_fn(n, |_, _, _| r.vec3())
}

/// A point of the closed triangle from two numbers in [0, 1): the unit square
/// folded along its diagonal.
fn fold(a: f64, b: f64) -> Bary {
    let (u, v) = if a + b > 1.0 {
        (1.0 - a, 1.0 - b)
    } else {
        (a, b)
    };
    [u, v, 1.0 - u - v]
}

/// A random point of the triangle.
fn random_bary(r: &mut Rng) -> Bary {
    fold(0.5 * (r.uniform() + 1.0), 0.5 * (r.uniform() + 1.0))
}

/// s₀a + s₁b + s₂c.
fn combine(corners: [Bary; 3], s: Bary) -> Bary {
    (0..3).fold([0.0; 3], |x, m| add(x, scale(corners[m], s[m])))
}

fn dist(a: Vec3, b: Vec3) -> f64 {
    norm(sub(a, b))
}

/// Max |T − S| over a set of points, the same barycentrics for both.
fn max_gap(t: &TriPatch, s: &TriPatch, pts: &[Bary]) -> f64 {
    pts.iter()
        .map(|&b| dist(t.eval(b), s.eval(b)))
        .fold(0.0, f64::max)
}

fn sample_points(count: usize, seed: u64) -> Vec<Bary> {
    let mut r = Rng::new(seed);
    let mut pts: Vec<Bary> = (0..count).map(|_| random_bary(&mut r)).collect();
    pts.extend([
        V1,
        V2,
        V3,
        [0.5, 0.5, 0.0],
        [0.0, 0.25, 0.75],
        [1.0 / 3.0; 3],
    ]);
    pts
}

// ---------------------------------------------------------------------------
// The Bernstein basis and evaluation

proptest! {
    #[test]
    fn bernstein_polynomials_are_a_nonnegative_partition_of_unity(
        n in 0usize..=12, a in 0.0..1.0f64, b in 0.0..1.0f64,
    ) {
        let x = fold(a, b);
        let basis = tri_bernstein_all(n, x);
        prop_assert!(basis.iter().all(|&v| v >= 0.0));
        prop_assert!((basis.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    }

    #[test]
    fn de_casteljau_equals_the_bernstein_form(
        n in 1usize..=12, seed in any::<u64>(), a in 0.0..1.0f64, b in 0.0..1.0f64,
    ) {
        let t = random_patch(n, seed);
        let x = fold(a, b);
        prop_assert!(dist(t.eval(x), t.eval_bernstein(x)) < 1e-14);
    }

    #[test]
    fn directional_derivatives_are_combinations_of_the_parametric_ones(
        n in 1usize..=10, seed in any::<u64>(), a in 0.0..1.0f64, b in 0.0..1.0f64,
    ) {
        let t = random_patch(n, seed);
        let x = fold(a, b);
        let mut r = Rng::new(seed ^ 0x5eed);
        // Two random directions (summing to 0).
        let (d, e) = (sub(random_bary(&mut r), x), sub(random_bary(&mut r), x));
        let p = t.derivatives(x);
        let scale_of = |v: Vec3| 1.0 + norm(v);
        let dd = add(scale(p.du, d[0]), scale(p.dv, d[1]));
        prop_assert!(dist(t.directional_derivative(x, d), dd) < 1e-13 * scale_of(dd));
        let de = add(
            add(scale(p.duu, d[0] * e[0]), scale(p.duv, d[0] * e[1] + d[1] * e[0])),
            scale(p.dvv, d[1] * e[1]),
        );
        let big = 1.0 + norm(p.duu) + norm(p.duv) + norm(p.dvv);
        prop_assert!(dist(t.second_directional_derivative(x, d, e), de) < 1e-13 * big);
        prop_assert_eq!(p.point, t.eval(x));
    }
}

#[test]
fn the_corners_and_edges_are_interpolated() {
    for n in 1..=8 {
        let t = random_patch(n, n as u64);
        assert_eq!(t.eval(V1), t.point(n, 0, 0));
        assert_eq!(t.eval(V2), t.point(0, n, 0));
        assert_eq!(t.eval(V3), t.point(0, 0, n));
        // Edge k runs from corner k+1 to corner k+2 with the barycentric k zero.
        for k in 0..3 {
            let c = t.edge(k);
            assert_eq!(c.degree(), n);
            for s in [0.0, 0.3, 0.71, 1.0] {
                let mut x = [0.0; 3];
                x[(k + 1) % 3] = 1.0 - s;
                x[(k + 2) % 3] = s;
                assert!(dist(c.eval(s), t.eval(x)) < 1e-14);
                // Along the edge, D_d T for d = V_{k+2} − V_{k+1} is C′(s).
                let mut d = [0.0; 3];
                d[(k + 1) % 3] = -1.0;
                d[(k + 2) % 3] = 1.0;
                let tangent = t.directional_derivative(x, d);
                let scale_of = 1.0 + norm(tangent);
                assert!(dist(c.derivative().eval(s), tangent) < 1e-13 * scale_of);
            }
        }
    }
}

#[test]
fn linear_precision_reproduces_the_plane_and_its_normal() {
    let (a, b, c) = ([1.0, -0.5, 2.0], [0.3, 2.0, -1.0], [-1.5, 0.25, 0.5]);
    let normal = normalize(cross(sub(a, c), sub(b, c))).unwrap();
    for n in 1..=12 {
        let nf = n as f64;
        let t = TriPatch::from_fn(n, |i, j, k| {
            let (i, j, k) = (i as f64 / nf, j as f64 / nf, k as f64 / nf);
            add(add(scale(a, i), scale(b, j)), scale(c, k))
        });
        for x in sample_points(50, 7 + n as u64) {
            let exact = add(add(scale(a, x[0]), scale(b, x[1])), scale(c, x[2]));
            assert!(dist(t.eval(x), exact) < 1e-14, "degree {n} at {x:?}");
            assert!(dist(t.eval_bernstein(x), exact) < 1e-14);
            let d = t.derivatives(x);
            assert!(dist(d.du, sub(a, c)) < 1e-13 && dist(d.dv, sub(b, c)) < 1e-13);
            assert!(norm(d.duu) + norm(d.duv) + norm(d.dvv) < 1e-12);
            assert!(dist(t.normal(x).unwrap(), normal) < 1e-14);
        }
    }
}

#[test]
fn relabelling_the_corners_permutes_the_barycentrics() {
    let perms = [
        [0, 1, 2],
        [1, 2, 0],
        [2, 0, 1],
        [1, 0, 2],
        [0, 2, 1],
        [2, 1, 0],
    ];
    for n in [1, 2, 3, 5, 8] {
        let t = random_patch(n, 100 + n as u64);
        for (p_index, perm) in perms.into_iter().enumerate() {
            // Q_λ = P_μ with μ[perm[m]] = λ[m], written out here.
            let by_hand = TriPatch::from_fn(n, |i, j, k| {
                let lambda = [i, j, k];
                let mut mu = [0; 3];
                (0..3).for_each(|m| mu[perm[m]] = lambda[m]);
                t.point(mu[0], mu[1], mu[2])
            });
            let q = t.permute_corners(perm);
            assert_eq!(q, by_hand);
            for x in sample_points(20, 3) {
                let mut y = [0.0; 3];
                (0..3).for_each(|m| y[perm[m]] = x[m]);
                assert!(dist(q.eval(x), t.eval(y)) < 1e-14);
                // Even permutations keep the normal, odd ones flip it.
                if let (Some(nq), Some(nt)) = (q.normal(x), t.normal(y)) {
                    let sign = if p_index < 3 { 1.0 } else { -1.0 };
                    assert!(dist(nq, scale(nt, sign)) < 1e-9);
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Derivatives

/// Central differences of the point only, in (u, v) with w = 1 − u − v.
fn finite_differences(t: &TriPatch, u: f64, v: f64) -> [Vec3; 5] {
    let at = |u: f64, v: f64| t.eval([u, v, 1.0 - u - v]);
    let (h, k) = (1e-5, 1e-4);
    let d1 = |a: Vec3, b: Vec3| scale(sub(a, b), 0.5 / h);
    let second = |a: Vec3, c: Vec3, b: Vec3| scale(add(sub(a, scale(c, 2.0)), b), 1.0 / (k * k));
    let mixed = scale(
        sub(
            sub(at(u + k, v + k), at(u + k, v - k)),
            sub(at(u - k, v + k), at(u - k, v - k)),
        ),
        0.25 / (k * k),
    );
    let c = at(u, v);
    [
        d1(at(u + h, v), at(u - h, v)),
        d1(at(u, v + h), at(u, v - h)),
        second(at(u + k, v), c, at(u - k, v)),
        mixed,
        second(at(u, v + k), c, at(u, v - k)),
    ]
}

#[test]
fn derivatives_match_central_differences() {
    for n in [1, 2, 3, 4, 6, 9] {
        let t = random_patch(n, 31 + n as u64);
        for [u, v, _] in [
            [0.2, 0.3, 0.5],
            [0.6, 0.1, 0.3],
            [0.1, 0.8, 0.1],
            [0.45, 0.45, 0.1],
        ] {
            let d = t.derivatives([u, v, 1.0 - u - v]);
            let fd = finite_differences(&t, u, v);
            // Relative to the size of the exact derivative, which grows like nʳ.
            let first_scale = 1.0 + norm(d.du) + norm(d.dv);
            let second_scale = 1.0 + norm(d.duu) + norm(d.duv) + norm(d.dvv);
            assert!(dist(fd[0], d.du) < 1e-8 * first_scale, "T_u, degree {n}");
            assert!(dist(fd[1], d.dv) < 1e-8 * first_scale, "T_v, degree {n}");
            assert!(dist(fd[2], d.duu) < 1e-5 * second_scale, "T_uu, degree {n}");
            assert!(dist(fd[3], d.duv) < 1e-5 * second_scale, "T_uv, degree {n}");
            assert!(dist(fd[4], d.dvv) < 1e-5 * second_scale, "T_vv, degree {n}");
        }
    }
}

#[test]
fn directional_derivatives_match_central_differences() {
    let h = 1e-5;
    for n in [2, 3, 5, 7] {
        let t = random_patch(n, 77 + n as u64);
        let x = [0.25, 0.35, 0.4];
        for d in [[1.0, -0.5, -0.5], [0.0, -1.0, 1.0], [0.3, 0.4, -0.7]] {
            let fd = scale(
                sub(t.eval(add(x, scale(d, h))), t.eval(sub(x, scale(d, h)))),
                0.5 / h,
            );
            let exact = t.directional_derivative(x, d);
            assert!(dist(fd, exact) < 1e-8 * (1.0 + norm(exact)));
            // D_d D_d T against differences of D_d T.
            let fd2 = scale(
                sub(
                    t.directional_derivative(add(x, scale(d, h)), d),
                    t.directional_derivative(sub(x, scale(d, h)), d),
                ),
                0.5 / h,
            );
            let exact2 = t.second_directional_derivative(x, d, d);
            assert!(dist(fd2, exact2) < 1e-8 * (1.0 + norm(exact2)));
        }
    }
}

/// z = f(u, v) = a u² + b uv + c v² + d u + e v + g over x = u, y = v.
struct Quadratic {
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    e: f64,
    g: f64,
}

impl Quadratic {
    /// The blossom of (u, v, f(u, v)) homogenised with u + v + w = 1, at two
    /// barycentric points; control point P_ijk is its value at two of the
    /// corners V₁, V₂, V₃.
    fn blossom(&self, x: Bary, y: Bary) -> Vec3 {
        let z = self.a * x[0] * y[0]
            + self.b * 0.5 * (x[0] * y[1] + x[1] * y[0])
            + self.c * x[1] * y[1]
            + self.d * 0.5 * (x[0] + y[0])
            + self.e * 0.5 * (x[1] + y[1])
            + self.g;
        [0.5 * (x[0] + y[0]), 0.5 * (x[1] + y[1]), z]
    }

    fn patch(&self) -> TriPatch {
        let corner = [V1, V2, V3];
        TriPatch::from_fn(2, |i, j, k| {
            let mut args = std::iter::repeat_n(corner[0], i)
                .chain(std::iter::repeat_n(corner[1], j))
                .chain(std::iter::repeat_n(corner[2], k));
            let (x, y) = (args.next().unwrap(), args.next().unwrap());
            self.blossom(x, y)
        })
    }
}

#[test]
fn a_quadratic_patch_has_the_analytic_derivatives_and_curvature() {
    let q = Quadratic {
        a: 0.7,
        b: -1.2,
        c: 0.4,
        d: 0.3,
        e: -0.8,
        g: 1.5,
    };
    let t = q.patch();
    for [u, v, w] in sample_points(40, 11) {
        let d = t.derivatives([u, v, w]);
        let f = q.a * u * u + q.b * u * v + q.c * v * v + q.d * u + q.e * v + q.g;
        let (fu, fv) = (2.0 * q.a * u + q.b * v + q.d, q.b * u + 2.0 * q.c * v + q.e);
        let (fuu, fuv, fvv) = (2.0 * q.a, q.b, 2.0 * q.c);
        assert!(dist(d.point, [u, v, f]) < 1e-14);
        assert!(dist(d.du, [1.0, 0.0, fu]) < 1e-14);
        assert!(dist(d.dv, [0.0, 1.0, fv]) < 1e-14);
        assert!(dist(d.duu, [0.0, 0.0, fuu]) < 1e-14);
        assert!(dist(d.duv, [0.0, 0.0, fuv]) < 1e-14);
        assert!(dist(d.dvv, [0.0, 0.0, fvv]) < 1e-14);
        // The curvature of the graph z = f(x, y), normal (−f_x, −f_y, 1)/W.
        let w2 = 1.0 + fu * fu + fv * fv;
        let k = (fuu * fvv - fuv * fuv) / (w2 * w2);
        let h = ((1.0 + fv * fv) * fuu - 2.0 * fu * fv * fuv + (1.0 + fu * fu) * fvv)
            / (2.0 * w2.powf(1.5));
        let c = curvature_from(&d).unwrap();
        assert!((c.gaussian - k).abs() < 1e-13 && (c.mean - h).abs() < 1e-13);
        let nrm = scale([-fu, -fv, 1.0], 1.0 / w2.sqrt());
        assert!(dist(t.normal([u, v, w]).unwrap(), nrm) < 1e-14);
    }
}

#[test]
fn a_collapsed_corner_has_no_normal() {
    let mut t = random_patch(3, 5);
    let c = t.point(0, 3, 0);
    t.set_point(1, 2, 0, c);
    t.set_point(0, 2, 1, c);
    assert_eq!(t.normal(V2), None);
    assert!(t.normal([0.3, 0.3, 0.4]).is_some());
}

// ---------------------------------------------------------------------------
// Degree elevation

#[test]
fn elevation_keeps_the_surface() {
    let pts = sample_points(100, 21);
    for n in 1..=8 {
        let t = random_patch(n, 200 + n as u64);
        for r in 1..=4 {
            let e = t.elevate(r);
            assert_eq!(e.degree(), n + r);
            assert!(max_gap(&t, &e, &pts) < 1e-14, "degree {n} by {r}");
            for m in 0..3 {
                assert_eq!(e.corner(m), t.corner(m));
            }
        }
    }
}

#[test]
fn elevating_twice_is_elevating_by_two() {
    for n in 1..=8 {
        let t = random_patch(n, 300 + n as u64);
        let (twice, by_two) = (t.elevate(1).elevate(1), t.elevate(2));
        for (p, q) in twice.points().iter().zip(by_two.points()) {
            assert!(dist(*p, *q) < 1e-15, "degree {n}");
        }
        let (thrice, by_three) = (t.elevate(2).elevate(1), t.elevate(3));
        for (p, q) in thrice.points().iter().zip(by_three.points()) {
            assert!(dist(*p, *q) < 1e-15, "degree {n}");
        }
    }
}

// ---------------------------------------------------------------------------
// Subdivision

#[test]
fn splitting_into_three_reproduces_the_surface() {
    let pts = sample_points(200, 41);
    for n in 1..=9 {
        let t = random_patch(n, 400 + n as u64);
        let mut r = Rng::new(n as u64);
        // An interior point away from the edges.
        let p = loop {
            let p = random_bary(&mut r);
            if p.iter().all(|&x| x > 0.05) {
                break p;
            }
        };
        let subs = t.subdivide_interior(p);
        for (m, s) in subs.iter().enumerate() {
            let mut corners = [V1, V2, V3];
            corners[m] = p;
            for &x in &pts {
                assert!(dist(s.eval(x), t.eval(combine(corners, x))) < 1e-14);
            }
            // Its corners are the original corners and the split point.
            for c in 0..3 {
                let expected = if c == m { t.eval(p) } else { t.corner(c) };
                assert_eq!(
                    s.corner(c),
                    expected,
                    "degree {n}, sub-patch {m}, corner {c}"
                );
            }
            // Its outer edge is the original edge, point for point.
            assert_eq!(s.edge(m), t.edge(m));
        }
        // Sub-patches a and b share the edge from p to the corner they both keep.
        for (a, b) in [(0, 1), (1, 2), (2, 0)] {
            let kept = 3 - a - b;
            let ea = subs[a].edge(b).points().to_vec();
            let mut eb = subs[b].edge(a).points().to_vec();
            eb.reverse();
            assert_eq!(
                ea, eb,
                "degree {n}, sub-patches {a} and {b} (corner {kept})"
            );
        }
    }
}

#[test]
fn splitting_into_two_reproduces_the_surface() {
    let pts = sample_points(200, 43);
    for n in 1..=9 {
        let t = random_patch(n, 500 + n as u64);
        for k in 0..3 {
            for s in [0.5, 0.13, 0.8] {
                let [a, b] = t.subdivide_edge(k, s);
                let (start, end) = ((k + 1) % 3, (k + 2) % 3);
                let mut q = [0.0; 3];
                q[start] = 1.0 - s;
                q[end] = s;
                let mut ca = [V1, V2, V3];
                ca[end] = q;
                let mut cb = [V1, V2, V3];
                cb[start] = q;
                for &x in &pts {
                    assert!(dist(a.eval(x), t.eval(combine(ca, x))) < 1e-14);
                    assert!(dist(b.eval(x), t.eval(combine(cb, x))) < 1e-14);
                }
                // Corners: the kept corner k, the edge's ends, the split point.
                assert_eq!(a.corner(k), t.corner(k));
                assert_eq!(b.corner(k), t.corner(k));
                assert_eq!(a.corner(start), t.corner(start));
                assert_eq!(b.corner(end), t.corner(end));
                assert_eq!(a.corner(end), t.eval(q));
                assert_eq!(b.corner(start), t.eval(q));
                assert!(dist(a.corner(end), t.edge(k).eval(s)) < 1e-14);
                // The common edge from q to corner k, bitwise.
                let ea = a.edge(start).points().to_vec(); // a: from q to corner k
                let mut eb = b.edge(end).points().to_vec(); // b: from corner k to q
                eb.reverse();
                assert_eq!(ea, eb, "degree {n}, edge {k}, t = {s}");
                // The other two edges are the original ones.
                assert_eq!(a.edge(end), t.edge(end));
                assert_eq!(b.edge(start), t.edge(start));
            }
        }
    }
}

#[test]
fn subdivision_of_a_quadratic_keeps_its_derivatives() {
    // The split pieces are the same polynomial in another parameterization:
    // second derivatives transform by the (constant) Jacobian.
    let q = Quadratic {
        a: 1.0,
        b: 0.5,
        c: -0.3,
        d: 0.0,
        e: 0.2,
        g: 0.0,
    };
    let t = q.patch();
    let p = [0.2, 0.5, 0.3];
    let [s0, _, _] = t.subdivide_interior(p);
    // s0 over (p, V₂, V₃): s0's u-direction is p − V₃, its v-direction V₂ − V₃.
    let x = [0.3, 0.3, 0.4];
    let y = combine([p, V2, V3], x);
    let (ds, dt) = (s0.derivatives(x), t.derivatives(y));
    let du = sub(p, V3);
    let expected_du = add(scale(dt.du, du[0]), scale(dt.dv, du[1]));
    assert!(dist(ds.du, expected_du) < 1e-14);
    assert!(dist(ds.dv, dt.dv) < 1e-14);
}

// ---------------------------------------------------------------------------
// Construction errors

#[test]
fn wrong_count_is_an_error_naming_both_counts() {
    let e = TriPatch::try_new(3, vec![[0.0; 3]; 9]).unwrap_err();
    match &e {
        Error::Mismatch { expected, got, .. } => {
            assert!(expected.starts_with("10"));
            assert_eq!(got, "9");
        }
        other => panic!("expected Mismatch, got {other:?}"),
    }
    assert!(e.to_string().contains("degree-3 triangular"));
    assert!(TriPatch::try_new(0, vec![]).is_err());
    assert!(TriPatch::try_new(1, vec![[0.0; 3]; 3]).is_ok());
    assert!(TriPatch::try_new(usize::MAX, vec![]).is_err());
}

#[test]
fn a_non_finite_point_is_an_error_naming_it() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut pts = vec![[0.0; 3]; 10];
        pts[7][2] = bad; // P_102 in the storage order
        assert_eq!(
            TriPatch::try_new(3, pts),
            Err(Error::NotFinite {
                what: "control point (1, 0, 2)".into()
            })
        );
    }
    // The storage order is the documented one.
    let order: Vec<[usize; 3]> = multi_indices(3).collect();
    assert_eq!(order[7], [1, 0, 2]);
}

#[test]
#[should_panic(expected = "TriPatch::new")]
fn new_panics_on_a_wrong_count() {
    TriPatch::new(2, vec![[0.0; 3]; 5]);
}
