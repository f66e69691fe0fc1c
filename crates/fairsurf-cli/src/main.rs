//! The `fairsurf` command: solve scene files, evaluate surfaces, print the
//! scene schema. Exit status: 0 success, 2 bad input (unreadable or invalid
//! scene, a problem the solver refuses), 1 anything else (e.g. a failed write),
//! 3 `fairsurf fill` wrote a fill measured beyond its tolerances.

/// Prints a line on standard output; a closed pipe (`fairsurf … | head`)
/// is not an error worth a panic, so write failures are ignored.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}
pub(crate) use say;

mod analyse;
mod blend;
mod compare;
mod eval;
mod export;
mod fill;
mod input;
mod render;
mod serve;
mod solve;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Fair surfaces by exact energy minimization (Wu & Yang 2015 and friends).
#[derive(Parser)]
#[command(name = "fairsurf", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Largest memory one solve may need, in GB (estimated before the work;
    /// larger problems are refused, saying the estimate). The server
    /// applies it to each request.
    #[arg(long, global = true, default_value_t = 8.0)]
    max_memory_gb: f64,
}

#[derive(Subcommand)]
enum Command {
    /// Solve scene files: fill the free control points by minimizing the
    /// energy, or build the surface by the scene's method.
    Solve(solve::Args),
    /// Compare four surfaces with the scene's boundary: harmonic extremal,
    /// harmonic mask, biharmonic surface, biharmonic extremal (Monterde & Ugail §4).
    Compare(compare::Args),
    /// Draw surfaces to a PNG: shaded, coloured by curvature, with control
    /// net, boundary, normal field, zebra stripes; several side by side.
    Render(render::Args),
    /// Write a solved surface as a mesh (OBJ, PLY, STL, glTF) or as the exact
    /// surface for CAD (STEP AP214, IGES).
    Export(export::Args),
    /// Fill the holes between faces (a STEP file or a JSON fill scene) with
    /// G1 B-spline patches and write the faces and fills, sewn, as STEP.
    /// Exit status 3: written, but a fill is beyond the tolerances.
    Fill(fill::Args),
    /// Blend two surfaces along one edge of each (a JSON blend scene) with
    /// a G1 B-spline transition surface and write them, sewn, as STEP.
    Blend(blend::Args),
    /// Evaluate points and unit normals of a solved surface at given (u, v).
    Eval(eval::Args),
    /// Measure surfaces as result files give them, without solving: area
    /// (with its error estimate), functionals, |H|; for triangular
    /// surfaces the functionals and the largest normal angle across edges.
    Analyse(analyse::Args),
    /// Open the editor in the browser: a local server for the page and its
    /// JSON API (solve, analyse, compare, export, examples).
    Serve(serve::Args),
    /// One job of `fairsurf serve` in a process of its own (started by the
    /// server, which kills it at its timeout).
    #[command(hide = true)]
    ServeWorker,
    /// Print the JSON Schema of scene files of one surface type (tensor by
    /// default; --type triangular or bspline), or of fill and blend scenes
    /// (--type fill, --type blend).
    Schema {
        /// The surface type: tensor, triangular or bspline; or fill, blend.
        #[arg(long = "type", default_value = "tensor", value_parser = ["tensor", "triangular", "bspline", "fill", "blend"])]
        kind: String,
        /// The same as --type triangular.
        #[arg(long, conflicts_with = "kind")]
        triangular: bool,
    },
}

/// An error with the exit status it deserves.
pub(crate) struct Failure {
    pub code: u8,
    pub message: String,
}

impl From<fairsurf_io::Error> for Failure {
    fn from(e: fairsurf_io::Error) -> Self {
        let code = match e {
            fairsurf_io::Error::Write { .. } => 1,
            _ => 2,
        };
        Failure {
            code,
            message: e.to_string(),
        }
    }
}

impl Failure {
    pub(crate) fn input(message: impl Into<String>) -> Self {
        Failure {
            code: 2,
            message: message.into(),
        }
    }
}

