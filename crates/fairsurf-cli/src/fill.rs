//! `fairsurf fill`: fill the holes between faces (a STEP file or a JSON
//! fill scene) and write the faces with the fills, sewn, as STEP.

use crate::input::with_file;
use crate::Failure;
use fairsurf::bspline::{BSplineSurface, FitTolerance};
use fairsurf::fill::{FillOptions, HoleFill};
use fairsurf::triangle::TriSurface;
use fairsurf_io::{
    sides_beyond, write_atomic, Batch, CadSurface, FillInput, HoleChoice, SurfaceMesh,
};
use fairsurf_render::{render, ColourBy, Panel, Range, RenderOptions};
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The faces: a STEP file (.step/.stp, as Open CASCADE, CadQuery or
    /// FreeCAD write them: B-spline and Bézier faces, rational or not,
    /// planes bounded by four straight edges, cylinders and cones bounded
    /// by two arcs and two rulings; B-spline, plane, cylinder, cone,
    /// sphere and torus faces trimmed otherwise or with holes, met through
    /// strips along their edges) or a JSON fill scene (`fairsurf schema
    /// --type fill`).
    input: PathBuf,
    /// The STEP file to write: the input faces and the fills, sewn.
    #[arg(short, long, required_unless_present = "list")]
    output: Option<PathBuf>,
    /// List the holes (index, sides, length, faces, whether filled by
    /// default) and fill nothing.
    #[arg(long)]
    list: bool,
    /// Fill hole K (repeatable; as `--list` numbers them). Default: every
    /// hole but the outer rims (each open sheet's: the loops that bound
    /// their faces from outside, and those that run across their normals,
    /// as a pipe's ends); none left is an error.
    #[arg(long = "hole", value_name = "K")]
    holes: Vec<usize>,
    /// Print the report as JSON on standard output instead of the summary.
    #[arg(long)]
    json: bool,
    /// Rational faces (cylinders, cones, rational B-splines) are met
    /// through a polynomial stand-in within this distance along their
    /// sides (at the same parameter), trimmed faces through strips along
    /// their edges likewise; a fill whose measured gap to a neighbour is
    /// larger is flagged.
    #[arg(long, value_name = "DISTANCE", default_value_t = 1e-6)]
    tolerance: f64,
    /// … and within this normal angle, degrees (likewise flagged).
    #[arg(long, value_name = "DEGREES", default_value_t = 0.01)]
    angle_tolerance: f64,
    #[command(flatten)]
    energy: EnergyArgs,
    #[command(flatten)]
    outputs: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Failure> {
    for (name, x) in [
        ("--tolerance", a.tolerance),
        ("--angle-tolerance", a.angle_tolerance),
    ] {
        if !(x.is_finite() && x > 0.0) {
            return Err(Failure::input(format!(
                "{name}: expected a positive number, got {x}"
            )));
        }
    }
    let mut input = FillInput::read(&a.input).map_err(with_file(&a.input))?;
    let fit = FitTolerance {
        position: a.tolerance,
        angle: a.angle_tolerance.to_radians(),
    };
    if fit != FitTolerance::default() {
        input.refit(fit).map_err(with_file(&a.input))?;
    }
    let asked = if a.holes.is_empty() {
        input.holes.clone()
    } else {
        Some(a.holes.clone())
    };
    let choice = HoleChoice::of(&input, asked.as_deref()).map_err(|e| match e {
        fairsurf_io::Error::Scene { message, .. } if !a.holes.is_empty() => {
            Failure::input(format!("--hole: {message}"))
        }
        e => with_file(&a.input)(e),
    })?;
    if a.list {
        let list = input.list_json(&choice);
        if a.json {
            crate::say!("{}", serde_json::to_string_pretty(&list).expect("JSON"));
        } else {
            crate::say!(
                "{}: {}, {}",
                a.input.display(),
                counted(input.file_faces(), "face"),
                counted(choice.holes.len(), "hole")
            );
            for h in list.as_array().expect("a list") {
                crate::say!(
                    "  hole {}: {} sides, length {:.6}, faces {}{}",
                    h["index"],
                    h["sides"],
                    h["length"].as_f64().unwrap_or(f64::NAN),
                    h["faces"],
                    if h["rim"] == true {
                        " (outer rim: not filled unless asked)"
                    } else {
                        ""
                    }
                );
            }
        }
        return Ok(());
    }
    // A fan's sides are one polynomial piece each: rational faces along
    // them stand in by one span.
    input.one_span_sides(&choice).map_err(with_file(&a.input))?;
    let mut options = input.options.clone();
    a.energy.apply(&mut options)?;
    let fills = choice
        .fill(&input.faces, &options)
        .map_err(|e| with_file(&a.input)(input.name_faces(e)))?;
    let output = a
        .output
        .as_deref()
        .expect("clap requires -o without --list");
    let surfaces = input.surfaces(&fills);
    // The picture and the mesh take the four-sided fills as B-splines and
    // the fans as triangular surfaces (no collapsed corners).
    let mut meshed: Vec<&BSplineSurface> = input.pictured_faces();
    let mut fans: Vec<&TriSurface> = Vec::new();
    for f in &fills {
        match f {
            HoleFill::Patch(p) => meshed.push(&p.surface),
            HoleFill::Fan(t) => fans.push(&t.surface),
        }
    }
    a.outputs
        .write(output, &surfaces, input.hole_tolerance(), &meshed, &fans)?;
    if a.json {
        let mut out = input.report_json(&choice, &fills, fit);
        out["stand_ins"] = input.stand_ins_json();
        out["input"] = json!(a.input.display().to_string());
        out["output"] = json!(output.display().to_string());
        crate::say!("{}", serde_json::to_string_pretty(&out).expect("JSON"));
    } else {
        crate::say!(
            "{}",
            summary(
                &a.input,
                output,
                &input,
                &choice,
                &fills,
                (a.tolerance, a.angle_tolerance),
                options.descent_steps
            )
        );
    }
    beyond_tolerances(&choice.chosen, &fills, (a.tolerance, a.angle_tolerance))
}

/// Exit status 3 when a written fill is measured beyond the tolerances
/// along some side (the summary and the JSON say where): the output is
/// whole, but not what was asked for — a script must not take it for a
/// fill within them.
fn beyond_tolerances(
    holes: &[usize],
    fills: &[HoleFill],
    (gap, degrees): (f64, f64),
) -> Result<(), Failure> {
    let fit = FitTolerance {
        position: gap,
        angle: degrees.to_radians(),
    };
    let beyond: Vec<String> = holes
        .iter()
        .zip(fills)
        .filter_map(|(h, f)| {
            let sides = sides_beyond(f, fit);
            let cut = match f {
                HoleFill::Patch(_) => "",
                HoleFill::Fan(_) => " (as cut for the fan)",
            };
            (!sides.is_empty()).then(|| format!("hole {h} along sides{cut} {sides:?}"))
        })
        .collect();
    if beyond.is_empty() {
        return Ok(());
    }
    Err(Failure {
        code: 3,
        message: format!(
            "written, but the fill is beyond the tolerances (gap {:e}, angle {:e}°): {} \
             (--tolerance and --angle-tolerance set them)",
            gap,
            degrees,
            beyond.join("; ")
        ),
    })
}

fn summary(
    path: &Path,
    output: &Path,
    input: &FillInput,
    choice: &HoleChoice,
    fills: &[HoleFill],
    (gap_tolerance, degrees): (f64, f64),
    budget: usize,
) -> String {
    let tolerance = FitTolerance {
        position: gap_tolerance,
        angle: degrees.to_radians(),
    };
    let faces = input.file_faces();
    let mut lines = vec![format!(
        "{}: {}, {}; filled {:?}{}",
        path.display(),
        counted(faces, "face"),
        counted(choice.holes.len(), "hole"),
        choice.chosen,
        match choice
            .rims
            .iter()
            .filter(|r| !choice.chosen.contains(r))
            .collect::<Vec<_>>()
            .as_slice()
        {
            [] => String::new(),
            [r] => format!(" (hole {r}, taken as the outer rim)"),
            rs => format!(
                " (holes {}, taken as outer rims)",
                rs.iter()
                    .map(|r| r.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    )];
    let rational: Vec<String> = input
        .stand_ins
        .iter()
        .enumerate()
        .take(faces)
        .filter_map(|(k, s)| {
            s.map(|(gap, angle)| {
                format!(
                    "{k} ({}: stand-in within {gap:.1e}, {:.1e}°)",
                    input.kinds[k],
                    angle.to_degrees()
                )
            })
        })
        .collect();
    if !rational.is_empty() {
        lines.push(format!(
            "  rational faces, met through polynomial stand-ins (G1 there to the stand-in's \
             tolerance, not exact): {}",
            rational.join(", ")
        ));
    }
    // Per trimmed face, its strips' largest distances from its edges (an
    // edge another face shares stands in by its curve alone: not counted).
    let mut trimmed: Vec<(usize, usize, f64, f64)> = Vec::new();
    for (s, strip) in input.strips().iter().enumerate() {
        if input.kinds[faces + s] != "strip" {
            continue;
        }
        let (gap, angle) = input.stand_ins[faces + s].unwrap_or((0.0, 0.0));
        match trimmed.iter_mut().find(|t| t.0 == strip.face) {
            Some(t) => *t = (t.0, t.1 + 1, t.2.max(gap), t.3.max(angle)),
            None => trimmed.push((strip.face, 1, gap, angle)),
        }
    }
    if !trimmed.is_empty() {
        let list: Vec<String> = trimmed
            .iter()
            .map(|&(k, n, gap, angle)| {
                format!(
                    "{k} ({}: {n} strips within {gap:.1e}, {:.1e}°)",
                    input.kinds[k],
                    angle.to_degrees()
                )
            })
            .collect();
        lines.push(format!(
            "  trimmed faces, met through strip stand-ins along their free edges (G1 there to \
             the strips' tolerance, not exact): {}",
            list.join(", ")
        ));
    }
    for (&h, fill) in choice.chosen.iter().zip(fills) {
        let gap = fill.sides().iter().map(|s| s.gap).fold(0.0, f64::max);
        let angle = fairsurf::fill::largest_angle(fill.sides()).to_degrees();
        let w = fill.curvature();
        let fit = format!(
            "largest gap {gap:.1e}, largest normal angle {angle:.1e}° ({} samples per side); \
             W = ∫κ₁²+κ₂² dA = {:.6} (±{:.0e})",
            fill.sides()[0].samples,
            w.value,
            w.error
        );
        match fill {
            HoleFill::Patch(f) => {
                let r = &f.report;
                let steps = crate::fill::steps_kept(&r.willmore);
                let (p, q) = f.surface.degree();
                let (cu, cv) = f.surface.counts();
                lines.push(format!(
                    "  hole {h}: degree {p}×{q}, {cu}×{cv} control points; {fit}; thin-plate solve \
                     checked to {:.0e}, W-lowering steps kept: {steps}; {:.1} ms",
                    r.solve.check.map_or(f64::NAN, |c| c.energy_error),
                    1e3 * r.seconds.total_with(&r.others)
                ));
                lines.extend(budget_ran_out(&r.willmore, budget));
                let c = &r.corners;
                if c.position > 0.0 || c.tangent > 1e-12 || c.twist > 1e-12 {
                    lines.push(format!(
                        "    corners: sides disagree by {:.1e} in position, {:.1e} in tangent, {:.1e} in twist",
                        c.position, c.tangent, c.twist
                    ));
                }
            }
            HoleFill::Fan(f) => {
                let r = &f.report;
                let ms = 1e3 * r.seconds.total_with(&r.others);
                let (n, degree) = (f.surface.patch_count(), f.surface.degree());
                let steps = crate::fill::steps_kept(&r.willmore);
                // Why one triangle: the fan was refused, beyond the angle
                // tolerance, or less fair.
                let fan_was = r
                    .others
                    .iter()
                    .find(|c| c.kind == "fan")
                    .map(|c| &c.outcome);
                let why = match fan_was {
                    Some(Err(_)) => "a fan was refused".to_string(),
                    Some(Ok((a, _))) if *a > tolerance.angle => {
                        format!("a fan missed its neighbours by {}°", in_degrees(*a))
                    }
                    _ => "fairer than a fan".to_string(),
                };
                lines.push(if n == 1 {
                    format!(
                        "  hole {h}: one triangular patch of degree {degree} ({why}); \
                         {fit}; W-lowering steps kept: {steps}; {ms:.1} ms"
                    )
                } else {
                    format!(
                        "  hole {h}: {n} triangular patches of degree {degree} around a centre; \
                         {fit}; between the patches {:.1e}°, {} of {} G1 conditions dropped; \
                         W-lowering steps kept: {steps}; {ms:.1} ms",
                        r.inner_angle.to_degrees(),
                        r.solve.triangular.as_ref().map_or(0, |t| t.dropped.len()),
                        r.solve.triangular.as_ref().map_or(0, |t| t.rows),
                    )
                });
                lines.extend(budget_ran_out(&r.willmore, budget));
                if let Some(note) = &r.descent_note {
                    lines.push(format!("    {note}"));
                }
                // A 4-sided hole: why not one patch.
                if let Some(c) = r.others.iter().find(|c| c.kind == "patch") {
                    lines.push(match &c.outcome {
                        Ok((a, w)) => format!(
                            "    one patch missed its neighbours by {}° (W {w:.6}): a fan instead",
                            in_degrees(*a)
                        ),
                        Err(e) => format!("    one patch was refused ({e}): a fan instead"),
                    });
                }
                let c = &r.corners;
                if c.position > 1e-12 || c.tangent > 1e-10 || c.twist > 1e-10 {
                    lines.push(format!(
                        "    corners: sides disagree by {:.1e} in position, {:.1e} in tangent, \
                         {:.1e} in twist",
                        c.position, c.tangent, c.twist
                    ));
                }
            }
        }
        let sides = sides_beyond(fill, tolerance);
        if !sides.is_empty() {
            lines.push(format!(
                "    beyond the tolerances (gap {gap_tolerance:e}, angle {degrees:e}°) along {} \
                 {sides:?}: not G1 to the neighbours there to the tolerance{}",
                match fill {
                    HoleFill::Patch(_) => "sides",
                    HoleFill::Fan(_) => "sides (as cut for the fan)",
                },
                if fill.corners().tangent > 1e-10 {
                    " (the sides disagree at a corner, above)"
                } else {
                    ""
                }
            ));
        }
    }
    lines.push(format!(
        "{}: {} faces",
        output.display(),
        faces + fills.iter().map(|f| f.patches().len()).sum::<usize>()
    ));
    lines.join("\n")
}

/// How many of the steps after the thin plate lowered W (each a new least
/// W in `history`, which begins with the thin plate's and lists every
/// step tried).
pub fn steps_kept(history: &[f64]) -> usize {
    let mut least = history.first().copied().unwrap_or(f64::INFINITY);
    history
        .iter()
        .skip(1)
        .filter(|&&w| {
            let lower = w < least;
            least = least.min(w);
            lower
        })
        .count()
}

/// The other files a fill and a blend write beside the STEP file.
#[derive(clap::Args)]
pub struct OutputArgs {
    /// Also draw the faces and the new surfaces, coloured by |H| (PNG).
    #[arg(long, value_name = "PNG")]
    render: Option<PathBuf>,
    /// Reflection-line stripes in the picture instead of curvature colours.
    #[arg(long)]
    zebra: bool,
    /// Also write the faces and the new surfaces as one triangle mesh
    /// (.obj, .ply with curvature, .stl, .glb, .gltf).
    #[arg(long, value_name = "FILE")]
    mesh: Option<PathBuf>,
    /// Mesh resolution: quads per parameter direction of each face (each
    /// triangular patch: subdivisions per side).
    #[arg(long, default_value_t = 24, value_parser = clap::value_parser!(u32).range(1..=512))]
    resolution: u32,
}

impl OutputArgs {
    /// Writes `surfaces` as STEP to `output` and, when asked, the picture
    /// and the mesh of `meshed` and `triangular` — made in memory first,
    /// written together (all or none).
    pub fn write(
        &self,
        output: &Path,
        surfaces: &[CadSurface],
        sew_within: f64,
        meshed: &[&BSplineSurface],
        triangular: &[&TriSurface],
    ) -> Result<(), Failure> {
        crate::solve::ensure_parent(output)?;
        let picture = self
            .render
            .as_ref()
            .map(|p| picture(meshed, triangular, self.zebra).map(|png| (p, png)))
            .transpose()?;
        if let Some((path, _)) = &picture {
            crate::solve::ensure_parent(path)?;
        }
        let mesh = match &self.mesh {
            Some(path) => {
                fairsurf_io::MeshFormat::from_path(path)?;
                crate::solve::ensure_parent(path)?;
                let r = self.resolution as usize;
                let parts = meshed
                    .iter()
                    .map(|s| {
                        let (ku, kv) = s.knots();
                        SurfaceMesh::from_patch(*s, r * ku.spans().len(), r * kv.spans().len())
                    })
                    .chain(
                        triangular
                            .iter()
                            .map(|t| SurfaceMesh::from_tri_surface(t, r)),
                    );
                Some((path, SurfaceMesh::joined(parts)))
            }
            None => None,
        };
        let batch = Batch::begin();
        fairsurf_io::write_step_sewn(output, surfaces, sew_within)?;
        if let Some((path, png)) = &picture {
            write_atomic(path, |w| w.write_all(png))?;
        }
        if let Some((path, mesh)) = &mesh {
            fairsurf_io::write_mesh(path, mesh)?;
        }
        batch.commit()?;
        Ok(())
    }
}

/// The summary's line when the descent on W took every step of its
/// `budget` (W from the thin plate's, then after each step): it stopped
/// short of its own ending, W still falling.
fn budget_ran_out(history: &[f64], budget: usize) -> Option<String> {
    let n = history.len();
    (budget > 0 && n > budget).then(|| {
        let gain = (history[n - 2] - history[n - 1]) / history[n - 1].abs();
        format!(
            "    W still falling when the descent's {budget} steps ran out (the last lowered it \
             by {gain:.1e} of itself; from {:.6} at the thin plate): --descent-steps lets it go on",
            history[0]
        )
    })
}

/// Energy options a fill and a blend take from the command line.
#[derive(clap::Args)]
pub struct EnergyArgs {
    /// The plain thin plate (no normal field from the boundary data), with
    /// or without the descent on W (by default the normal field guides the
    /// thin plate only when `--descent-steps 0` turns the descent off).
    #[arg(long, conflicts_with = "lambda")]
    plain: bool,
    /// λ of the normal field from the boundary data, per unit area: it then
    /// guides the thin plate before the descent on W too (default: 100,
    /// only with `--descent-steps 0`).
    #[arg(long)]
    lambda: Option<f64>,
    /// Degrees the patch gets above its sides' largest.
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=10))]
    elevate: Option<u32>,
    /// The most steps that lower W itself after the thin plate (200 by
    /// default; 0 for none).
    #[arg(long)]
    descent_steps: Option<usize>,
}

impl EnergyArgs {
    /// The scene's options with these flags applied.
    pub fn apply(&self, options: &mut FillOptions) -> Result<(), Failure> {
        if self.plain {
            options.normal_weight = 0.0;
        }
        if let Some(l) = self.lambda {
            if !(l >= 0.0 && l.is_finite()) {
                return Err(Failure::input(format!(
                    "--lambda: expected a number ≥ 0, got {l}"
                )));
            }
            options.guide_with(l);
        }
        if let Some(e) = self.elevate {
            options.elevate = e as usize;
        }
        if let Some(n) = self.descent_steps {
            options.descent_steps = n;
        }
        Ok(())
    }
}

/// The picture of B-spline surfaces and triangular ones (drawn over their
/// triangles: their tensor form's collapsed side would put a singular row
/// of samples in the colour range), in one panel, coloured by |H| or
/// striped.
fn picture(
    surfaces: &[&BSplineSurface],
    triangular: &[&TriSurface],
    zebra: bool,
) -> Result<Vec<u8>, Failure> {
    let mut png = Vec::new();
    drawn(surfaces, triangular, zebra)?
        .encode_png(&mut png)
        .map_err(|e| Failure::input(e.to_string()))?;
    Ok(png)
}

/// [`picture`] before its encoding.
fn drawn(
    surfaces: &[&BSplineSurface],
    triangular: &[&TriSurface],
    zebra: bool,
) -> Result<fairsurf_render::Picture, Failure> {
    let patches = surfaces
        .iter()
        .flat_map(|s| s.bezier_pieces().into_iter().map(|p| p.patch))
        .collect();
    let panel = Panel {
        patches,
        triangles: triangular.iter().flat_map(|t| t.patches()).collect(),
        ..Panel::default()
    };
    let opts = RenderOptions {
        colour: ColourBy::AbsMean,
        range: Range::Auto,
        zebra: zebra.then_some(20),
        ..RenderOptions::default()
    };
    render(&[panel], &opts).map_err(|e| Failure::input(e.to_string()))
}

/// "1 face", "2 faces".
fn counted(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

/// An angle (radians) in degrees for the summary: two decimals from 0.01°,
/// else in scientific notation.
fn in_degrees(a: f64) -> String {
    let d = a.to_degrees();
    if d >= 0.01 {
        format!("{d:.2}")
    } else {
        format!("{d:.1e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan on a sphere of radius 1.5 (the bundled trimmed_revolved.step's
    /// hole in its sphere face) is coloured over |H| ≈ 1/1.5: drawn over
    /// its triangles, not as tensor patches with a collapsed side (whose
    /// row of near-singular samples had put the colour range at 2e14).
    #[test]
    fn a_fan_is_coloured_by_its_curvature() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cad/trimmed_revolved.step");
        let mut input = FillInput::read(&path).unwrap();
        let sphere = input
            .kinds
            .iter()
            .position(|k| *k == "trimmed sphere")
            .unwrap();
        let all = input.choose(None).unwrap();
        let hole = *all
            .chosen
            .iter()
            .find(|&&h| {
                all.holes[h]
                    .faces()
                    .iter()
                    .all(|&f| input.face_of(f) == sphere)
            })
            .unwrap();
        let choice = input.choose(Some(&[hole])).unwrap();
        let fills = choice.fill(&input.faces, &input.options).unwrap();
        let HoleFill::Fan(fan) = &fills[0] else {
            panic!("a fan on the sphere")
        };
        let Ok(picture) = drawn(&[], &[&fan.surface], false) else {
            panic!("drawn")
        };
        let (lo, hi) = picture.range.unwrap();
        assert_eq!(lo, 0.0);
        assert!((hi - 1.0 / 1.5).abs() < 0.05, "{hi}");
    }
}
