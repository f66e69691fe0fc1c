//! The internal energy of triangular patches over the equilateral domain
//! (Veltkamp & Wesselink eq. (6)–(7), (25)–(27)) and multi-patch triangular
//! surfaces: exact integrals against quadrature, corner-permutation
//! invariance, null spaces, degree elevation, shared control points,
//! boundaries, mesh errors and global assembly.

use crate::common::Rng;
use faer::{Mat, Side};
use fairsurf::basis::GaussLegendre;
use fairsurf::triangle::{
    bend_matrix, bend_value, multi_indices, point_count, stretch_matrix, stretch_value,
    tri_bernstein_all, tri_gram_matrix, tri_product_integral, Bary, InternalEnergy, EQUILATERAL,
    EQUILATERAL_AREA,
};
use fairsurf::vector::{dot, sub};
use fairsurf::{Error, TriPatch, TriSurface, Vec3};

const PERMUTATIONS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [1, 2, 0],
    [2, 0, 1],
    [0, 2, 1],
    [2, 1, 0],
    [1, 0, 2],
];

fn random_patch(n: usize, seed: u64) -> TriPatch {
    let mut r = Rng::new(seed);
    TriPatch::from_fn(n, |_, _, _| r.vec3())
}

/// ∫ f dA over a triangle of unit area in barycentrics, by the Duffy map
/// (u, v, w) = (s, (1−s)t, (1−s)(1−t)), dA = 2(1−s) ds dt, with q×q
/// Gauss–Legendre points: exact for polynomials of degree ≤ 2q − 2.
fn triangle_quadrature(q: usize, f: impl Fn(Bary) -> f64) -> f64 {
    let g = GaussLegendre::new(q);
    let mut total = 0.0;
    for (&s, &ws) in g.nodes.iter().zip(&g.weights) {
        for (&t, &wt) in g.nodes.iter().zip(&g.weights) {
            let b = [s, (1.0 - s) * t, (1.0 - s) * (1.0 - t)];
            total += ws * wt * 2.0 * (1.0 - s) * f(b);
        }
    }
    total
}

/// Barycentrics of (x, y) in the equilateral domain.
fn bary_of(p: [f64; 2]) -> Bary {
    let [v1, v2, v3] = EQUILATERAL;
    let (a, b) = (
        [v1[0] - v3[0], v1[1] - v3[1]],
        [v2[0] - v3[0], v2[1] - v3[1]],
    );
    let (x, y) = (p[0] - v3[0], p[1] - v3[1]);
    let det = a[0] * b[1] - a[1] * b[0];
    let u = (x * b[1] - y * b[0]) / det;
    let v = (a[0] * y - a[1] * x) / det;
    [u, v, 1.0 - u - v]
}

/// The barycentric directions of ∂/∂x and ∂/∂y on the equilateral domain.
fn cartesian_directions() -> [Bary; 2] {
    let o = bary_of([0.0, 0.0]);
    let dx = sub(bary_of([1.0, 0.0]), o);
    let dy = sub(bary_of([0.0, 1.0]), o);
    [dx, dy]
}

/// ½∫∫ |T_x|² + |T_y|² and ½∫∫ |T_xx|² + 2|T_xy|² + |T_yy|² over the
/// equilateral domain by quadrature, with the patch's own derivatives.
fn quadrature_energies(t: &TriPatch) -> (f64, f64) {
    let [dx, dy] = cartesian_directions();
    let q = t.degree() + 4;
    let stretch = triangle_quadrature(q, |b| {
        let (tx, ty) = (
            t.directional_derivative(b, dx),
            t.directional_derivative(b, dy),
        );
        dot(tx, tx) + dot(ty, ty)
    });
    let bend = triangle_quadrature(q, |b| {
        let txx = t.second_directional_derivative(b, dx, dx);
        let txy = t.second_directional_derivative(b, dx, dy);
        let tyy = t.second_directional_derivative(b, dy, dy);
        dot(txx, txx) + 2.0 * dot(txy, txy) + dot(tyy, tyy)
    });
    (
        0.5 * EQUILATERAL_AREA * stretch,
        0.5 * EQUILATERAL_AREA * bend,
    )
}

