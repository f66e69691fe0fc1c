//! Panels in, picture out: layout, colouring, rasterization and overlays.

use crate::camera::Camera;
use crate::overlay::{self, Size, ARROW, BOUNDARY, INK, KNOT, NET};
use crate::raster::{rasterize, Layer, Soup, Stripes};
use crate::{ColourBy, Error, Range, RenderOptions, Result};
use fairsurf::analysis::Curvature;
use fairsurf::bspline::BSplineSurface;
use fairsurf::colour::ColourMap;
use fairsurf::vector::{add, norm, normalize, scale, sub};
use fairsurf::{TensorPatch, TriMesh, TriPatch, Vec3};
use tiny_skia::Pixmap;

/// An arrow attached to the surface, e.g. one sample of a guide normal field
/// (Wu & Yang 2015, eq. 6). Drawn with a length of 8% of the surface's size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrow {
    /// Where the arrow starts.
    pub base: Vec3,
    /// Its direction (need not be unit; only the direction is drawn).
    pub direction: Vec3,
}

/// One surface to draw: its patches (tensor-product, triangular or both),
/// an optional title, arrows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Panel {
    /// The tensor-product patches (one for a single surface).
    pub patches: Vec<TensorPatch>,
    /// Triangular patches (Veltkamp & Wesselink), tessellated natively over
    /// their triangle, so their curvature colours stay right at the corners
    /// (their tensor form collapses a side, where curvature blows up).
    pub triangles: Vec<TriPatch>,
    /// A caption drawn above the panel.
    pub title: Option<String>,
    /// Arrows drawn when [`RenderOptions::arrows`] is on.
    pub arrows: Vec<Arrow>,
    /// A B-spline surface whose Bézier pieces are `patches`: its knot lines
    /// are drawn (thin), and its own control net and outer boundary stand
    /// for the pieces' when those are asked for.
    pub bspline: Option<BSplineSurface>,
}

impl Panel {
    /// A panel of one patch with no title or arrows.
    pub fn new(patch: TensorPatch) -> Self {
        Panel {
            patches: vec![patch],
            ..Panel::default()
        }
    }
    /// A panel of a B-spline surface: its Bézier pieces, knot lines drawn.
    pub fn bspline(surface: BSplineSurface) -> Self {
        Panel {
            patches: surface
                .bezier_pieces()
                .into_iter()
                .map(|p| p.patch)
                .collect(),
            bspline: Some(surface),
            ..Panel::default()
        }
    }

    /// A panel of triangular patches, e.g. `surface.patches().collect()`.
    pub fn triangular(patches: Vec<TriPatch>) -> Self {
        Panel {
            triangles: patches,
            ..Panel::default()
        }
    }
    /// Sets the title.
    pub fn with_title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
}

/// What was drawn in one panel.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelStats {
    /// Fraction of the panel's drawing area covered by the surface, in [0, 1].
    pub coverage: f64,
    /// Smallest and largest value of the colouring quantity at the
    /// tessellation's vertices (NaN when colouring is off).
    pub min: f64,
    /// See `min`.
    pub max: f64,
    /// Vertices where the surface is singular (no normal, no curvature).
    pub singular: usize,
}

/// A rendered picture: straight (non-premultiplied) RGBA8, rows top to
/// bottom, and what it shows.
#[derive(Clone, Debug)]
pub struct Picture {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// 4 bytes per pixel, opaque.
    pub rgba: Vec<u8>,
    /// The colour map's range, when colouring by a quantity.
    pub range: Option<(f64, f64)>,
    /// Per panel, in the order given.
    pub panels: Vec<PanelStats>,
}

impl Picture {
    /// Encodes the picture as an 8-bit RGBA PNG.
    pub fn encode_png(&self, w: &mut dyn std::io::Write) -> Result<()> {
        let mut enc = png::Encoder::new(w, self.width, self.height);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        let png_err = |e: png::EncodingError| Error::Png(e.to_string());
        let mut writer = enc.write_header().map_err(png_err)?;
        writer.write_image_data(&self.rgba).map_err(png_err)?;
        writer.finish().map_err(png_err)
    }
}

