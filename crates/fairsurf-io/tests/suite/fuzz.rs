//! Mutation fuzzing of the bundled example scenes (issue 17): thousands of
//! scenes, each an example with one random change (a number made huge, tiny,
//! negative or fractional, an element removed or repeated, a key removed or
//! added, a string or type swapped, a value nulled), parsed, validated and
//! solved. Nothing may panic; every error must be one of the crate's errors;
//! every solve that returns (tensor or triangular) must carry a passed check
//! of its written net. Deterministic (a fixed seed), bounded in time:
//! degrees above 12, large sample grids and B-splines of more than 200
//! control points are validated, not solved (`mutate::small`).

use crate::mutate::{mutate, small, small_examples, Rng};
use fairsurf_io::{Outcome, Scene, TensorScene};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Parses, validates and (when small) solves; panics only on a finding.
/// Whether the scene was accepted (solved, or validated when not solved).
fn exercise(text: &str, solve: bool) -> bool {
    let scene = match Scene::from_json(text) {
        Ok(Scene::Triangular(scene)) => scene,
        Ok(Scene::Tensor(scene)) => return exercise_tensor(scene, text, solve),
        Ok(Scene::BSpline(scene)) => {
            if !solve {
                return scene.problem().is_ok();
            }
            let Ok(solved) = scene.solve() else {
                return false;
            };
            let r = &solved.solution.report;
            assert!(
                r.energy.is_finite() && r.check.unwrap().energy_error <= 1e-10,
                "{r:?}\n{text}"
            );
            return true;
        }
        Err(_) => return false,
    };
    {
        if !solve {
            return scene.problem().is_ok();
        }
        let Ok(solved) = scene.solve() else {
            return false;
        };
        let r = &solved.solution.report;
        // Nothing free (every point fixed): nothing to check.
        if r.unknowns > 0 {
            let check = r.check.as_ref().expect("free points were solved for");
            assert!(
                check.passed(),
                "a returned solve failed its check: {check:?}\n{text}"
            );
            assert!(r.energy.is_finite() && r.energy == check.energy, "{text}");
        }
        true
    }
}

fn exercise_tensor(scene: TensorScene, text: &str, solve: bool) -> bool {
    if !solve {
        return scene.build().is_ok();
    }
    let Ok(solved) = scene.solve() else {
        return false;
    };
    if let Outcome::Minimized(s) = &solved.outcome {
        let check = s.report.check.as_ref().expect("built-in terms are checked");
        assert!(
            check.passed(),
            "a returned solve failed its check: {check:?}\n{text}"
        );
        assert!(
            s.report.energy >= 0.0 && s.report.energy.is_finite(),
            "{text}"
        );
    }
    true
}

#[test]
fn mutated_examples_never_panic_and_every_solve_is_checked() {
    let seeds = small_examples();
    assert!(seeds.len() >= 10, "{} small examples", seeds.len());
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let (mut tried, mut solved, mut accepted) = (0, 0, 0);
    let budget = std::time::Instant::now();
    for round in 0..3000 {
        let (name, seed) = &seeds[round % seeds.len()];
        let mut v = seed.clone();
        for _ in 0..1 + rng.below(2) {
            mutate(&mut v, &mut rng);
        }
        let text = v.to_string();
        let solve = small(&v);
        tried += 1;
        solved += usize::from(solve);
        let outcome = catch_unwind(AssertUnwindSafe(|| exercise(&text, solve)));
        let Ok(ok) = outcome else {
            panic!("round {round}, from {name}: panicked on\n{text}");
        };
        accepted += usize::from(ok);
        if budget.elapsed().as_secs() > 120 {
            break;
        }
    }
    println!(
        "{tried} mutated scenes: {solved} solved, the rest validated; {accepted} accepted, \
         {} refused with an error",
        tried - accepted
    );
    // Both outcomes occur: the mutations reach the checks and the solver.
    assert!(
        accepted > tried / 10 && accepted < tried,
        "{accepted} of {tried} accepted"
    );
    assert!(tried >= 1000, "only {tried} mutations in the time budget");
}
