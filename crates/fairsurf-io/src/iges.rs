//! IGES 5.3 (US PRO/IPO-100-1996): fixed 80-column Start, Global,
//! Directory Entry, Parameter Data and Terminate sections; each patch one
//! entity 128 (rational B-spline surface, §4.24).

use crate::cad::{real, utc_now, write_cad_text, CadSurface};
use crate::Result;
use fairsurf::TensorPatch;
use std::path::Path;

/// Writes tensor-product Bézier patches as an IGES 5.3 file, atomically:
/// the exact surfaces, for CAD.
///
/// Each patch of degree (n, m) is one independent entity 128 (form 0) with
/// K1 = M1 = n, K2 = M2 = m, polynomial (PROP3 = 1, all weights 1), open and
/// non-periodic, knots S = 0ⁿ⁺¹ 1ⁿ⁺¹ and T = 0ᵐ⁺¹ 1ᵐ⁺¹, parameter range
/// [0, 1]², control points in IGES order (the u index i fastest:
/// P_00, P_10, …, P_n0, P_01, …, P_nm, with u going with i as in
/// [`TensorPatch`]). The surfaces are untrimmed: their natural boundary is
/// the patch boundary. Units are millimetres; reals carry every digit of
/// the `f64`s. Triangular patches (when they exist) are not written here:
/// they go to meshes only.
///
/// Open CASCADE (and so FreeCAD, gmsh, …) reads B-splines of degree ≤ 25
/// only and silently drops a higher one (measured with gmsh 4.15); this
/// writer still writes any degree, the standard has no limit.
///
/// An empty list or a patch of degree 0 in u or v is an
/// [`Error::Export`](crate::Error::Export); nothing is written then.
///
/// ```
/// use fairsurf::TensorPatch;
/// let p = TensorPatch::from_fn(3, 2, |i, j| [i as f64, j as f64, (i * j) as f64 / 6.0]);
/// let dir = std::env::temp_dir().join(format!("fairsurf-doc-iges-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let path = dir.join("patch.igs");
/// fairsurf_io::write_iges(&path, &[p]).unwrap();
/// let text = std::fs::read_to_string(&path).unwrap();
/// assert!(text.lines().all(|l| l.len() == 80));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_iges(path: &Path, patches: &[TensorPatch]) -> Result<()> {
    let surfaces: Vec<CadSurface> = patches.iter().map(CadSurface::from).collect();
    write_iges_surfaces(path, &surfaces)
}

/// Writes B-spline surfaces as [`write_iges`] does: each one entity 128
/// with K1 = rows − 1, K2 = columns − 1, its degrees, its full knot vectors
/// and its parameter domain; a rational one with PROP3 = 0 and its weights.
/// A trimmed face ([`CadSurface::loops`]) is an [`Error::Export`](crate::Error::Export):
/// only STEP writes it.
pub fn write_iges_surfaces(path: &Path, surfaces: &[CadSurface]) -> Result<()> {
    if let Some(k) = surfaces.iter().position(|s| !s.loops.is_empty()) {
        return Err(crate::Error::Export {
            path: path.to_path_buf(),
            message: format!(
                "surface {k} is a trimmed face: IGES is written with untrimmed surfaces only \
                 (entity 128); write STEP"
            ),
        });
    }
    write_cad_text(path, surfaces, iges_text)
}

