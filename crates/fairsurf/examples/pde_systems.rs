//! Measures the harmonic and biharmonic Bézier systems (Monterde & Ugail
//! 2004): for a random boundary at each degree pair, whether the surface
//! exists, the residual of Δx / Δ²x relative to the net, the condition
//! number and the refinement steps.
//!
//! `cargo run --release -p fairsurf --example pde_systems`

use fairsurf::harmonic::{biharmonic_with, harmonic_with, ConstructOptions};
use fairsurf::TensorPatch;

fn net(n: usize, m: usize, seed: u64) -> TensorPatch {
    let mut s = seed;
    let mut r = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s % 1_000_000) as f64 / 1e6 - 0.5
    };
    TensorPatch::from_fn(n, m, |i, j| {
        [
            i as f64 / n as f64 + 0.1 * r(),
            j as f64 / m as f64 + 0.1 * r(),
            r(),
        ]
    })
}

fn main() {
    let opts = ConstructOptions {
        least_squares: true,
        analyse: false,
    };
    println!("method      degree    exists  residual   backward   cond       steps  overridden");
    let mut pairs: Vec<(usize, usize)> = (2..=24).map(|n| (n, n)).collect();
    pairs.extend([
        (3, 4),
        (4, 3),
        (4, 5),
        (4, 6),
        (3, 9),
        (5, 7),
        (6, 8),
        (3, 5),
        (2, 5),
        (5, 2),
        (6, 4),
    ]);
    for &(n, m) in &pairs {
        for (name, f) in [
            ("harmonic", harmonic_with as fn(&_, &_) -> _),
            ("biharmonic", biharmonic_with),
        ] {
            match f(&net(n, m, 88172645463325252 ^ (n * 31 + m) as u64), &opts) {
                Ok(c) => {
                    let r = &c.report;
                    println!(
                        "{name:<11} {n:>2}×{m:<2}     {:<7} {:<10.2e} {:<10.2e} {:<10.2e} {:<6} {}",
                        r.exact,
                        r.residual,
                        r.backward_error,
                        r.condition_estimate,
                        r.refinement_steps,
                        r.overridden.len()
                    )
                }
                Err(e) => println!("{name:<11} {n:>2}×{m:<2}     error: {e}"),
            }
        }
    }
}
