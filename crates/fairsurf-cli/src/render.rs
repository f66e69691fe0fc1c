//! `fairsurf render`: pictures of scenes and results.

use crate::input::{surface, with_file, Loaded};
use crate::Failure;
use fairsurf::energy::NormalGuide;
use fairsurf::ParamSurface;
use fairsurf_io::{write_atomic, Scene, SolvedScene, Surface};
use fairsurf_render::{render, Arrow, ColourBy, Panel, Range, RenderOptions, View};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// Scene or result files. A scene is solved first; a result file (one
    /// with a "report") is drawn as it is. Several are drawn side by side
    /// with one scale, view and colour range.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// The PNG file to write.
    #[arg(short, long)]
    output: PathBuf,
    /// Colour by: none, mean, gaussian, abs-mean.
    #[arg(long, default_value = "abs-mean")]
    colour: String,
    /// Colour range: auto, or LO,HI (e.g. 0,1 as in Monterde & Ugail's figures).
    #[arg(long, default_value = "auto", allow_hyphen_values = true)]
    range: String,
    /// View: iso, top, front, side, or AZIMUTH,ELEVATION in degrees.
    #[arg(long, default_value = "iso", allow_hyphen_values = true)]
    view: String,
    /// Image size WIDTHxHEIGHT in pixels.
    #[arg(long, default_value = "1200x900")]
    size: String,
    /// Draw the control net.
    #[arg(long)]
    net: bool,
    /// Leave out the boundary curves.
    #[arg(long)]
    no_boundary: bool,
    /// Draw the scene's guide normal field as arrows (Wu & Yang's λ term;
    /// tensor and B-spline scenes).
    #[arg(long)]
    normals: bool,
    /// Reflection-line (zebra) stripes; optionally how many (default 20).
    #[arg(long, num_args = 0..=1, default_missing_value = "20")]
    zebra: Option<u32>,
    /// Isophotes (bands of constant n·L); optionally how many (default 16).
    #[arg(long, num_args = 0..=1, default_missing_value = "16", conflicts_with = "zebra")]
    isophotes: Option<u32>,
    /// Draw the four surfaces of `fairsurf compare` (one scene) side by side.
    #[arg(long)]
    compare: bool,
    /// Tessellation: quads per patch direction.
    #[arg(long, default_value_t = 64)]
    resolution: usize,
    /// Leave out the colour bar.
    #[arg(long)]
    no_colour_bar: bool,
}

fn parse_size(s: &str) -> Result<(u32, u32), Failure> {
    let bad = || Failure::input(format!("--size: expected WIDTHxHEIGHT, got {s:?}"));
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    Ok((
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    ))
}

fn options(a: &Args) -> Result<RenderOptions, Failure> {
    let opt = |e: fairsurf_render::Error| Failure::input(format!("--{e}"));
    let (width, height) = parse_size(&a.size)?;
    let opts = RenderOptions {
        width,
        height,
        colour: ColourBy::parse(&a.colour).map_err(opt)?,
        range: Range::parse(&a.range).map_err(opt)?,
        view: View::parse(&a.view).map_err(opt)?,
        control_net: a.net,
        boundary: !a.no_boundary,
        arrows: a.normals,
        zebra: a.zebra,
        isophotes: a.isophotes,
        resolution: a.resolution,
        colour_bar: !a.no_colour_bar,
        ..RenderOptions::default()
    };
    opts.validate().map_err(opt)?;
    Ok(opts)
}

pub fn run(a: Args) -> Result<(), Failure> {
    let opts = options(&a)?;
    let ext = a.output.extension().and_then(|e| e.to_str());
    if !ext.is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        return Err(Failure::input(format!(
            "-o {}: pictures are PNG files; name it *.png",
            a.output.display()
        )));
    }
    if a.compare && a.files.len() != 1 {
        return Err(Failure::input("--compare takes exactly one scene"));
    }
    let panels = if a.compare {
        compare_panels(&a.files[0])?
    } else {
        a.files
            .iter()
            .map(|f| panel(f, a.normals))
            .collect::<Result<Vec<_>, _>>()?
    };
    let picture = render(&panels, &opts).map_err(|e| Failure::input(e.to_string()))?;
    crate::solve::ensure_parent(&a.output)?;
    write_atomic(&a.output, |w| {
        picture.encode_png(w).map_err(std::io::Error::other)
    })?;
    let range = picture
        .range
        .map(|(lo, hi)| format!(", {} from {lo:.4} to {hi:.4}", opts.colour.label()))
        .unwrap_or_default();
    crate::say!(
        "{}: {}×{}{range}",
        a.output.display(),
        picture.width,
        picture.height
    );
    for (p, s) in panels.iter().zip(&picture.panels) {
        let title = p.title.as_deref().unwrap_or("");
        let mut line = format!("  {title}: covers {:.0}%", 100.0 * s.coverage);
        if opts.colour != ColourBy::None {
            line += &format!(", {} in [{:.4}, {:.4}]", opts.colour.label(), s.min, s.max);
        }
        if s.singular > 0 {
            line += &format!(", {} singular samples", s.singular);
        }
        crate::say!("{line}");
    }
    Ok(())
}