/// ½ Σ_c P_cᵀ K P_c.
fn quadratic_form(k: &Mat<f64>, points: &[Vec3]) -> f64 {
    (0..3)
        .map(|c| {
            let mut s = 0.0;
            for i in 0..points.len() {
                for j in 0..points.len() {
                    s += points[i][c] * k[(i, j)] * points[j][c];
                }
            }
            0.5 * s
        })
        .sum()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

fn max_abs(k: &Mat<f64>) -> f64 {
    let mut m: f64 = 0.0;
    for i in 0..k.nrows() {
        for j in 0..k.ncols() {
            m = m.max(k[(i, j)].abs());
        }
    }
    m
}

// (a) ------------------------------------------------------------------------

#[test]
fn the_product_integral_formula_matches_quadrature() {
    let mut worst: f64 = 0.0;
    for p in 0..=6 {
        for q in 0..=6 {
            for l in multi_indices(p) {
                for m in multi_indices(q) {
                    let exact = tri_product_integral(l, m);
                    let bl = |b: Bary| {
                        tri_bernstein_all(p, b)
                            [fairsurf::triangle::linear_index(p, l[0], l[1], l[2])]
                    };
                    let bm = |b: Bary| {
                        tri_bernstein_all(q, b)
                            [fairsurf::triangle::linear_index(q, m[0], m[1], m[2])]
                    };
                    let numeric = triangle_quadrature(10, |b| bl(b) * bm(b));
                    worst = worst.max(rel(numeric, exact));
                }
            }
        }
    }
    eprintln!("product integral vs quadrature: max relative error {worst:.2e}");
    assert!(worst < 1e-13, "max relative error {worst:e}");
}

#[test]
fn the_gram_matrix_reproduces_the_integral_of_a_product_of_patches() {
    // ∫ f g for two scalar Bézier polynomials of degrees 3 and 4.
    let mut r = Rng::new(7);
    let f: Vec<f64> = (0..point_count(3)).map(|_| r.uniform()).collect();
    let g: Vec<f64> = (0..point_count(4)).map(|_| r.uniform()).collect();
    let gram = tri_gram_matrix(3, 4);
    let mut exact = 0.0;
    for i in 0..f.len() {
        for j in 0..g.len() {
            exact += f[i] * gram[(i, j)] * g[j];
        }
    }
    let eval = |c: &[f64], n: usize, b: Bary| -> f64 {
        tri_bernstein_all(n, b)
            .iter()
            .zip(c)
            .map(|(x, y)| x * y)
            .sum()
    };
    let numeric = triangle_quadrature(8, |b| eval(&f, 3, b) * eval(&g, 4, b));
    assert!((numeric - exact).abs() < 1e-15, "{numeric} vs {exact}");
}

// (b) ------------------------------------------------------------------------

#[test]
fn patch_energies_match_quadrature_of_the_integrands() {
    let mut worst: f64 = 0.0;
    for n in 1..=6 {
        for seed in 0..4 {
            let t = random_patch(n, 100 * n as u64 + seed);
            let (qs, qb) = quadrature_energies(&t);
            let (s, b) = (stretch_value(&t), bend_value(&t));
            let (ks, kb) = (
                quadratic_form(&stretch_matrix(n), t.points()),
                quadratic_form(&bend_matrix(n), t.points()),
            );
            worst = worst.max(rel(s, qs)).max(rel(ks, qs));
            if n >= 2 {
                worst = worst.max(rel(b, qb)).max(rel(kb, qb));
            } else {
                assert!(b == 0.0 && kb == 0.0 && qb == 0.0);
            }
        }
    }
    eprintln!("patch energies vs quadrature, degrees 1–6: max relative error {worst:.2e}");
    assert!(worst < 1e-12, "max relative error {worst:e}");
}

#[test]
fn eq_27_in_u_v_with_its_betas_gives_the_same_stretch_matrix() {
    // a_ij = ∫∫ [β₀ B_i,u B_j,u + β₁(B_i,u B_j,v + B_i,v B_j,u) + β₂ B_i,v B_j,v] J du dv
    // with β₀ = β₂ = 4/3, β₁ = −2/3, J = √3/2, over the (u, v) triangle of area ½.
    for n in 1..=5 {
        let (du, dv) = (
            derivative_matrix(n, [1.0, 0.0, -1.0]),
            derivative_matrix(n, [0.0, 1.0, -1.0]),
        );
        let g = tri_gram_matrix(n - 1, n - 1);
        let (uu, uv, vv) = (
            congruence(&du, &g, &du),
            congruence(&du, &g, &dv),
            congruence(&dv, &g, &dv),
        );
        let jac = 3f64.sqrt() / 2.0;
        let k = stretch_matrix(n);
        let size = point_count(n);
        let mut worst: f64 = 0.0;
        for i in 0..size {
            for j in 0..size {
                let a = 0.5
                    * jac
                    * (4.0 / 3.0 * uu[(i, j)] - 2.0 / 3.0 * (uv[(i, j)] + uv[(j, i)])
                        + 4.0 / 3.0 * vv[(i, j)]);
                worst = worst.max((a - k[(i, j)]).abs());
            }
        }
        assert!(worst < 1e-14 * max_abs(&k), "degree {n}: {worst:e}");
    }
}

/// The (n)(n+1)/2 × (n+1)(n+2)/2 matrix of D_d on Bernstein coefficients:
/// (D_d P)_λ = n Σ_a d_a P_{λ+e_a}.
fn derivative_matrix(n: usize, d: Bary) -> Mat<f64> {
    let mut m = Mat::<f64>::zeros(point_count(n - 1), point_count(n));
    for (l, lam) in multi_indices(n - 1).enumerate() {
        for a in 0..3 {
            let mut mu = lam;
            mu[a] += 1;
            m[(l, fairsurf::triangle::linear_index(n, mu[0], mu[1], mu[2]))] += n as f64 * d[a];
        }
    }
    m
}

/// Aᵀ G B.
fn congruence(a: &Mat<f64>, g: &Mat<f64>, b: &Mat<f64>) -> Mat<f64> {
    a.transpose() * g * b
}

// (c) ------------------------------------------------------------------------

#[test]
fn the_energy_is_invariant_under_permuting_the_corners() {
    let mut worst: f64 = 0.0;
    for n in 1..=6 {
        let t = random_patch(n, 31 + n as u64);
        let (s, b) = (stretch_value(&t), bend_value(&t));
        for perm in PERMUTATIONS {
            let q = t.permute_corners(perm);
            worst = worst.max(rel(stretch_value(&q), s));
            if n >= 2 {
                worst = worst.max(rel(bend_value(&q), b));
            }
        }
    }
    eprintln!("energy under corner permutations: max relative change {worst:.2e}");
    assert!(worst < 1e-13, "{worst:e}");
}

#[test]
fn the_matrices_are_invariant_under_permuting_the_corners() {
    // New P_λ is old P_μ with μ[perm[m]] = λ[m], so K' = Πᵀ K Π requires
    // K'[λ][λ'] = K[μ][μ'].
    let mut worst: f64 = 0.0;
    for n in 1..=6 {
        for k in [stretch_matrix(n), bend_matrix(n)] {
            let scale = max_abs(&k).max(f64::MIN_POSITIVE);
            for perm in PERMUTATIONS {
                let old: Vec<usize> = multi_indices(n)
                    .map(|l| {
                        let mut mu = [0; 3];
                        for m in 0..3 {
                            mu[perm[m]] = l[m];
                        }
                        fairsurf::triangle::linear_index(n, mu[0], mu[1], mu[2])
                    })
                    .collect();
                for i in 0..old.len() {
                    for j in 0..old.len() {
                        worst = worst.max((k[(i, j)] - k[(old[i], old[j])]).abs() / scale);
                    }
                }
            }
        }
    }
    eprintln!("K under corner permutations: max entry change {worst:.2e} of max |K|");
    assert!(worst < 1e-13, "{worst:e}");
}

#[test]
fn the_plain_u_v_parameterization_is_not_invariant() {
    // The paper's remark before eq. (25): ∫∫ |T_u|² + |T_v|² du dv changes
    // when the corners are relabelled.
    let n = 3;
    let (du, dv) = (
        derivative_matrix(n, [1.0, 0.0, -1.0]),
        derivative_matrix(n, [0.0, 1.0, -1.0]),
    );
    let g = tri_gram_matrix(n - 1, n - 1);
    let k = congruence(&du, &g, &du) + congruence(&dv, &g, &dv);
    let t = random_patch(n, 5);
    let e0 = quadratic_form(&k, t.points());
    let e1 = quadratic_form(&k, t.permute_corners([1, 2, 0]).points());
    assert!(rel(e1, e0) > 1e-3, "{e0} vs {e1}");
}

// (d) ------------------------------------------------------------------------

/// The degree-n patch of T(x, y) = A (x, y) + b over the equilateral domain.
fn affine_patch(n: usize, a: [[f64; 2]; 3], b: Vec3) -> TriPatch {
    let at = |p: [f64; 2]| -> Vec3 { [0, 1, 2].map(|c| a[c][0] * p[0] + a[c][1] * p[1] + b[c]) };
    let corners = EQUILATERAL.map(at);
    TriPatch::new(1, corners.to_vec()).elevate(n - 1)
}

#[test]
fn an_affine_patch_has_no_bend_and_the_closed_form_stretch() {
    let mut r = Rng::new(11);
    for n in 1..=6 {
        let a = [
            [r.uniform(), r.uniform()],
            [r.uniform(), r.uniform()],
            [r.uniform(), r.uniform()],
        ];
        let t = affine_patch(n, a, r.vec3());
        // ½ ∫ |T_x|² + |T_y|² = ½ A ‖A‖²_F.
        let frob: f64 = a.iter().flatten().map(|x| x * x).sum();
        let expected = 0.5 * EQUILATERAL_AREA * frob;
        assert!(rel(stretch_value(&t), expected) < 1e-14, "degree {n}");
        assert!(rel(quadratic_form(&stretch_matrix(n), t.points()), expected) < 1e-13);
        assert!(
            bend_value(&t).abs() < 1e-28,
            "degree {n}: {}",
            bend_value(&t)
        );
        // From K the zero comes from cancelling terms of size |K||P|².
        let kb = bend_matrix(n);
        let p2: f64 = t.points().iter().map(|p| dot(*p, *p)).sum();
        let from_k = quadratic_form(&kb, t.points()).abs() / (max_abs(&kb).max(1.0) * p2);
        eprintln!("degree {n}: bend of an affine patch from K {from_k:.2e} of |K||P|²");
        assert!(from_k < 1e-15);
    }
}

#[test]
fn the_domain_itself_has_stretch_equal_to_its_area() {
    // T = (x, y, 0): |T_x|² + |T_y|² = 2, so ½∫ = A.
    let t = affine_patch(3, [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]], [0.0; 3]);
    assert!(rel(stretch_value(&t), EQUILATERAL_AREA) < 1e-15);
}

