//! Assembly and solve of Wu & Yang's E1 (membrane) and E2 (thin plate) with a
//! normal field (λ = 10, a degree-3×3 Bézier field) and a guide surface
//! (γ = 1), at degrees 5, 10, 20, 30; and the re-solve with the
//! factorization kept. Run: `cargo bench -p fairsurf`.
#![allow(missing_docs)]

use fairsurf::{
    Bend, EnergyTerm, GuideSurface, NormalField, Problem, SolveOptions, Stretch, TensorPatch,
};

fn main() {
    divan::main();
}

fn net(n: usize) -> TensorPatch {
    TensorPatch::from_fn(n, n, |i, j| {
        let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
        [x, y, 0.3 * (3.0 * x).sin() * (2.0 * y + 0.5).cos()]
    })
}

fn field() -> TensorPatch {
    TensorPatch::from_fn(3, 3, |i, j| {
        [0.2 * (i as f64 - 1.5), 0.15 * (j as f64 - 1.5), 1.0]
    })
}

/// The net with its boundary lifted: a dragged boundary.
fn moved(n: usize) -> TensorPatch {
    let net = net(n);
    TensorPatch::from_fn(n, n, |i, j| {
        let p = net.point(i, j);
        [p[0], p[1], p[2] + 0.1 * (i as f64 / n as f64)]
    })
}

fn terms(n: usize, thin_plate: bool) -> Vec<Box<dyn EnergyTerm>> {
    terms_on(&net(n), thin_plate)
}

fn terms_on(net: &TensorPatch, thin_plate: bool) -> Vec<Box<dyn EnergyTerm>> {
    let fair: Box<dyn EnergyTerm> = if thin_plate {
        Box::new(Bend::new(1.0))
    } else {
        Box::new(Stretch::new(1.0))
    };
    vec![
        fair,
        Box::new(NormalField::new(10.0, field())),
        Box::new(GuideSurface::new(1.0, net.clone())),
    ]
}

fn problem(n: usize, thin_plate: bool) -> Problem {
    problem_on(&net(n), thin_plate)
}

fn problem_on(net: &TensorPatch, thin_plate: bool) -> Problem {
    let mut p = Problem::new(net.degree()).with_fixed_rings(net, if thin_plate { 2 } else { 1 });
    for t in terms_on(net, thin_plate) {
        p.push_term(t);
    }
    p
}

const DEGREES: [usize; 4] = [5, 10, 20, 30];

/// Exact quadratic forms of all three terms (no solve).
#[divan::bench(args = DEGREES, sample_count = 5)]
fn assemble_membrane(n: usize) {
    for t in terms(n, false) {
        divan::black_box(t.form((n, n)).unwrap());
    }
}

#[divan::bench(args = DEGREES, sample_count = 5)]
fn assemble_thin_plate(n: usize) {
    for t in terms(n, true) {
        divan::black_box(t.form((n, n)).unwrap());
    }
}

/// Assembly, reduction, Cholesky, refinement, condition estimate, report
/// energies (no area).
#[divan::bench(args = DEGREES, sample_count = 5)]
fn solve_membrane(bencher: divan::Bencher, n: usize) {
    let p = problem(n, false);
    let opts = SolveOptions::default().with_analyse(false);
    bencher.bench(|| p.solve_with(&opts).unwrap());
}

#[divan::bench(args = DEGREES, sample_count = 5)]
fn solve_thin_plate(bencher: divan::Bencher, n: usize) {
    let p = problem(n, true);
    let opts = SolveOptions::default().with_analyse(false);
    bencher.bench(|| p.solve_with(&opts).unwrap());
}

/// Re-solve with the factorization kept: `Problem::factor` once, then
/// `Factored::solve` of the problem with the boundary and guide moved (a
/// drag in the editor): right-hand side, triangular solves, refinement,
/// report energies (no area).
#[divan::bench(args = DEGREES, sample_count = 20)]
fn resolve_membrane(bencher: divan::Bencher, n: usize) {
    resolve(bencher, n, false);
}

#[divan::bench(args = DEGREES, sample_count = 20)]
fn resolve_thin_plate(bencher: divan::Bencher, n: usize) {
    resolve(bencher, n, true);
}

fn resolve(bencher: divan::Bencher, n: usize, thin_plate: bool) {
    let opts = SolveOptions::default().with_analyse(false);
    let f = problem(n, thin_plate).factor(&opts).unwrap();
    let p = problem_on(&moved(n), thin_plate);
    bencher.bench(|| f.solve(&p, &opts).unwrap());
}

/// Area to 1e-13 relative by adaptive Gauss–Legendre.
#[divan::bench(args = DEGREES, sample_count = 5)]
fn area(bencher: divan::Bencher, n: usize) {
    let p = net(n);
    bencher.bench(|| fairsurf::analysis::area(&p));
}

/// The G1 fill of a bi-quintic hole: two rings fixed, thin plate only
/// (4 free points), with the full report (area, functionals, |H| on the
/// 65×65 grid, folds) or the solve and its check alone.
#[divan::bench(args = [true, false], sample_count = 50)]
fn hole_fill_quintic(analyse: bool) -> fairsurf::Solution {
    let net = net(5);
    let opts = SolveOptions::default().with_analyse(analyse);
    Problem::new((5, 5))
        .with_fixed_rings(&net, 2)
        .with_term(Bend::new(1.0))
        .solve_with(&opts)
        .unwrap()
}

/// A bicubic B-spline of c × c control points over uniform knots, two
/// rings fixed (a wavy boundary), the thin plate: sparse Cholesky of the
/// 3(c − 4)² unknowns and the energy's second road.
#[divan::bench(args = [50, 100, 200], sample_count = 3)]
fn bspline_bend(bencher: divan::Bencher, c: usize) {
    let problem = bspline_problem(c);
    bencher.bench(|| problem.solve().unwrap());
}

/// The same with a normal field (λ = 10, a bicubic field; x, y and z
/// coupled): the 50 × 50 target.
#[divan::bench(args = [50, 100], sample_count = 3)]
fn bspline_bend_normal_field(bencher: divan::Bencher, c: usize) {
    let field = TensorPatch::from_fn(3, 3, |i, j| [0.1 * i as f64 - 0.15, 0.05 * j as f64, 1.0]);
    let problem = bspline_problem(c).with_term(NormalField::new(10.0, field));
    bencher.bench(|| problem.solve().unwrap());
}

/// A bicubic B-spline of c × c control points over uniform knots, two
/// rings fixed (a wavy boundary), the thin plate.
fn bspline_problem(c: usize) -> fairsurf::bspline::BSplineProblem {
    use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
    let k = KnotVector::uniform(3, c - 3);
    let points = (0..c * c)
        .map(|q| {
            let (i, j) = ((q / c) as f64, (q % c) as f64);
            [i, j, (0.3 * i).sin() * (0.2 * j).cos()]
        })
        .collect();
    let surface = BSplineSurface::new(k.clone(), k, points).unwrap();
    BSplineProblem::from_surface(surface)
        .with_fixed_rings(2)
        .with_term(Bend::new(1.0))
}
