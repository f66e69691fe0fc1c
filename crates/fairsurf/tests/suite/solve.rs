//! Facts about the solve: minimality, reproduction, accuracy, monotone
//! response to λ and γ, and every error.

use crate::common::{max_dist, random_net, tilted_field, Rng};
use fairsurf::analysis::normal_deviation;
use fairsurf::{
    Bend, EnergyTerm, Error, GuideSurface, Measure, NormalField, Problem, SampleGrid, SolveOptions,
    Stretch, TensorPatch, Vec3,
};

fn total(terms: &[std::sync::Arc<dyn EnergyTerm>], degree: (usize, usize), x: &[Vec3]) -> f64 {
    let p = TensorPatch::new(degree.0, degree.1, x.to_vec());
    terms.iter().map(|t| t.value(&p).unwrap()).sum()
}

/// E1 and E2 with λ > 0 and γ > 0: the relative gradient at the solution is
/// ≤ 1e-10 for every degree up to 12 (the requirement), and the
/// energy rises under random perturbations of the free points.
#[test]
fn solution_is_a_true_minimizer_up_to_degree_12() {
    for deg in 3..=12 {
        for (rings, fair) in [(1, 0), (2, 1)] {
            if rings == 2 && deg < 4 {
                continue;
            }
            let net = random_net(deg, deg, deg as u64);
            let mut pb = Problem::new((deg, deg)).with_fixed_rings(&net, rings);
            if fair == 0 {
                pb = pb.with_term(Stretch::new(1.0));
            } else {
                pb = pb.with_term(Bend::new(1.0));
            }
            let pb = pb
                .with_term(NormalField::new(20.0, tilted_field()))
                .with_term(GuideSurface::new(5.0, net.clone()));
            let sol = pb.solve().unwrap();
            let r = &sol.report;
            assert!(
                r.relative_gradient <= 1e-10,
                "deg {deg} rings {rings}: {}",
                r.relative_gradient
            );
            assert!(r.coupled);
            // Perturb free points: energy must rise.
            let e0 = total(pb.terms(), (deg, deg), sol.surface.points());
            assert!((e0 - r.energy).abs() <= 1e-12 * e0);
            let mut rng = Rng::new(deg as u64 + 100);
            for scale in [1e-3, 1e-1] {
                let mut x = sol.surface.points().to_vec();
                for (k, p) in x.iter_mut().enumerate() {
                    if pb.known()[k].is_none() {
                        let d = rng.vec3();
                        *p = [
                            p[0] + scale * d[0],
                            p[1] + scale * d[1],
                            p[2] + scale * d[2],
                        ];
                    }
                }
                let e1 = total(pb.terms(), (deg, deg), &x);
                assert!(e1 > e0, "deg {deg}: perturbed {e1} ≤ optimum {e0}");
            }
        }
    }
}

/// With λ = γ = 0 the extra terms change nothing: the result is the plain
/// Dirichlet (or thin-plate) extremal.
#[test]
fn zero_weights_give_the_plain_extremals() {
    let net = random_net(6, 6, 3);
    let fair = |bend: bool| -> Box<dyn EnergyTerm> {
        if bend {
            Box::new(Bend::new(1.0))
        } else {
            Box::new(Stretch::new(1.0))
        }
    };
    for (bend, rings) in [(false, 1), (true, 2)] {
        let mut plain = Problem::new((6, 6)).with_fixed_rings(&net, rings);
        plain.push_term(fair(bend));
        let mut ext = Problem::new((6, 6)).with_fixed_rings(&net, rings);
        ext.push_term(fair(bend));
        let ext = ext
            .with_term(NormalField::new(0.0, tilted_field()))
            .with_term(GuideSurface::new(0.0, net.clone()));
        let a = plain.solve().unwrap();
        let b = ext.solve().unwrap();
        assert!(max_dist(&a.surface, &b.surface) < 1e-12);
    }
}

