//! Facts about rendered pictures: size, coverage against the framing's
//! geometry, shared scale, views, colour bar orientation, determinism, error
//! paths, and golden images (tolerant comparison).
//!
//! Regenerate the golden images after an intended change with
//! `FAIRSURF_BLESS=1 cargo test -p fairsurf-render --test render`, look at
//! them, and commit them.

use fairsurf::colour::ColourMap;
use fairsurf::{TensorPatch, TriPatch};
use fairsurf_render::{render, Arrow, ColourBy, Error, Panel, Range, RenderOptions, View};
use std::path::PathBuf;

/// The flat square [0, s]² at z = 0, degree 2×2.
fn square(s: f64) -> TensorPatch {
    TensorPatch::from_fn(2, 2, |i, j| [s * i as f64 / 2.0, s * j as f64 / 2.0, 0.0])
}

/// A smooth bump over the unit square.
fn bump() -> TensorPatch {
    TensorPatch::from_fn(4, 4, |i, j| {
        let z = if (1..=3).contains(&i) && (1..=3).contains(&j) {
            0.5
        } else {
            0.0
        };
        [i as f64 / 4.0, j as f64 / 4.0, z]
    })
}

fn plain(w: u32, h: u32) -> RenderOptions {
    RenderOptions {
        colour: ColourBy::None,
        boundary: false,
        colour_bar: false,
        ..RenderOptions::default().with_size(w, h)
    }
}

/// A B-spline panel draws its knot lines: a flat sheet of 3 × 2 spans in
/// top view, plain shading, has dark pixels along the 2 + 1 interior knot
/// lines (and the same surface without interior knots has none); the
/// shading is the same surface either way.
#[test]
fn bspline_panels_draw_their_knot_lines() {
    use fairsurf::bspline::{BSplineSurface, KnotVector};
    let sheet = |u: KnotVector, v: KnotVector| {
        let (cu, cv) = (u.count(), v.count());
        // Greville abscissae: a flat, evenly parameterized sheet.
        let g = |k: &KnotVector, i: usize| {
            let p = k.degree();
            k.knots()[i + 1..=i + p].iter().sum::<f64>() / p as f64
        };
        let points = (0..cu * cv)
            .map(|q| [g(&u, q / cv), g(&v, q % cv), 0.0])
            .collect();
        BSplineSurface::new(u, v, points).unwrap()
    };
    let opts = RenderOptions {
        view: View::TOP,
        ..plain(200, 200)
    };
    let draw = |s: BSplineSurface| render(&[Panel::bspline(s)], &opts).unwrap().rgba;
    let with = draw(sheet(KnotVector::uniform(3, 3), KnotVector::uniform(3, 2)));
    let without = draw(sheet(KnotVector::bezier(3), KnotVector::bezier(3)));
    // Pixels where the lines darken the shading by more than 30 levels.
    let darker = with
        .chunks(4)
        .zip(without.chunks(4))
        .filter(|(a, b)| (b[0] as i32 - a[0] as i32) > 30)
        .count();
    let lighter = with
        .chunks(4)
        .zip(without.chunks(4))
        .filter(|(a, b)| (a[0] as i32 - b[0] as i32) > 30)
        .count();
    // Three lines across a ~180-pixel square, a pixel or two wide each; the
    // rest of the picture is about the same (the pieces' tessellation
    // differs from the whole patch's along a few edges).
    assert!(
        darker > 300 && 5 * lighter < darker,
        "{darker} darker, {lighter} lighter"
    );
}

#[test]
fn picture_has_the_asked_size_and_is_opaque() {
    let pic = render(
        &[Panel::new(bump())],
        &RenderOptions::default().with_size(333, 201),
    )
    .unwrap();
    assert_eq!((pic.width, pic.height), (333, 201));
    assert_eq!(pic.rgba.len(), 333 * 201 * 4);
    assert!(pic.rgba.chunks(4).all(|p| p[3] == 255));
    let mut png = Vec::new();
    pic.encode_png(&mut png).unwrap();
    let dec = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .unwrap();
    assert_eq!((dec.info().width, dec.info().height), (333, 201));
}

