//! What the CAD writers (STEP, IGES) share: which patches they accept, how
//! they write a real number, and the time stamp in their headers.

use crate::{write_atomic, Error, Result};
use fairsurf::bspline::BSplineSurface;
use fairsurf::{TensorPatch, Vec3};
use std::path::Path;

/// A surface as the CAD writers hold it: a polynomial B-spline with
/// clamped knots (a Bézier patch of degree (n, m) is the one with knots
/// 0ⁿ⁺¹ 1ⁿ⁺¹ × 0ᵐ⁺¹ 1ᵐ⁺¹), control points row-major with the u index i
/// first, as in [`TensorPatch`] and [`BSplineSurface`].
#[derive(Clone, Debug, PartialEq)]
pub struct CadSurface {
    /// (p, q).
    pub degree: (usize, usize),
    /// The full knot vectors in u and v.
    pub knots: [Vec<f64>; 2],
    /// Control points in u and in v.
    pub counts: (usize, usize),
    /// The control points, row-major.
    pub points: Vec<Vec3>,
    /// A rational surface's weights, row-major as the points (`None`: a
    /// polynomial one).
    pub weights: Option<Vec<f64>>,
    /// A trimmed face's loops, each a chain of curves that runs with the
    /// face on its left seen from the surface's normal R_u × R_v (written
    /// as FACE_BOUNDs); empty: the face is bounded by the surface's four
    /// sides.
    pub loops: Vec<Vec<CadCurve>>,
}

/// A polynomial B-spline curve as the CAD writers hold it.
#[derive(Clone, Debug, PartialEq)]
pub struct CadCurve {
    /// The degree.
    pub degree: usize,
    /// The full (clamped) knot vector.
    pub knots: Vec<f64>,
    /// The control points.
    pub points: Vec<Vec3>,
}

impl From<&TensorPatch> for CadSurface {
    fn from(p: &TensorPatch) -> Self {
        let (n, m) = p.degree();
        let clamped = |d: usize| {
            (0..2 * (d + 1))
                .map(|k| if k <= d { 0.0 } else { 1.0 })
                .collect()
        };
        Self {
            degree: (n, m),
            knots: [clamped(n), clamped(m)],
            counts: (n + 1, m + 1),
            points: p.points().to_vec(),
            weights: None,
            loops: Vec::new(),
        }
    }
}

impl From<&BSplineSurface> for CadSurface {
    fn from(s: &BSplineSurface) -> Self {
        let (u, v) = s.knots();
        Self {
            degree: s.degree(),
            knots: [u.knots().to_vec(), v.knots().to_vec()],
            counts: s.counts(),
            points: s.points().to_vec(),
            weights: None,
            loops: Vec::new(),
        }
    }
}

impl From<&fairsurf::bspline::RationalSurface> for CadSurface {
    fn from(r: &fairsurf::bspline::RationalSurface) -> Self {
        Self {
            weights: Some(r.weights().to_vec()),
            ..Self::from(r.net())
        }
    }
}

impl CadSurface {
    /// P_ij.
    pub fn point(&self, i: usize, j: usize) -> Vec3 {
        self.points[i * self.counts.1 + j]
    }

    /// w_ij (1 for a polynomial surface).
    pub fn weight(&self, i: usize, j: usize) -> f64 {
        self.weights
            .as_ref()
            .map_or(1.0, |w| w[i * self.counts.1 + j])
    }

    /// The distinct knots of direction `k` (0 = u) and their multiplicities.
    pub(crate) fn distinct_knots(&self, k: usize) -> (Vec<f64>, Vec<usize>) {
        distinct(&self.knots[k])
    }

    /// The parameter domain of direction `k`: [t_p, t_c].
    pub(crate) fn domain(&self, k: usize) -> (f64, f64) {
        let (p, c) = if k == 0 {
            (self.degree.0, self.counts.0)
        } else {
            (self.degree.1, self.counts.1)
        };
        (self.knots[k][p], self.knots[k][c])
    }
}