fn title(path: &Path) -> String {
    path.file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
}

/// The surface of a scene (solved) or result file (as it is), with the
/// scene's guide normal field as arrows when asked.
fn panel(path: &Path, normals: bool) -> Result<Panel, Failure> {
    let Loaded {
        scene,
        solved,
        surface,
    } = surface(path)?;
    let patches = surface.tensor_patches();
    let arrows = match (normals, &scene, solved) {
        (true, Scene::Tensor(scene), solved) => {
            let built = match solved {
                Some(SolvedScene::Tensor(s)) => s.built,
                _ => scene.build().map_err(with_file(path))?,
            };
            built
                .normal_field
                .map(|nf| field_arrows(|u, v| patches[0].eval(u, v), &nf.guide))
                .unwrap_or_default()
        }
        (true, Scene::BSpline(scene), solved) => {
            let field = match solved {
                Some(SolvedScene::BSpline(s)) => s.normal_field.map(|f| *f),
                _ => scene.problem().map_err(with_file(path))?.normal_field(),
            };
            match (&surface, field) {
                // The field lives on the knot domain mapped onto [0, 1]².
                (Surface::BSpline(b), Some(nf)) => {
                    field_arrows(|u, v| b.eval_unit(u, v), &nf.guide)
                }
                _ => vec![],
            }
        }
        _ => vec![],
    };
    // Triangular surfaces are drawn over their own triangles (their tensor
    // form's collapsed sides would spoil the curvature colours).
    let (patches, triangles, bspline) = match surface {
        Surface::Triangular(t) => (vec![], t.patches().collect(), None),
        Surface::BSpline(b) => (patches, vec![], Some(b)),
        Surface::Tensor(_) => (patches, vec![], None),
    };
    Ok(Panel {
        patches,
        triangles,
        title: Some(title(path)),
        arrows,
        bspline,
    })
}

/// Arrows of a guide normal field attached to the surface (`point` at
/// (u, v) of [0, 1]², a B-spline's knot domain mapped onto it): a field on
/// a 7×7 grid, or the given samples (thinned to at most ~9 per direction).
fn field_arrows(point: impl Fn(f64, f64) -> fairsurf::Vec3, guide: &NormalGuide) -> Vec<Arrow> {
    let at = |u: f64, v: f64, d| Arrow {
        base: point(u, v),
        direction: d,
    };
    match guide {
        NormalGuide::Field(f) => (0..=6)
            .flat_map(|i| (0..=6).map(move |j| (i as f64 / 6.0, j as f64 / 6.0)))
            .map(|(u, v)| at(u, v, f.eval(u, v)))
            .collect(),
        NormalGuide::Spline(f) => (0..=6)
            .flat_map(|i| (0..=6).map(move |j| (i as f64 / 6.0, j as f64 / 6.0)))
            .map(|(u, v)| at(u, v, f.eval_unit(u, v)))
            .collect(),
        NormalGuide::Samples { grid, normals, .. } => {
            let (np, mp) = grid.size();
            let (si, sj) = (np.div_ceil(8).max(1), mp.div_ceil(8).max(1));
            let mut out = vec![];
            for ip in (0..=np).step_by(si) {
                for jp in (0..=mp).step_by(sj) {
                    let (u, v) = (ip as f64 / np as f64, jp as f64 / mp as f64);
                    out.push(at(u, v, normals[ip * (mp + 1) + jp]));
                }
            }
            out
        }
    }
}

/// The four surfaces of the comparison table, titled by column.
fn compare_panels(path: &Path) -> Result<Vec<Panel>, Failure> {
    let scene = crate::input::tensor_scene(path, "render --compare")?;
    let c = scene.compare().map_err(with_file(path))?;
    Ok(c.columns()
        .iter()
        .map(|(name, col)| Panel::new(col.patch.clone()).with_title(name.replace('_', " ")))
        .collect())
}
