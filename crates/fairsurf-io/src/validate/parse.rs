//! The parsers every scene kind shares, each error naming its JSON path:
//! weights, control nets (null for free points), patches, rational weights,
//! the free-point mask from `fixed_rings` / `free_points`, sampling grids.

use super::*;

pub(crate) fn check_weight(path: &str, w: f64) -> Result<()> {
    if !w.is_finite() {
        return Err(Error::scene(
            path,
            format!("expected a finite number, got {w}"),
        ));
    }
    if w < 0.0 {
        return Err(Error::scene(
            path,
            format!("expected a weight ≥ 0, got {w}"),
        ));
    }
    Ok(())
}

/// Rows × columns of points `[x, y, z]` (or null where allowed), row-major.
pub(crate) fn parse_net(
    net: &Net,
    path: &str,
    (n, m): (usize, usize),
    allow_null: bool,
) -> Result<Vec<Option<Vec3>>> {
    if net.len() != n + 1 {
        return Err(Error::scene(
            path,
            format!("expected {} rows, got {}", n + 1, net.len()),
        ));
    }
    let mut out = Vec::with_capacity((n + 1) * (m + 1));
    for (i, row) in net.iter().enumerate() {
        if row.len() != m + 1 {
            return Err(Error::scene(
                format!("{path}[{i}]"),
                format!("expected {} points, got {}", m + 1, row.len()),
            ));
        }
        for (j, p) in row.iter().enumerate() {
            let here = || format!("{path}[{i}][{j}]");
            match p {
                None if allow_null => out.push(None),
                None => return Err(Error::scene(here(), "expected 3 numbers, got null")),
                Some(c) if c.len() != 3 => {
                    return Err(Error::scene(
                        here(),
                        format!("expected 3 numbers, got {}", c.len()),
                    ))
                }
                Some(c) => {
                    if let Some(k) = c.iter().position(|x| !x.is_finite()) {
                        return Err(Error::scene(
                            format!("{}[{k}]", here()),
                            "expected a finite number",
                        ));
                    }
                    if let Some(k) = c.iter().position(|x| x.abs() > MAX_COORDINATE) {
                        return Err(Error::scene(
                            format!("{}[{k}]", here()),
                            format!(
                                "{:e} is too large: coordinates must be at most {MAX_COORDINATE:e} \
                                 in magnitude (energies square them; scale the scene)",
                                c[k]
                            ),
                        ));
                    }
                    out.push(Some([c[0], c[1], c[2]]));
                }
            }
        }
    }
    Ok(out)
}

/// A complete net whose degree is given or read off its shape.
/// The Bézier field N of `energy.normal_field`; a field that is zero
/// everywhere is an error (it gives no direction).
pub(crate) fn normal_field_patch(net: &Net, degree: Option<[usize; 2]>) -> Result<TensorPatch> {
    let patch = parse_patch(net, degree, "energy.normal_field")?;
    if patch.points().iter().flatten().all(|&x| x == 0.0) {
        return Err(Error::scene(
            "energy.normal_field.control_points",
            "the field is zero everywhere and gives no direction: give the normals N to follow",
        ));
    }
    Ok(patch)
}

pub(super) fn parse_patch(
    net: &Net,
    degree: Option<[usize; 2]>,
    path: &str,
) -> Result<TensorPatch> {
    let cp = format!("{path}.control_points");
    let [n, m] = match degree {
        Some(d) => d,
        None => {
            let rows = net.len();
            let cols = net.first().map_or(0, Vec::len);
            if rows == 0 || cols == 0 {
                return Err(Error::scene(
                    cp,
                    "expected at least one row of at least one point",
                ));
            }
            [rows - 1, cols - 1]
        }
    };
    if n > MAX_DEGREE || m > MAX_DEGREE {
        return Err(Error::scene(
            format!("{path}.degree"),
            format!("expected degrees ≤ {MAX_DEGREE}, got [{n}, {m}]"),
        ));
    }
    let pts = parse_net(net, &cp, (n, m), false)?;
    Ok(TensorPatch::new(
        n,
        m,
        pts.into_iter().map(|p| p.expect("no null")).collect(),
    ))
}

