//! Harmonic and biharmonic Bézier surfaces, masks, extremals and the
//! comparison (Monterde & Ugail 2004), checked against facts that do not
//! come from the code under test: polynomial identities checked by
//! evaluation, the paper's closed forms, exact reproduction of known
//! (bi)harmonic polynomials, minimality, planarity.

use crate::common::{max_dist, random_net, Rng};
use fairsurf::basis::{binomial, GaussLegendre};
use fairsurf::harmonic::{
    apply, biharmonic, biharmonic_mask, biharmonic_with, compare, extremal, harmonic,
    harmonic_mask, harmonic_with, relative_residual, ConstructOptions, Functional, Operator,
};
use fairsurf::vector::{cross, dot, norm, sub};
use fairsurf::{Error, TensorPatch};

/// Area and curvature of random (folded) nets are beside the point here.
const NO_ANALYSIS: ConstructOptions = ConstructOptions {
    least_squares: false,
    analyse: false,
};

fn max_abs(p: &TensorPatch) -> f64 {
    p.points()
        .iter()
        .flat_map(|q| q.iter())
        .fold(0.0f64, |a, v| a.max(v.abs()))
}

/// max |op(x)(u, v)| over the (n+1)×(m+1) grid u = a/n, v = b/m, from the
/// patch's own second derivatives (Δ) or from Δ applied twice by finite
/// differences of nothing: Δ² is checked through the coefficient net's
/// evaluation. A polynomial of bidegree ≤ (n, m) that vanishes on that grid
/// is zero (tensor-grid unisolvence), so this checks the identity.
fn laplacian_on_grid(p: &TensorPatch) -> f64 {
    let (n, m) = p.degree();
    let mut worst: f64 = 0.0;
    for a in 0..=n {
        for b in 0..=m {
            let d = p.derivatives(a as f64 / n as f64, b as f64 / m as f64);
            for c in 0..3 {
                worst = worst.max((d.duu[c] + d.dvv[c]).abs());
            }
        }
    }
    worst
}

/// The net of a polynomial given by integer monomial coefficients per
/// coordinate, scaled so that every control point is an integer:
/// u^k = Σ_i C(i,k)/C(n,k) B_i^n(u) (exact conversion, no fitting). The
/// data then carry no rounding, and the exact solution is the net itself.
fn polynomial_net(n: usize, m: usize, terms: &[(usize, usize, [i64; 3])]) -> TensorPatch {
    fn c(a: usize, b: usize) -> i128 {
        binomial(a, b).round() as i128
    }
    fn gcd(a: i128, b: i128) -> i128 {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }
    let scale = terms.iter().fold(1i128, |acc, &(k, l, _)| {
        let d = c(n, k) * c(m, l);
        acc / gcd(acc, d) * d
    });
    TensorPatch::from_fn(n, m, |i, j| {
        let mut s = [0i128; 3];
        for &(k, l, co) in terms {
            let w = c(i, k) * c(j, l) * scale / (c(n, k) * c(m, l));
            for q in 0..3 {
                s[q] += w * co[q] as i128;
            }
        }
        assert!(s.iter().all(|v| v.abs() < 1 << 53), "exact in f64");
        [s[0] as f64, s[1] as f64, s[2] as f64]
    })
}

#[test]
fn harmonic_surfaces_satisfy_the_laplace_identity() {
    for (n, m) in (2..=12)
        .map(|n| (n, n))
        .chain([(4, 3), (5, 2), (6, 4), (9, 5)])
    {
        let net = random_net(n, m, 7 * n as u64 + m as u64);
        let h = harmonic_with(&net, &NO_ANALYSIS).unwrap();
        let r = &h.report;
        assert!(r.exact && r.residual < 1e-11, "{n}×{m}: {r:?}");
        // Independent check: Δx from the patch's derivatives on the grid.
        let scale = ((n * n + m * m) as f64) * max_abs(&h.patch);
        assert!(laplacian_on_grid(&h.patch) < 1e-11 * scale, "{n}×{m}");
        // The first and last rows are kept (except an overridden corner).
        for j in 0..=m {
            assert_eq!(h.patch.point(0, j), net.point(0, j));
            if (n, j) != (n, m) || r.overridden.is_empty() {
                assert_eq!(h.patch.point(n, j), net.point(n, j));
            }
        }
        // Prop. 1: for n = m the corner P_nn is determined exactly when n is even.
        if n == m {
            assert_eq!(r.overridden.len(), usize::from(n % 2 == 0), "{n}×{m}");
        }
    }
}