// (e) ------------------------------------------------------------------------

fn eigenvalues(k: &Mat<f64>) -> Vec<f64> {
    k.self_adjoint_eigenvalues(Side::Lower).unwrap()
}

#[test]
fn the_matrices_are_psd_with_the_right_null_spaces() {
    for n in 1..=8 {
        for (k, nullity) in [(stretch_matrix(n), 1), (bend_matrix(n), 3)] {
            for i in 0..k.nrows() {
                for j in 0..i {
                    assert_eq!(k[(i, j)], k[(j, i)]);
                }
            }
            let ev = eigenvalues(&k);
            let top = *ev.last().unwrap();
            let tol = 1e-12 * top.max(1e-300);
            assert!(ev.iter().all(|&x| x > -tol), "degree {n}: {ev:?}");
            let zeros = ev.iter().filter(|&&x| x.abs() <= tol).count();
            assert_eq!(zeros, nullity.min(k.nrows()), "degree {n}: {ev:?}");
            if n >= 2 || nullity == 1 {
                let gap = ev[nullity] / top;
                assert!(gap > 1e-8, "degree {n}: smallest nonzero {gap:e}");
            }
        }
    }
}

#[test]
fn constants_and_affine_functions_are_in_the_null_spaces() {
    for n in 1..=6 {
        let (ks, kb) = (stretch_matrix(n), bend_matrix(n));
        let size = point_count(n);
        let one = vec![1.0; size];
        let u: Vec<f64> = multi_indices(n).map(|m| m[0] as f64 / n as f64).collect();
        let v: Vec<f64> = multi_indices(n).map(|m| m[1] as f64 / n as f64).collect();
        let apply = |k: &Mat<f64>, x: &[f64]| -> f64 {
            (0..size)
                .map(|i| (0..size).map(|j| k[(i, j)] * x[j]).sum::<f64>().abs())
                .fold(0.0, f64::max)
        };
        assert!(apply(&ks, &one) < 1e-13 * max_abs(&ks));
        for x in [&one, &u, &v] {
            assert!(apply(&kb, x) < 1e-13 * max_abs(&kb).max(1.0));
        }
        // But u is not in the stretch null space.
        assert!(apply(&ks, &u) > 1e-3 * max_abs(&ks));
    }
}