#[test]
fn top_view_of_a_square_covers_the_framed_fraction() {
    // The framing leaves 5% of the smaller side free on each side: a square
    // seen from the top fills 90% × 90% of a square viewport.
    let pic = render(
        &[Panel::new(square(1.0))],
        &plain(400, 400).with_view(View::TOP),
    )
    .unwrap();
    let c = pic.panels[0].coverage;
    assert!((c - 0.81).abs() < 0.006, "coverage {c}");
    // In a 2:1 viewport the square is limited by the height: 0.9·h squared over w·h.
    let pic = render(
        &[Panel::new(square(1.0))],
        &plain(800, 400).with_view(View::TOP),
    )
    .unwrap();
    let c = pic.panels[0].coverage;
    assert!((c - 0.405).abs() < 0.004, "coverage {c}");
}

#[test]
fn edge_on_plane_covers_almost_nothing() {
    for view in [View::FRONT, View::SIDE] {
        let pic = render(&[Panel::new(square(1.0))], &plain(300, 300).with_view(view)).unwrap();
        assert!(
            pic.panels[0].coverage < 0.01,
            "{view:?}: {}",
            pic.panels[0].coverage
        );
    }
}

#[test]
fn panels_share_one_scale() {
    // A square of half the side next to a unit square covers a quarter of its area.
    let panels = [Panel::new(square(1.0)), Panel::new(square(0.5))];
    let pic = render(&panels, &plain(800, 400).with_view(View::TOP)).unwrap();
    let (a, b) = (pic.panels[0].coverage, pic.panels[1].coverage);
    assert!((b / a - 0.25).abs() < 0.01, "{a} {b}");
}

#[test]
fn grid_layout_for_more_than_four_panels() {
    let panels: Vec<Panel> = (0..5).map(|_| Panel::new(square(1.0))).collect();
    let pic = render(&panels, &plain(600, 400).with_view(View::TOP)).unwrap();
    // 3 columns × 2 rows of 200×200: each square covers 0.81 of its panel.
    for s in &pic.panels {
        assert!((s.coverage - 0.81).abs() < 0.01, "{}", s.coverage);
    }
}

/// The grid is the one whose panels let the surfaces be largest: four
/// squares in a 4:3 picture go 2 × 2 (each 0.9 of a 450-pixel panel height:
/// 405² of 600 × 450, against 270² of 300 × 900 in a row), and two wide
/// strips in a tall picture are stacked, two tall ones side by side.
#[test]
fn the_grid_lets_the_surfaces_fill_their_panels() {
    let four: Vec<Panel> = (0..4).map(|_| Panel::new(square(1.0))).collect();
    let pic = render(&four, &plain(1200, 900).with_view(View::TOP)).unwrap();
    for s in &pic.panels {
        let want = 405.0 * 405.0 / (600.0 * 450.0);
        assert!((s.coverage - want).abs() < 0.01, "{} vs {want}", s.coverage);
    }
    // A 4 × 1 strip (x from 0 to 4), seen from the top.
    let strip = |wide: bool| {
        let (a, b) = if wide { (4.0, 1.0) } else { (1.0, 4.0) };
        Panel::new(TensorPatch::from_fn(1, 1, |i, j| {
            [a * i as f64, b * j as f64, 0.0]
        }))
    };
    for (wide, (w, h)) in [(true, (400, 800)), (false, (800, 400))] {
        let pic = render(
            &[strip(wide), strip(wide)],
            &plain(w, h).with_view(View::TOP),
        )
        .unwrap();
        // Stacked (or side by side): 400 × 400 panels, the strip 360 × 90
        // of them; the other way round it would be 45 pixels across.
        for s in &pic.panels {
            let want = 360.0 * 90.0 / (400.0 * 400.0);
            assert!(
                (s.coverage - want).abs() < 0.01,
                "wide {wide}: {} vs {want}",
                s.coverage
            );
        }
    }
}

