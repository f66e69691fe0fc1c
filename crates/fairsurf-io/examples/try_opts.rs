//! scratch
use fairsurf::fill::HoleFill;
use fairsurf_io::FillInput;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut input = FillInput::read(std::path::Path::new(&args[1])).unwrap();
    let choice = input.choose(None).unwrap();
    let env = |k: &str, d: usize| std::env::var(k).ok().map_or(d, |v| v.parse().unwrap());
    input.options.willmore_steps = env("WS", 0);
    input.options.descent_steps = env("DS", 200);
    input.options.elevate = env("EL", 2);
    let t = std::time::Instant::now();
    let fills = choice.fill(&input.faces, &input.options).unwrap();
    for f in &fills {
        if let HoleFill::Patch(p) = f {
            let r = &p.report;
            let w = &r.willmore;
            eprintln!(
                "{:?} W {} -> {} ({} evals) angle {:e} time {:.3}",
                p.surface.counts(),
                w[0],
                w[w.len() - 1],
                w.len(),
                fairsurf::fill::largest_angle(&r.sides).to_degrees(),
                t.elapsed().as_secs_f64()
            );
        }
    }
}