const BACKGROUND: overlay::Rgb = [255, 255, 255];
const NEUTRAL: [f32; 3] = [0.70, 0.75, 0.82];
const TITLE_H: f32 = 28.0;
const BAR_W: f32 = 120.0;
/// Arrow length as a fraction of the surface's bounding-box diagonal.
const ARROW_LENGTH: f64 = 0.08;

/// A panel made ready to draw: tessellations and per-vertex values.
struct Prepared {
    meshes: Vec<TriMesh>,
    values: Vec<Vec<f64>>,
    frame_points: Vec<Vec3>,
    size: f64,
}

fn prepare(panel: &Panel, index: usize, opts: &RenderOptions) -> Result<Prepared> {
    if panel.patches.is_empty() && panel.triangles.is_empty() {
        return Err(Error::EmptyPanel { panel: index });
    }
    let r = opts.resolution;
    let (mut meshes, mut values, mut frame_points) = (vec![], vec![], vec![]);
    let tensor = panel.patches.iter().map(|p| {
        let (mesh, k) = TriMesh::with_curvature(p, r, r);
        (mesh, k, p.points())
    });
    let triangular = panel.triangles.iter().map(|p| {
        let (mesh, k) = p.mesh_with_curvature(r);
        (mesh, k, p.points())
    });
    for (mesh, curvature, net) in tensor.chain(triangular) {
        values.push(colour_values(opts.colour, &curvature));
        frame_points.extend_from_slice(&mesh.positions);
        if opts.control_net {
            frame_points.extend_from_slice(net);
        }
        meshes.push(mesh);
    }
    let (lo, hi) = bounds(&frame_points);
    let size = norm(sub(hi, lo)).max(1e-12);
    if opts.arrows {
        for a in &panel.arrows {
            if let Some(d) = normalize(a.direction) {
                frame_points.push(add(a.base, scale(d, ARROW_LENGTH * size)));
            }
        }
    }
    Ok(Prepared {
        meshes,
        values,
        frame_points,
        size,
    })
}

/// The colouring quantity at each vertex (NaN: none, or singular there).
fn colour_values(colour: ColourBy, curvature: &[Option<Curvature>]) -> Vec<f64> {
    curvature
        .iter()
        .map(|k| match (colour, k) {
            (ColourBy::None, _) | (_, None) => f64::NAN,
            (ColourBy::Mean, Some(k)) => k.mean,
            (ColourBy::Gaussian, Some(k)) => k.gaussian,
            (ColourBy::AbsMean, Some(k)) => k.mean.abs(),
        })
        .collect()
}

fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points.iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                std::array::from_fn(|k| lo[k].min(p[k])),
                std::array::from_fn(|k| hi[k].max(p[k])),
            )
        },
    )
}

/// The colour range for the options and the values of all panels.
fn colour_range(opts: &RenderOptions, prepared: &[Prepared]) -> Option<(f64, f64)> {
    if opts.colour == ColourBy::None {
        return None;
    }
    if let Range::Fixed(lo, hi) = opts.range {
        return Some((lo, hi));
    }
    let mut mags: Vec<f64> = prepared
        .iter()
        .flat_map(|p| p.values.iter().flatten())
        .filter(|v| v.is_finite())
        .map(|v| v.abs())
        .collect();
    if mags.is_empty() {
        return Some((0.0, 1.0));
    }
    mags.sort_by(f64::total_cmp);
    let q = mags[((mags.len() - 1) as f64 * 0.99).round() as usize];
    let q = if q > 0.0 { q } else { 1.0 };
    Some(if opts.colour.is_signed() {
        (-q, q)
    } else {
        (0.0, q)
    })
}