/// Polynomial reproduction: the Dirichlet extremal of the boundary of the
/// harmonic surface (u, v, u² − v² + uv) is that surface; the thin-plate
/// extremal with two rings fixed reproduces the biharmonic z = u³ + uv²
/// (Δ²z = 0, not harmonic). Both lie in the degree-(5, 5) space, so the
/// continuous minimizers are Bézier surfaces.
#[test]
fn harmonic_and_biharmonic_polynomials_are_reproduced() {
    // Bernstein coefficients of t^k at degree 5 are C(i,k)/C(5,k).
    let c = |k: usize, i: usize| fairsurf::basis::binomial(i, k) / fairsurf::basis::binomial(5, k);
    let harmonic = TensorPatch::from_fn(5, 5, |i, j| {
        [c(1, i), c(1, j), c(2, i) - c(2, j) + c(1, i) * c(1, j)]
    });
    let biharm = TensorPatch::from_fn(5, 5, |i, j| [c(1, i), c(1, j), c(3, i) + c(1, i) * c(2, j)]);
    // Check the nets really are the surfaces.
    for &(u, v) in &[(0.3, 0.7), (0.9, 0.2)] {
        assert!((harmonic.eval(u, v)[2] - (u * u - v * v + u * v)).abs() < 1e-14);
        assert!((biharm.eval(u, v)[2] - (u * u * u + u * v * v)).abs() < 1e-14);
    }
    let h = Problem::new((5, 5))
        .with_known(fixed_boundary(&harmonic, 1))
        .unwrap()
        .with_term(Stretch::new(1.0))
        .solve()
        .unwrap();
    assert!(
        max_dist(&h.surface, &harmonic) < 1e-12,
        "harmonic: {}",
        max_dist(&h.surface, &harmonic)
    );
    let b = Problem::new((5, 5))
        .with_known(fixed_boundary(&biharm, 2))
        .unwrap()
        .with_term(Bend::new(1.0))
        .solve()
        .unwrap();
    assert!(
        max_dist(&b.surface, &biharm) < 1e-12,
        "biharmonic: {}",
        max_dist(&b.surface, &biharm)
    );
}

fn fixed_boundary(p: &TensorPatch, k: usize) -> Vec<Option<Vec3>> {
    let (n, m) = p.degree();
    (0..p.len())
        .map(|q| {
            let (i, j) = (q / (m + 1), q % (m + 1));
            (i.min(j).min(n - i).min(m - j) < k).then(|| p.points()[q])
        })
        .collect()
}

/// A planar boundary gives a planar surface, for E1 and E2, with the normal
/// field set to the plane's normal and a planar guide surface.
#[test]
fn planar_boundary_gives_a_planar_surface() {
    let nrm = fairsurf::vector::normalize([0.3, -0.5, 0.8]).unwrap();
    let e1 = fairsurf::vector::normalize(fairsurf::vector::cross(nrm, [1.0, 0.0, 0.0])).unwrap();
    let e2 = fairsurf::vector::cross(nrm, e1);
    let mut rng = Rng::new(4);
    let net = TensorPatch::from_fn(7, 6, |i, j| {
        let (a, b) = (
            i as f64 + 0.3 * rng.uniform(),
            j as f64 + 0.3 * rng.uniform(),
        );
        [
            2.0 + a * e1[0] + b * e2[0],
            -1.0 + a * e1[1] + b * e2[1],
            0.5 + a * e1[2] + b * e2[2],
        ]
    });
    let field = TensorPatch::new(0, 0, vec![nrm]);
    for (rings, fair) in [
        (1, Box::new(Stretch::new(1.0)) as Box<dyn EnergyTerm>),
        (2, Box::new(Bend::new(1.0))),
    ] {
        let mut pb = Problem::new((7, 6)).with_fixed_rings(&net, rings);
        pb.push_term(fair);
        let pb = pb
            .with_term(NormalField::new(50.0, field.clone()))
            .with_term(GuideSurface::new(3.0, net.clone()));
        let sol = pb.solve().unwrap();
        let off = sol
            .surface
            .points()
            .iter()
            .map(|p| fairsurf::vector::dot(fairsurf::vector::sub(*p, net.point(0, 0)), nrm).abs())
            .fold(0.0, f64::max);
        // Planarity is exact for the exact system; the assembled one carries
        // rounding of relative size ε in H, amplified by its conditioning.
        assert!(off < 1e-12 * 10.0, "rings {rings}: {off} (net extent ≈ 10)");
    }
}