// (f) ------------------------------------------------------------------------

#[test]
fn degree_elevation_keeps_the_energy() {
    let mut worst: f64 = 0.0;
    for n in 1..=6 {
        let t = random_patch(n, 77 + n as u64);
        for r in [1, 3] {
            let e = t.elevate(r);
            worst = worst.max(rel(stretch_value(&e), stretch_value(&t)));
            if n >= 2 {
                worst = worst.max(rel(bend_value(&e), bend_value(&t)));
            }
        }
    }
    eprintln!("energy under degree elevation: max relative change {worst:.2e}");
    assert!(worst < 1e-13, "{worst:e}");
}

#[test]
fn internal_energy_combines_the_two_terms() {
    let t = random_patch(4, 3);
    let e = InternalEnergy::new(0.7, 2.5);
    let v = e.value(&t).unwrap();
    assert!(rel(v, 0.7 * stretch_value(&t) + 2.5 * bend_value(&t)) < 1e-15);
    assert!(rel(quadratic_form(&e.matrix(4).unwrap(), t.points()), v) < 1e-13);
    assert!(matches!(
        InternalEnergy::new(-1.0, 0.0).value(&t),
        Err(Error::NegativeWeight { .. })
    ));
    assert!(matches!(
        InternalEnergy::new(1.0, f64::INFINITY).matrix(4),
        Err(Error::NotFinite { .. })
    ));
}

