//! `fairsurf eval`.

use crate::Failure;
use serde_json::json;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// A result file (or any scene whose control points are all given).
    file: PathBuf,
    /// A parameter pair u,v in [0, 1] (a B-spline surface's knot domain
    /// mapped onto [0, 1]²); repeat for more points.
    #[arg(long = "uv", value_parser = parse_uv)]
    uv: Vec<(f64, f64)>,
    /// Evaluate on a (k+1)×(k+1) uniform grid instead.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=10000))]
    grid: Option<u32>,
}

fn parse_uv(s: &str) -> Result<(f64, f64), String> {
    let (u, v) = s
        .split_once(',')
        .ok_or_else(|| format!("expected u,v (two numbers separated by a comma), got {s:?}"))?;
    let num = |x: &str, name: &str| -> Result<f64, String> {
        let t: f64 = x
            .trim()
            .parse()
            .map_err(|_| format!("{name}: expected a number, got {x:?}"))?;
        if !(0.0..=1.0).contains(&t) {
            return Err(format!("{name}: expected a value in [0, 1], got {t}"));
        }
        Ok(t)
    };
    Ok((num(u, "u")?, num(v, "v")?))
}

pub fn run(a: Args) -> Result<(), Failure> {
    let with_file = crate::input::with_file(&a.file);
    let scene = fairsurf_io::Scene::from_json(&crate::input::read(&a.file)?).map_err(&with_file)?;
    let surface = scene.surface().map_err(&with_file)?;
    if surface.derivatives(0.0, 0.0).is_none() {
        return Err(Failure::input(format!(
            "{}: surface.type: eval works on tensor-product surfaces (tensor, bspline); this one \
             is {}",
            a.file.display(),
            surface.surface_type().name()
        )));
    }
    let mut uv = a.uv.clone();
    if let Some(k) = a.grid {
        let k = k as usize;
        uv.extend(
            (0..=k).flat_map(|i| (0..=k).map(move |j| (i as f64 / k as f64, j as f64 / k as f64))),
        );
    }
    if uv.is_empty() {
        return Err(Failure::input("give at least one --uv u,v or --grid k"));
    }
    let out: Vec<_> = uv
        .iter()
        .map(|&(u, v)| {
            let d = surface.derivatives(u, v).expect("a tensor-product surface");
            json!({"u": u, "v": v, "point": d.point, "normal": d.normal()})
        })
        .collect();
    crate::say!("{}", serde_json::to_string_pretty(&out).expect("json"));
    Ok(())
}