/// Raising λ never raises the unweighted normal-field misfit
/// ∫ (R_u·N)² + (R_v·N)² (a penalty-method fact) — even when N cannot be
/// followed, where the surface may shrink tangentially instead of turning.
#[test]
fn raising_lambda_lowers_the_normal_misfit() {
    let net = random_net(6, 6, 17);
    let field = tilted_field();
    let misfit = |p: &TensorPatch| {
        NormalField::new(1.0, field.clone())
            .form((6, 6))
            .unwrap()
            .value(p.points())
    };
    let mut last = f64::INFINITY;
    for lam in [0.0, 1.0, 10.0, 100.0, 1000.0] {
        let sol = Problem::new((6, 6))
            .with_fixed_rings(&net, 1)
            .with_term(Stretch::new(1.0))
            .with_term(NormalField::new(lam, field.clone()))
            .solve()
            .unwrap();
        let m = misfit(&sol.surface);
        assert!(m < last, "λ={lam}: misfit {m} ≥ {last}");
        last = m;
    }
}

/// Where the field can be followed — boundary and normals of a ground-truth
/// bump, flat initial interior, as in Wu & Yang Fig. 4 — raising λ lowers the
/// measured angle between the surface normal and N, and the surface moves
/// toward the ground truth.
#[test]
fn raising_lambda_lowers_the_measured_normal_angle() {
    let truth = TensorPatch::from_fn(7, 7, |i, j| {
        let (x, y) = (i as f64 / 7.0, j as f64 / 7.0);
        [
            x,
            y,
            0.6 * (std::f64::consts::PI * x).sin().powi(2)
                * (std::f64::consts::PI * y).sin().powi(2)
                + 0.2 * x * y,
        ]
    });
    let grid = SampleGrid::new(28, 28);
    let normals: Vec<Vec3> = (0..grid.len())
        .map(|k| {
            let (u, v) = grid.param(k);
            truth.normal(u, v).unwrap()
        })
        .collect();
    let field = NormalField::sampled(1.0, grid, normals.clone(), None);
    let mut last = (f64::INFINITY, f64::INFINITY);
    let mut first = None;
    for lam in [0.0, 1.0, 10.0, 100.0, 1000.0] {
        let sol = Problem::new((7, 7))
            .with_fixed_rings(&truth, 2)
            .with_term(Bend::new(1.0).with_measure(Measure::Grid(grid)))
            .with_term(NormalField::sampled(lam, grid, normals.clone(), None))
            .solve()
            .unwrap();
        let dev = normal_deviation(&sol.surface, &field, (28, 28));
        let dist = max_dist(&sol.surface, &truth);
        assert!(
            dev.mean < last.0,
            "λ={lam}: mean angle {} ≥ {}",
            dev.mean,
            last.0
        );
        assert!(dist < last.1, "λ={lam}: distance {dist} ≥ {}", last.1);
        last = (dev.mean, dist);
        first.get_or_insert(dev.mean);
    }
    let first = first.unwrap();
    assert!(
        last.0 < 0.1 * first,
        "λ=1000 follows the normals: mean angle {} vs {first} at λ=0",
        last.0
    );
}

/// Raising γ never raises ∫ |R − S|².
#[test]
fn raising_gamma_lowers_the_distance_to_the_guide() {
    let net = random_net(5, 5, 23);
    let guide = net.map(|p| [p[0], p[1], p[2] + 0.4 * (p[0] * 3.0).cos()]);
    let dist = |p: &TensorPatch| {
        GuideSurface::new(1.0, guide.clone())
            .form((5, 5))
            .unwrap()
            .value(p.points())
    };
    let mut last = f64::INFINITY;
    for gamma in [0.0, 1.0, 10.0, 100.0, 1000.0] {
        let sol = Problem::new((5, 5))
            .with_fixed_rings(&net, 1)
            .with_term(Bend::new(1.0))
            .with_term(NormalField::new(5.0, tilted_field()))
            .with_term(GuideSurface::new(gamma, guide.clone()))
            .solve()
            .unwrap();
        let d = dist(&sol.surface);
        assert!(d < last, "γ={gamma}: {d} ≥ {last}");
        last = d;
    }
}