#[test]
fn colour_bar_runs_from_the_range_top_to_bottom() {
    let opts = RenderOptions::default()
        .with_size(400, 300)
        .with_range(Range::Fixed(0.0, 1.0));
    let pic = render(&[Panel::new(bump())], &opts).unwrap();
    assert_eq!(pic.range, Some((0.0, 1.0)));
    // The bar is 18 px wide, 14 px from the start of the 120 px strip on the right.
    let x = 400 - 120 + 14 + 9;
    let px = |y: u32| {
        let i = 4 * (y * 400 + x) as usize;
        [pic.rgba[i], pic.rgba[i + 1], pic.rgba[i + 2]]
    };
    let top = 44.0f32.min(0.15 * 300.0) as u32;
    let want = |t: f64| ColourMap::Viridis.at(t).map(|v| (v * 255.0).round() as u8);
    let near = |a: [u8; 3], b: [u8; 3]| a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= 3);
    // Row s of the bar shows t = 1 − (s + ½)/height: the top is the range's top.
    let height = 300 - 2 * top;
    let t = |s: u32| 1.0 - (s as f64 + 0.5) / height as f64;
    assert!(near(px(top + 1), want(t(1))), "{:?}", px(top + 1));
    assert!(near(px(top + height - 2), want(t(height - 2))));
    assert!(t(1) > 0.99 && t(height - 2) < 0.01);
}

#[test]
fn automatic_ranges_follow_the_quantity() {
    let run = |c| {
        render(
            &[Panel::new(bump())],
            &RenderOptions::default().with_size(200, 150).with_colour(c),
        )
        .unwrap()
    };
    let (lo, hi) = run(ColourBy::AbsMean).range.unwrap();
    assert!(lo == 0.0 && hi > 0.0);
    let (lo, hi) = run(ColourBy::Mean).range.unwrap();
    assert!(lo == -hi && hi > 0.0);
    let p = run(ColourBy::Gaussian);
    let (lo, hi) = p.range.unwrap();
    assert!(lo == -hi && hi > 0.0);
    // The bump is elliptic on top and hyperbolic at its flanks.
    assert!(p.panels[0].min < 0.0 && p.panels[0].max > 0.0);
    assert_eq!(run(ColourBy::None).range, None);
}

/// The paraboloid z = (x² + y²)/2 over the triangle (0,0), (0.6,0), (0,0.6),
/// exactly: a quadratic triangular patch whose control points are the
/// blossom, P_ijk = f[A^i B^j C^k].
fn paraboloid_triangle() -> TriPatch {
    let corners = [[0.0, 0.0], [0.6, 0.0], [0.0, 0.6]];
    TriPatch::from_fn(2, |i, j, k| {
        let mut args = vec![];
        for (c, m) in [i, j, k].into_iter().enumerate() {
            args.extend(std::iter::repeat_n(corners[c], m));
        }
        let (a, b): ([f64; 2], [f64; 2]) = (args[0], args[1]);
        [
            0.5 * (a[0] + b[0]),
            0.5 * (a[1] + b[1]),
            0.5 * (a[0] * b[0] + a[1] * b[1]),
        ]
    })
}

#[test]
fn triangular_patches_are_coloured_by_their_true_curvature() {
    // H = (2 + r²) / (2 (1 + r²)^{3/2}) on the paraboloid: 1 at the
    // origin, falling with r; over this triangle r ≤ 0.6.
    let h = |r: f64| (2.0 + r * r) / (2.0 * (1.0 + r * r).powf(1.5));
    let t = paraboloid_triangle();
    let opts = RenderOptions::default()
        .with_size(200, 150)
        .with_colour(ColourBy::AbsMean);
    let p = render(&[Panel::triangular(vec![t.clone()])], &opts).unwrap();
    let s = &p.panels[0];
    assert_eq!(s.singular, 0);
    assert!((s.max - 1.0).abs() < 1e-12, "{}", s.max);
    assert!((s.min - h(0.6)).abs() < 1e-12, "{} vs {}", s.min, h(0.6));
    assert!(s.coverage > 0.1);
    // Its tensor form collapses a side onto a corner, where the sampled
    // curvature is not the surface's: the reason for native tessellation.
    let q = render(&[Panel::new(t.to_tensor())], &opts).unwrap();
    let s = &q.panels[0];
    assert!(s.singular > 0 || s.max > 1.0 + 1e-6 || s.min < h(0.6) - 1e-6);
}

