//! Constrained solves of cubic triangular surfaces of about 1,000 and
//! 10,000 patches (Veltkamp & Wesselink §6): a rectangular grid of
//! triangles, boundary fixed on a smooth non-planar frame, stretch + bend,
//! without continuity conditions (C0; the KKT system is then the energy's
//! own), with G1 at the vertices, with relaxed G1 across edges, and with
//! exact G1 (1,000 patches: on this bent fixed frame cubics cannot meet it
//! everywhere, the conditions are nearly dependent and are reduced with a
//! loose pivot tolerance; at 10,000 patches that classification's fill
//! makes it take minutes). Peak heap is reported by divan's allocation
//! profiler ("max alloc"). `resolve_*`: a point constraint's target moved
//! and solved again with the kept KKT factorization (`FactorCache`), as
//! an editor drag does; `reweight_*`: the stretch weight changed and solved
//! again, the kept factorization's symbolic analysis reused (as a weight
//! slider does). Run: `cargo bench -p fairsurf --bench triangle`.
#![allow(missing_docs)]

use fairsurf::triangle::{Constraint, Continuity, DomainPoint, EdgeContinuity, TriProblem};
use fairsurf::{Bend, Stretch};
use fairsurf::{FactorCache, TriSurface};

#[global_allocator]
static ALLOC: divan::AllocProfiler = divan::AllocProfiler::system();

fn main() {
    divan::main();
}