/// Per-coordinate and coupled assembly are the same math: a degree-0 normal
/// field with λ = 0 forces the coupled path and must give the same answer.
#[test]
fn coupled_and_per_coordinate_paths_agree() {
    let net = random_net(6, 5, 2);
    let a = Problem::new((6, 5))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .solve()
        .unwrap();
    let b = Problem::new((6, 5))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .with_term(NormalField::new(0.0, tilted_field()))
        .solve()
        .unwrap();
    assert!(!a.report.coupled && b.report.coupled);
    assert!(max_dist(&a.surface, &b.surface) < 1e-12);
}

/// Eq. (5) is a plain sum over the samples, so (after dividing by the
/// sample count) it is a first-order rule for the integral: edge samples
/// carry the weight of interior ones. The sampled minimizer therefore tends
/// to the continuous one at rate O(1/k): each 4× refinement cuts the
/// distance by about 4.
#[test]
fn sampled_minimizer_converges_at_first_order() {
    let net = random_net(5, 5, 31);
    let field = tilted_field();
    let cont = Problem::new((5, 5))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .with_term(NormalField::new(10.0, field.clone()))
        .solve()
        .unwrap();
    let mut errs = vec![];
    for k in [64, 256, 1024] {
        let g = SampleGrid::new(k, k);
        let fairsurf::NormalGuide::Samples { normals, .. } =
            fairsurf::NormalGuide::sample_field(&field, g, None).unwrap()
        else {
            unreachable!()
        };
        // The samples are normalized; weight each by |N|² to sample the same integrand.
        let w: Vec<f64> = (0..g.len())
            .map(|s| {
                let (u, v) = g.param(s);
                fairsurf::vector::dot(field.eval(u, v), field.eval(u, v))
            })
            .collect();
        let s = Problem::new((5, 5))
            .with_fixed_rings(&net, 1)
            .with_term(Stretch::new(1.0).with_measure(Measure::Grid(g)))
            .with_term(NormalField::sampled(10.0, g, normals, Some(w)))
            .solve()
            .unwrap();
        errs.push(max_dist(&s.surface, &cont.surface));
    }
    for w in errs.windows(2) {
        let ratio = w[0] / w[1];
        assert!((3.0..5.0).contains(&ratio), "not first order: {errs:?}");
    }
}