/// The whole file.
fn iges_text(file_name: &str, patches: &[CadSurface]) -> String {
    let mut out = String::new();
    let start = [
        "fairsurf: tensor-product Bezier patches as IGES entity 128",
        "(rational B-spline surfaces with unit weights).",
    ];
    for (k, line) in start.iter().enumerate() {
        out.push_str(&record(line, 'S', k + 1));
    }
    let global = global_section(file_name, patches);
    let g = global.len();
    for (k, line) in global.iter().enumerate() {
        out.push_str(&record(line, 'G', k + 1));
    }
    // Parameter data first (the directory needs its line numbers).
    let mut params = Vec::new();
    let mut directory = Vec::new();
    for (e, patch) in patches.iter().enumerate() {
        let de = 2 * e + 1;
        let lines = pack(&surface_128(patch), 64);
        let first = params.len() + 1;
        for line in &lines {
            params.push(format!("{line:<64} {de:>7}"));
        }
        directory.push(format!(
            "{:>8}{first:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            128, 0, 0, 0, 0, 0, 0, "00000000"
        ));
        directory.push(format!(
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            128,
            0,
            0,
            lines.len(),
            0,
            "",
            "",
            "PATCH",
            e + 1
        ));
    }
    for (k, line) in directory.iter().enumerate() {
        out.push_str(&record(line, 'D', k + 1));
    }
    for (k, line) in params.iter().enumerate() {
        out.push_str(&record(line, 'P', k + 1));
    }
    let counts = format!(
        "S{:>7}G{g:>7}D{:>7}P{:>7}",
        start.len(),
        directory.len(),
        params.len()
    );
    out.push_str(&record(&counts, 'T', 1));
    out
}

/// One 80-column line: 72 columns of data, the section letter, the
/// sequence number right-justified in 7.
fn record(data: &str, section: char, seq: usize) -> String {
    debug_assert!(data.len() <= 72, "{data}");
    format!("{data:<72}{section}{seq:>7}\n")
}

/// Tokens (each ending in its delimiter) packed into lines of at most
/// `width` columns, never splitting a token.
fn pack(tokens: &[String], width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for t in tokens {
        let line = lines.last_mut().expect("one line");
        if !line.is_empty() && line.len() + t.len() > width {
            lines.push(t.clone());
        } else {
            line.push_str(t);
        }
    }
    lines
}

/// Parameters with their delimiters: `,` between, `;` after the last.
fn delimited(params: Vec<String>) -> Vec<String> {
    let last = params.len().saturating_sub(1);
    params
        .into_iter()
        .enumerate()
        .map(|(k, p)| p + if k == last { ";" } else { "," })
        .collect()
}

/// A Hollerith string `nH…`, ASCII only (others become `_`).
fn hollerith(s: &str) -> String {
    let s: String = s
        .chars()
        .map(|c| if (' '..='~').contains(&c) { c } else { '_' })
        .collect();
    if s.is_empty() {
        String::new() // defaulted
    } else {
        format!("{}H{s}", s.len())
    }
}

/// The 26 global parameters of IGES 5.3 §2.2.4.3.
fn global_section(file_name: &str, patches: &[CadSurface]) -> Vec<String> {
    let [y, mo, d, h, mi, s] = utc_now();
    let stamp = hollerith(&format!("{y:04}{mo:02}{d:02}.{h:02}{mi:02}{s:02}"));
    let extent = patches
        .iter()
        .flat_map(|p| p.points.iter().flatten())
        .fold(0.0f64, |a, c| a.max(c.abs()));
    let me = format!("fairsurf {}", env!("CARGO_PKG_VERSION"));
    let params = vec![
        "1H,".to_string(),                                          // 1 parameter delimiter
        "1H;".to_string(),                                          // 2 record delimiter
        hollerith("fairsurf"),                                      // 3 product id (sender)
        hollerith(&file_name.chars().take(60).collect::<String>()), // 4 file name
        hollerith(&me),                                             // 5 native system
        hollerith(&me),                                             // 6 preprocessor version
        "32".to_string(),                                           // 7 integer bits
        "38".to_string(),      // 8 single precision: max power of ten
        "6".to_string(),       // 9 single precision: digits
        "308".to_string(),     // 10 double precision: max power of ten
        "15".to_string(),      // 11 double precision: digits
        hollerith("fairsurf"), // 12 product id (receiver)
        real(1.0),             // 13 model space scale
        "2".to_string(),       // 14 units flag: millimetres
        hollerith("MM"),       // 15 units name
        "1".to_string(),       // 16 line weight gradations
        real(1.0),             // 17 maximum line width
        stamp.clone(),         // 18 file generated
        real(1e-7),            // 19 minimum resolution
        real(extent),          // 20 maximum coordinate
        String::new(),         // 21 author
        String::new(),         // 22 organization
        "11".to_string(),      // 23 version: 5.3
        "0".to_string(),       // 24 drafting standard: none
        stamp,                 // 25 model created or changed
        String::new(),         // 26 application protocol
    ];
    pack(&delimited(params), 72)
}