// (g) ------------------------------------------------------------------------

/// A fan of k triangles around vertex 0 on a unit circle, centre lifted.
fn fan(k: usize, lift: f64) -> (Vec<Vec3>, Vec<[usize; 3]>) {
    let mut v = vec![[0.0, 0.0, lift]];
    for i in 0..k {
        let a = std::f64::consts::TAU * i as f64 / k as f64;
        v.push([a.cos(), a.sin(), 0.0]);
    }
    let t = (0..k).map(|i| [0, 1 + i, 1 + (i + 1) % k]).collect();
    (v, t)
}

/// Every interior edge: the two patches have the same control points along
/// it (in opposite order), bit for bit.
fn assert_edges_shared(s: &TriSurface) {
    for (e, edge) in s.edges().iter().enumerate() {
        let [Some(t0), Some(t1)] = edge.triangles else {
            continue;
        };
        let side = |t: usize| (0..3).find(|&m| s.triangle_edges(t)[m] == e).unwrap();
        let c0 = s.patch(t0).edge(side(t0));
        let mut c1 = s.patch(t1).edge(side(t1)).points().to_vec();
        c1.reverse();
        assert_eq!(c0.points(), &c1[..], "edge {e}");
        // Along the edge, patch t0 runs vertices[0] → vertices[1].
        let g: Vec<Vec3> = s.edge_points(e).iter().map(|&g| s.points()[g]).collect();
        assert_eq!(c0.points(), &g[..], "edge {e}");
    }
}