/// mimalloc keeps freed memory for reuse: a solve allocates its dense
/// systems afresh (tens of MB at degree 20), and with the system allocator
/// every one came back from the kernel as new pages (page faults measured
/// at 10-15% of a degree-20 solve).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// No transparent huge pages for this process (and the server's worker
/// processes, which inherit the flag). mimalloc asks for them on its
/// arenas, and the kernel zeroes a whole 2 MB page at the first touch of a
/// few kB: a fill from a JSON scene spent 15% of its process time in that
/// zeroing (`perf`); `perf stat` of `fairsurf fill fill_network.json` with
/// and without it, same binary otherwise: 10.3–10.7 → 9.5 ms. A degree-20
/// solve, whose matrices fill their pages, took the same time either way.
/// (mimalloc's `MIMALLOC_ALLOW_THP=0` does the same from the environment.)
/// Failure (an old kernel) leaves the default, which is only slower.
/// This flag comes too late for mimalloc's first arena, which it advises
/// for huge pages and touches in the runtime's start-up before `main`: the
/// workspace builds mimalloc with its `no_thp` feature (no such advice),
/// which took a 2 MB zeroing — 9% of a `fairsurf fill` of the bench's
/// bezier hole, `perf record` — out of every process (task-clock 9.3 →
/// 8.4 ms, three interleaved `perf stat -r 40` pairs; where the kernel's
/// THP mode is `always` the first arena is still huge).
fn no_huge_pages() {
    #[cfg(target_os = "linux")]
    let _ = nix::sys::prctl::set_thp_disable(true);
}

/// faer's solvers take their thread count from its global parallelism,
/// whose default asks rayon for it, and asking starts rayon's pool: a
/// `fairsurf fill` started two threads for a 10-unknown least-squares fit
/// (degree elevation) that runs on this thread, and they spun in
/// `sched_yield` beside it on 2 cores. Set the count here (rayon's own
/// rule: `RAYON_NUM_THREADS`, else the cores available); the pool starts
/// when work is parallel.
fn thread_count() {
    let n = std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    faer::set_global_parallelism(if n > 1 {
        faer::Par::rayon(n)
    } else {
        faer::Par::Seq
    });
}

fn main() -> ExitCode {
    no_huge_pages();
    thread_count();
    let cli = Cli::parse();
    // Interrupted (SIGINT, SIGTERM, SIGHUP): remove the temporaries of files
    // being written, so every output keeps its old contents, and exit 130.
    let _ = ctrlc::set_handler(|| {
        fairsurf_io::remove_temporaries();
        std::process::exit(130);
    });
    if !(cli.max_memory_gb > 0.0 && cli.max_memory_gb <= 1e6) {
        eprintln!(
            "error: --max-memory-gb {}: expected a positive number of GB",
            cli.max_memory_gb
        );
        return ExitCode::from(2);
    }
    let max_bytes = (cli.max_memory_gb * 1e9) as usize;
    let budget = fairsurf::budget::Budget {
        max_bytes,
        cancel: None,
    };
    let result = fairsurf::budget::with_budget(budget, || run(cli.command, max_bytes));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            // One line: the message names the file and the JSON path. Exit
            // 3 is a whole output short of what was asked (a fill beyond
            // the tolerances): a warning, not an error.
            let kind = if f.code == 3 { "warning" } else { "error" };
            eprintln!("{kind}: {}", f.message.replace('\n', " "));
            ExitCode::from(f.code)
        }
    }
}

fn run(command: Command, max_bytes: usize) -> Result<(), Failure> {
    match command {
        Command::Solve(a) => solve::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Eval(a) => eval::run(a),
        Command::Analyse(a) => analyse::run(a),
        Command::Export(a) => export::run(a),
        Command::Fill(a) => fill::run(a),
        Command::Blend(a) => blend::run(a),
        Command::Serve(a) => serve::run(a, max_bytes),
        Command::ServeWorker => serve::run_worker(),
        Command::Render(a) => render::run(a),
        Command::Schema { kind, triangular } => {
            let kind = if triangular {
                "triangular"
            } else {
                kind.as_str()
            };
            let schema = match kind {
                "fill" => fairsurf_io::FillScene::json_schema(),
                "blend" => fairsurf_io::BlendScene::json_schema(),
                _ => fairsurf_io::SurfaceType::ALL
                    .into_iter()
                    .find(|t| t.name() == kind)
                    .expect("clap checked the name")
                    .json_schema(),
            };
            say!("{}", serde_json::to_string_pretty(&schema).expect("schema"));
            Ok(())
        }
    }
}
