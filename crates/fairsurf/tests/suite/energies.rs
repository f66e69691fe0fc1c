//! Every energy term's closed form equals independent quadrature of its
//! integrand (or the direct sum over samples), computed from the patch's own
//! derivatives — not from the assembly code.

use crate::common::{random_net, tilted_field, Rng};
use fairsurf::basis::GaussLegendre;
use fairsurf::vector::{dot, sub};
use fairsurf::{
    Bend, EnergyTerm, GuideSurface, Measure, NormalField, SampleGrid, Stretch, SurfaceDerivatives,
    TensorPatch,
};

/// ∫∫ f over [0,1]² by a tensor Gauss rule exact for degree 2q−1 per direction.
fn quad2(q: usize, mut f: impl FnMut(f64, f64) -> f64) -> f64 {
    let gl = GaussLegendre::new(q);
    let mut s = 0.0;
    for (&u, &wu) in gl.nodes.iter().zip(&gl.weights) {
        for (&v, &wv) in gl.nodes.iter().zip(&gl.weights) {
            s += wu * wv * f(u, v);
        }
    }
    s
}

fn sq(a: [f64; 3]) -> f64 {
    dot(a, a)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

#[test]
fn stretch_and_bend_equal_quadrature() {
    for &(n, m) in &[(1, 1), (2, 3), (5, 5), (8, 6), (12, 12)] {
        let p = random_net(n, m, (n * 31 + m) as u64);
        let d = |u, v| p.derivatives(u, v);
        let q = n.max(m) + 2;
        let stretch = quad2(q, |u, v| {
            let x: SurfaceDerivatives = d(u, v);
            0.5 * (sq(x.du) + sq(x.dv))
        });
        let bend = quad2(q, |u, v| {
            let x = d(u, v);
            0.5 * (sq(x.duu) + 2.0 * sq(x.duv) + sq(x.dvv))
        });
        let s = Stretch::new(1.0).form((n, m)).unwrap().value(p.points());
        let b = Bend::new(1.0).form((n, m)).unwrap().value(p.points());
        assert!(
            rel(s, stretch) < 1e-12,
            "stretch ({n},{m}): {s} vs {stretch}"
        );
        if bend > 0.0 {
            assert!(rel(b, bend) < 1e-11, "bend ({n},{m}): {b} vs {bend}");
        } else {
            assert!(b.abs() < 1e-12);
        }
        let w = Stretch::new(2.5).form((n, m)).unwrap().value(p.points());
        assert!(rel(w, 2.5 * stretch) < 1e-12, "weights scale linearly");
    }
}

#[test]
fn normal_field_term_equals_quadrature() {
    for (n, m, field) in [
        (3, 3, tilted_field()),
        (5, 4, random_net(3, 2, 9)),
        (7, 7, random_net(1, 4, 4)),
    ] {
        let p = random_net(n, m, 77);
        let lam = 3.5;
        let (n1, m1) = field.degree();
        let q = n.max(m) + n1.max(m1) + 2;
        let expect = quad2(q, |u, v| {
            let x = p.derivatives(u, v);
            let nn = field.eval(u, v);
            0.5 * lam * (dot(x.du, nn).powi(2) + dot(x.dv, nn).powi(2))
        });
        let got = NormalField::new(lam, field.clone())
            .form((n, m))
            .unwrap()
            .value(p.points());
        assert!(
            rel(got, expect) < 1e-12,
            "({n},{m}) field {:?}: {got} vs {expect}",
            field.degree()
        );
    }
}

#[test]
fn guide_surface_term_equals_quadrature_even_when_elevated() {
    let p = random_net(6, 5, 3);
    for s in [random_net(6, 5, 4), random_net(3, 2, 5)] {
        let gamma = 7.0;
        let expect = quad2(10, |u, v| 0.5 * gamma * sq(sub(p.eval(u, v), s.eval(u, v))));
        let got = GuideSurface::new(gamma, s.clone())
            .form((6, 5))
            .unwrap()
            .value(p.points());
        assert!(rel(got, expect) < 1e-12, "{got} vs {expect}");
    }
}

/// Eq. (5): every term summed over the grid equals the direct sum of the
/// integrands at the samples.
#[test]
fn sampled_terms_equal_direct_sums() {
    let (n, m) = (6, 5);
    let p = random_net(n, m, 11);
    let s = random_net(n, m, 12);
    let grid = SampleGrid::new(7, 9);
    let mut rng = Rng::new(5);
    let normals: Vec<[f64; 3]> = (0..grid.len())
        .map(|_| [rng.uniform(), rng.uniform(), 1.5 + rng.uniform()])
        .collect();
    let lam_w: Vec<f64> = (0..grid.len()).map(|_| 1.0 + rng.uniform()).collect();
    let gam_w: Vec<f64> = (0..grid.len()).map(|_| 2.0 + rng.uniform()).collect();
    let (mut st, mut be, mut nf, mut gs) = (0.0, 0.0, 0.0, 0.0);
    for k in 0..grid.len() {
        let (u, v) = grid.param(k);
        let x = p.derivatives(u, v);
        st += 0.5 * (sq(x.du) + sq(x.dv));
        be += 0.5 * (sq(x.duu) + 2.0 * sq(x.duv) + sq(x.dvv));
        let nk = fairsurf::vector::normalize(normals[k]).unwrap();
        nf += 0.5 * 4.0 * lam_w[k] * (dot(x.du, nk).powi(2) + dot(x.dv, nk).powi(2));
        gs += 0.5 * 3.0 * gam_w[k] * sq(sub(x.point, s.eval(u, v)));
    }
    let g = Measure::Grid(grid);
    let val = |t: &dyn EnergyTerm| t.form((n, m)).unwrap().value(p.points());
    assert!(rel(val(&Stretch::new(1.0).with_measure(g.clone())), st) < 1e-12);
    assert!(rel(val(&Bend::new(1.0).with_measure(g.clone())), be) < 1e-12);
    assert!(
        rel(
            val(&NormalField::sampled(
                4.0,
                grid,
                normals.clone(),
                Some(lam_w.clone())
            )),
            nf
        ) < 1e-12
    );
    assert!(
        rel(
            val(&GuideSurface::new(3.0, s.clone()).with_measure(g, Some(gam_w))),
            gs
        ) < 1e-12
    );
}

/// Each term's direct value (from derivative nets) equals its assembled
/// form's value, and at high degree stays accurate where the expanded form
/// does not: z = u² + v² at degree 24 has stretch energy ½∫4u²+4v² = 4/3.
#[test]
fn direct_values_equal_forms_and_stay_exact_at_high_degree() {
    let p = random_net(7, 6, 5);
    let s = random_net(7, 6, 6);
    let g = Measure::Grid(SampleGrid::new(9, 8));
    let terms: Vec<Box<dyn EnergyTerm>> = vec![
        Box::new(Stretch::new(1.5)),
        Box::new(Bend::new(0.5).with_measure(g.clone())),
        Box::new(NormalField::new(3.0, tilted_field())),
        Box::new(GuideSurface::new(2.0, s).with_measure(g, None)),
    ];
    for t in &terms {
        let a = t.value(&p).unwrap();
        let b = t.form((7, 6)).unwrap().value(p.points());
        assert!(rel(a, b) < 1e-12, "{}: {a} vs {b}", t.name());
    }
    let n = 24;
    let c = |k: usize, i: usize| fairsurf::basis::binomial(i, k) / fairsurf::basis::binomial(n, k);
    let bowl = TensorPatch::from_fn(n, n, |i, j| [0.0, 0.0, c(2, i) + c(2, j)]);
    let e = Stretch::new(1.0).value(&bowl).unwrap();
    assert!(rel(e, 4.0 / 3.0) < 1e-13, "{e}");
}

/// A Hessian is only determined by its quadratic form if it is symmetric;
/// check symmetry and positive semi-definiteness on random vectors.
#[test]
fn forms_are_symmetric_and_positive_semidefinite() {
    let p = random_net(4, 4, 1);
    let terms: Vec<Box<dyn EnergyTerm>> = vec![
        Box::new(Stretch::new(1.0)),
        Box::new(Bend::new(1.0)),
        Box::new(NormalField::new(1.0, tilted_field())),
        Box::new(GuideSurface::new(1.0, p.clone())),
    ];
    let mut rng = Rng::new(2);
    for t in &terms {
        let f = t.form((4, 4)).unwrap();
        for _ in 0..20 {
            let x: Vec<[f64; 3]> = (0..25).map(|_| rng.vec3()).collect();
            assert!(f.value(&x) >= -1e-14, "{} not PSD", t.name());
        }
        let m = match &f.hessian {
            fairsurf::energy::Hessian::PerCoordinate(m) | fairsurf::energy::Hessian::Coupled(m) => {
                m
            }
        };
        for i in 0..m.nrows() {
            for j in 0..i {
                assert!(
                    (m[(i, j)] - m[(j, i)]).abs() <= 1e-15 * (1.0 + m[(i, j)].abs()),
                    "{} asymmetric",
                    t.name()
                );
            }
        }
    }
}

/// Energies are invariant under rigid motions of the net (and the field).
#[test]
fn fairness_is_invariant_under_rotation_and_translation() {
    let p = random_net(5, 4, 21);
    let (c, s) = (0.6f64, 0.8f64);
    let rot = |x: &[f64; 3]| {
        [
            c * x[0] - s * x[2] + 3.0,
            x[1] - 1.0,
            s * x[0] + c * x[2] + 0.5,
        ]
    };
    let q = p.map(rot);
    for t in [&Stretch::new(1.0) as &dyn EnergyTerm, &Bend::new(1.0)] {
        let f = t.form((5, 4)).unwrap();
        assert!(rel(f.value(q.points()), f.value(p.points())) < 1e-12);
    }
    let field = tilted_field();
    let rf = field.map(|x| [c * x[0] - s * x[2], x[1], s * x[0] + c * x[2]]);
    let a = NormalField::new(2.0, field)
        .form((5, 4))
        .unwrap()
        .value(p.points());
    let b = NormalField::new(2.0, rf)
        .form((5, 4))
        .unwrap()
        .value(q.points());
    assert!(rel(a, b) < 1e-12);
}

#[test]
fn degree_zero_field_is_a_constant_direction() {
    // N ≡ (0,0,1): the term is ½λ∫ z_u² + z_v², the Dirichlet energy of z alone.
    let p = random_net(4, 3, 8);
    let up = TensorPatch::new(0, 0, vec![[0.0, 0.0, 1.0]]);
    let t = NormalField::new(1.0, up)
        .form((4, 3))
        .unwrap()
        .value(p.points());
    let z_only = p.map(|x| [0.0, 0.0, x[2]]);
    let d = Stretch::new(1.0)
        .form((4, 3))
        .unwrap()
        .value(z_only.points());
    assert!(rel(t, d) < 1e-13);
}
