//! The library fill of one input, repeated in a warm loop, and where its
//! time goes (the fills' own figures, averaged): for profiling.
//!
//!     CARGO_PROFILE_RELEASE_DEBUG=true cargo build --release -p fairsurf-io --example fill_loop
//!     perf record -g target/release/examples/fill_loop INPUT.step 1000
use fairsurf::fill::HoleFill;
use fairsurf_io::FillInput;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(2).map_or(100, |a| a.parse().expect("a count"));
    let path = std::path::Path::new(&args[1]);
    let t = std::time::Instant::now();
    let reads = 20;
    for _ in 0..reads {
        std::hint::black_box(FillInput::read(path).unwrap());
    }
    eprintln!(
        "{:.3} ms per read",
        t.elapsed().as_secs_f64() * 1e3 / reads as f64
    );
    let mut input = FillInput::read(path).unwrap();
    let choice = input.choose(None).unwrap();
    let t = std::time::Instant::now();
    let mut s = [0.0; 8];
    for _ in 0..n {
        let fills = choice.fill(&input.faces, &input.options).unwrap();
        for f in &fills {
            if let HoleFill::Patch(p) = f {
                let r = &p.report;
                let ti = &r.solve.timings;
                for (a, b) in s.iter_mut().zip([
                    r.seconds.setup,
                    r.seconds.solve,
                    r.seconds.measure,
                    ti.assemble,
                    ti.analyse,
                    ti.factor,
                    ti.solve,
                    r.willmore.len() as f64,
                ]) {
                    *a += b;
                }
            }
        }
        std::hint::black_box(fills);
    }
    eprintln!(
        "{:.3} ms per fill; setup solve measure | assemble analyse factor solve | willmore evals",
        t.elapsed().as_secs_f64() * 1e3 / n as f64
    );
    eprintln!("{:?}", s.map(|x| (x / n as f64 * 1e6).round() / 1e3));
}