/// Renders panels side by side with one shared scale, view and colour
/// range: in one row, or in the grid whose panels let the surfaces be
/// drawn more than 1.25 times larger (the largest such).
///
/// ```
/// use fairsurf::TensorPatch;
/// use fairsurf_render::{render, Panel, RenderOptions};
/// let saddle = TensorPatch::from_fn(2, 2, |i, j| {
///     let (u, v) = (i as f64 / 2.0, j as f64 / 2.0);
///     [u, v, if i == 1 && j == 1 { 0.5 } else { 0.0 }]
/// });
/// let pic = render(&[Panel::new(saddle)], &RenderOptions::default().with_size(200, 150)).unwrap();
/// assert_eq!((pic.width, pic.height, pic.rgba.len()), (200, 150, 200 * 150 * 4));
/// assert!(pic.panels[0].coverage > 0.2);
/// ```
pub fn render(panels: &[Panel], opts: &RenderOptions) -> Result<Picture> {
    opts.validate()?;
    if panels.is_empty() {
        return Err(Error::NoPanels);
    }
    let prepared = panels
        .iter()
        .enumerate()
        .map(|(i, p)| prepare(p, i, opts))
        .collect::<Result<Vec<_>>>()?;
    let range = colour_range(opts, &prepared);
    let (w, h) = (opts.width as f32, opts.height as f32);
    let bar = if range.is_some() && opts.colour_bar {
        BAR_W.min(0.3 * w)
    } else {
        0.0
    };
    let n = panels.len();
    let has_title = panels.iter().any(|p| p.title.is_some());
    // The panels' grid: one row unless fewer columns let the surfaces be
    // drawn at least 1.25 times larger (a wide surface in a tall picture
    // stacked, four in a 4:3 picture 2 × 2), so that they fill their panels;
    // of those grids the largest scale.
    let layout = |cols: usize| {
        let rows = n.div_ceil(cols);
        let (pw, ph) = (((w - bar) / cols as f32).floor(), (h / rows as f32).floor());
        let title_h = if has_title {
            TITLE_H.min(0.2 * ph)
        } else {
            0.0
        };
        let viewport = (pw.max(1.0) as f64, (ph - title_h).max(1.0) as f64);
        let cams: Vec<Camera> = prepared
            .iter()
            .map(|p| Camera::fit(opts.view, &p.frame_points, viewport, 0.05))
            .collect();
        let common = cams.iter().map(|c| c.scale).fold(f64::INFINITY, f64::min);
        (common, cols, pw, ph, title_h, cams)
    };
    let row = layout(n);
    let grid = (1..n)
        .map(layout)
        .reduce(|best, next| if next.0 > best.0 { next } else { best });
    let (common, cols, pw, ph, title_h, mut cams) = match grid {
        Some(g) if g.0 > 1.25 * row.0 => g,
        _ => row,
    };
    for c in &mut cams {
        c.scale = common;
    }
    let mut pm = Pixmap::new(opts.width, opts.height).ok_or(Error::Option {
        name: "width",
        message: "cannot allocate the image".into(),
    })?;
    overlay::clear(&mut pm, BACKGROUND);
    let mut stats = Vec::with_capacity(n);
    for (k, (panel, prep)) in panels.iter().zip(&prepared).enumerate() {
        let (x0, y0) = ((k % cols) as f32 * pw, (k / cols) as f32 * ph);
        let cam = &cams[k];
        let soup = soup(prep, opts.colour, range);
        let stripes = match (opts.zebra, opts.isophotes) {
            (Some(k), _) => Some(Stripes::Reflection(k)),
            (None, Some(k)) => Some(Stripes::Isophote(k)),
            _ => None,
        };
        let layer = rasterize(&soup, cam, opts.supersample as usize, stripes);
        blit(&mut pm, &layer, x0 as usize, (y0 + title_h) as usize);
        draw_overlays(&mut pm, panel, prep, cam, &layer, opts, (x0, y0 + title_h));
        if let Some(t) = &panel.title {
            let tw = Size::Large.width(t);
            overlay::text(
                &mut pm,
                x0 + (0.5 * (pw - tw)).max(4.0),
                y0 + 0.5 * (title_h - Size::Large.height()).max(0.0),
                t,
                Size::Large,
                INK,
            );
        }
        let finite = || prep.values.iter().flatten().filter(|v| v.is_finite());
        stats.push(PanelStats {
            coverage: layer.coverage(),
            min: finite().fold(f64::NAN, |a, &b| a.min(b)),
            max: finite().fold(f64::NAN, |a, &b| a.max(b)),
            singular: match opts.colour {
                ColourBy::None => 0,
                _ => prep.values.iter().flatten().filter(|v| v.is_nan()).count(),
            },
        });
    }
    if let (Some(r), true) = (range, bar > 0.0) {
        colour_bar(&mut pm, r, opts.colour, w - bar, h);
    }
    let rgba = pm.take_demultiplied();
    Ok(Picture {
        width: opts.width,
        height: opts.height,
        rgba,
        range,
        panels: stats,
    })
}