/// Distinct knots and their multiplicities.
pub(crate) fn distinct(knots: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let (mut values, mut mults) = (Vec::new(), Vec::<usize>::new());
    for &t in knots {
        match values.last() {
            Some(&last) if last == t => *mults.last_mut().expect("one per value") += 1,
            _ => {
                values.push(t);
                mults.push(1);
            }
        }
    }
    (values, mults)
}

/// Checks the surfaces, builds the file's text from its name and the
/// surfaces, and writes it atomically.
pub(crate) fn write_cad_text(
    path: &Path,
    patches: &[CadSurface],
    text: impl Fn(&str, &[CadSurface]) -> String,
) -> Result<()> {
    check_patches(path, patches)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let text = text(&name, patches);
    write_atomic(path, |w| w.write_all(text.as_bytes()))
}

/// A B-spline needs degree ≥ 1 and a shell needs a face: refuses anything else.
pub(crate) fn check_patches(path: &Path, patches: &[CadSurface]) -> Result<()> {
    let refuse = |message: String| {
        Err(Error::Export {
            path: path.to_path_buf(),
            message,
        })
    };
    if patches.is_empty() {
        return refuse("no patches to write".into());
    }
    if let Some(k) = patches
        .iter()
        .position(|p| p.degree.0 == 0 || p.degree.1 == 0)
    {
        let (n, m) = patches[k].degree;
        return refuse(format!(
            "patch {k} has degree ({n}, {m}); a B-spline surface needs degree ≥ 1 in u and v"
        ));
    }
    Ok(())
}

/// A finite real with every digit needed to read back the same `f64`
/// (the shortest round-trip form), always with a decimal point and an
/// upper-case `E` exponent: `0.1`, `-3.0`, `1.0E-7`, `1.5E16`. Both
/// ISO 10303-21 §6.3.3 and IGES 5.3 §2.2.2.3 accept this form.
pub(crate) fn real(x: f64) -> String {
    Real(x).to_string()
}

/// [`real`] as it is written into a text, without allocating.
#[derive(Clone, Copy)]
pub(crate) struct Real(pub f64);

impl std::fmt::Display for Real {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = self.0;
        debug_assert!(x.is_finite(), "patch coordinates are finite");
        let x = if x == 0.0 { 0.0 } else { x }; // no "-0.0"
        let mut buffer = ryu::Buffer::new();
        let s = buffer.format(x);
        match s.split_once('e') {
            Some((mantissa, exp)) if mantissa.contains('.') => write!(f, "{mantissa}E{exp}"),
            Some((mantissa, exp)) => write!(f, "{mantissa}.0E{exp}"),
            None => f.write_str(s),
        }
    }
}

/// The current UTC time as (year, month, day, hour, minute, second).
pub(crate) fn utc_now() -> [u32; 6] {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    let (y, mo, d) = civil_from_days(days);
    [
        y as u32,
        mo,
        d,
        (rem / 3600) as u32,
        (rem / 60 % 60) as u32,
        (rem % 60) as u32,
    ]
}

/// Proleptic Gregorian date of a day count since 1970-01-01 (Howard Hinnant,
/// "chrono-compatible low-level date algorithms", `civil_from_days`).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reals_round_trip_and_always_have_a_point() {
        for x in [
            0.0,
            -0.0,
            1.0,
            -3.0,
            0.1,
            1.0 / 3.0,
            1e-7,
            -2.5e-300,
            1.5e16,
            1e17,
            123456.789,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-5,
            1.2345678901234568e-5,
            -9.99e-5,
        ] {
            let s = real(x);
            assert!(s.contains('.'), "{s}");
            assert!(!s.contains('e') && s != "-0.0", "{s}");
            assert_eq!(s.parse::<f64>().unwrap(), x, "{s}");
        }
        assert_eq!(real(1e-7), "1.0E-7");
        assert_eq!(real(0.25), "0.25");
        // ryu's form: positional down to 1e-5 (Rust's `{:?}` changes to an
        // exponent below 1e-4: "5.0E-5" before session 37), an exponent
        // from 1e16.
        assert_eq!(real(5e-5), "0.00005");
        assert_eq!(real(1e16), "1.0E16");
    }

    #[test]
    fn civil_dates_match_known_days() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(19_723), (2024, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
    }
}