#[test]
fn errors_name_the_problem() {
    let net = random_net(3, 3, 1);
    // Every point known.
    let all = Problem::new((3, 3))
        .with_fixed_rings(&net, 2)
        .with_term(Stretch::new(1.0))
        .solve();
    assert!(matches!(all, Err(Error::NoFreePoints { .. })), "{all:?}");
    // No terms.
    let none = Problem::new((3, 3)).with_fixed_rings(&net, 1).solve();
    assert_eq!(none.unwrap_err(), Error::NoEnergy);
    // Only a normal field: (R_u·N)² does not see moves along the tangent plane.
    let only_n = Problem::new((4, 4))
        .with_fixed_rings(&random_net(4, 4, 2), 1)
        .with_term(NormalField::new(1.0, tilted_field()))
        .solve();
    assert!(
        matches!(
            only_n,
            Err(Error::NotPositiveDefinite { .. } | Error::Singular { .. })
        ),
        "{only_n:?}"
    );
    let msg = only_n.unwrap_err().to_string();
    assert!(
        msg.contains("normal_field") && msg.contains("stretch or bend"),
        "{msg}"
    );
    // Negative and non-finite weights.
    let neg = Problem::new((3, 3))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(-1.0))
        .solve();
    assert_eq!(
        neg.unwrap_err(),
        Error::NegativeWeight {
            what: "stretch weight".into(),
            value: -1.0
        }
    );
    let nan = Problem::new((3, 3))
        .with_fixed_rings(&net, 1)
        .with_term(Bend::new(f64::NAN))
        .solve();
    assert_eq!(
        nan.unwrap_err(),
        Error::NotFinite {
            what: "bend weight".into()
        }
    );
    // Zero normal sample and wrong sample count.
    let g = SampleGrid::new(2, 2);
    let mut normals = vec![[0.0, 0.0, 1.0]; 9];
    normals[4] = [0.0; 3];
    let zero = Problem::new((3, 3))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .with_term(NormalField::sampled(1.0, g, normals, None))
        .solve();
    assert_eq!(
        zero.unwrap_err(),
        Error::ZeroNormal {
            what: "normal sample 4".into()
        }
    );
    let short = Problem::new((3, 3))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .with_term(NormalField::sampled(1.0, g, vec![[0.0, 0.0, 1.0]; 8], None))
        .solve();
    assert!(matches!(short, Err(Error::Mismatch { .. })), "{short:?}");
    // Guide of higher degree than the surface.
    let hi = Problem::new((3, 3))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .with_term(GuideSurface::new(1.0, random_net(4, 3, 1)))
        .solve();
    assert!(matches!(hi, Err(Error::Mismatch { .. })), "{hi:?}");
    // Wrong known-count.
    assert!(matches!(
        Problem::new((3, 3)).with_known(vec![None; 15]),
        Err(Error::ControlPointCount { .. })
    ));
    assert!(SampleGrid::try_new(0, 3).is_err());
}

/// The report's analysis agrees with the analysis functions, and the
/// optional parts can be turned off.
#[test]
fn report_is_complete() {
    let net = random_net(5, 5, 5);
    let pb = Problem::new((5, 5))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0));
    let sol = pb.solve().unwrap();
    let m = sol.report.measures.unwrap();
    assert!(
        (m.dirichlet - sol.report.energy).abs() <= 1e-13 * m.dirichlet,
        "D equals the stretch energy"
    );
    assert!(m.area > 0.0 && m.area_error <= 1e-10 * m.area);
    assert!(sol.report.condition_estimate > 1.0);
    assert_eq!(sol.report.free_points, 16);
    assert_eq!(sol.report.unknowns, 16);
    let quick = pb
        .solve_with(
            &SolveOptions::default()
                .with_analyse(false)
                .with_condition_estimate(false),
        )
        .unwrap();
    assert!(quick.report.measures.is_none() && quick.report.condition_estimate.is_nan());
    assert!(max_dist(&quick.surface, &sol.surface) == 0.0);
}

/// Without polishing (the editor's quick answers) the check keeps the net
/// as solved only when it meets the tolerance and the correction would move
/// no control point by more than 1e-6 of the net (`check::NET_STEP`). At
/// degree 10 the solve's net is ~5e-8 off (the closed-form Hessian in doubles
/// is off by ~ε per entry, the Bernstein system's condition ~1e8 makes that
/// ~1e-8 in the net): kept, 0 corrections, the excess the solve left (still
/// ≤ 1e-10, above the polished one's). At degree 20 it is further off in
/// nearly energy-free directions: corrected as when polishing. Either way
/// the net is the polished one's to 1e-6 of its size and the energy the
/// same.
#[test]
fn unpolished_answers_keep_only_nets_that_are_close() {
    let opts = SolveOptions::default().with_analyse(false);
    for deg in [10, 20] {
        for seed in [11, 12] {
            let net = random_net(deg, deg, seed);
            let pb = Problem::new((deg, deg))
                .with_fixed_rings(&net, 1 + (seed as usize % 2))
                .with_term(Stretch::new(1.0))
                .with_term(NormalField::new(10.0, tilted_field()))
                .with_term(GuideSurface::new(1.0, net.clone()));
            let polished = pb.solve_with(&opts).unwrap();
            let quick = pb.solve_with(&opts.with_polish(false)).unwrap();
            let (p, q) = (polished.report.check.unwrap(), quick.report.check.unwrap());
            assert!(p.corrections >= 1 && q.passed(), "{p:?} {q:?}");
            if deg == 10 {
                assert!(q.corrections == 0 && q.excess > p.excess, "{q:?}");
            } else {
                assert!(q.corrections >= 1, "degree {deg}: {q:?}");
            }
            let size = net
                .points()
                .iter()
                .flatten()
                .fold(0.0f64, |m, x| m.max(x.abs()));
            let d = max_dist(&quick.surface, &polished.surface);
            assert!(d <= 1e-6 * size, "degree {deg}: {d}");
            assert!((q.energy - p.energy).abs() <= 1e-12 * p.energy);
        }
    }
}