#[test]
fn rendering_is_deterministic() {
    let opts = RenderOptions::default()
        .with_size(240, 180)
        .with_control_net(true);
    let panel = Panel::new(bump()).with_title("bump");
    let a = render(std::slice::from_ref(&panel), &opts).unwrap();
    let b = render(&[panel], &opts).unwrap();
    assert!(a.rgba == b.rgba);
}

#[test]
fn zebra_stripes_split_a_curved_surface_into_dark_and_light() {
    let opts = plain(300, 300).with_zebra(Some(12));
    let pic = render(&[Panel::new(bump())], &opts).unwrap();
    let lum: Vec<u32> = pic
        .rgba
        .chunks(4)
        .map(|p| (p[0] as u32 + p[1] as u32 + p[2] as u32) / 3)
        .collect();
    let dark = lum.iter().filter(|&&l| l < 40).count() as f64;
    let covered = pic.panels[0].coverage * (300 * 300) as f64;
    let frac = dark / covered;
    assert!((0.2..0.8).contains(&frac), "dark fraction {frac}");
}

#[test]
fn isophotes_band_a_curved_surface_and_leave_a_plane_one_colour() {
    let opts = plain(300, 300).with_isophotes(Some(12));
    let dark_fraction = |p: TensorPatch| {
        let pic = render(&[Panel::new(p)], &opts).unwrap();
        let dark = pic
            .rgba
            .chunks(4)
            .filter(|p| (p[0] as u32 + p[1] as u32 + p[2] as u32) / 3 < 40)
            .count() as f64;
        dark / (pic.panels[0].coverage * (300 * 300) as f64)
    };
    let f = dark_fraction(bump());
    assert!((0.2..0.8).contains(&f), "bump: dark fraction {f}");
    // A plane has one normal: one band, all dark or all light.
    let f = dark_fraction(square(1.0));
    assert!(!(0.02..0.98).contains(&f), "plane: dark fraction {f}");
}

#[test]
fn bad_input_is_an_error_naming_what() {
    let p = [Panel::new(bump())];
    let name = |e: Error| match e {
        Error::Option { name, .. } => name,
        e => panic!("{e}"),
    };
    assert_eq!(name(render(&p, &plain(8, 100)).unwrap_err()), "width");
    assert_eq!(name(render(&p, &plain(100, 9000)).unwrap_err()), "height");
    assert_eq!(
        name(render(&p, &plain(100, 100).with_resolution(1)).unwrap_err()),
        "resolution"
    );
    assert_eq!(
        name(render(&p, &plain(100, 100).with_zebra(Some(0))).unwrap_err()),
        "zebra"
    );
    let both = plain(100, 100).with_zebra(Some(4)).with_isophotes(Some(4));
    assert_eq!(name(render(&p, &both).unwrap_err()), "isophotes");
    let bad_range = plain(100, 100).with_range(Range::Fixed(1.0, 1.0));
    assert_eq!(name(render(&p, &bad_range).unwrap_err()), "range");
    let bad_view = plain(100, 100).with_view(View {
        azimuth: 0.0,
        elevation: 91.0,
    });
    assert_eq!(name(render(&p, &bad_view).unwrap_err()), "view");
    assert!(matches!(
        render(&[], &plain(100, 100)),
        Err(Error::NoPanels)
    ));
    let empty = Panel::default();
    assert!(matches!(
        render(&[Panel::new(bump()), empty], &plain(100, 100)),
        Err(Error::EmptyPanel { panel: 1 })
    ));
}