#[test]
fn harmonic_polynomials_are_reproduced_without_overrides() {
    // x = u² − v², y = uv, z = u³ − 3uv² at degree (n, n) (z needs n ≥ 3).
    for n in [3, 4, 7, 10] {
        let net = polynomial_net(
            n,
            n,
            &[
                (2, 0, [1, 0, 0]),
                (0, 2, [-1, 0, 0]),
                (1, 1, [0, 1, 0]),
                (3, 0, [0, 0, 1]),
                (1, 2, [0, 0, -3]),
            ],
        );
        let h = harmonic(&net).unwrap();
        assert!(h.report.overridden.is_empty(), "n = {n}");
        let err = max_dist(&h.patch, &net) / max_abs(&net);
        assert!(err < 1e-14, "n = {n}: relative forward error {err:e}");
    }
}

#[test]
fn even_degree_harmonic_corner_is_overridden_and_said() {
    let mut net = random_net(4, 4, 3);
    let h0 = harmonic(&net).unwrap();
    let o = h0.report.overridden[0];
    assert_eq!(o.index, (4, 4));
    assert_eq!(o.given, net.point(4, 4));
    // Giving the determined value back: nothing to override, same surface.
    net.set_point(4, 4, o.determined);
    let h1 = harmonic(&net).unwrap();
    assert!(h1.report.overridden.is_empty());
    assert!(max_dist(&h0.patch, &h1.patch) < 1e-12);
}

