//! Monterde & Ugail 2004 constructions: harmonic and biharmonic surfaces
//! (dense refined least squares), the masks (sparse Cholesky), and the
//! whole four-column comparison, at degrees 5, 10, 15. Analysis (area,
//! curvature) is off except in `compare`, which reports it.
//! Run: `cargo bench -p fairsurf --bench harmonic`.
#![allow(missing_docs)]

use fairsurf::harmonic::{
    biharmonic_mask_with, biharmonic_with, compare, harmonic_mask_with, harmonic_with,
    ConstructOptions,
};
use fairsurf::TensorPatch;

fn main() {
    divan::main();
}

fn net(n: usize) -> TensorPatch {
    TensorPatch::from_fn(n, n, |i, j| {
        let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
        [x, y, 0.3 * (3.0 * x).sin() * (2.0 * y + 0.5).cos()]
    })
}

const OPTS: ConstructOptions = ConstructOptions {
    least_squares: false,
    analyse: false,
};

#[divan::bench(args = [5, 10, 15])]
fn harmonic(b: divan::Bencher, n: usize) {
    let p = net(n);
    b.bench(|| harmonic_with(&p, &OPTS).unwrap());
}

#[divan::bench(args = [5, 10, 15])]
fn biharmonic(b: divan::Bencher, n: usize) {
    let p = net(n);
    b.bench(|| biharmonic_with(&p, &OPTS).unwrap());
}

#[divan::bench(args = [5, 10, 15, 40])]
fn masks(b: divan::Bencher, n: usize) {
    let p = net(n);
    b.bench(|| {
        (
            harmonic_mask_with(&p, &OPTS).unwrap(),
            biharmonic_mask_with(&p, &OPTS).unwrap(),
        )
    });
}

#[divan::bench(args = [5, 10, 15])]
fn compare_four(b: divan::Bencher, n: usize) {
    let p = net(n);
    b.bench(|| compare(&p).unwrap());
}
