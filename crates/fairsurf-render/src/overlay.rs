//! 2D overlays drawn with tiny-skia over the shaded surface: polylines,
//! points, arrows, text (Noto Sans Mono, pre-rasterized) and the colour bar.

use noto_sans_mono_bitmap::{get_raster, get_raster_width, FontWeight, RasterHeight};
use tiny_skia::{
    Color, FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform,
};

/// An RGB colour in 0–255.
pub(crate) type Rgb = [u8; 3];

pub(crate) const INK: Rgb = [30, 30, 34];
pub(crate) const NET: Rgb = [200, 40, 40];
pub(crate) const BOUNDARY: Rgb = [20, 20, 24];
/// Knot lines of a B-spline surface: the borders of its polynomial pieces.
pub(crate) const KNOT: Rgb = [70, 70, 80];
pub(crate) const ARROW: Rgb = [20, 90, 200];

fn paint(c: Rgb, alpha: u8) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(c[0], c[1], c[2], alpha);
    p.anti_alias = true;
    p
}

/// A polyline through pixel points (skips the line if fewer than two).
pub(crate) fn polyline(pm: &mut Pixmap, pts: &[(f32, f32)], c: Rgb, width: f32, alpha: u8) {
    if pts.len() < 2 {
        return;
    }
    let mut pb = PathBuilder::new();
    pb.move_to(pts[0].0, pts[0].1);
    for p in &pts[1..] {
        pb.line_to(p.0, p.1);
    }
    if let Some(path) = pb.finish() {
        let stroke = Stroke {
            width,
            line_cap: LineCap::Round,
            line_join: LineJoin::Round,
            ..Stroke::default()
        };
        pm.stroke_path(
            &path,
            &paint(c, alpha),
            &stroke,
            Transform::identity(),
            None,
        );
    }
}

fn fill(pm: &mut Pixmap, path: Option<tiny_skia::Path>, c: Rgb) {
    if let Some(path) = path {
        let p = paint(c, 255);
        pm.fill_path(&path, &p, FillRule::Winding, Transform::identity(), None);
    }
}

/// A filled dot.
pub(crate) fn dot(pm: &mut Pixmap, p: (f32, f32), radius: f32, c: Rgb) {
    fill(pm, PathBuilder::from_circle(p.0, p.1, radius), c);
}

/// An arrow from `a` to `b` with a filled head.
pub(crate) fn arrow(pm: &mut Pixmap, a: (f32, f32), b: (f32, f32), c: Rgb) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = (dx * dx + dy * dy).sqrt();
    if len < 1.0 {
        dot(pm, a, 1.5, c);
        return;
    }
    let (ux, uy) = (dx / len, dy / len);
    let head = (0.3 * len).clamp(3.0, 9.0);
    let base = (b.0 - ux * head, b.1 - uy * head);
    polyline(pm, &[a, base], c, 1.5, 255);
    let mut pb = PathBuilder::new();
    pb.move_to(b.0, b.1);
    pb.line_to(base.0 - uy * head * 0.45, base.1 + ux * head * 0.45);
    pb.line_to(base.0 + uy * head * 0.45, base.1 - ux * head * 0.45);
    pb.close();
    fill(pm, pb.finish(), c);
}

/// A filled axis-aligned rectangle in a straight colour.
pub(crate) fn rect(pm: &mut Pixmap, x: f32, y: f32, w: f32, h: f32, c: Rgb) {
    if let Some(r) = Rect::from_xywh(x, y, w, h) {
        pm.fill_rect(r, &paint(c, 255), Transform::identity(), None);
    }
}

/// Text size: small (16 px rows) or large (20 px rows).
#[derive(Clone, Copy)]
pub(crate) enum Size {
    Small,
    Large,
}

impl Size {
    fn raster(self) -> RasterHeight {
        match self {
            Size::Small => RasterHeight::Size16,
            Size::Large => RasterHeight::Size20,
        }
    }
    /// Row height in pixels.
    pub fn height(self) -> f32 {
        self.raster().val() as f32
    }
    /// Width of `text` in pixels (monospace).
    pub fn width(self, text: &str) -> f32 {
        (get_raster_width(FontWeight::Regular, self.raster()) * text.chars().count()) as f32
    }
}

/// Draws `text` with its top-left corner at (x, y); characters the font
/// lacks are drawn as '?'.
pub(crate) fn text(pm: &mut Pixmap, x: f32, y: f32, s: &str, size: Size, c: Rgb) {
    let (w, h) = (pm.width() as i64, pm.height() as i64);
    let advance = get_raster_width(FontWeight::Regular, size.raster()) as i64;
    let (x0, y0) = (x.round() as i64, y.round() as i64);
    let data = pm.data_mut();
    for (k, ch) in s.chars().enumerate() {
        let Some(glyph) = get_raster(ch, FontWeight::Regular, size.raster())
            .or_else(|| get_raster('?', FontWeight::Regular, size.raster()))
        else {
            continue;
        };
        for (gy, row) in glyph.rows().enumerate() {
            for (gx, &a) in row.iter().enumerate() {
                let (px, py) = (x0 + k as i64 * advance + gx as i64, y0 + gy as i64);
                if a == 0 || px < 0 || py < 0 || px >= w || py >= h {
                    continue;
                }
                let i = 4 * (py * w + px) as usize;
                let t = a as f32 / 255.0;
                for ch in 0..3 {
                    let bg = data[i + ch] as f32;
                    data[i + ch] = (bg + (c[ch] as f32 - bg) * t).round() as u8;
                }
                data[i + 3] = data[i + 3].max(a);
            }
        }
    }
}

/// Formats a colour-bar value compactly: plain decimals for moderate
/// magnitudes, scientific notation otherwise.
pub(crate) fn format_value(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&a) {
        // Four significant digits.
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.2e}")
    }
}

/// Fills the whole pixmap with an opaque colour.
pub(crate) fn clear(pm: &mut Pixmap, c: Rgb) {
    pm.fill(Color::from_rgba8(c[0], c[1], c[2], 255));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_short_and_exact_enough() {
        assert_eq!(format_value(0.0), "0");
        assert_eq!(format_value(1.0), "1");
        assert_eq!(format_value(0.25), "0.25");
        assert_eq!(format_value(-1.5), "-1.5");
        assert_eq!(format_value(23.97207), "23.97");
        assert_eq!(format_value(-2.517741), "-2.518");
        assert_eq!(format_value(1234.4), "1234");
        assert_eq!(format_value(12345.0), "1.23e4");
        assert_eq!(format_value(1.5e-5), "1.50e-5");
    }

    #[test]
    fn text_darkens_pixels_inside_its_box_only() {
        let mut pm = Pixmap::new(80, 30).unwrap();
        clear(&mut pm, [255, 255, 255]);
        text(&mut pm, 5.0, 5.0, "H=1", Size::Small, [0, 0, 0]);
        let w = Size::Small.width("H=1") as usize;
        let dark = |x: usize, y: usize| pm.data()[4 * (y * 80 + x)] < 128;
        assert!((5..5 + w).any(|x| (5..21).any(|y| dark(x, y))));
        assert!((0..80).all(|x| !dark(x, 0) && !dark(x, 29)));
        assert!((5 + w..80).all(|x| (0..30).all(|y| !dark(x, y))));
    }
}
