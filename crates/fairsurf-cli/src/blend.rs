//! `fairsurf blend`: a transition surface between two surfaces along one
//! edge of each (a JSON blend scene), written with the surfaces, sewn, as
//! STEP.

use crate::fill::{EnergyArgs, OutputArgs};
use crate::input::with_file;
use crate::Failure;
use fairsurf::bspline::BSplineSurface;
use fairsurf_io::{blend_json, BlendInput};
use serde_json::json;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The blend scene (`fairsurf schema --type blend`): two surfaces,
    /// inline or faces of STEP files, and one edge of each.
    input: PathBuf,
    /// The STEP file to write: every input face and the blend, sewn.
    #[arg(short, long)]
    output: PathBuf,
    /// Print the report as JSON on standard output instead of the summary.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    energy: EnergyArgs,
    #[command(flatten)]
    outputs: OutputArgs,
    /// The tangent lengths across at A's and B's edge, relative to the gap
    /// (overrides the scene's `bulge`): two numbers > 0 and ≤ 10. Default:
    /// the pair with the least W.
    #[arg(long, value_name = "A,B", value_delimiter = ',')]
    bulge: Option<Vec<f64>>,
}

pub fn run(a: Args) -> Result<(), Failure> {
    let mut input = BlendInput::read(&a.input).map_err(with_file(&a.input))?;
    a.energy.apply(&mut input.options.fill)?;
    if let Some(b) = &a.bulge {
        let pair = match b[..] {
            [x, y] => fairsurf_io::check_bulge([x, y]).ok(),
            _ => None,
        };
        let Some(pair) = pair else {
            return Err(Failure::input(format!(
                "--bulge: expected two numbers > 0 and ≤ 10 (A,B), got {b:?}"
            )));
        };
        input.options.bulge = fairsurf::fill::Bulge::Fixed(pair);
    }
    let blend = input.blend().map_err(with_file(&a.input))?;
    let surfaces = input.surfaces(&blend);
    let shown: Vec<&BSplineSurface> = input.faces.iter().chain([&blend.surface]).collect();
    a.outputs.write(&a.output, &surfaces, 0.0, &shown, &[])?;
    let mut out = blend_json(&input, &blend);
    if a.json {
        out["input"] = json!(a.input.display().to_string());
        out["output"] = json!(a.output.display().to_string());
        crate::say!("{}", serde_json::to_string_pretty(&out).expect("JSON"));
        return Ok(());
    }
    let r = &blend.report;
    let [(fa, _), (fb, _)] = input.ends;
    let (p, q) = blend.surface.degree();
    let (cu, cv) = blend.surface.counts();
    let steps = crate::fill::steps_kept(&r.willmore);
    let mut lines = vec![format!(
        "{}: blend between face {fa} and face {fb}: degree {p}×{q}, {cu}×{cv} control points, \
         α = [{:.4}, {:.4}]{}",
        a.input.display(),
        r.alpha[0],
        r.alpha[1],
        if r.flipped {
            " (face B's normal faces the other way: measured against its turned normal)"
        } else {
            ""
        }
    )];
    for (name, f) in ["A", "B"].iter().zip(&r.sides) {
        lines.push(format!(
            "  against {name}: largest gap {:.1e}, largest normal angle {:.1e}° ({} samples)",
            f.gap,
            f.angle.to_degrees(),
            f.samples
        ));
    }
    lines.push(format!(
        "  W = ∫κ₁²+κ₂² dA = {:.6} (±{:.0e}); thin-plate solve checked to {:.0e}, W-lowering steps \
         kept: {steps}; {:.1} ms",
        r.curvature.value,
        r.curvature.error,
        r.solve.check.map_or(f64::NAN, |c| c.energy_error),
        1e3 * (r.seconds.setup + r.seconds.solve + r.seconds.measure)
    ));
    match r.bulge_search {
        Some(s) => lines.push(format!(
            "  bulge [{:.4}, {:.4}] chosen by W ({} blends, {:.0} ms; W at [1, 1]: {:.6})",
            r.bulge[0],
            r.bulge[1],
            s.evaluations,
            1e3 * s.seconds,
            s.w_at_one
        )),
        None => lines.push(format!("  bulge [{}, {}] as given", r.bulge[0], r.bulge[1])),
    }
    lines.push(format!(
        "{}: {} faces",
        a.output.display(),
        input.faces.len() + 1
    ));
    crate::say!("{}", lines.join("\n"));
    Ok(())
}