/// An a × b grid of unit squares, each cut into two triangles: 2ab cubic
/// patches, control points lifted onto a smooth bump.
fn sheet(a: usize, b: usize) -> TriSurface {
    let id = |i: usize, j: usize| j * (a + 1) + i;
    let mut v = Vec::new();
    for j in 0..=b {
        for i in 0..=a {
            v.push([i as f64, j as f64, 0.0]);
        }
    }
    let mut t = Vec::new();
    for j in 0..b {
        for i in 0..a {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut s = TriSurface::new(&v, &t, 3);
    let (sa, sb) = (a as f64, b as f64);
    let pts = s
        .points()
        .iter()
        .map(|p| {
            let (x, y) = (p[0] / sa, p[1] / sb);
            [
                p[0],
                p[1],
                0.2 * sa * (3.0 * x).sin() * (2.0 * y + 0.5).cos(),
            ]
        })
        .collect();
    s.set_points(pts).unwrap();
    s
}

fn solve(bencher: divan::Bencher, (a, b): (usize, usize), continuity: Continuity) {
    let problem = TriProblem::from_mesh(sheet(a, b))
        .with_term(Stretch::new(0.1))
        .with_term(Bend::new(1.0))
        .with_fixed_boundary()
        .with_continuity(continuity);
    bencher.bench(|| {
        let s = problem.solve().unwrap();
        assert!(s.report.kkt.unwrap().relative_residual < 1e-12);
        s
    });
}

/// 1,000 and 10,000 patches.
#[divan::bench(args = [(25, 20), (100, 50)], sample_count = 3, sample_size = 1)]
fn c0(bencher: divan::Bencher, size: (usize, usize)) {
    solve(bencher, size, Continuity::none());
}

fn edges(edges: EdgeContinuity) -> Continuity {
    Continuity {
        edges,
        ..Continuity::default()
    }
}

/// G1 at the vertices (eq. 9–10), no edge conditions.
#[divan::bench(args = [(25, 20), (100, 50)], sample_count = 3, sample_size = 1)]
fn g1_at_vertices(bencher: divan::Bencher, size: (usize, usize)) {
    solve(bencher, size, edges(EdgeContinuity::Off));
}

/// G1 at the vertices and relaxed G1 across edges (eq. 12).
#[divan::bench(args = [(25, 20), (100, 50)], sample_count = 3, sample_size = 1)]
fn g1_relaxed(bencher: divan::Bencher, size: (usize, usize)) {
    solve(bencher, size, edges(EdgeContinuity::Relaxed));
}

/// Exact G1 (eq. 11), 1,000 patches.
#[divan::bench(args = [(25, 20)], sample_count = 3, sample_size = 1)]
fn g1_exact(bencher: divan::Bencher, size: (usize, usize)) {
    solve(bencher, size, edges(EdgeContinuity::Exact));
}

/// The sheet with a point constraint at the middle patch's centre, lifted
/// by `lift` above the sheet there.
fn pulled(size: (usize, usize), continuity: Continuity, lift: f64) -> TriProblem {
    pulled_with(size, continuity, lift, 0.1)
}

/// [`pulled`] with the stretch weight α.
fn pulled_with(
    (a, b): (usize, usize),
    continuity: Continuity,
    lift: f64,
    stretch: f64,
) -> TriProblem {
    let s = sheet(a, b);
    let at = DomainPoint {
        triangle: a * b + a,
        bary: [1.0 / 3.0; 3],
    };
    let mut target = s.patch(at.triangle).eval(at.bary);
    target[2] += lift;
    TriProblem::from_mesh(s)
        .with_term(Stretch::new(stretch))
        .with_term(Bend::new(1.0))
        .with_fixed_boundary()
        .with_continuity(continuity)
        .with_constraint("pull", Constraint::Point { at, target })
}

/// A cache holding the factorization of the unlifted sheet.
fn warm(size: (usize, usize), continuity: &Continuity) -> FactorCache {
    let cache = FactorCache::new(1, usize::MAX);
    cache
        .solve_triangular(&pulled(size, continuity.clone(), 0.0))
        .unwrap();
    cache
}

fn resolve(bencher: divan::Bencher, size: (usize, usize), continuity: Continuity) {
    let cache = warm(size, &continuity);
    let mut step = 0;
    bencher
        .with_inputs(|| {
            step += 1;
            pulled(size, continuity.clone(), 0.05 * step as f64)
        })
        .bench_local_refs(|p| {
            let s = cache.solve_triangular(p).unwrap();
            assert!(s.report.reused && s.report.max_violation < 1e-9);
            s
        });
}

/// Re-solves, C0: 1,000 and 10,000 patches.
#[divan::bench(args = [(25, 20), (100, 50)], sample_count = 3, sample_size = 1)]
fn resolve_c0(bencher: divan::Bencher, size: (usize, usize)) {
    resolve(bencher, size, Continuity::none());
}

/// Re-solves, G1 at the vertices: 1,000 patches.
#[divan::bench(args = [(25, 20)], sample_count = 3, sample_size = 1)]
fn resolve_g1_at_vertices(bencher: divan::Bencher, size: (usize, usize)) {
    resolve(bencher, size, edges(EdgeContinuity::Off));
}

fn reweight(bencher: divan::Bencher, size: (usize, usize), continuity: Continuity) {
    let cache = warm(size, &continuity);
    let mut step = 0;
    bencher
        .with_inputs(|| {
            step += 1;
            pulled_with(size, continuity.clone(), 0.0, 0.1 + 0.05 * step as f64)
        })
        .bench_local_refs(|p| {
            let s = cache.solve_triangular(p).unwrap();
            let k = s.report.kkt.unwrap();
            assert!(!s.report.reused && k.reused_symbolic);
            s
        });
}

/// A changed weight, C0: 1,000 and 10,000 patches.
#[divan::bench(args = [(25, 20), (100, 50)], sample_count = 3, sample_size = 1)]
fn reweight_c0(bencher: divan::Bencher, size: (usize, usize)) {
    reweight(bencher, size, Continuity::none());
}

/// A changed weight, G1 at the vertices: 1,000 and 10,000 patches.
#[divan::bench(args = [(25, 20), (100, 50)], sample_count = 3, sample_size = 1)]
fn reweight_g1_at_vertices(bencher: divan::Bencher, size: (usize, usize)) {
    reweight(bencher, size, edges(EdgeContinuity::Off));
}