fn colour_map(colour: ColourBy) -> ColourMap {
    if colour.is_signed() {
        ColourMap::CoolWarm
    } else {
        ColourMap::Viridis
    }
}

fn soup(prep: &Prepared, colour: ColourBy, range: Option<(f64, f64)>) -> Soup {
    let mut s = Soup::default();
    for (mesh, vals) in prep.meshes.iter().zip(&prep.values) {
        let offset = s.positions.len() as u32;
        s.positions.extend_from_slice(&mesh.positions);
        s.normals.extend_from_slice(&mesh.normals);
        s.colours.extend(vals.iter().map(|&v| match range {
            Some((lo, hi)) if colour != ColourBy::None => {
                colour_map(colour).at((v - lo) / (hi - lo))
            }
            _ => NEUTRAL,
        }));
        s.triangles
            .extend(mesh.triangles.iter().map(|t| t.map(|k| k + offset)));
    }
    s
}

/// Composites a premultiplied layer over the opaque pixmap at (x0, y0).
fn blit(pm: &mut Pixmap, layer: &Layer, x0: usize, y0: usize) {
    let (w, h) = (pm.width() as usize, pm.height() as usize);
    let data = pm.data_mut();
    for y in 0..layer.height.min(h.saturating_sub(y0)) {
        for x in 0..layer.width.min(w.saturating_sub(x0)) {
            let p = layer.rgba[y * layer.width + x];
            if p[3] <= 0.0 {
                continue;
            }
            let i = 4 * ((y0 + y) * w + x0 + x);
            for c in 0..3 {
                let bg = data[i + c] as f32 / 255.0;
                data[i + c] = ((p[c] + bg * (1.0 - p[3])) * 255.0)
                    .round()
                    .clamp(0.0, 255.0) as u8;
            }
        }
    }
}

/// Draws a polyline through world points: the parts in front of the
/// surface solid, the parts it hides faint.
fn depth_polyline(
    pm: &mut Pixmap,
    pts: &[Vec3],
    cam: &Camera,
    layer: &Layer,
    origin: (f32, f32),
    c: overlay::Rgb,
    width: f32,
) {
    let proj: Vec<(f32, f32, bool)> = pts
        .iter()
        .map(|&p| {
            let (x, y, z) = cam.project(p);
            (
                origin.0 + x as f32,
                origin.1 + y as f32,
                layer.visible(x, y, z),
            )
        })
        .collect();
    let draw = |pm: &mut Pixmap, run: &[(f32, f32)], vis: bool| {
        overlay::polyline(pm, run, c, width, if vis { 255 } else { 60 });
    };
    let Some(first) = proj.first() else { return };
    let mut run = vec![(first.0, first.1)];
    let mut run_vis = None;
    for w in proj.windows(2) {
        let vis = w[0].2 && w[1].2;
        if let Some(rv) = run_vis.filter(|&rv| rv != vis) {
            draw(pm, &run, rv);
            run = vec![(w[0].0, w[0].1)];
        }
        run_vis = Some(vis);
        run.push((w[1].0, w[1].1));
    }
    if let Some(rv) = run_vis {
        draw(pm, &run, rv);
    }
}

