//! Mutation fuzzing of `fill` and `blend` inputs (bad input never panics):
//! the bundled CAD scenes with one or two random changes (a coordinate made
//! huge, tiny, negative, zero or fractional; an element removed or
//! repeated; a key removed or added; a value nulled), and the bundled
//! Open CASCADE STEP file with one number changed, taken through the
//! command's steps (read, choose the holes, stand-ins of one span, fill;
//! read, blend). Nothing may panic; every fill or blend that returns must
//! report finite figures. Deterministic (fixed seeds).

use crate::mutate::{mutate, Rng};
use fairsurf::fill::HoleFill;
use fairsurf_io::{BlendInput, FillInput};
use serde_json::Value;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

fn cad(name: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cad");
    std::fs::read_to_string(root.join(name)).unwrap()
}

/// The command's steps on a fill input; whether a fill came back (its
/// figures checked finite; a finding names `shown`).
fn fill(text: &str, step: bool, shown: &str) -> bool {
    let Ok(mut input) = FillInput::from_text(text, step) else {
        return false;
    };
    let Ok(choice) = input.choose(None) else {
        return false;
    };
    let Ok(fills) = choice.fill(&input.faces, &input.options) else {
        return false;
    };
    for f in &fills {
        let w = f.curvature();
        assert!(
            w.value.is_finite() && w.error.is_finite(),
            "W {w:?}\n{shown}"
        );
        for s in f.sides() {
            assert!(s.gap.is_finite() && s.angle.is_finite(), "{s:?}\n{shown}");
        }
        if let HoleFill::Fan(fan) = f {
            assert!(fan.report.inner_angle.is_finite(), "{shown}");
        }
    }
    true
}

/// The command's steps on a blend input; whether a blend came back.
fn blend(text: &str) -> bool {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cad");
    let Ok(input) = BlendInput::from_text(text, &folder) else {
        return false;
    };
    let Ok(b) = input.blend() else {
        return false;
    };
    assert!(b
        .report
        .sides
        .iter()
        .all(|s| s.gap.is_finite() && s.angle.is_finite()));
    true
}

/// Runs `f`; a panic is a finding, reported with the input.
fn no_panic(what: &str, text: &str, f: impl FnOnce() -> bool) -> bool {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(ok) => ok,
        Err(_) => panic!("{what}: panicked on\n{text}"),
    }
}

#[test]
fn mutated_fill_and_blend_scenes_never_panic() {
    let seeds: Vec<(&str, Value)> = [
        "fill_network.json",
        "fill_pentagon.json",
        "fill_lens.json",
        "blend_sheets.json",
    ]
    .iter()
    .map(|n| (*n, serde_json::from_str(&cad(n)).unwrap()))
    .collect();
    let mut rng = Rng(0x5DEE_CE66_D1CE_4E5B);
    let (mut tried, mut accepted) = (0, 0);
    for round in 0..120 {
        let (name, seed) = &seeds[round % seeds.len()];
        let mut v = seed.clone();
        for _ in 0..1 + rng.below(2) {
            mutate(&mut v, &mut rng);
        }
        // Fewer descent steps: the mutations aim at the reading, the
        // boundary data and the solve, not the descent.
        if let Some(fill) = v.get_mut("fill").and_then(Value::as_object_mut) {
            fill.entry("descent_steps").or_insert(4.into());
        }
        let text = v.to_string();
        tried += 1;
        accepted += usize::from(no_panic(name, &text, || {
            if name.starts_with("blend") {
                blend(&text)
            } else {
                fill(&text, false, &text)
            }
        }));
    }
    println!("{tried} mutated scenes, {accepted} filled or blended");
    assert!(
        accepted > tried / 10 && accepted < tried,
        "{accepted} of {tried}"
    );
}

/// The rounded-corner hole of an Open CASCADE file with one number of its
/// DATA section changed (scaled by 1 + 1e-3, negated, zeroed, made huge or
/// tiny): read, the holes found, filled, or refused — never a panic.
#[test]
fn step_files_with_a_number_changed_never_panic() {
    let text = cad("fillet_hole.step");
    let data = text.find("DATA;").unwrap();
    // The byte ranges of the real literals after DATA (digits with a point).
    let bytes = text.as_bytes();
    let mut reals = Vec::new();
    let mut k = data;
    while k < bytes.len() {
        if (bytes[k].is_ascii_digit() || bytes[k] == b'-')
            && !bytes[k - 1].is_ascii_alphanumeric()
            && bytes[k - 1] != b'#'
        {
            let end = k + text[k..]
                .find(|c: char| !(c.is_ascii_digit() || "+-.E".contains(c)))
                .unwrap();
            if text[k..end].contains('.') {
                reals.push((k, end));
            }
            k = end;
        } else {
            k += 1;
        }
    }
    assert!(reals.len() > 100, "{} reals", reals.len());
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let (mut tried, mut accepted) = (0, 0);
    for round in 0..60 {
        let (a, b) = reals[rng.below(reals.len())];
        let x: f64 = text[a..b].parse().unwrap();
        let y = match round % 5 {
            0 => x * (1.0 + 1e-3),
            1 => -x,
            2 => 0.0,
            3 => 1e300,
            _ => 1e-300,
        };
        let changed = format!("{}{y:.6E}{}", &text[..a], &text[b..]);
        tried += 1;
        let what = format!("fillet_hole.step, the real at byte {a}: {x} → {y:.6E}");
        accepted += usize::from(no_panic(&what, "", || fill(&changed, true, &what)));
    }
    println!("{tried} changed files, {accepted} filled");
    assert!(accepted > 0 && accepted < tried, "{accepted} of {tried}");
}
