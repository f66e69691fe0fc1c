//! `fairsurf solve`.

use crate::Failure;
use fairsurf_io::{write_mesh, MeshFormat, Outcome, Scene, SolvedScene, SurfaceMesh};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// Scene files (JSON). Several may be given: then -o names a directory.
    #[arg(required = true)]
    scenes: Vec<PathBuf>,
    /// Result file (one scene) or directory (several; created if missing,
    /// results named SCENE.result.json). Without it nothing is written.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also write the surface as a triangle mesh: .obj, .ply or .stl (one scene only).
    #[arg(long)]
    mesh: Option<PathBuf>,
    /// Mesh resolution: quads per parameter direction.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    resolution: u32,
    /// Print the report as JSON on standard output instead of the summary.
    #[arg(long)]
    json: bool,
    /// Print nothing on success.
    #[arg(short, long)]
    quiet: bool,
    /// B-spline scenes: split every knot span into A parts in u and B in v
    /// before solving (exact refinement, as the scene's "refine": {"split":
    /// [A, B]}; the result file holds the refined knots and net).
    #[arg(long, value_name = "A,B", value_parser = parse_split)]
    refine: Option<[usize; 2]>,
    /// B-spline scenes: raise the degree by A in u and B in v before solving
    /// (exact degree elevation, as the scene's "refine": {"elevate": [A, B]};
    /// done before any --refine split).
    #[arg(long, value_name = "A,B", value_parser = parse_elevate)]
    elevate: Option<[usize; 2]>,
}

/// `A,B` with each number in `lo..=hi`.
fn parse_pair(s: &str, lo: usize, hi: usize) -> Result<[usize; 2], String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("expected A,B (two whole numbers), got {s:?}"))?;
    let num = |x: &str| -> Result<usize, String> {
        match x.trim().parse::<usize>() {
            Ok(k) if (lo..=hi).contains(&k) => Ok(k),
            _ => Err(format!(
                "expected a whole number from {lo} to {hi}, got {x:?}"
            )),
        }
    };
    Ok([num(a)?, num(b)?])
}

fn parse_split(s: &str) -> Result<[usize; 2], String> {
    parse_pair(s, 1, 16)
}

fn parse_elevate(s: &str) -> Result<[usize; 2], String> {
    parse_pair(s, 0, 14)
}

