//! What to draw and how: colouring, range, view, overlays.

use crate::{Error, Result};

/// The scalar that colours the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ColourBy {
    /// One neutral colour; shading only.
    None,
    /// Mean curvature H = (k₁ + k₂)/2 (signed, cool-warm map).
    Mean,
    /// Gaussian curvature K = k₁ k₂ (signed, cool-warm map).
    Gaussian,
    /// Absolute mean curvature |H| (viridis), as in Monterde & Ugail 2004, Fig. 8–9.
    #[default]
    AbsMean,
}

impl ColourBy {
    /// Parses `none`, `mean`, `gaussian`, `abs-mean` (also `abs_mean`, `|H|`).
    pub fn parse(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "none" => Ok(ColourBy::None),
            "mean" | "h" => Ok(ColourBy::Mean),
            "gaussian" | "k" => Ok(ColourBy::Gaussian),
            "abs-mean" | "abs_mean" | "absmean" | "|h|" => Ok(ColourBy::AbsMean),
            _ => Err(Error::Option {
                name: "colour",
                message: format!("expected none, mean, gaussian or abs-mean, got {s:?}"),
            }),
        }
    }

    /// The colour bar's title.
    pub fn label(self) -> &'static str {
        match self {
            ColourBy::None => "",
            ColourBy::Mean => "mean curvature H",
            ColourBy::Gaussian => "Gaussian curvature K",
            ColourBy::AbsMean => "|H|",
        }
    }

    /// Whether the quantity is signed (diverging map, symmetric automatic range).
    pub fn is_signed(self) -> bool {
        matches!(self, ColourBy::Mean | ColourBy::Gaussian)
    }
}

/// The value range the colour map spans; values outside are clamped to its ends.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Range {
    /// From the samples of all panels together: [0, q₉₉] for |H|, [−a, a] with
    /// a = q₉₉(|x|) for signed quantities (q₉₉: the 99th percentile, so a
    /// singular point does not wash out the picture).
    #[default]
    Auto,
    /// Given ends, e.g. [0, 1] as in Monterde & Ugail's figures.
    Fixed(f64, f64),
}

impl Range {
    /// Parses `auto` or `LO,HI` with finite LO < HI.
    pub fn parse(s: &str) -> Result<Self> {
        if s.eq_ignore_ascii_case("auto") {
            return Ok(Range::Auto);
        }
        let bad = |m: String| Error::Option {
            name: "range",
            message: m,
        };
        let (lo, hi) = pair(s, "range", "auto or LO,HI")?;
        if lo >= hi {
            return Err(bad(format!("expected LO < HI, got {lo},{hi}")));
        }
        Ok(Range::Fixed(lo, hi))
    }
}

/// Two finite numbers "A,B"; errors name the option and what it expects.
fn pair(s: &str, name: &'static str, expected: &str) -> Result<(f64, f64)> {
    let bad = |message: String| Error::Option { name, message };
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| bad(format!("expected {expected}, got {s:?}")))?;
    let num = |x: &str| {
        x.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(format!("expected a finite number, got {x:?}")))
    };
    Ok((num(a)?, num(b)?))
}

/// The direction the surface is seen from, as azimuth (degrees about +z,
/// from +x) and elevation (degrees above the xy-plane) of the eye. The
/// projection is orthographic, z is up on screen unless looking along z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Azimuth of the eye in degrees.
    pub azimuth: f64,
    /// Elevation of the eye in degrees, in [−90, 90].
    pub elevation: f64,
}

impl Default for View {
    fn default() -> Self {
        View::ISO
    }
}

impl View {
    /// Isometric: from (1, −1, 1)-ish, front right and above.
    pub const ISO: View = View {
        azimuth: -50.0,
        elevation: 32.0,
    };
    /// From +z, looking down; x right, y up on screen.
    pub const TOP: View = View {
        azimuth: -90.0,
        elevation: 90.0,
    };
    /// From −y; x right, z up.
    pub const FRONT: View = View {
        azimuth: -90.0,
        elevation: 0.0,
    };
    /// From +x; y right, z up.
    pub const SIDE: View = View {
        azimuth: 0.0,
        elevation: 0.0,
    };

    /// Parses `iso`, `top`, `front`, `side` or `AZ,EL` in degrees.
    pub fn parse(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "iso" => return Ok(View::ISO),
            "top" => return Ok(View::TOP),
            "front" => return Ok(View::FRONT),
            "side" => return Ok(View::SIDE),
            _ => {}
        }
        let bad = |m: String| Error::Option {
            name: "view",
            message: m,
        };
        let (azimuth, elevation) = pair(s, "view", "iso, top, front, side or AZ,EL in degrees")?;
        if !(-90.0..=90.0).contains(&elevation) {
            return Err(bad(format!(
                "elevation must be in [-90, 90] degrees, got {elevation}"
            )));
        }
        Ok(View { azimuth, elevation })
    }
}

