//! The library fill of the bundled holes (`examples/cad`): boundary data,
//! the solve with its check, the descent on W, the side fits
//! and W — what `fairsurf fill` spends between reading and writing.
//!
//!     cargo bench -p fairsurf-io --bench fill

use fairsurf_io::FillInput;
use std::path::Path;

fn main() {
    divan::main();
}

fn input(name: &str) -> FillInput {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/cad")
        .join(name);
    FillInput::read(&path).expect("the bundled example")
}

/// Every chosen hole of each bundled fill example, filled at the scene's
/// options (the defaults: a normal-guided, Willmore-lowered fill).
#[divan::bench(args = ["fill_network.json", "fill_pentagon.json", "fillet_hole.step"], sample_count = 20)]
fn fill(bencher: divan::Bencher, name: &str) {
    let mut input = input(name);
    let choice = input.choose(None).unwrap();
    bencher.bench(|| choice.fill(&input.faces, &input.options).unwrap());
}

/// Reading a fill's input: `fillet_hole.step` (22 kB, 8 faces: planes,
/// cylinders) parsed, its faces converted and their rectangles checked.
#[divan::bench(sample_count = 20)]
fn read_step() -> FillInput {
    input("fillet_hole.step")
}