/// The Jacobi-basis preconditioner and the plain equilibrated Bernstein
/// solve give the same minimizer where both work.
#[test]
fn both_bases_agree_where_both_work() {
    for deg in [6, 10, 13] {
        let net = random_net(deg, deg, 40 + deg as u64);
        let pb = Problem::new((deg, deg))
            .with_fixed_rings(&net, 1)
            .with_term(Stretch::new(1.0))
            .with_term(NormalField::new(10.0, tilted_field()));
        let plain = SolveOptions {
            tensor_basis: false,
            ..SolveOptions::default()
        };
        let a = pb.solve_with(&plain).unwrap();
        let b = pb.solve().unwrap();
        assert_eq!(
            (a.report.basis.as_str(), b.report.basis.as_str()),
            ("bernstein", "jacobi")
        );
        let d = max_dist(&a.surface, &b.surface);
        assert!(
            d < 1e-10 * a.report.condition_estimate.max(1.0),
            "deg {deg}: {d}"
        );
        assert!((a.report.energy - b.report.energy).abs() <= 1e-12 * a.report.energy);
    }
}

/// Past degree ~17 the equilibrated Bernstein system is beyond double
/// precision (condition > 1/ε): without the better basis the solve refuses
/// with a clear error rather than returning garbage; with it, degree 24 E1
/// and E2 with λ > 0 are solved to a backward error near ε and are true
/// minimizers.
#[test]
fn high_degree_needs_and_gets_the_better_basis() {
    let deg = 24;
    let net = random_net(deg, deg, 7);
    let plain = SolveOptions {
        tensor_basis: false,
        ..SolveOptions::default().with_analyse(false)
    };
    let stretch = Problem::new((deg, deg))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0));
    let refused = stretch.solve_with(&plain).unwrap_err();
    assert!(
        matches!(
            refused,
            Error::NotPositiveDefinite { .. } | Error::Singular { .. }
        ),
        "{refused}"
    );
    for rings in [1, 2] {
        let mut pb = Problem::new((deg, deg)).with_fixed_rings(&net, rings);
        pb = if rings == 1 {
            pb.with_term(Stretch::new(1.0))
        } else {
            pb.with_term(Bend::new(1.0))
        };
        let pb = pb
            .with_term(NormalField::new(10.0, tilted_field()))
            .with_term(GuideSurface::new(1.0, net.clone()));
        let sol = pb
            .solve_with(&SolveOptions::default().with_analyse(false))
            .unwrap();
        let r = &sol.report;
        assert_eq!(r.basis, "jacobi");
        assert!(
            r.relative_gradient < 1e-14,
            "rings {rings}: {}",
            r.relative_gradient
        );
        assert!(
            r.condition_estimate < 1e4,
            "rings {rings}: {}",
            r.condition_estimate
        );
        let e0 = total(pb.terms(), (deg, deg), sol.surface.points());
        let mut rng = Rng::new(rings as u64);
        let mut x = sol.surface.points().to_vec();
        for (k, p) in x.iter_mut().enumerate() {
            if pb.known()[k].is_none() {
                let d = rng.vec3();
                *p = [p[0] + 1e-4 * d[0], p[1] + 1e-4 * d[1], p[2] + 1e-4 * d[2]];
            }
        }
        assert!(total(pb.terms(), (deg, deg), &x) > e0);
    }
}
