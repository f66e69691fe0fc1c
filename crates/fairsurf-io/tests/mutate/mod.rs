//! Random one-step mutations of scene JSON, shared by the library's fuzz
//! test (`fuzz.rs`) and the command line's (`fairsurf-cli/tests/cli.rs`).

#![allow(dead_code)]

use serde_json::{json, Value};

/// xorshift64*: a small deterministic generator.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// JSON pointers of every node of `v`.
fn pointers(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Array(a) => {
            for (k, x) in a.iter().enumerate() {
                pointers(x, format!("{at}/{k}"), out);
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                pointers(
                    x,
                    format!("{at}/{}", k.replace('~', "~0").replace('/', "~1")),
                    out,
                );
            }
        }
        _ => {}
    }
    out.push(at);
}

const NUMBERS: &[f64] = &[
    0.0,
    -1.0,
    1.0,
    0.5,
    2.0,
    3.0,
    41.0,
    1e6,
    1e99,
    1e101,
    1e154,
    1e300,
    -1e300,
    5e-324,
    1e-300,
    9007199254740993.0,
    -0.0,
];

/// One random change somewhere in `v`.
pub fn mutate(v: &mut Value, rng: &mut Rng) {
    let mut all = Vec::new();
    pointers(v, String::new(), &mut all);
    let at = &all[rng.below(all.len())];
    let node = v.pointer_mut(at).expect("a pointer of v");
    let choice = rng.below(4);
    *node = match (node.take(), choice) {
        (Value::Number(_), 0..=2) => json!(NUMBERS[rng.below(NUMBERS.len())]),
        (Value::Number(n), _) => json!(n.as_f64().unwrap_or(0.0) * -3.0),
        (Value::Array(mut a), 0) if !a.is_empty() => {
            let k = rng.below(a.len());
            a.remove(k);
            Value::Array(a)
        }
        (Value::Array(mut a), 1) if !a.is_empty() => {
            let x = a[rng.below(a.len())].clone();
            a.push(x);
            Value::Array(a)
        }
        (Value::Array(_), 2) => json!([]),
        (Value::Object(mut o), 0) if !o.is_empty() => {
            let k = o.keys().nth(rng.below(o.len())).cloned().expect("a key");
            o.remove(&k);
            Value::Object(o)
        }
        (Value::Object(mut o), 1) => {
            o.insert("bogus".into(), json!(1));
            Value::Object(o)
        }
        (Value::String(_), c) => json!(["", "triangular", "tensor", "harmonic", "zzz"][c]),
        (Value::Bool(b), _) => json!(!b),
        (_, 3) => Value::Null,
        (_, _) => json!("x"),
    };
}

/// Whether the scene is small enough to solve within the test's budget
/// (fill scenes, without a `"surface"`, are not solve scenes): degrees up
/// to 12 (8 for triangles), sample grids up to 40, up to 64 triangles and
/// 200 B-spline control points (14 × 14; the 16 × 16 and 20 × 20 examples
/// took half of the test's time).
pub fn small(v: &Value) -> bool {
    seedable(v) && bspline_points(v) <= 200
}

/// The control points of a B-spline scene's surface, (knots − degree − 1)
/// per direction; 0 for other scenes.
fn bspline_points(v: &Value) -> usize {
    match (
        v.pointer("/surface/knots").and_then(Value::as_array),
        v.pointer("/surface/degree").and_then(Value::as_array),
    ) {
        (Some(k), Some(d)) if k.len() == 2 && d.len() == 2 => (0..2)
            .map(|i| {
                let knots = k[i].as_array().map_or(0, Vec::len);
                let degree = d[i].as_u64().unwrap_or(0) as usize;
                knots.saturating_sub(degree + 1)
            })
            .product(),
        _ => 0,
    }
}

/// [`small`] but for the B-spline control points: the examples mutated
/// (the larger B-spline ones are validated, not solved).
fn seedable(v: &Value) -> bool {
    if v.get("surface").is_none() {
        return false;
    }
    let degree_ok = |d: &Value| match d {
        Value::Array(a) => a.iter().all(|x| x.as_f64().is_some_and(|x| x <= 12.0)),
        Value::Number(n) => n.as_f64().is_some_and(|x| x <= 8.0),
        _ => true,
    };
    let grid_ok = v
        .pointer("/energy/sampling/grid")
        .and_then(Value::as_array)
        .is_none_or(|g| g.iter().all(|x| x.as_f64().is_some_and(|x| x <= 40.0)));
    let triangles = v
        .pointer("/surface/triangles")
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    degree_ok(&v["surface"]["degree"]) && grid_ok && triangles <= 64
}

/// The bundled examples small enough to mutate (and most to solve), sorted
/// by name.
pub fn small_examples() -> Vec<(String, Value)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut seeds: Vec<(String, Value)> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.ok()?.path();
            (p.extension()? == "json").then_some(())?;
            let v: Value = serde_json::from_str(&std::fs::read_to_string(&p).ok()?).ok()?;
            Some((p.file_name()?.to_string_lossy().into_owned(), v))
        })
        .filter(|(_, v)| seedable(v))
        .collect();
    seeds.sort_by(|a, b| a.0.cmp(&b.0));
    seeds
}