/// Per-sample weights: one number or a (np+1)×(mp+1) grid, each finite ≥ 0.
pub(super) fn parse_weights(
    w: Option<&NumberOrGrid>,
    path: &str,
    (np, mp): (usize, usize),
) -> Result<Option<Vec<f64>>> {
    match w {
        None => Ok(None),
        Some(NumberOrGrid::Number(x)) => {
            check_weight(path, *x)?;
            Ok(Some(vec![*x; (np + 1) * (mp + 1)]))
        }
        Some(NumberOrGrid::Grid(rows)) => {
            if rows.len() != np + 1 {
                return Err(Error::scene(
                    path,
                    format!("expected {} rows (grid[0] + 1), got {}", np + 1, rows.len()),
                ));
            }
            let mut out = Vec::with_capacity((np + 1) * (mp + 1));
            for (i, row) in rows.iter().enumerate() {
                if row.len() != mp + 1 {
                    return Err(Error::scene(
                        format!("{path}[{i}]"),
                        format!(
                            "expected {} numbers (grid[1] + 1), got {}",
                            mp + 1,
                            row.len()
                        ),
                    ));
                }
                for (j, &x) in row.iter().enumerate() {
                    check_weight(&format!("{path}[{i}][{j}]"), x)?;
                    out.push(x);
                }
            }
            Ok(Some(out))
        }
    }
}

/// Which points of a `rows × cols` net are free: the outer `fixed_rings`
/// fixed and the rest free, or the null ones and `free_points`. Errors
/// name the path; `shape` ends the message for too many rings ("degree
/// [n, m]: both degrees must be at least" and 2k follows).
pub(crate) fn free_mask(
    fixed_rings: Option<usize>,
    free_points: Option<&[[usize; 2]]>,
    given: &[Option<Vec3>],
    (rows, cols): (usize, usize),
    shape: &str,
) -> Result<Vec<bool>> {
    let at = |k: usize| (k / cols, k % cols);
    let mut free: Vec<bool> = given.iter().map(Option::is_none).collect();
    if let Some(k) = fixed_rings {
        if k == 0 {
            return Err(Error::scene(
                "fixed_rings",
                "expected k ≥ 1 (omit fixed_rings to fix exactly the given points)",
            ));
        }
        if free_points.is_some() {
            return Err(Error::scene(
                "free_points",
                "cannot be combined with fixed_rings",
            ));
        }
        if rows <= 2 * k || cols <= 2 * k {
            return Err(Error::scene(
                "fixed_rings",
                format!(
                    "{k} fixed ring(s) leave no free control point at {shape} {}",
                    2 * k
                ),
            ));
        }
        for (q, f) in free.iter_mut().enumerate() {
            let (i, j) = at(q);
            let ring = i.min(j).min(rows - 1 - i).min(cols - 1 - j);
            *f = ring >= k;
            if !*f && given[q].is_none() {
                return Err(Error::scene(
                    format!("surface.control_points[{i}][{j}]"),
                    format!("is null but lies in the {k} fixed ring(s); give its value"),
                ));
            }
        }
    }
    for (q, &[i, j]) in free_points.into_iter().flatten().enumerate() {
        if i >= rows || j >= cols {
            return Err(Error::scene(
                format!("free_points[{q}]"),
                format!("[{i}, {j}] is outside the {rows} × {cols} net"),
            ));
        }
        free[i * cols + j] = true;
    }
    if !free.contains(&true) {
        return Err(Error::scene(
            "surface.control_points",
            "no free control point: mark free points with null, list them in free_points, or set fixed_rings",
        ));
    }
    Ok(free)
}

/// The sample grid of `energy.sampling`, each count 1 to [`MAX_GRID`].
pub(crate) fn sample_grid(sampling: Option<&crate::SamplingSpec>) -> Result<Option<SampleGrid>> {
    let Some(s) = sampling else {
        return Ok(None);
    };
    for (k, d) in s.grid.into_iter().enumerate() {
        if d == 0 || d > MAX_GRID {
            return Err(Error::scene(
                format!("energy.sampling.grid[{k}]"),
                format!("expected 1 to {MAX_GRID}, got {d}"),
            ));
        }
    }
    Ok(Some(SampleGrid::new(s.grid[0], s.grid[1])))
}