#[test]
fn harmonic_with_fewer_rows_than_columns_does_not_exist() {
    // Rows 0 and n of a 3×4 net do not determine a harmonic surface (measured:
    // every n < m tried is inconsistent for generic rows).
    let net = random_net(3, 4, 5);
    match harmonic(&net) {
        Err(Error::Inconsistent { residual, .. }) => assert!(residual > 1e-3),
        other => panic!("{other:?}"),
    }
    let ls = harmonic_with(
        &net,
        &ConstructOptions {
            least_squares: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(!ls.report.exact && ls.report.residual > 1e-3);
}

#[test]
fn biharmonic_surfaces_satisfy_the_identity_to_1e9_through_degree_16() {
    for n in 3..=16 {
        let net = random_net(n, n, 100 + n as u64);
        let b = biharmonic_with(&net, &NO_ANALYSIS).unwrap();
        let r = &b.report;
        assert!(r.exact, "{n}: {r:?}");
        assert!(r.residual <= 1e-9, "{n}: residual {}", r.residual);
        // The boundary ring is kept.
        for i in 0..=n {
            for j in 0..=n {
                if i == 0 || j == 0 || i == n || j == n {
                    assert_eq!(b.patch.point(i, j), net.point(i, j));
                }
            }
        }
        // Independent check: Δ²x = Δ(Δx); Δx is the patch with the Laplacian
        // net, whose own Laplacian evaluated on the grid must vanish.
        let lap = apply(Operator::Laplacian, &b.patch);
        let scale = (4 * n * n * n * n) as f64 * max_abs(&b.patch);
        assert!(laplacian_on_grid(&lap) < 1e-9 * scale, "{n}");
    }
}

#[test]
fn biharmonic_polynomials_are_reproduced() {
    // x = u⁴ − 6u²v² + v⁴ (harmonic), y = u³ + uv² = (u²+v²)u, z = u⁴ − v⁴:
    // all biharmonic, bidegree ≤ (4, 4). Written at degree n, the boundary
    // determines them, so the solver must return the whole net (forward
    // accuracy, not just a small residual).
    let terms = [
        (4, 0, [1, 0, 1]),
        (2, 2, [-6, 0, 0]),
        (0, 4, [1, 0, -1]),
        (3, 0, [0, 1, 0]),
        (1, 2, [0, 1, 0]),
    ];
    for n in [4, 6, 10, 12, 14] {
        let net = polynomial_net(n, n, &terms);
        let b = biharmonic(&net).unwrap();
        let err = max_dist(&b.patch, &net) / max_abs(&net);
        assert!(err < 1e-14, "n = {n}: relative forward error {err:e}");
    }
}

/// Monterde & Ugail's closed form for n = m = 3 (after Theorem 2).
#[test]
fn cubic_biharmonic_matches_the_papers_formulas() {
    let net = random_net(3, 3, 9);
    let b = biharmonic(&net).unwrap();
    let p = |i, j| net.point(i, j);
    let comb = |terms: &[(f64, (usize, usize))]| {
        let mut s = [0.0; 3];
        for &(w, (i, j)) in terms {
            for c in 0..3 {
                s[c] += w * p(i, j)[c] / 9.0;
            }
        }
        s
    };
    let expect = [
        (
            (1, 1),
            comb(&[
                (-4.0, (0, 0)),
                (6.0, (0, 1)),
                (-2.0, (0, 3)),
                (6.0, (1, 0)),
                (3.0, (1, 3)),
                (-2.0, (3, 0)),
                (3.0, (3, 1)),
                (-1.0, (3, 3)),
            ]),
        ),
        (
            (1, 2),
            comb(&[
                (-2.0, (0, 0)),
                (6.0, (0, 2)),
                (-4.0, (0, 3)),
                (3.0, (1, 0)),
                (6.0, (1, 3)),
                (-1.0, (3, 0)),
                (3.0, (3, 2)),
                (-2.0, (3, 3)),
            ]),
        ),
        (
            (2, 1),
            comb(&[
                (-2.0, (0, 0)),
                (3.0, (0, 1)),
                (-1.0, (0, 3)),
                (6.0, (2, 0)),
                (3.0, (2, 3)),
                (-4.0, (3, 0)),
                (6.0, (3, 1)),
                (-2.0, (3, 3)),
            ]),
        ),
        (
            (2, 2),
            comb(&[
                (-1.0, (0, 0)),
                (3.0, (0, 2)),
                (-2.0, (0, 3)),
                (3.0, (2, 0)),
                (6.0, (2, 3)),
                (-2.0, (3, 0)),
                (6.0, (3, 2)),
                (-4.0, (3, 3)),
            ]),
        ),
    ];
    for ((i, j), e) in expect {
        let d = norm(sub(b.patch.point(i, j), e));
        assert!(d < 1e-14, "P{i}{j}: {d:e}");
    }
}

#[test]
fn unequal_degrees_without_a_biharmonic_surface_are_refused() {
    // Measured: 4×6, 3×9, 6×8, 6×4 are inconsistent for a generic boundary;
    // 3×4, 4×5, 3×5, 5×7 are not.
    for (n, m) in [(4, 6), (3, 9), (6, 4)] {
        let net = random_net(n, m, 11);
        match biharmonic(&net) {
            Err(Error::Inconsistent { residual, .. }) => assert!(residual > 1e-4, "{n}×{m}"),
            other => panic!("{n}×{m}: {other:?}"),
        }
        let ls = biharmonic_with(
            &net,
            &ConstructOptions {
                least_squares: true,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(!ls.report.exact);
        // The least-squares net is stationary: perturbing an inner point
        // raises the sum of squared Δ²x coefficients.
        let ss = |p: &TensorPatch| {
            apply(Operator::Bilaplacian, p)
                .points()
                .iter()
                .map(|q| dot(*q, *q))
                .sum::<f64>()
        };
        let base = ss(&ls.patch);
        let mut q = ls.patch.clone();
        let mut x = q.point(1, 1);
        x[2] += 1e-4;
        q.set_point(1, 1, x);
        assert!(ss(&q) > base, "{n}×{m}");
    }
    for (n, m) in [(3, 4), (3, 5), (5, 7)] {
        let b = biharmonic(&random_net(n, m, 12)).unwrap();
        assert!(b.report.residual < 1e-11, "{n}×{m}");
    }
}

#[test]
fn masks_satisfy_their_stencils_and_reproduce_what_they_should() {
    // Harmonic mask: bilinear nets are discrete-harmonic.
    let bilinear = TensorPatch::from_fn(6, 4, |i, j| {
        [i as f64, j as f64, 0.5 * (i * j) as f64 - j as f64]
    });
    let mut holed = bilinear.clone();
    holed.set_point(2, 2, [9.0, 9.0, 9.0]);
    let h = harmonic_mask(&holed).unwrap();
    assert!(max_dist(&h.patch, &bilinear) < 1e-12);
    // Biharmonic mask: grid functions cubic in (i, j) are discrete-biharmonic.
    let cubic = TensorPatch::from_fn(7, 6, |i, j| {
        let (x, y) = (i as f64, j as f64);
        [x, y, 0.01 * (x * x * x - 3.0 * x * y * y + x * x - y)]
    });
    let mut holed = cubic.clone();
    holed.set_point(3, 3, [0.0; 3]);
    let b = biharmonic_mask(&holed).unwrap();
    assert!(max_dist(&b.patch, &cubic) < 1e-12);
    // Stencils hold on random data; the outer rings are kept.
    let net = random_net(9, 8, 4);
    let h = harmonic_mask(&net).unwrap();
    let b = biharmonic_mask(&net).unwrap();
    assert!(h.report.exact && b.report.exact);
    for i in 1..9 {
        for j in 1..8 {
            let p = |a: usize, c: usize| h.patch.point(a, c);
            for k in 0..3 {
                let lap = 4.0 * p(i, j)[k]
                    - p(i + 1, j)[k]
                    - p(i - 1, j)[k]
                    - p(i, j + 1)[k]
                    - p(i, j - 1)[k];
                assert!(lap.abs() < 1e-13);
            }
        }
    }
    for i in 0..=9 {
        for j in 0..=8 {
            if i.min(j).min(9 - i).min(8 - j) <= 1 {
                assert_eq!(b.patch.point(i, j), net.point(i, j));
            }
        }
    }
}

#[test]
fn extremals_are_smallest_in_their_own_functional() {
    for (n, m, seed) in [(5, 5, 1), (6, 4, 2), (7, 7, 3), (4, 8, 4)] {
        let net = random_net(n, m, seed);
        let c = compare(&net).unwrap();
        let cols = c.columns();
        let d_min = cols
            .iter()
            .map(|(_, k)| k.measures.dirichlet)
            .fold(f64::INFINITY, f64::min);
        let b_min = cols
            .iter()
            .map(|(_, k)| k.measures.biharmonic)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(c.harmonic_extremal.measures.dirichlet, d_min, "{n}×{m}");
        assert_eq!(c.biharmonic_extremal.measures.biharmonic, b_min, "{n}×{m}");
        // And minimal under perturbation of an inner point.
        let e = extremal(&net, Functional::Dirichlet).unwrap();
        let mut q = e.surface.clone();
        let mut x = q.point(2, 2);
        x[0] += 1e-3;
        q.set_point(2, 2, x);
        assert!(fairsurf::analysis::dirichlet(&q) > fairsurf::analysis::dirichlet(&e.surface));
    }
}

#[test]
fn a_planar_boundary_gives_the_plane_for_every_method() {
    // Boundary in the tilted plane through o with normal nrm.
    let (o, nrm) = ([0.3, -0.2, 1.0], [0.2, -0.4, 1.0]);
    let mut rng = Rng::new(77);
    let (e1, e2) = ([1.0, 0.0, -0.2], [0.0, 1.0, 0.4]);
    let net = TensorPatch::from_fn(6, 6, |i, j| {
        let (s, t) = (
            i as f64 + 0.2 * rng.uniform(),
            j as f64 + 0.2 * rng.uniform(),
        );
        [
            o[0] + s * e1[0] + t * e2[0],
            o[1] + s * e1[1] + t * e2[1],
            o[2] + s * e1[2] + t * e2[2],
        ]
    });
    let c = compare(&net).unwrap();
    let off_plane = |p: &TensorPatch| {
        p.points()
            .iter()
            .map(|q| dot(sub(*q, o), nrm).abs() / norm(nrm))
            .fold(0.0, f64::max)
    };
    for (name, col) in c.columns() {
        let d = off_plane(&col.patch);
        assert!(d < 1e-12 * max_abs(&net), "{name}: {d:e}");
    }
    assert!(off_plane(&harmonic(&net).unwrap().patch) < 1e-13 * max_abs(&net));
    assert!(off_plane(&biharmonic_mask(&net).unwrap().patch) < 1e-13 * max_abs(&net));
    // The plane's normal is the surface normal everywhere: |H| = 0.
    for (_, col) in c.columns() {
        assert!(col.measures.abs_mean_curvature.max < 1e-9);
    }
    assert!(norm(cross(e1, e2)) > 0.0);
}

/// §4.3.2 with the misprint corrected: (cosh v cos u, cosh v sin u, v) on
/// [0, π]×[0, arccosh 2] is isothermal, so its area equals its Dirichlet
/// value, π(a/2 + sinh(2a)/4) = 7.51007…, and its biharmonic value is
/// 2π√3 = 10.8828 (Table 2, first column).
#[test]
fn exact_catenoid_has_the_tables_area_and_functionals() {
    let a = 2f64.acosh();
    let gl = GaussLegendre::new(30);
    let pi = std::f64::consts::PI;
    // Partial derivatives of the corrected parametrization.
    let xu = |u: f64, v: f64| [-v.cosh() * u.sin(), v.cosh() * u.cos(), 0.0];
    let xv = |u: f64, v: f64| [v.sinh() * u.cos(), v.sinh() * u.sin(), 1.0];
    let area = gl.integrate_on(0.0, pi, |u| {
        gl.integrate_on(0.0, a, |v| norm(cross(xu(u, v), xv(u, v))))
    });
    let dirichlet = gl.integrate_on(0.0, pi, |u| {
        gl.integrate_on(0.0, a, |v| {
            0.5 * (dot(xu(u, v), xu(u, v)) + dot(xv(u, v), xv(u, v)))
        })
    });
    let closed = pi * (a / 2.0 + (2.0 * a).sinh() / 4.0);
    assert!((area - closed).abs() < 1e-12 * closed);
    assert!((dirichlet - area).abs() < 1e-12 * area);
    assert_eq!(format!("{area:.5}"), "7.51007");
    // The printed parametrization (cosh v cos u, cosh u sin u, v) is not
    // isothermal: its area and Dirichlet value differ.
    let yu = |u: f64, v: f64| {
        [
            -v.cosh() * u.sin(),
            u.sinh() * u.sin() + u.cosh() * u.cos(),
            0.0,
        ]
    };
    let yv = |u: f64, v: f64| [v.sinh() * u.cos(), 0.0, 1.0];
    let a2 = gl.integrate_on(0.0, pi, |u| {
        gl.integrate_on(0.0, a, |v| norm(cross(yu(u, v), yv(u, v))))
    });
    let d2 = gl.integrate_on(0.0, pi, |u| {
        gl.integrate_on(0.0, a, |v| {
            0.5 * (dot(yu(u, v), yu(u, v)) + dot(yv(u, v), yv(u, v)))
        })
    });
    assert!((a2 - d2).abs() > 0.1, "{a2} {d2}");
    // B = ½∫∫|x_uu|² + 2|x_uv|² + |x_vv|² = ∫∫ cosh 2v = 2π√3.
    let b = gl.integrate_on(0.0, pi, |_| gl.integrate_on(0.0, a, |v| (2.0 * v).cosh()));
    assert!((b - 2.0 * pi * 3f64.sqrt()).abs() < 1e-12);
    assert_eq!(format!("{b:.4}"), "10.8828");
}

#[test]
fn residual_measures_distance_from_biharmonic() {
    // A random net is not biharmonic; its residual is O(1), and the solved
    // one's is tiny: the measure can fail.
    let net = random_net(6, 6, 21);
    assert!(relative_residual(Operator::Bilaplacian, &net) > 1.0);
    let b = biharmonic(&net).unwrap();
    assert!(relative_residual(Operator::Bilaplacian, &b.patch) < 1e-11);
}

#[test]
fn degrees_too_low_are_errors_not_panics() {
    let net = random_net(1, 3, 1);
    assert!(matches!(harmonic(&net), Err(Error::Mismatch { .. })));
    assert!(matches!(biharmonic(&net), Err(Error::Mismatch { .. })));
    assert!(matches!(harmonic_mask(&net), Err(Error::Mismatch { .. })));
    assert!(matches!(
        biharmonic_mask(&random_net(3, 6, 1)),
        Err(Error::Mismatch { .. })
    ));
}

#[test]
fn singular_high_degree_is_an_error() {
    // Measured: past degree ≈ 19 the Bernstein system is beyond double
    // precision; the construction says so instead of returning noise.
    match harmonic(&random_net(22, 22, 1)) {
        Err(Error::Singular { condition, .. }) => assert!(condition > 1e15),
        other => panic!("{:?}", other.map(|c| c.report)),
    }
}

/// The area of a surface whose corners are singular (Monterde & Ugail's
/// Fig. 7: four semicircles meeting vertically) against an independent
/// rule: 20-point Gauss on a mesh graded geometrically toward all edges.
#[test]
fn area_with_singular_corners_matches_a_graded_rule() {
    let s = [
        [-1.0, 0.0],
        [-1.0, 0.72],
        [-0.515308, 1.25143],
        [0.515308, 1.25143],
        [1.0, 0.72],
        [1.0, 0.0],
    ];
    let net = TensorPatch::from_fn(5, 5, |i, j| match (i, j) {
        (0, _) => [1.0 + s[j][0], 0.0, s[j][1]],
        (5, _) => [1.0 + s[j][0], 2.0, s[j][1]],
        (_, 0) => [0.0, 1.0 + s[i][0], s[i][1]],
        (_, 5) => [2.0, 1.0 + s[i][0], s[i][1]],
        _ => [0.0; 3],
    });
    let b = biharmonic(&net).unwrap();
    assert!(b.report.measures.unwrap().abs_mean_curvature.singular > 0);
    let ours = fairsurf::analysis::area(&b.patch);
    let mut breaks = vec![0.0, 1.0];
    for k in 0..30 {
        let d = 0.5 * 0.3f64.powi(k);
        breaks.extend([d, 1.0 - d]);
    }
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    let gl = GaussLegendre::new(20);
    let mut reference = 0.0;
    for w in breaks.windows(2) {
        for z in breaks.windows(2) {
            reference += gl.integrate_on(w[0], w[1], |u| {
                gl.integrate_on(z[0], z[1], |v| {
                    let d = b.patch.derivatives(u, v);
                    norm(cross(d.du, d.dv))
                })
            });
        }
    }
    let rel = (ours.value - reference).abs() / reference;
    assert!(rel < 1e-12, "{} vs {reference}: {rel:e}", ours.value);
    assert!(ours.error < 1e-10 * ours.value);
}