pub fn run(a: Args) -> Result<(), Failure> {
    let many = a.scenes.len() > 1;
    if many && a.mesh.is_some() {
        return Err(Failure::input(
            "--mesh takes a single scene; solve the scenes one at a time to mesh them",
        ));
    }
    if let Some(m) = &a.mesh {
        MeshFormat::from_path(m)?;
    }
    if many {
        if let Some(dir) = &a.output {
            std::fs::create_dir_all(dir).map_err(|e| Failure {
                code: 1,
                message: format!("cannot create directory {}: {e}", dir.display()),
            })?;
        }
    }
    if let (true, Some(dir)) = (many, &a.output) {
        let mut seen: std::collections::HashMap<String, &PathBuf> = Default::default();
        for path in &a.scenes {
            if let Some(first) = seen.insert(result_name(path), path) {
                return Err(Failure::input(format!(
                    "{} and {} would both write {}: give scenes with different file names",
                    first.display(),
                    path.display(),
                    dir.join(result_name(path)).display()
                )));
            }
        }
    }
    let bar = progress(a.scenes.len());
    let mut failures = 0;
    for path in &a.scenes {
        bar.set_message(path.display().to_string());
        let out = match (&a.output, many) {
            (Some(o), false) => Some(o.clone()),
            (Some(dir), true) => Some(dir.join(result_name(path))),
            (None, _) => None,
        };
        match solve_one(path, out.as_deref(), &a) {
            Ok(lines) => {
                if !a.quiet {
                    bar.suspend(|| crate::say!("{lines}"));
                }
            }
            Err(f) if many => {
                failures += 1;
                bar.suspend(|| eprintln!("error: {}", f.message.replace('\n', " ")));
            }
            Err(f) => return Err(f),
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    if failures > 0 {
        return Err(Failure::input(format!(
            "{failures} of {} scenes failed",
            a.scenes.len()
        )));
    }
    Ok(())
}

fn progress(n: usize) -> ProgressBar {
    if n < 2 || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(n as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed} {msg}")
            .expect("valid template"),
    );
    bar
}

fn result_name(scene: &Path) -> String {
    let stem = scene
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    format!("{stem}.result.json")
}

fn solve_one(path: &Path, out: Option<&Path>, a: &Args) -> Result<String, Failure> {
    let with_file = crate::input::with_file(path);
    let mut scene = Scene::from_json(&crate::input::read(path)?).map_err(&with_file)?;
    for (flag, given, what) in [
        ("--refine", a.refine, "splits the knot spans"),
        ("--elevate", a.elevate, "raises the degrees"),
    ] {
        let Some(pair) = given else { continue };
        let Scene::BSpline(b) = &mut scene else {
            return Err(Failure::input(format!(
                "{}: {flag} {what} of B-spline scenes; this one is {}",
                path.display(),
                scene.surface_type().name()
            )));
        };
        let r = b.refine.get_or_insert_with(Default::default);
        if flag == "--refine" {
            r.split = Some(pair);
        } else {
            r.elevate = Some(pair);
        }
    }
    let spinner = spinner_for(&scene);
    let solved = scene.solve().map_err(&with_file);
    spinner.finish_and_clear();
    let solved = solved?;
    let r = a.resolution as usize;
    let written = write_outputs(
        out,
        a.mesh.as_deref().map(|m| (m, solved.mesh_triangles(r))),
        |o| solved.write(o),
        || solved.mesh(r),
    )?;
    if a.json {
        return Ok(serde_json::to_string_pretty(&solved.report_json()).expect("json"));
    }
    Ok(summary(path, &solved, &written))
}

/// Meshes of at least this many triangles are built and written under a
/// spinner (on a terminal): about a second's work.
const LARGE_MESH: usize = 1 << 20;

/// Writes a solve's result file and mesh (path and about how many
/// triangles) as one batch: both appear or neither. A large mesh is built
/// and written under a spinner on a terminal that says which phase runs and
/// for how long. Returns the summary's entry: the files and the time their
/// writing took.
fn write_outputs(
    out: Option<&Path>,
    mesh: Option<(&Path, usize)>,
    write_result: impl FnOnce(&Path) -> fairsurf_io::Result<()>,
    build_mesh: impl FnOnce() -> SurfaceMesh,
) -> Result<Vec<String>, Failure> {
    for file in out.iter().copied().chain(mesh.map(|m| m.0)) {
        ensure_parent(file)?;
    }
    let t = std::time::Instant::now();
    let mut written = Vec::new();
    let batch = fairsurf_io::Batch::begin();
    if let Some(o) = out {
        write_result(o)?;
        written.push(o.display().to_string());
    }
    if let Some((m, triangles)) = mesh {
        let spinner = if triangles >= LARGE_MESH && std::io::stderr().is_terminal() {
            let s = ProgressBar::new_spinner();
            s.set_style(
                ProgressStyle::with_template("{spinner} {elapsed} {msg}").expect("valid template"),
            );
            s.enable_steady_tick(std::time::Duration::from_millis(200));
            s
        } else {
            ProgressBar::hidden()
        };
        spinner.set_message(format!(
            "building a mesh of about {:.1} M triangles",
            triangles as f64 / 1e6
        ));
        let built = build_mesh();
        spinner.set_message(format!("writing {}", m.display()));
        let done = write_mesh(m, &built);
        spinner.finish_and_clear();
        done?;
        written.push(m.display().to_string());
    }
    batch.commit()?;
    if written.is_empty() {
        return Ok(written);
    }
    Ok(vec![format!(
        "{} in {:.3} s",
        written.join(", "),
        t.elapsed().as_secs_f64()
    )])
}

/// "N free points (M unknowns[, coordinates coupled])".
fn free_words(r: &fairsurf::SolveReport) -> String {
    format!(
        "{} free points ({} unknowns{})",
        r.free_points,
        r.unknowns,
        if r.coupled {
            ", coordinates coupled"
        } else {
            ""
        }
    )
}

/// A minimization's lines, the same for every surface kind: the energy and
/// its terms, the operators and constraints, the check of the written net
/// (`road`: how it recomputed the energy), the measures, and the solve's
/// accuracy.
fn report_lines(lines: &mut Vec<String>, r: &fairsurf::SolveReport, road: &str) {
    let mut terms: Vec<String> = r
        .terms
        .iter()
        .map(|t| format!("{} {:.10e}", t.name, t.value))
        .collect();
    if !r.operators.is_empty() {
        terms.push(format!("operators {:.10e}", r.external));
    }
    lines.push(format!(
        "  energy {:.10e} = {}",
        r.energy,
        terms.join(" + ")
    ));
    operator_lines(lines, &r.operators, r.newton.as_ref());
    constraint_lines(lines, &r.constraints);
    if !r.constraints.is_empty() {
        lines.push(format!(
            "  max constraint violation {:.2e}",
            r.max_violation
        ));
    }
    let why_not = if r.unknowns == 0 {
        "nothing was free"
    } else {
        "a term does not describe its integrand"
    };
    lines.push(check_line(
        r.check.as_ref(),
        road,
        why_not,
        r.newton.is_some(),
    ));
    measures_lines(lines, r.measures.as_ref());
    if r.unknowns == 0 {
        return; // nothing was solved: no gradient, residual or factor
    }
    lines.push(match &r.kkt {
        Some(k) => kkt_line(r.gradient_norm, r.relative_gradient, k),
        None => format!(
            "  gradient {:.2e} (relative {:.2e})  residual {:.2e}  condition ≈ {:.2e}  refinement steps {}{}",
            r.gradient_norm,
            r.relative_gradient,
            r.residual,
            r.condition_estimate,
            r.refinement_steps,
            r.factor_nonzeros
                .map(|n| format!("  Cholesky factor {n} nonzeros"))
                .unwrap_or_default()
        ),
    });
}

/// The gradient and the sparse KKT solve: its size, factorization,
/// residual, condition and refinement.
fn kkt_line(gradient: f64, relative: f64, k: &fairsurf::triangle::KktInfo) -> String {
    format!(
        "  gradient {gradient:.2e} (relative {relative:.2e})  KKT {}×{}{} by {}: residual {:.2e}, condition ≈ {:.2e}, refinement steps {}",
        k.size,
        k.size,
        if k.per_coordinate { " (one for x, y and z)" } else { "" },
        k.factorization.name(),
        k.relative_residual,
        k.condition,
        k.refinement_steps
    )
}

/// The summary's last line: the solve's time and what was written.
fn solved_line(seconds: f64, written: &[String]) -> String {
    if written.is_empty() {
        format!("  solved in {seconds:.3} s")
    } else {
        format!("  solved in {seconds:.3} s → wrote {}", written.join(", "))
    }
}

/// The summary's line for the independent check of the written net; `road`
/// says how it recomputed the energy. With `repellors` an excess of 0 is
/// not a measurement (a B-spline solve leaves it to Newton's relative
/// gradient, [`fairsurf::Check::excess`]) and is said so.
fn check_line(
    check: Option<&fairsurf::Check>,
    road: &str,
    why_not: &str,
    repellors: bool,
) -> String {
    match check {
        Some(c) => {
            let excess = if repellors && c.excess == 0.0 {
                "the excess not measured (the energy is not quadratic: Newton's relative gradient \
                 stands for it"
                    .to_string()
            } else {
                format!("{:.1e} above the minimum (relative", c.excess)
            };
            format!(
                "  checked on the written net: energy {:.10e} by {road} (closed forms agree to \
                 {:.1e}), {excess}; tolerance {:.0e}), {} correction(s)",
                c.energy, c.energy_error, c.tolerance, c.corrections
            )
        }
        None => format!("  not checked: {why_not}"),
    }
}

pub(crate) fn ensure_parent(file: &Path) -> Result<(), Failure> {
    match file.parent() {
        Some(d) if !d.as_os_str().is_empty() => std::fs::create_dir_all(d).map_err(|e| Failure {
            code: 1,
            message: format!("cannot create directory {}: {e}", d.display()),
        }),
        _ => Ok(()),
    }
}

/// A spinner on a terminal for solves that take noticeable time.
fn spinner_for(scene: &Scene) -> ProgressBar {
    let [n, m] = match scene {
        Scene::Tensor(s) => s.surface.degree,
        Scene::Triangular(_) | Scene::BSpline(_) => return ProgressBar::hidden(),
    };
    if n.max(m) < 16 || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let s = ProgressBar::new_spinner();
    s.set_message(format!("assembling and solving degree {n}×{m}"));
    s.enable_steady_tick(std::time::Duration::from_millis(100));
    s
}

/// One line per operator (energy, how far its target is met) and one for
/// Newton's method when there were repellors.
fn operator_lines(
    lines: &mut Vec<String>,
    operators: &[fairsurf::operator::OperatorOutcome],
    newton: Option<&fairsurf::operator::NewtonReport>,
) {
    for o in operators {
        let (what, unit) = if o.kind == "director" {
            ("mean angle to its direction", " rad")
        } else {
            ("rms distance to its target", "")
        };
        lines.push(format!(
            "  {} ({}, strength {}): energy {:.6e}, {what} {:.4e}{unit} (max {:.4e}{unit})",
            o.name, o.kind, o.strength, o.energy, o.measure, o.max
        ));
    }
    if let Some(n) = newton {
        lines.push(format!(
            "  Newton (repellors): {} iterations ({} convex), objective {:.10e} → {:.10e}, relative gradient {:.2e}",
            n.iterations, n.convex_steps, n.start_energy, n.energy, n.relative_gradient
        ));
    }
}

/// What the command prints of a solved scene, whatever its kind: a line
/// naming the surface, the report's lines (the same for every kind that
/// minimizes: energy and terms, operators, constraints, the check, the
/// measures, the solve's accuracy), what only its kind has, notes, and the
/// time with what was written.
fn summary(path: &Path, solved: &SolvedScene, written: &[String]) -> String {
    let mut lines = Vec::new();
    let surface = match solved {
        SolvedScene::Tensor(s) => {
            let (n, m) = s.patch().degree();
            format!("degree {n}×{m}")
        }
        SolvedScene::BSpline(s) => {
            let surface = s.surface();
            let ((p, q), (cu, cv)) = (surface.degree(), surface.counts());
            let (su, sv) = (
                surface.knots().0.spans().len(),
                surface.knots().1.spans().len(),
            );
            format!("B-spline, degree {p}×{q}, {su}×{sv} spans, {cu}×{cv} control points")
        }
        SolvedScene::Triangular(s) => {
            let t = s.solution.figures();
            format!(
                "triangular, degree {}, {} patches ({} vertices, {} control points)",
                s.surface().degree(),
                t.patches,
                t.vertices,
                t.points
            )
        }
    };
    let total = match what_was_done(solved) {
        Done::Minimized(r) => {
            lines.push(format!("{}: {surface}, {}", path.display(), free_words(r)));
            let road = match solved {
                SolvedScene::BSpline(_) => "Gauss quadrature span by span",
                _ => "double-double quadrature",
            };
            report_lines(&mut lines, r, road);
            r.timings.total
        }
        Done::Constructed(c) => construction_lines(&mut lines, path, &surface, c),
    };
    match solved {
        SolvedScene::Tensor(s) => {
            if let Some(d) = &s.normal_deviation {
                lines.push(format!(
                    "  normal deviation from N: max {:.3}°, mean {:.3}°",
                    d.max.to_degrees(),
                    d.mean.to_degrees()
                ));
            }
            if let Some(d) = s.guide_distance {
                lines.push(format!("  max distance to the guide surface {d:.6e}"));
            }
        }
        SolvedScene::BSpline(s) => {
            if let Some(t) = s.normal_turn {
                lines.push(format!(
                    "  largest normal turn between neighbouring samples {:.2}°",
                    t.angle.to_degrees()
                ));
            }
        }
        SolvedScene::Triangular(s) => {
            triangular_lines(&mut lines, &s.solution.report, s.solution.figures())
        }
    }
    for note in &solved.notes() {
        lines.push(format!("  note: {note}"));
    }
    lines.push(solved_line(total, written));
    lines.join("\n")
}

/// What a solve did: minimized an energy (every kind) or constructed a
/// Monterde & Ugail surface (a tensor patch by a method).
enum Done<'a> {
    Minimized(&'a fairsurf::SolveReport),
    Constructed(&'a fairsurf::harmonic::ConstructionReport),
}

fn what_was_done(solved: &SolvedScene) -> Done<'_> {
    match solved {
        SolvedScene::Tensor(s) => match &s.outcome {
            Outcome::Minimized(sol) => Done::Minimized(&sol.report),
            Outcome::Constructed(c) => Done::Constructed(&c.report),
        },
        SolvedScene::BSpline(s) => Done::Minimized(&s.solution.report),
        SolvedScene::Triangular(s) => Done::Minimized(&s.solution.report),
    }
}

/// A Monterde & Ugail construction's lines (its equations' residual,
/// conditioning, the points the method determined, the measures); its
/// time.
fn construction_lines(
    lines: &mut Vec<String>,
    path: &Path,
    surface: &str,
    r: &fairsurf::harmonic::ConstructionReport,
) -> f64 {
    lines.push(format!(
        "{}: {surface}, {} surface, {} free points",
        path.display(),
        r.method.name(),
        r.unknowns
    ));
    lines.push(format!(
        "  {}: max {:.2e} relative to the net (backward error {:.2e}){}",
        r.method.equations(),
        r.residual,
        r.backward_error,
        if r.exact {
            ""
        } else {
            " — NOT exact: least-squares net, no such surface has this boundary"
        }
    ));
    if r.condition_estimate.is_finite() {
        lines.push(format!(
            "  condition ≈ {:.2e}  refinement steps {}",
            r.condition_estimate, r.refinement_steps
        ));
    }
    for o in &r.overridden {
        lines.push(format!(
            "  note: P[{}][{}] is determined by the other points: given {:?}, used {:?}",
            o.index.0, o.index.1, o.given, o.determined
        ));
    }
    measures_lines(lines, r.measures.as_ref());
    r.timings.total
}

/// What only a triangular surface has: its rows (independent, dependent,
/// dropped, inconsistent), fixed control points, how far the continuity
/// rows are off, the row tolerance used, the largest angle across edges.
fn triangular_lines(lines: &mut Vec<String>, r: &fairsurf::SolveReport, t: &fairsurf::TriFigures) {
    lines.push(format!(
        "  constraint rows {}: {} independent, {} dependent (reduced), {} continuity dropped, {} inconsistent",
        t.rows,
        t.independent_rows,
        t.dependent_rows,
        t.dropped.len(),
        t.inconsistent.len()
    ));
    let fixed: Vec<f64> = r
        .constraints
        .iter()
        .filter(|c| c.kind == "fixed")
        .map(|c| c.violation)
        .collect();
    if !fixed.is_empty() {
        let worst = fixed.iter().fold(0.0f64, |m, v| m.max(*v));
        lines.push(format!(
            "  {} fixed control points: violation {worst:.2e}",
            fixed.len()
        ));
    }
    lines.push(format!(
        "  continuity rows off by {:.2e} (kept), {:.2e} (left out)",
        t.continuity_residual, t.unenforced_residual
    ));
    if t.row_tolerance > 1e-9 {
        lines.push(format!(
            "  note: the continuity conditions are nearly dependent; they were reduced with pivot tolerance {:.0e} ({} classification(s) of the rows, {} KKT system(s) factored)",
            t.row_tolerance, t.classifications, t.factorizations
        ));
    }
    if let Some((angle, [a, b])) = t.max_edge_normal_angle {
        lines.push(format!(
            "  largest normal angle across interior edges {angle:.2e} rad (edge {a}–{b})"
        ));
    }
    const LIST: usize = 5;
    for (what, list) in [("dropped", &t.dropped), ("inconsistent", &t.inconsistent)] {
        for d in list.iter().take(LIST) {
            lines.push(format!(
                "  {what}: {} (residual {:.2e})",
                d.name, d.residual
            ));
        }
        if list.len() > LIST {
            lines.push(format!(
                "  … and {} more {what} (see the report)",
                list.len() - LIST
            ));
        }
    }
}

fn measures_lines(lines: &mut Vec<String>, ms: Option<&fairsurf::SurfaceMeasures>) {
    if let Some(ms) = ms {
        lines.push(format!(
            "  area {:.12} (±{:.1e})  dirichlet {:.10e}  biharmonic {:.10e}",
            ms.area, ms.area_error, ms.dirichlet, ms.biharmonic
        ));
        let h = &ms.abs_mean_curvature;
        lines.push(format!(
            "  |H| min {:.4e} max {:.4e} mean {:.4e} ({} grid points{})",
            h.min,
            h.max,
            h.mean,
            h.samples,
            if h.singular > 0 {
                format!(", {} singular skipped", h.singular)
            } else {
                String::new()
            }
        ));
    }
}

/// One line per constraint (fixed control points are summed up apart).
fn constraint_lines(
    lines: &mut Vec<String>,
    constraints: &[fairsurf::constraint::ConstraintOutcome],
) {
    for c in constraints.iter().filter(|c| c.kind != "fixed") {
        lines.push(format!(
            "  {} ({}): violation {:.2e}",
            c.name, c.kind, c.violation
        ));
    }
}
