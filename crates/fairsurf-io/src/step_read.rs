//! Reading STEP files (ISO 10303-21) for `fill`: the faces of every shell
//! (OPEN_SHELL, CLOSED_SHELL, in whichever representation holds them), by
//! the `truck-stepio` crate (ruststep's parser). The faces must be B-spline
//! surfaces (`B_SPLINE_SURFACE_WITH_KNOTS`, `BEZIER_SURFACE`, … or a
//! rational one whose weights are all equal) bounded by their own four
//! sides: every other face is refused by name, nothing is dropped silently.

use crate::{Error, Result};
use fairsurf::bspline::{BSplineSurface, KnotVector};
use fairsurf::Vec3;
use truck_stepio::r#in::alias::Surface as StepSurface;
use truck_stepio::r#in::Table;

/// The error for a STEP file's content (as a scene error with the entity
/// or face as its path).
fn bad(path: impl Into<String>, message: impl Into<String>) -> Error {
    Error::scene(path, message)
}

/// The B-spline and Bézier faces of every shell in a STEP file's text, in
/// the order of the shells' entity numbers and their faces in each.
///
/// Errors name what is wrong: not STEP (with the parser's message), no
/// shell, a face that is not a B-spline surface (a plane, cylinder, …), a
/// rational face with unequal weights, a face whose boundary is not its
/// surface's four sides (trimmed), a face the reader could not convert.
pub fn read_step_faces(text: &str) -> Result<Vec<BSplineSurface>> {
    let exchange = ruststep::parser::parse(text).map_err(|e| {
        bad(
            "",
            format!("not a STEP file (ISO 10303-21) this reader can parse: {e}"),
        )
    })?;
    let Some(data) = exchange.data.first() else {
        return Err(bad("", "the STEP file has no DATA section"));
    };
    let table = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        Table::from_data_section(data)
    }))
    .map_err(|_| bad("", "the STEP reader (truck-stepio) failed on this file"))?;
    let mut shells: Vec<_> = table.shell.iter().collect();
    if shells.is_empty() {
        return Err(bad(
            "",
            "no shell (OPEN_SHELL or CLOSED_SHELL) in the STEP file: fill reads the faces of shells",
        ));
    }
    shells.sort_by_key(|(id, _)| **id);
    let mut faces = Vec::new();
    for (id, shell) in shells {
        let compressed = table
            .to_compressed_shell(shell)
            .map_err(|e| bad(format!("#{id}"), format!("cannot read the shell: {e}")))?;
        if compressed.faces.len() != shell.cfs_faces.len() {
            return Err(bad(
                format!("#{id}"),
                format!(
                    "the shell has {} faces and the reader converted {}: some face's surface is \
                     of a kind it does not read",
                    shell.cfs_faces.len(),
                    compressed.faces.len()
                ),
            ));
        }
        for (k, face) in compressed.faces.iter().enumerate() {
            let path = format!("#{id} face {k}");
            let surface = surface(&face.surface).map_err(|m| bad(&path, m))?;
            // The face is its whole surface: one boundary loop whose
            // vertices are all corners of the surface.
            if face.boundaries.len() != 1 {
                return Err(bad(
                    &path,
                    format!(
                        "the face has {} boundary loops: faces with holes in them are not filled \
                         around yet",
                        face.boundaries.len()
                    ),
                ));
            }
            let corners = corner_points(&surface);
            let tol = fairsurf::fill::tolerance(std::slice::from_ref(&surface));
            for e in &face.boundaries[0] {
                let edge = &compressed.edges[e.index];
                for v in [edge.vertices.0, edge.vertices.1] {
                    let p = compressed.vertices[v];
                    let p = [p.x, p.y, p.z];
                    if !corners.iter().any(|c| dist(*c, p) <= tol) {
                        return Err(bad(
                            &path,
                            format!(
                                "the face is trimmed: its boundary has a vertex at ({}, {}, {}) \
                                 that is not a corner of its surface; trimmed faces are not \
                                 filled around yet",
                                p[0], p[1], p[2]
                            ),
                        ));
                    }
                }
            }
            faces.push(surface);
        }
    }
    Ok(faces)
}

fn dist(a: Vec3, b: Vec3) -> f64 {
    fairsurf::vector::norm(fairsurf::vector::sub(a, b))
}

/// The four corner points of a surface.
fn corner_points(s: &BSplineSurface) -> [Vec3; 4] {
    let (cu, cv) = s.counts();
    [
        s.point(0, 0),
        s.point(cu - 1, 0),
        s.point(0, cv - 1),
        s.point(cu - 1, cv - 1),
    ]
}

