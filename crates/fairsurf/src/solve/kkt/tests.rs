//! Tests of the constrained solves against closed forms.
use super::*;

#[test]
fn equality_constrained_least_distance() {
    // min ½|x|² s.t. x0 + x1 + x2 = 3, x0 − x1 = 1: x = (1.5, 0.5, 1).
    let t: Vec<_> = (0..3).map(|i| Triplet::new(i, i, 1.0)).collect();
    let h = SparseColMat::try_new_from_triplets(3, 3, &t).unwrap();
    let r0 = [(0, 1.0), (1, 1.0), (2, 1.0)];
    let r1 = [(0, 1.0), (1, -1.0)];
    let (_, s) = solve_kkt(&h, &[&r0, &r1], &[0.0; 3], &[3.0, 1.0]).unwrap();
    for (got, want) in s.x.iter().zip([1.5, 0.5, 1.0]) {
        assert!((got - want).abs() < 1e-14, "{got} vs {want}");
    }
    // Stationarity: x + Fᵀλ = 0.
    assert!((s.x[2] + s.lambda[0]).abs() < 1e-14);
    assert!(s.info.relative_residual < 1e-15);
}

#[test]
fn singular_hessian_made_definite_by_constraints() {
    // H = 0 on x1: only the constraint x1 = 2 determines it.
    let t = vec![Triplet::new(0, 0, 2.0), Triplet::new(1, 1, 0.0)];
    let h = SparseColMat::try_new_from_triplets(2, 2, &t).unwrap();
    let r = [(1, 1.0)];
    let (_, s) = solve_kkt(&h, &[&r], &[-2.0, 0.0], &[2.0]).unwrap();
    assert!((s.x[0] - 1.0).abs() < 1e-14 && (s.x[1] - 2.0).abs() < 1e-14);
}

/// A 1-D biharmonic-like H (second differences squared, ends free) with
/// a few constraints tying far-apart unknowns.
type Chain = (
    SparseColMat<usize, f64>,
    Vec<Vec<(usize, f64)>>,
    Vec<f64>,
    Vec<f64>,
);

fn chain(n: usize) -> Chain {
    let mut t = Vec::new();
    for i in 0..n - 2 {
        let d = [(i, 1.0), (i + 1, -2.0), (i + 2, 1.0)];
        for &(a, x) in &d {
            for &(b, y) in &d {
                t.push(Triplet::new(a, b, x * y));
            }
        }
    }
    let h = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
    let rows = vec![
        vec![(0, 1.0)],
        vec![(n - 1, 1.0)],
        vec![(1, 1.0), (n - 2, -1.0)],
        vec![(n / 2, 2.0), (n / 3, 1.0)],
    ];
    let b: Vec<f64> = (0..n).map(|i| ((i * 7) % 5) as f64 - 2.0).collect();
    (h, rows, b, vec![1.0, -1.0, 0.5, 0.25])
}

#[test]
fn ldlt_and_lu_agree_and_both_solve() {
    let (h, rows, b, g) = chain(40);
    let f: Vec<&[(usize, f64)]> = rows.iter().map(|r| r.as_slice()).collect();
    let (fa, fc) = (
        KktFactor::ldlt(&h, &f, None).unwrap(),
        KktFactor::lu(&h, &f).unwrap(),
    );
    let (a, c) = (fa.solve(&b, &g).unwrap(), fc.solve(&b, &g).unwrap());
    // Both hold H, F and a factor at least as large as H's triangle.
    for k in [&fa, &fc] {
        assert!(
            k.bytes() > 16 * (h.compute_nnz() + h.compute_nnz() / 2),
            "{}",
            k.bytes()
        );
    }
    assert_eq!(a.info.factorization, Factorization::Ldlt);
    assert_eq!(c.info.factorization, Factorization::Lu);
    assert!(a.info.relative_residual < 1e-14 && c.info.relative_residual < 1e-14);
    let scale = a.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (x, y) in a.x.iter().zip(&c.x).chain(a.lambda.iter().zip(&c.lambda)) {
        assert!((x - y).abs() <= 1e-10 * scale, "{x} vs {y}");
    }
    // The constraints hold.
    for (row, gi) in rows.iter().zip(&g) {
        let v: f64 = row.iter().map(|&(i, a)| a * c.x[i]).sum();
        assert!((v - gi).abs() < 1e-12 * scale);
    }
    // Both condition estimates see the same matrix.
    let ratio = a.info.condition / c.info.condition;
    assert!((0.5..2.0).contains(&ratio), "{ratio}");
}