/// Each patch is its flat triangle raised to degree n.
fn assert_flat(s: &TriSurface, v: &[Vec3]) {
    for (t, tri) in s.triangles().iter().enumerate() {
        let flat = TriPatch::new(1, tri.map(|c| v[c]).to_vec()).elevate(s.degree() - 1);
        for (p, q) in s.patch(t).points().iter().zip(flat.points()) {
            assert!(fairsurf::vector::norm(sub(*p, *q)) < 1e-15);
        }
    }
}

#[test]
fn two_triangles_share_their_common_edge() {
    let v = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.5],
        [0.0, 1.0, 0.0],
    ];
    for n in 1..=5 {
        let s = TriSurface::new(&v, &[[0, 1, 2], [0, 2, 3]], n);
        let interior = if n >= 3 { (n - 1) * (n - 2) / 2 } else { 0 };
        assert_eq!(s.point_count(), 4 + 5 * (n - 1) + 2 * interior);
        assert_eq!(s.edges().len(), 5);
        assert_edges_shared(&s);
        assert_flat(&s, &v);
        assert_eq!(s.boundary_vertices(), vec![0, 1, 2, 3]);
        assert_eq!(s.boundary_edges().len(), 4);
        assert_eq!(s.boundary_points().len(), 4 + 4 * (n - 1));
        assert!(!s.is_closed());
        // Each global point is used; patch maps hit (n+1)(n+2)/2 distinct ones.
        for t in 0..2 {
            let mut g = s.patch_indices(t).to_vec();
            g.sort_unstable();
            g.dedup();
            assert_eq!(g.len(), point_count(n));
        }
    }
}

#[test]
fn a_shared_point_moves_both_patches() {
    let v = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let mut s = TriSurface::new(&v, &[[0, 1, 2], [0, 2, 3]], 3);
    let diag = s.edges().iter().position(|e| e.vertices == [0, 2]).unwrap();
    let g = s.edge_points(diag)[1];
    s.set_point(g, [0.3, 0.4, 1.0]);
    // On patch 0 = (0, 1, 2) the diagonal is edge 1 (from corner 2 to 0):
    // its point next to vertex 0 is P_{2,0,1}.
    assert_eq!(s.global_index(0, 2, 0, 1), g);
    assert_eq!(s.patch(0).point(2, 0, 1), [0.3, 0.4, 1.0]);
    assert_eq!(s.patch(1).point(2, 1, 0), [0.3, 0.4, 1.0]);
    assert_edges_shared(&s);
}

#[test]
fn fans_of_valence_five_and_six_are_c0_with_the_rim_as_boundary() {
    for k in [3, 4, 5, 6, 7] {
        let (v, tris) = fan(k, 0.4);
        for n in [1, 2, 3, 4] {
            let s = TriSurface::new(&v, &tris, n);
            let interior = if n >= 3 { (n - 1) * (n - 2) / 2 } else { 0 };
            assert_eq!(s.edges().len(), 2 * k);
            assert_eq!(s.point_count(), (k + 1) + 2 * k * (n - 1) + k * interior);
            assert_edges_shared(&s);
            assert_flat(&s, &v);
            assert_eq!(s.boundary_vertices(), (1..=k).collect::<Vec<_>>());
            assert_eq!(s.boundary_edges().len(), k);
            assert_eq!(s.boundary_points().len(), k * n);
            // The centre is a corner of all k patches.
            for t in 0..k {
                assert_eq!(s.global_index(t, n, 0, 0), 0);
            }
            // C0 along every spoke, evaluated: the two patches meet.
            for t in 0..k {
                let (a, b) = (s.patch(t), s.patch((t + 1) % k));
                for x in [0.1, 0.5, 0.9] {
                    // The spoke from the centre to vertex 1 + (t+1) mod k: edge 1 of
                    // patch t (v = 0), edge 2 of patch t+1 (w = 0).
                    let p = a.eval([x, 0.0, 1.0 - x]);
                    let q = b.eval([x, 1.0 - x, 0.0]);
                    assert!(fairsurf::vector::norm(sub(p, q)) < 1e-15);
                }
            }
        }
    }
}

