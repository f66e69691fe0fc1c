//! Picture rendering: one panel at 1200×900 (tessellation 64² per patch,
//! 2×2 supersampling, |H| colouring, boundary), four panels side by side,
//! and zebra stripes with the control net.
//! Run: `cargo bench -p fairsurf-render`.
#![allow(missing_docs)]

use fairsurf::TensorPatch;
use fairsurf_render::{render, Panel, RenderOptions};

fn main() {
    divan::main();
}

fn surface(n: usize) -> TensorPatch {
    TensorPatch::from_fn(n, n, |i, j| {
        let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
        [x, y, 0.3 * (3.0 * x).sin() * (2.0 * y + 0.5).cos()]
    })
}

#[divan::bench(args = [1, 4])]
fn panels(bencher: divan::Bencher, k: usize) {
    let panels: Vec<Panel> = (0..k).map(|_| Panel::new(surface(8))).collect();
    let opts = RenderOptions::default();
    bencher.bench(|| render(&panels, &opts).unwrap());
}

#[divan::bench]
fn zebra_and_net(bencher: divan::Bencher) {
    let panels = [Panel::new(surface(8))];
    let opts = RenderOptions::default()
        .with_zebra(Some(20))
        .with_control_net(true);
    bencher.bench(|| render(&panels, &opts).unwrap());
}

#[divan::bench(args = [64, 256])]
fn resolution(bencher: divan::Bencher, r: usize) {
    let panels = [Panel::new(surface(8))];
    let opts = RenderOptions::default().with_resolution(r);
    bencher.bench(|| render(&panels, &opts).unwrap());
}