/// Entity 128's parameters (§4.24), with delimiters.
fn surface_128(s: &CadSurface) -> Vec<String> {
    let ((n, m), (cu, cv)) = (s.degree, s.counts);
    let ints = |v: &[usize]| v.iter().map(|k| k.to_string()).collect::<Vec<_>>();
    // K1, K2, M1, M2, PROP1..PROP5 (not closed, polynomial unless there
    // are weights, not periodic).
    let polynomial = usize::from(s.weights.is_none());
    let mut p = ints(&[128, cu - 1, cv - 1, n, m, 0, 0, polynomial, 0, 0]);
    p.extend(s.knots[0].iter().map(|&t| real(t)));
    p.extend(s.knots[1].iter().map(|&t| real(t)));
    // Weights and points with the u index running fastest.
    for j in 0..cv {
        for i in 0..cu {
            p.push(real(s.weight(i, j)));
        }
    }
    for j in 0..cv {
        for i in 0..cu {
            p.extend(s.point(i, j).map(real));
        }
    }
    let ((u0, u1), (v0, v1)) = (s.domain(0), s.domain(1));
    p.extend([u0, u1, v0, v1].map(real));
    delimited(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sections_are_80_columns_and_the_terminate_line_counts_them() {
        let a = TensorPatch::from_fn(3, 4, |i, j| [i as f64 / 3.0, j as f64 / 4.0, 0.1]);
        let b = TensorPatch::from_fn(1, 2, |i, j| [1.0 + i as f64, j as f64 / 3.0, -0.7]);
        let text = iges_text("two.igs", &[(&a).into(), (&b).into()]);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines.iter().all(|l| l.len() == 80 && l.is_ascii()));
        let count = |c: char| lines.iter().filter(|l| l.as_bytes()[72] == c as u8).count();
        let t = lines.last().unwrap();
        assert_eq!(
            &t[..32],
            format!(
                "S{:>7}G{:>7}D{:>7}P{:>7}",
                count('S'),
                count('G'),
                count('D'),
                count('P')
            )
        );
        assert_eq!(count('D'), 4);
        // Each directory entry points to its first parameter line, and every
        // parameter line points back to its directory entry.
        let d: Vec<&str> = lines
            .iter()
            .copied()
            .filter(|l| &l[72..73] == "D")
            .collect();
        let p: Vec<&str> = lines
            .iter()
            .copied()
            .filter(|l| &l[72..73] == "P")
            .collect();
        for e in 0..2 {
            let first: usize = d[2 * e][8..16].trim().parse().unwrap();
            let n_lines: usize = d[2 * e + 1][24..32].trim().parse().unwrap();
            assert!(p[first - 1].starts_with("128,"));
            assert!(p[first + n_lines - 2][..64].trim_end().ends_with(';'));
            for line in &p[first - 1..first - 1 + n_lines] {
                assert_eq!(line[65..72].trim(), (2 * e + 1).to_string());
            }
        }
    }

    #[test]
    fn parameters_of_a_bilinear_patch_are_in_iges_order() {
        let patch = TensorPatch::from_fn(1, 1, |i, j| [i as f64, j as f64, (10 * i + j) as f64]);
        let p = surface_128(&(&patch).into()).concat();
        assert_eq!(
            p,
            "128,1,1,1,1,0,0,1,0,0,0.0,0.0,1.0,1.0,0.0,0.0,1.0,1.0,1.0,1.0,1.0,1.0,\
             0.0,0.0,0.0,1.0,0.0,10.0,0.0,1.0,1.0,1.0,1.0,11.0,0.0,1.0,0.0,1.0;"
        );
    }
}