#[test]
fn a_closed_mesh_has_no_boundary() {
    // A tetrahedron with outward normals.
    let v = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let tris = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    let s = TriSurface::new(&v, &tris, 3);
    assert!(s.is_closed());
    assert!(s.boundary_edges().is_empty() && s.boundary_points().is_empty());
    assert_eq!(s.point_count(), 4 + 6 * 2 + 4);
    assert_edges_shared(&s);
}

#[test]
fn triangles_meeting_at_one_vertex_share_only_that_point() {
    // A bow tie: two triangles with the common vertex 0.
    let v = vec![
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [-1.0, -1.0, 0.0],
    ];
    let s = TriSurface::new(&v, &[[0, 1, 2], [0, 3, 4]], 2);
    assert_eq!(s.point_count(), 5 + 6);
    assert_eq!(s.boundary_vertices(), vec![0, 1, 2, 3, 4]);
    assert_eq!(s.global_index(0, 2, 0, 0), s.global_index(1, 2, 0, 0));
}

fn mismatch_text(r: Result<TriSurface, Error>) -> String {
    match r {
        Err(Error::Mismatch {
            what,
            expected,
            got,
        }) => format!("{what} | {expected} | {got}"),
        other => panic!("expected a Mismatch error, got {other:?}"),
    }
}

#[test]
fn invalid_meshes_are_errors_that_say_what_is_wrong() {
    let v = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let msg = mismatch_text(TriSurface::try_new(&v, &[[0, 1, 7]], 3));
    assert!(
        msg.contains("triangle 0") && msg.contains("[0, 1, 7]") && msg.contains("< 4"),
        "{msg}"
    );
    let msg = mismatch_text(TriSurface::try_new(&v, &[[0, 1, 2], [2, 3, 2]], 3));
    assert!(
        msg.contains("triangle 1") && msg.contains("degenerate"),
        "{msg}"
    );
    // Three triangles on the edge (0, 2).
    let v5 = [v.clone(), vec![[0.5, 0.5, 1.0]]].concat();
    let msg = mismatch_text(TriSurface::try_new(
        &v5,
        &[[0, 1, 2], [0, 2, 3], [2, 0, 4]],
        3,
    ));
    assert!(
        msg.contains("(0, 2)") && msg.contains("non-manifold"),
        "{msg}"
    );
    // Both triangles run 2 → 0 (the consistent second one is [0, 2, 3]).
    let msg = mismatch_text(TriSurface::try_new(&v, &[[0, 1, 2], [2, 0, 3]], 3));
    assert!(
        msg.contains("(0, 2)") && msg.contains("inconsistent orientation") && msg.contains("2 → 0"),
        "{msg}"
    );
    let msg = mismatch_text(TriSurface::try_new(&v, &[[0, 1, 2]], 3));
    assert!(
        msg.contains("vertex 3") && msg.contains("no triangle"),
        "{msg}"
    );
    let msg = mismatch_text(TriSurface::try_new(&v, &[[0, 1, 2], [0, 2, 3]], 0));
    assert!(msg.contains("degree"), "{msg}");
    let msg = mismatch_text(TriSurface::try_new(&v, &[], 3));
    assert!(msg.contains("at least one"), "{msg}");
    let mut bad = v.clone();
    bad[2][1] = f64::NAN;
    assert_eq!(
        TriSurface::try_new(&bad, &[[0, 1, 2], [0, 2, 3]], 3),
        Err(Error::NotFinite {
            what: "mesh vertex 2".into()
        })
    );
}

