//! Headless pictures of fairsurf surfaces: shaded with exact normals,
//! coloured by mean, Gaussian or absolute mean curvature with a colour bar,
//! with control nets, boundary curves, arrows (normal fields), reflection-line
//! (zebra) stripes, any view, and several surfaces side by side.
//!
//! Rasterization is euc (a CPU rasterizer with a depth buffer, supersampled
//! for anti-aliasing), overlays and text are tiny-skia and pre-rasterized
//! Noto Sans Mono; no GPU or window system is needed.
//!
//! ```
//! use fairsurf::TensorPatch;
//! use fairsurf_render::{render, ColourBy, Panel, Range, RenderOptions, View};
//! let bump = TensorPatch::from_fn(3, 3, |i, j| {
//!     let z = if (1..=2).contains(&i) && (1..=2).contains(&j) { 0.4 } else { 0.0 };
//!     [i as f64 / 3.0, j as f64 / 3.0, z]
//! });
//! let opts = RenderOptions::default()
//!     .with_size(240, 180)
//!     .with_colour(ColourBy::AbsMean)
//!     .with_range(Range::Fixed(0.0, 1.0))
//!     .with_view(View::ISO);
//! let picture = render(&[Panel::new(bump).with_title("bump")], &opts).unwrap();
//! let mut png = Vec::new();
//! picture.encode_png(&mut png).unwrap();
//! assert_eq!(&png[1..4], b"PNG");
//! ```

mod camera;
mod error;
mod options;
mod overlay;
mod picture;
mod raster;

pub use error::{Error, Result};
pub use options::{ColourBy, Range, RenderOptions, View};
pub use picture::{render, Arrow, Panel, PanelStats, Picture};
