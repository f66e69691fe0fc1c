//! Curvature and continuity measures against analytic values and
//! constructed joins.

use crate::common::random_net;
use faer::linalg::solvers::Solve;
use faer::Mat;
use fairsurf::analysis::{abs_mean_curvature, continuity, curvature, Edge};
use fairsurf::basis::bernstein_all;
use fairsurf::TensorPatch;

/// The sphere of radius R over (θ, φ) ∈ [0.3, 0.9] × [0.2, 0.8] (colatitude,
/// longitude), interpolated at degree n.
fn sphere_patch(n: usize, r: f64) -> TensorPatch {
    interpolated(n, |u, v| {
        let (th, ph) = (0.3 + 0.6 * u, 0.2 + 0.6 * v);
        [
            r * th.sin() * ph.cos(),
            r * th.sin() * ph.sin(),
            r * th.cos(),
        ]
    })
}

/// The degree-(n, n) patch interpolating f on Chebyshev–Lobatto points.
fn interpolated(n: usize, f: impl Fn(f64, f64) -> [f64; 3]) -> TensorPatch {
    let ts: Vec<f64> = (0..=n)
        .map(|k| 0.5 - 0.5 * (std::f64::consts::PI * k as f64 / n as f64).cos())
        .collect();
    // Collocation: B Pᶜ Bᵀ = X per coordinate, B_ki = B_i^n(t_k).
    let b = Mat::from_fn(n + 1, n + 1, |k, i| bernstein_all(n, ts[k])[i]);
    let lu = b.partial_piv_lu();
    let mut coords = Vec::new();
    for c in 0..3 {
        let x = Mat::from_fn(n + 1, n + 1, |k, l| f(ts[k], ts[l])[c]);
        let y = lu.solve(&x); // B⁻¹ X
        let p = lu.solve(y.transpose().to_owned()); // B⁻¹ (B⁻¹ X)ᵀ = Pᵀ
        coords.push(p.transpose().to_owned());
    }
    TensorPatch::from_fn(n, n, |i, j| {
        [coords[0][(i, j)], coords[1][(i, j)], coords[2][(i, j)]]
    })
}

#[test]
fn sphere_curvatures_converge_to_the_analytic_values() {
    let r = 2.0;
    let mut prev = f64::INFINITY;
    for n in [3, 5, 7, 9] {
        let p = sphere_patch(n, r);
        let mut err: f64 = 0.0;
        for &(u, v) in &[(0.1, 0.2), (0.5, 0.5), (0.9, 0.7), (0.3, 0.95)] {
            let c = curvature(&p, u, v).unwrap();
            err = err
                .max((c.gaussian - 1.0 / (r * r)).abs() * r * r)
                .max((c.mean.abs() - 1.0 / r).abs() * r)
                .max((c.principal.0.abs() - 1.0 / r).abs() * r)
                .max((c.principal.1.abs() - 1.0 / r).abs() * r);
        }
        assert!(err < prev, "n = {n}: {err:e} did not improve on {prev:e}");
        prev = err;
    }
    assert!(prev < 1e-9, "{prev:e}");
    // |H| statistics: everywhere ≈ 1/R.
    let s = abs_mean_curvature(&sphere_patch(9, r), 16);
    assert!(
        (s.min - 0.5).abs() < 1e-5 && (s.max - 0.5).abs() < 1e-5 && (s.mean - 0.5).abs() < 1e-5
    );
}

#[test]
fn cylinder_curvatures_converge_to_zero_and_half_inverse_radius() {
    let r = 1.5;
    let mut prev = f64::INFINITY;
    for n in [2, 4, 6, 8] {
        let p = interpolated(n, |u, v| {
            let a = 1.2 * u;
            [r * a.cos(), r * a.sin(), 2.0 * v]
        });
        let mut err: f64 = 0.0;
        for &(u, v) in &[(0.0, 0.0), (0.5, 0.5), (0.8, 0.1), (1.0, 1.0)] {
            let c = curvature(&p, u, v).unwrap();
            err = err
                .max(c.gaussian.abs() * r * r)
                .max((c.mean.abs() - 0.5 / r).abs() * r);
        }
        assert!(err < prev, "n = {n}: {err:e} after {prev:e}");
        prev = err;
    }
    assert!(prev < 1e-5, "{prev:e}");
}

