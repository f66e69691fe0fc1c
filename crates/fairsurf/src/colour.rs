//! Colour maps for scalar fields on surfaces (curvature, deviation), shared by
//! the picture renderer and the mesh writers so a glTF file and a PNG of the
//! same surface agree.
//!
//! ```
//! use fairsurf::colour::ColourMap;
//! let [r, g, b] = ColourMap::Viridis.at(1.0);
//! assert!(r > 0.9 && g > 0.85 && b < 0.2); // viridis ends in yellow
//! ```

/// A map from t ∈ [0, 1] to linear-ish RGB in [0, 1]³. Values outside [0, 1]
/// are clamped; NaN maps to [`ColourMap::NAN`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourMap {
    /// Sequential, perceptually uniform (matplotlib's viridis): for
    /// non-negative quantities such as |H| (Monterde & Ugail 2004, Fig. 8–9).
    Viridis,
    /// Diverging blue–grey–red (Moreland's cool-warm): for signed quantities
    /// such as H or K, with 0 in the middle of a symmetric range.
    CoolWarm,
}

impl ColourMap {
    /// The colour of samples with no value (a singular point of the surface).
    pub const NAN: [f32; 3] = [0.55, 0.55, 0.55];

    /// The colour at t (clamped to [0, 1]).
    pub fn at(self, t: f64) -> [f32; 3] {
        if t.is_nan() {
            return Self::NAN;
        }
        let t = t.clamp(0.0, 1.0);
        match self {
            ColourMap::Viridis => viridis(t),
            ColourMap::CoolWarm => cool_warm(t),
        }
    }
}

/// Viridis by its degree-6 polynomial fit (Matt Zucker's fit of matplotlib's
/// table; max error ≈ 0.01 per channel).
fn viridis(t: f64) -> [f32; 3] {
    const C: [[f64; 3]; 7] = [
        [
            0.277_727_327_223_417_7,
            0.005_407_344_544_966_578,
            0.334_099_805_335_306_1,
        ],
        [
            0.105_093_043_108_577_4,
            1.404_613_529_898_575,
            1.384_590_162_594_685,
        ],
        [
            -0.330_861_828_725_556_3,
            0.214_847_559_468_213,
            0.095_095_163_028_236_59,
        ],
        [
            -4.634_230_498_983_486,
            -5.799_100_973_351_585,
            -19.332_440_956_279_87,
        ],
        [
            6.228_269_936_347_081,
            14.179_933_366_805_09,
            56.690_552_600_681_05,
        ],
        [
            4.776_384_997_670_288,
            -13.745_145_377_746_01,
            -65.353_032_633_372_34,
        ],
        [
            -5.435_455_855_934_631,
            4.645_852_612_178_535,
            26.312_435_249_583_2,
        ],
    ];
    std::array::from_fn(|c| {
        let v = C.iter().rev().fold(0.0, |acc, k| acc * t + k[c]);
        v.clamp(0.0, 1.0) as f32
    })
}

/// Moreland's cool-warm map, piecewise linear through five of its table's
/// colours (t = 0, ¼, ½, ¾, 1).
fn cool_warm(t: f64) -> [f32; 3] {
    const K: [[f64; 3]; 5] = [
        [0.2298, 0.2987, 0.7537],
        [0.5543, 0.6901, 0.9955],
        [0.8650, 0.8650, 0.8650],
        [0.9567, 0.5980, 0.4773],
        [0.7057, 0.0156, 0.1502],
    ];
    let x = t * 4.0;
    let i = (x.floor() as usize).min(3);
    let f = x - i as f64;
    std::array::from_fn(|c| (K[i][c] * (1.0 - f) + K[i + 1][c] * f) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_match_matplotlib() {
        // matplotlib's table: viridis(0) = (0.267, 0.005, 0.329), viridis(1) = (0.993, 0.906, 0.144).
        let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 0.015);
        assert!(close(ColourMap::Viridis.at(0.0), [0.267, 0.005, 0.329]));
        assert!(close(ColourMap::Viridis.at(1.0), [0.993, 0.906, 0.144]));
        assert!(close(ColourMap::Viridis.at(0.5), [0.128, 0.567, 0.551]));
    }

    #[test]
    fn cool_warm_is_symmetric_in_lightness_and_grey_in_the_middle() {
        assert_eq!(ColourMap::CoolWarm.at(0.5), [0.865, 0.865, 0.865]);
        assert_eq!(ColourMap::CoolWarm.at(-3.0), ColourMap::CoolWarm.at(0.0));
        assert_eq!(ColourMap::CoolWarm.at(f64::NAN), ColourMap::NAN);
    }
}
