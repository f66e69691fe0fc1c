//! `fairsurf analyse`: measures of surfaces as the files give them.

use crate::Failure;
use fairsurf_io::Scene;
use serde_json::{json, Value};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Result files (or scenes whose control points are all given),
    /// tensor-product or triangular.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Print JSON: one object per file, {"file", "kind", "measures": {label: value}}.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), Failure> {
    let mut out = Vec::new();
    for path in &a.files {
        let with_file = crate::input::with_file(path);
        let scene = Scene::from_json(&crate::input::read(path)?).map_err(&with_file)?;
        let measures = scene.analyse().map_err(&with_file)?;
        let kind = scene.surface_type().name();
        if a.json {
            let m: serde_json::Map<String, Value> = measures.into_iter().collect();
            out.push(json!({"file": path.display().to_string(), "kind": kind, "measures": m}));
        } else {
            crate::say!("{}: {kind}", path.display());
            let width = measures
                .iter()
                .map(|(l, _)| l.chars().count())
                .max()
                .unwrap_or(0);
            for (label, value) in &measures {
                let shown = match value {
                    Value::String(s) => s.clone(),
                    Value::Null => "—".into(),
                    v => v.to_string(),
                };
                crate::say!("  {label:<width$}  {shown}");
            }
        }
    }
    if a.json {
        crate::say!("{}", serde_json::to_string_pretty(&out).expect("json"));
    }
    Ok(())
}