#[test]
fn subdivided_patches_join_with_zero_gap_angle_and_curvature_jump() {
    let p = random_net(5, 4, 3);
    let (a, b) = p.subdivide_u(0.37);
    let c = continuity(&a, Edge::U1, &b, Edge::U0, false, 200);
    assert!(c.gap.max < 1e-12, "{c:?}");
    assert!(c.normal_angle.max < 1e-12, "{c:?}");
    let h = abs_mean_curvature(&p, 8).max;
    assert!(c.mean_curvature_jump.max < 1e-9 * h.max(1.0), "{c:?}");
    // The same join seen from b with its edge parameter reversed.
    let flipped = TensorPatch::from_fn(5, 4, |i, j| b.point(i, 4 - j));
    let c2 = continuity(&a, Edge::U1, &flipped, Edge::U0, true, 200);
    assert!(c2.gap.max < 1e-12 && c2.normal_angle.max < 1e-12, "{c2:?}");
    assert!(c2.mean_curvature_jump.max < 1e-9 * h.max(1.0), "{c2:?}");
    // Along v: subdivide_v, edges V1 / V0.
    let (a, b) = p.subdivide_v(0.6);
    let c3 = continuity(&a, Edge::V1, &b, Edge::V0, false, 200);
    assert!(c3.gap.max < 1e-12 && c3.normal_angle.max < 1e-12, "{c3:?}");
}

#[test]
fn a_deliberate_kink_and_a_curvature_jump_are_detected() {
    let p = random_net(5, 5, 8);
    let (a, b) = p.subdivide_u(0.5);
    // Kink: move the first inner row of b off the tangent plane.
    let mut kinked = b.clone();
    for j in 0..=5 {
        let mut q = kinked.point(1, j);
        q[2] += 0.2;
        kinked.set_point(1, j, q);
    }
    let c = continuity(&a, Edge::U1, &kinked, Edge::U0, false, 100);
    assert!(c.gap.max < 1e-12);
    assert!(c.normal_angle.max > 0.01, "{c:?}");
    // G1 but not G2: moving the second inner row keeps the tangent plane
    // and changes the curvature across the edge.
    let mut bent = b.clone();
    for j in 0..=5 {
        let mut q = bent.point(2, j);
        q[2] += 0.2;
        bent.set_point(2, j, q);
    }
    let c = continuity(&a, Edge::U1, &bent, Edge::U0, false, 100);
    assert!(c.normal_angle.max < 1e-12, "{c:?}");
    assert!(c.mean_curvature_jump.max > 0.01, "{c:?}");
    // A gap.
    let shifted = b.map(|q| [q[0], q[1], q[2] + 1e-3]);
    let c = continuity(&a, Edge::U1, &shifted, Edge::U0, false, 10);
    assert!((c.gap.max - 1e-3).abs() < 1e-12 && (c.gap.mean - 1e-3).abs() < 1e-12);
}

/// The deviation from a normal field over a grid is the angle between the
/// patch normal and the field direction at each grid point, evaluated one
/// point at a time.
#[test]
fn normal_deviation_is_the_pointwise_angle() {
    use fairsurf::analysis::normal_deviation;
    use fairsurf::energy::NormalField;
    use fairsurf::vector::{cross, dot, norm};
    let patch = random_net(6, 5, 11);
    let field = NormalField::new(1.0, random_net(3, 4, 12));
    let (ku, kv) = (17, 13);
    let mut angles = Vec::new();
    for i in 0..=ku {
        for j in 0..=kv {
            let (u, v) = (i as f64 / ku as f64, j as f64 / kv as f64);
            if let (Some(n), Some(g)) = (patch.normal(u, v), field.direction(u, v)) {
                angles.push(norm(cross(n, g)).atan2(dot(n, g).abs()));
            }
        }
    }
    let d = normal_deviation(&patch, &field, (ku, kv));
    assert_eq!(d.samples, angles.len());
    let mean = angles.iter().sum::<f64>() / angles.len() as f64;
    let max = angles.iter().copied().fold(0.0, f64::max);
    assert!((d.mean - mean).abs() < 1e-12, "{} vs {mean}", d.mean);
    assert!((d.max - max).abs() < 1e-12, "{} vs {max}", d.max);
    assert!(d.mean > 0.1, "a random field is far from the patch normals");
}