/// Everything about a picture but the surfaces.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels (16 … 8192).
    pub width: u32,
    /// Image height in pixels (16 … 8192).
    pub height: u32,
    /// Surface colouring.
    pub colour: ColourBy,
    /// Colour range.
    pub range: Range,
    /// Viewing direction.
    pub view: View,
    /// Draw the control net (polygon and points).
    pub control_net: bool,
    /// Draw the patches' boundary curves.
    pub boundary: bool,
    /// Draw the panels' arrows (e.g. a guide normal field).
    pub arrows: bool,
    /// Reflection-line (zebra) stripes: this many stripes over the half-sphere of
    /// reflected directions, or none. Reflection lines break at a G1 kink and
    /// bend at a G2 jump.
    pub zebra: Option<u32>,
    /// Isophotes: this many bands of the angle between the normal and the
    /// key light, over [0, π]; curves of constant n·L. Like reflection lines
    /// they show G1 breaks as jumps and G2 breaks as kinks. Not together with
    /// `zebra`.
    pub isophotes: Option<u32>,
    /// Quads per patch parameter direction in the tessellation (2 … 1024).
    pub resolution: usize,
    /// Supersampling factor per axis for anti-aliasing (1 … 4).
    pub supersample: u32,
    /// Draw the colour bar (when colouring by a quantity).
    pub colour_bar: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 1200,
            height: 900,
            colour: ColourBy::AbsMean,
            range: Range::Auto,
            view: View::ISO,
            control_net: false,
            boundary: true,
            arrows: true,
            zebra: None,
            isophotes: None,
            resolution: 64,
            supersample: 2,
            colour_bar: true,
        }
    }
}

impl RenderOptions {
    /// Sets the image size.
    pub fn with_size(mut self, width: u32, height: u32) -> Self {
        self.width = width;
        self.height = height;
        self
    }
    /// Sets the colouring.
    pub fn with_colour(mut self, colour: ColourBy) -> Self {
        self.colour = colour;
        self
    }
    /// Sets the colour range.
    pub fn with_range(mut self, range: Range) -> Self {
        self.range = range;
        self
    }
    /// Sets the view.
    pub fn with_view(mut self, view: View) -> Self {
        self.view = view;
        self
    }
    /// Turns the control net on or off.
    pub fn with_control_net(mut self, on: bool) -> Self {
        self.control_net = on;
        self
    }
    /// Turns the boundary curves on or off.
    pub fn with_boundary(mut self, on: bool) -> Self {
        self.boundary = on;
        self
    }
    /// Sets zebra stripes.
    pub fn with_zebra(mut self, stripes: Option<u32>) -> Self {
        self.zebra = stripes;
        self
    }
    /// Sets isophote bands.
    pub fn with_isophotes(mut self, bands: Option<u32>) -> Self {
        self.isophotes = bands;
        self
    }
    /// Sets the tessellation resolution.
    pub fn with_resolution(mut self, resolution: usize) -> Self {
        self.resolution = resolution;
        self
    }

    /// Checks every field's range; the error names the field.
    pub fn validate(&self) -> Result<()> {
        let bad = |name: &'static str, message: String| Err(Error::Option { name, message });
        for (name, v) in [("width", self.width), ("height", self.height)] {
            if !(16..=8192).contains(&v) {
                return bad(name, format!("must be 16 … 8192 pixels, got {v}"));
            }
        }
        if !(2..=1024).contains(&self.resolution) {
            return bad(
                "resolution",
                format!("must be 2 … 1024, got {}", self.resolution),
            );
        }
        if !(1..=4).contains(&self.supersample) {
            return bad(
                "supersample",
                format!("must be 1 … 4, got {}", self.supersample),
            );
        }
        for (name, stripes) in [("zebra", self.zebra), ("isophotes", self.isophotes)] {
            if let Some(z) = stripes {
                if !(1..=200).contains(&z) {
                    return bad(name, format!("must be 1 … 200 stripes, got {z}"));
                }
            }
        }
        if self.zebra.is_some() && self.isophotes.is_some() {
            return bad(
                "isophotes",
                "draw either zebra stripes or isophotes, not both".into(),
            );
        }
        if let Range::Fixed(lo, hi) = self.range {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return bad("range", format!("expected finite LO < HI, got {lo},{hi}"));
            }
        }
        if !(-90.0..=90.0).contains(&self.view.elevation) || !self.view.azimuth.is_finite() {
            return bad(
                "view",
                format!(
                    "azimuth must be finite and elevation in [-90, 90], got {},{}",
                    self.view.azimuth, self.view.elevation
                ),
            );
        }
        Ok(())
    }
}
