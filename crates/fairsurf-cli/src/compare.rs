//! `fairsurf compare`: the table of Monterde & Ugail 2004, §4.

use crate::Failure;
use fairsurf::harmonic::Comparison;
use fairsurf_io::comparison_json;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// A scene (or result) file; only the boundary ring of its surface is used.
    scene: PathBuf,
    /// Print the table as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), Failure> {
    let scene = crate::input::tensor_scene(&a.scene, "compare")?;
    let c = scene.compare().map_err(crate::input::with_file(&a.scene))?;
    if a.json {
        crate::say!(
            "{}",
            serde_json::to_string_pretty(&comparison_json(&c)).expect("json")
        );
    } else {
        crate::say!("{}", table(&a.scene.display().to_string(), &c));
    }
    Ok(())
}

/// Ten significant digits.
fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = v.abs().log10().floor() as i32;
    format!("{:.*}", (9 - digits).clamp(0, 15) as usize, v)
}

/// One row of the table: a number of the measures.
type Measure = fn(&fairsurf::SurfaceMeasures) -> f64;

fn table(name: &str, c: &Comparison) -> String {
    let cols = c.columns();
    let (n, m) = cols[0].1.patch.degree();
    let mut out = vec![format!(
        "{name}: degree {n}×{m}, four surfaces with one boundary (Monterde & Ugail 2004, §4); * marks the smallest in each row"
    )];
    let headers = [
        "harmonic extremal",
        "harmonic mask",
        "biharmonic surface",
        "biharmonic extremal",
    ];
    let mut head = format!("{:<12}", "");
    for h in headers {
        head.push_str(&format!("{h:>22}"));
    }
    out.push(head);
    let rows: [(&str, Measure); 4] = [
        ("area", |m| m.area),
        ("harmonic", |m| m.dirichlet),
        ("biharmonic", |m| m.biharmonic),
        ("mean |H|", |m| m.abs_mean_curvature.mean),
    ];
    for (label, f) in rows {
        let vals: Vec<f64> = cols.iter().map(|(_, col)| f(&col.measures)).collect();
        let min = vals.iter().cloned().fold(f64::INFINITY, f64::min);
        let mut line = format!("{label:<12}");
        for v in vals {
            let mark = if v == min { "*" } else { " " };
            line.push_str(&format!("{:>21}{mark}", sig(v)));
        }
        out.push(line);
    }
    let bs = &c.biharmonic_surface;
    if !bs.exact {
        out.push(format!(
            "note: no biharmonic Bézier surface of degree {n}×{m} has this boundary; the column shows the \
             least-squares net (max Δ²x coefficient {:.3e} relative to the net)",
            bs.residual
        ));
    }
    let area_err = cols
        .iter()
        .map(|(_, col)| col.measures.area_error / col.measures.area)
        .fold(0.0, f64::max);
    out.push(format!(
        "areas by adaptive Gauss–Legendre (relative error ≤ {area_err:.1e}); functionals exact; mean |H| area-weighted on a 65×65 grid"
    ));
    out.join("\n")
}