/// A kept factorization solves for other right-hand sides as a fresh
/// one does, and knows its own matrix from a changed one.
#[test]
fn a_factorization_solves_again() {
    let (h, rows, b, g) = chain(40);
    let f: Vec<&[(usize, f64)]> = rows.iter().map(|r| r.as_slice()).collect();
    let (kept, _) = solve_kkt(&h, &f, &b, &g).unwrap();
    assert!(kept.is_for(&h, &f));
    let b2: Vec<f64> = b
        .iter()
        .enumerate()
        .map(|(i, v)| v + (i % 3) as f64)
        .collect();
    let g2 = [0.5, 2.0, -1.0, 3.0];
    let again = kept.solve(&b2, &g2).unwrap();
    let (_, fresh) = solve_kkt(&h, &f, &b2, &g2).unwrap();
    let scale = fresh.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (x, y) in again.x.iter().zip(&fresh.x) {
        assert!((x - y).abs() <= 1e-13 * scale, "{x} vs {y}");
    }
    assert!(
        again.info.relative_residual < 1e-12,
        "{:e}",
        again.info.relative_residual
    );
    // Another value in H or F is another matrix.
    let mut other = rows.clone();
    other[3][1].1 += 1e-15;
    let o: Vec<&[(usize, f64)]> = other.iter().map(|r| r.as_slice()).collect();
    assert!(!kept.is_for(&h, &o));
    let t: Vec<_> = (0..40).map(|i| Triplet::new(i, i, 1.0)).collect();
    let h2 = SparseColMat::try_new_from_triplets(40, 40, &t).unwrap();
    assert!(!kept.is_for(&h2, &f));
    assert!(!kept.is_for(&h, &f[..3]));
}

#[test]
fn lu_calls_a_singular_system_singular() {
    // Ends free and only one of them constrained: a linear function
    // along the chain costs nothing.
    let (h, _, b, _) = chain(20);
    let r = [(0usize, 1.0)];
    let err = KktFactor::lu(&h, &[&r]).err().unwrap();
    assert!(matches!(err, Error::Singular { .. }), "{err}");
    let err = solve_kkt(&h, &[&r], &b, &[0.0]).err().unwrap();
    assert!(matches!(err, Error::Singular { .. }), "{err}");
}

#[test]
fn an_undetermined_unknown_is_an_error() {
    let t = vec![Triplet::new(0, 0, 1.0), Triplet::new(1, 1, 0.0)];
    let h = SparseColMat::try_new_from_triplets(2, 2, &t).unwrap();
    let err = solve_kkt(&h, &[], &[0.0, 1.0], &[]).err().unwrap();
    assert!(matches!(err, Error::Singular { .. }), "{err}");
}

/// A singular system of x, y and z alike (H = K ⊗ I₃, F = F₁ ⊗ I₃) is
/// found singular on the one system, and the error counts the whole
/// system's free coordinates and rows.
#[test]
fn a_singular_system_per_coordinate_is_named_with_its_whole_counts() {
    let (k, _, _, _) = chain(20);
    let mut t = Vec::new();
    for j in 0..20 {
        for (i, &v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
            for c in 0..3 {
                t.push(Triplet::new(3 * i + c, 3 * j + c, v));
            }
        }
    }
    let h = SparseColMat::try_new_from_triplets(60, 60, &t).unwrap();
    // Only one end held, in all three coordinates: a linear function along
    // the chain costs nothing.
    let rows: Vec<Vec<(usize, f64)>> = (0..3).map(|c| vec![(c, 1.0)]).collect();
    let f: Vec<&[(usize, f64)]> = rows.iter().map(Vec::as_slice).collect();
    let b = vec![0.5; 60];
    match solve_kkt(&h, &f, &b, &[0.0; 3]) {
        Err(Error::Singular { unknowns, hint, .. }) => {
            assert_eq!(unknowns, 60);
            assert!(
                hint.contains("the 3 independent constraint equations"),
                "{hint}"
            );
            assert!(hint.contains("the 60 free coordinates"), "{hint}");
        }
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("a singular system solved"),
    }
}