/// Points along the segment a–b, `n` pieces.
fn segment(a: Vec3, b: Vec3, n: usize) -> impl Iterator<Item = Vec3> {
    (0..=n).map(move |k| add(a, scale(sub(b, a), k as f64 / n as f64)))
}

fn draw_overlays(
    pm: &mut Pixmap,
    panel: &Panel,
    prep: &Prepared,
    cam: &Camera,
    layer: &Layer,
    opts: &RenderOptions,
    origin: (f32, f32),
) {
    let px = |p: Vec3| {
        let (x, y, _) = cam.project(p);
        (origin.0 + x as f32, origin.1 + y as f32)
    };
    let grid_line = |pm: &mut Pixmap, pts: &[Vec3], colour, width| {
        depth_polyline(pm, pts, cam, layer, origin, colour, width)
    };
    if let Some(b) = &panel.bspline {
        // Knot lines: the surface along every interior knot, both ways.
        let ((u0, u1), (v0, v1)) = (b.knots().0.domain(), b.knots().1.domain());
        let k = 2 * opts.resolution;
        for (dir, knots) in [(0, b.knots().0), (1, b.knots().1)] {
            for &(_, t, _) in knots.spans().iter().skip(1) {
                let pts: Vec<Vec3> = (0..=k)
                    .map(|s| {
                        let w = s as f64 / k as f64;
                        match dir {
                            0 => b.eval(t, v0 + w * (v1 - v0)),
                            _ => b.eval(u0 + w * (u1 - u0), t),
                        }
                    })
                    .collect();
                grid_line(pm, &pts, KNOT, 0.9);
            }
        }
        if opts.control_net {
            let (cu, cv) = b.counts();
            for i in 0..cu {
                for j in 0..cv {
                    if j + 1 < cv {
                        let pts: Vec<Vec3> =
                            segment(b.point(i, j), b.point(i, j + 1), 16).collect();
                        grid_line(pm, &pts, NET, 1.2);
                    }
                    if i + 1 < cu {
                        let pts: Vec<Vec3> =
                            segment(b.point(i, j), b.point(i + 1, j), 16).collect();
                        grid_line(pm, &pts, NET, 1.2);
                    }
                    overlay::dot(pm, px(b.point(i, j)), 2.6, NET);
                }
            }
        }
        if opts.boundary {
            let k = 4 * opts.resolution;
            let at = |w: f64, side: usize| match side {
                0 => b.eval(u0 + w * (u1 - u0), v0),
                1 => b.eval(u1, v0 + w * (v1 - v0)),
                2 => b.eval(u1 - w * (u1 - u0), v1),
                _ => b.eval(u0, v1 - w * (v1 - v0)),
            };
            for side in 0..4 {
                let pts: Vec<Vec3> = (0..=k).map(|s| at(s as f64 / k as f64, side)).collect();
                grid_line(pm, &pts, BOUNDARY, 2.0);
            }
        }
    }
    if opts.control_net && panel.bspline.is_none() {
        for patch in &panel.patches {
            let (n, m) = patch.degree();
            let mut line = |a: Vec3, b: Vec3| {
                let pts: Vec<Vec3> = segment(a, b, 16).collect();
                depth_polyline(pm, &pts, cam, layer, origin, NET, 1.2);
            };
            for i in 0..=n {
                for j in 0..=m {
                    if j < m {
                        line(patch.point(i, j), patch.point(i, j + 1));
                    }
                    if i < n {
                        line(patch.point(i, j), patch.point(i + 1, j));
                    }
                }
            }
            for p in patch.points() {
                overlay::dot(pm, px(*p), 2.6, NET);
            }
        }
        for patch in &panel.triangles {
            let n = patch.degree();
            let mut line = |a: Vec3, b: Vec3| {
                let pts: Vec<Vec3> = segment(a, b, 16).collect();
                depth_polyline(pm, &pts, cam, layer, origin, NET, 1.2);
            };
            // Each upward sub-triangle P_{i+1,j,k}, P_{i,j+1,k}, P_{i,j,k+1}.
            for i in 0..n {
                for j in 0..n - i {
                    let k = n - 1 - i - j;
                    let (a, b, c) = (
                        patch.point(i + 1, j, k),
                        patch.point(i, j + 1, k),
                        patch.point(i, j, k + 1),
                    );
                    line(a, b);
                    line(b, c);
                    line(c, a);
                }
            }
            for p in patch.points() {
                overlay::dot(pm, px(*p), 2.6, NET);
            }
        }
    }
    if opts.boundary && panel.bspline.is_none() {
        let k = 4 * opts.resolution;
        for patch in &panel.patches {
            let edges: [fn(f64) -> (f64, f64); 4] = [
                |s| (s, 0.0),
                |s| (1.0, s),
                |s| (1.0 - s, 1.0),
                |s| (0.0, 1.0 - s),
            ];
            for e in edges {
                let pts: Vec<Vec3> = (0..=k)
                    .map(|s| {
                        let (u, v) = e(s as f64 / k as f64);
                        patch.eval(u, v)
                    })
                    .collect();
                depth_polyline(pm, &pts, cam, layer, origin, BOUNDARY, 2.0);
            }
        }
        for patch in &panel.triangles {
            for e in 0..3 {
                let curve = patch.edge(e);
                let pts: Vec<Vec3> = (0..=k).map(|s| curve.eval(s as f64 / k as f64)).collect();
                depth_polyline(pm, &pts, cam, layer, origin, BOUNDARY, 2.0);
            }
        }
    }
    if opts.arrows {
        for a in &panel.arrows {
            if let Some(d) = normalize(a.direction) {
                let tip = add(a.base, scale(d, ARROW_LENGTH * prep.size));
                overlay::arrow(pm, px(a.base), px(tip), ARROW);
            }
        }
    }
}

