//! Prints the estimated condition number of the reduced, equilibrated system
//! by degree, for E1 and E2 with and without a normal field.
//! Run: `cargo run --release -p fairsurf --example conditioning`.
use fairsurf::{Bend, NormalField, Problem, SolveOptions, Stretch, TensorPatch};

fn main() {
    let field = TensorPatch::from_fn(3, 3, |i, j| {
        [0.2 * (i as f64 - 1.5), 0.15 * (j as f64 - 1.5), 1.0]
    });
    println!("degree | E1 λ=0 | E1 λ=10 | E2 λ=0 | E2 λ=10   (condition estimate, or the failure)");
    for n in [5, 8, 10, 12, 15, 18, 20, 25, 30] {
        let net = TensorPatch::from_fn(n, n, |i, j| {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            [x, y, 0.3 * (3.0 * x).sin() * (2.0 * y + 0.5).cos()]
        });
        let mut cells = vec![];
        for (bend, lam) in [(false, 0.0), (false, 10.0), (true, 0.0), (true, 10.0)] {
            let mut p = Problem::new((n, n)).with_fixed_rings(&net, if bend { 2 } else { 1 });
            p = if bend {
                p.with_term(Bend::new(1.0))
            } else {
                p.with_term(Stretch::new(1.0))
            };
            if lam > 0.0 {
                p = p.with_term(NormalField::new(lam, field.clone()));
            }
            let opts = SolveOptions {
                singular_condition: f64::INFINITY,
                ..SolveOptions::default().with_analyse(false)
            };
            cells.push(match p.solve_with(&opts) {
                Ok(s) => format!(
                    "{:.1e} (rel.grad {:.0e}, {} steps)",
                    s.report.condition_estimate,
                    s.report.relative_gradient,
                    s.report.refinement_steps
                ),
                Err(e) => format!(
                    "FAIL {}",
                    e.to_string().chars().take(40).collect::<String>()
                ),
            });
        }
        println!("{n} | {}", cells.join(" | "));
    }
}