#[test]
fn set_points_checks_count_and_finiteness() {
    let (v, tris) = fan(5, 0.0);
    let mut s = TriSurface::new(&v, &tris, 3);
    let count = s.point_count();
    assert!(matches!(
        s.set_points(vec![[0.0; 3]; count - 1]),
        Err(Error::Mismatch { .. })
    ));
    let mut pts = s.points().to_vec();
    pts[count - 1] = [f64::INFINITY, 0.0, 0.0];
    assert!(matches!(s.set_points(pts), Err(Error::NotFinite { .. })));
    let moved: Vec<Vec3> = s
        .points()
        .iter()
        .map(|p| [p[0], p[1], p[2] + 1.0])
        .collect();
    s.set_points(moved).unwrap();
    assert_eq!(s.points()[0][2], 1.0);
}

#[test]
fn the_assembled_energy_is_the_sum_of_the_patch_energies() {
    let mut worst: f64 = 0.0;
    for k in [5, 6] {
        let (v, tris) = fan(k, 0.3);
        for n in [2, 3, 4] {
            let mut s = TriSurface::new(&v, &tris, n);
            let mut r = Rng::new(1000 + (k * 10 + n) as u64);
            let pts: Vec<Vec3> = s
                .points()
                .iter()
                .map(|p| {
                    let d = r.vec3();
                    [p[0] + 0.1 * d[0], p[1] + 0.1 * d[1], p[2] + 0.3 * d[2]]
                })
                .collect();
            s.set_points(pts).unwrap();
            let e = InternalEnergy::new(1.0, 0.25);
            let sum: f64 = s.patches().map(|p| e.value(&p).unwrap()).sum();
            assert!(rel(e.surface_value(&s).unwrap(), sum) < 1e-15);
            let dense = e.surface_matrix_dense(&s).unwrap();
            let sparse = e.surface_matrix(&s).unwrap().to_dense();
            worst = worst
                .max(rel(quadratic_form(&dense, s.points()), sum))
                .max(rel(quadratic_form(&sparse, s.points()), sum));
        }
    }
    eprintln!("assembled global energy vs Σ patch energies: max relative error {worst:.2e}");
    assert!(worst < 1e-12, "{worst:e}");
}

#[test]
fn rotating_each_triangles_corners_keeps_the_surface_energy() {
    // Same mesh, triangles listed from another corner: a different global
    // map of the interiors, the same surface and energy.
    let (v, tris) = fan(6, 0.5);
    let rotated: Vec<[usize; 3]> = tris
        .iter()
        .enumerate()
        .map(|(t, &[a, b, c])| match t % 3 {
            0 => [a, b, c],
            1 => [b, c, a],
            _ => [c, a, b],
        })
        .collect();
    let mut s = TriSurface::new(&v, &tris, 3);
    let mut q = TriSurface::new(&v, &rotated, 3);
    // Bend the rim edges' points the same way in both.
    for surf in [&mut s, &mut q] {
        for e in surf.boundary_edges() {
            for g in surf.edge_points(e) {
                let p = surf.points()[g];
                surf.set_point(g, [p[0], p[1], 0.2 * (3.0 * p[0]).sin()]);
            }
        }
    }
    let e = InternalEnergy::new(1.0, 1.0);
    let (a, b) = (e.surface_value(&s).unwrap(), e.surface_value(&q).unwrap());
    assert!(rel(a, b) < 1e-13, "{a} vs {b}");
}

#[test]
fn energies_stay_accurate_at_higher_degree() {
    // Measured ≤ 6.4e-15 up to degree 20 (from the nets and from K).
    for n in [8, 12, 16] {
        let t = random_patch(n, 5 + n as u64);
        let (qs, qb) = quadrature_energies(&t);
        let (ks, kb) = (stretch_matrix(n), bend_matrix(n));
        assert!(rel(stretch_value(&t), qs) < 1e-13);
        assert!(rel(bend_value(&t), qb) < 1e-13);
        assert!(rel(quadratic_form(&ks, t.points()), qs) < 1e-13);
        assert!(rel(quadratic_form(&kb, t.points()), qb) < 1e-13);
        assert!(rel(bend_value(&t.permute_corners([2, 0, 1])), qb) < 1e-13);
    }
}