/// A vertical colour bar with its ends and middle labelled.
fn colour_bar(pm: &mut Pixmap, (lo, hi): (f64, f64), colour: ColourBy, x0: f32, h: f32) {
    let top = 44.0f32.min(0.15 * h);
    let height = (h - 2.0 * top).max(10.0);
    let (bx, bw) = (x0 + 14.0, 18.0);
    let map = colour_map(colour);
    let steps = height.max(1.0) as usize;
    for s in 0..steps {
        let t = 1.0 - (s as f64 + 0.5) / steps as f64;
        let c = map.at(t).map(|v| (v * 255.0).round() as u8);
        overlay::rect(pm, bx, top + s as f32, bw, 1.0, c);
    }
    let title = match colour {
        ColourBy::Mean => "H (mean)",
        ColourBy::Gaussian => "K (Gauss)",
        _ => "|H|",
    };
    overlay::text(pm, x0 + 8.0, top - 24.0, title, Size::Small, INK);
    let label_h = Size::Small.height();
    for (t, v) in [(0.0, hi), (0.5, 0.5 * (lo + hi)), (1.0, lo)] {
        let y = top + t * height;
        overlay::rect(pm, bx + bw, y - 0.5, 4.0, 1.0, INK);
        let s = overlay::format_value(v);
        overlay::text(pm, bx + bw + 7.0, y - 0.5 * label_h, &s, Size::Small, INK);
    }
}