/// A STEP face's surface as a B-spline, or why not.
fn surface(s: &StepSurface) -> std::result::Result<BSplineSurface, String> {
    type Net = Vec<Vec<Vec3>>;
    let (knots, points): ((Vec<f64>, Vec<f64>), Net) = match s {
        StepSurface::BSplineSurface(b) => (
            (b.uknot_vec().to_vec(), b.vknot_vec().to_vec()),
            b.control_points()
                .iter()
                .map(|row| row.iter().map(|p| [p.x, p.y, p.z]).collect())
                .collect(),
        ),
        StepSurface::NurbsSurface(n) => {
            let b = n.non_rationalized();
            let w0 = b.control_points()[0][0].w;
            let equal = b
                .control_points()
                .iter()
                .flatten()
                .all(|p| (p.w - w0).abs() <= 1e-12 * w0.abs());
            if !equal || w0 == 0.0 {
                return Err(
                    "a rational B-spline face with unequal weights: only polynomial faces are \
                     filled around so far"
                        .into(),
                );
            }
            (
                (b.uknot_vec().to_vec(), b.vknot_vec().to_vec()),
                b.control_points()
                    .iter()
                    .map(|row| {
                        row.iter()
                            .map(|p| [p.x / p.w, p.y / p.w, p.z / p.w])
                            .collect()
                    })
                    .collect(),
            )
        }
        StepSurface::ElementarySurface(_) => return Err(
            "an elementary surface (plane, cylinder, cone, sphere or torus): only B-spline and \
                 Bézier faces are filled around so far"
                .into(),
        ),
        StepSurface::SweptCurve(_) => {
            return Err(
                "a swept surface (extrusion or revolution): only B-spline and Bézier faces are \
                 filled around so far"
                    .into(),
            )
        }
    };
    let (cu, cv) = (points.len(), points.first().map_or(0, Vec::len));
    if cu < 2 || cv < 2 || points.iter().any(|r| r.len() != cv) {
        return Err(format!(
            "a control net of {cu} rows that are not all {cv} long"
        ));
    }
    let (p, q) = (
        knots.0.len().saturating_sub(cu + 1),
        knots.1.len().saturating_sub(cv + 1),
    );
    let kv = |d: usize, k: Vec<f64>, name: &str| {
        KnotVector::new(d, k).map_err(|e| format!("its {name} knots: {e}"))
    };
    let u = kv(p, knots.0, "u")?;
    let v = kv(q, knots.1, "v")?;
    BSplineSurface::new(u, v, points.into_iter().flatten().collect()).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::CadSurface;
    use fairsurf::TensorPatch;

    /// fairsurf's own STEP output reads back with the same surfaces.
    #[test]
    fn a_written_shell_reads_back() {
        let a = TensorPatch::from_fn(3, 2, |i, j| [i as f64, j as f64, 0.1 * (i * j) as f64]);
        let b = TensorPatch::from_fn(3, 2, |i, j| {
            [3.0 + i as f64, j as f64, 0.3 * (i * j) as f64]
        });
        let s = BSplineSurface::new(
            KnotVector::new(3, vec![0., 0., 0., 0., 0.5, 1., 1., 1., 1.]).unwrap(),
            KnotVector::bezier(2),
            (0..15)
                .map(|k| [(k / 3) as f64, (k % 3) as f64, -1.0])
                .collect(),
        )
        .unwrap();
        let surfaces: Vec<CadSurface> = vec![(&a).into(), (&b).into(), (&s).into()];
        let text = crate::step::step_text("x.step", &surfaces);
        let faces = read_step_faces(&text).unwrap();
        assert_eq!(faces.len(), 3);
        assert_eq!(faces[0], BSplineSurface::from_bezier(&a));
        assert_eq!(faces[1], BSplineSurface::from_bezier(&b));
        assert_eq!(faces[2], s);
    }

    #[test]
    fn what_is_not_read_is_said() {
        let e = read_step_faces("not a step file").unwrap_err().to_string();
        assert!(e.contains("not a STEP file"), "{e}");
        let a = TensorPatch::from_fn(1, 1, |i, j| [i as f64, j as f64, 0.0]);
        let text = crate::step::step_text("x.step", &[(&a).into()]);
        let e = read_step_faces(&text.replace("OPEN_SHELL", "OPEN_SHELF"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no shell"), "{e}");
        // The surface made a plane through the file's own placement.
        let axes = text
            .lines()
            .find(|l| l.contains("=AXIS2_PLACEMENT_3D("))
            .and_then(|l| l.split('=').next())
            .unwrap();
        let plane: String = text
            .lines()
            .map(|l| match l.split_once("=B_SPLINE_SURFACE_WITH_KNOTS(") {
                Some((id, _)) => format!("{id}=PLANE('',{axes});\n"),
                None => format!("{l}\n"),
            })
            .collect();
        let e = read_step_faces(&plane).unwrap_err().to_string();
        assert!(e.contains("an elementary surface (plane"), "{e}");
    }
}