#[test]
fn options_parse_and_name_their_errors() {
    assert_eq!(ColourBy::parse("abs-mean").unwrap(), ColourBy::AbsMean);
    assert_eq!(ColourBy::parse("Gaussian").unwrap(), ColourBy::Gaussian);
    assert_eq!(Range::parse("0,1").unwrap(), Range::Fixed(0.0, 1.0));
    assert_eq!(Range::parse("auto").unwrap(), Range::Auto);
    assert_eq!(View::parse("top").unwrap(), View::TOP);
    assert_eq!(
        View::parse("30,-10").unwrap(),
        View {
            azimuth: 30.0,
            elevation: -10.0
        }
    );
    for (r, name) in [
        (ColourBy::parse("hue").map(|_| ()), "colour"),
        (Range::parse("1,0").map(|_| ()), "range"),
        (Range::parse("0,nan").map(|_| ()), "range"),
        (View::parse("up").map(|_| ()), "view"),
        (View::parse("0,100").map(|_| ()), "view"),
    ] {
        assert!(matches!(r, Err(Error::Option { name: n, .. }) if n == name));
    }
}

/// Golden images: small pictures compared with a tolerance (mean absolute
/// channel difference ≤ 1.5 and at most 0.5% of pixels off by more than 48),
/// so that harmless floating-point differences pass and a changed picture fails.
fn golden(name: &str, panels: &[Panel], opts: &RenderOptions) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(format!("{name}.png"));
    let pic = render(panels, opts).unwrap();
    if std::env::var_os("FAIRSURF_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        let mut f = std::fs::File::create(&path).unwrap();
        pic.encode_png(&mut f).unwrap();
        return;
    }
    let file = std::fs::File::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (bless with FAIRSURF_BLESS=1)", path.display()));
    let mut dec = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; dec.output_buffer_size().unwrap()];
    let info = dec.next_frame(&mut buf).unwrap();
    assert_eq!(
        (info.width, info.height),
        (pic.width, pic.height),
        "{name}: size"
    );
    assert_eq!(info.color_type, png::ColorType::Rgba);
    let diffs: Vec<u32> = buf
        .chunks(4)
        .zip(pic.rgba.chunks(4))
        .map(|(a, b)| (0..3).map(|c| a[c].abs_diff(b[c]) as u32).max().unwrap())
        .collect();
    let mean = diffs.iter().sum::<u32>() as f64 / diffs.len() as f64;
    let off = diffs.iter().filter(|&&d| d > 48).count() as f64 / diffs.len() as f64;
    assert!(
        mean <= 1.5 && off <= 0.005,
        "{name}: mean difference {mean:.3}, {:.3}% of pixels off",
        100.0 * off
    );
}

#[test]
fn golden_bump_with_net_arrows_and_abs_mean() {
    let b = bump();
    let arrows = [(0.5, 0.5), (0.25, 0.25), (0.75, 0.25)]
        .iter()
        .map(|&(u, v)| Arrow {
            base: b.eval(u, v),
            direction: b.normal(u, v).unwrap(),
        })
        .collect();
    let panel = Panel {
        patches: vec![b],
        title: Some("bump".into()),
        arrows,
        ..Panel::default()
    };
    let opts = RenderOptions::default()
        .with_size(240, 180)
        .with_control_net(true)
        .with_range(Range::Fixed(0.0, 3.0));
    golden("bump_abs_mean", &[panel], &opts);
}

#[test]
fn golden_two_panels_zebra_and_gaussian() {
    let saddle = TensorPatch::from_fn(3, 3, |i, j| {
        let (u, v) = (i as f64 / 3.0 - 0.5, j as f64 / 3.0 - 0.5);
        [u, v, 2.0 * u * v]
    });
    let zebra = RenderOptions::default()
        .with_size(240, 120)
        .with_colour(ColourBy::None)
        .with_zebra(Some(10));
    golden(
        "zebra_pair",
        &[Panel::new(bump()), Panel::new(saddle.clone())],
        &zebra,
    );
    let gauss = RenderOptions::default()
        .with_size(200, 150)
        .with_colour(ColourBy::Gaussian)
        .with_view(View::parse("20,50").unwrap());
    golden("saddle_gaussian", &[Panel::new(saddle)], &gauss);
}
