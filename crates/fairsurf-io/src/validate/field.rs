//! A scene's normal field: a Bézier patch or a B-spline on its own knots,
//! given as control points or sampled, into the library's `NormalField`.

use super::*;

/// A normal field as a scene gives it: a Bézier patch, or a B-spline on
/// its own knots (B-spline scenes).
pub(super) enum Field {
    Bezier(TensorPatch),
    Spline(fairsurf::bspline::BSplineSurface),
}

impl Field {
    /// N at (u, v) of [0, 1]² (a B-spline's domain mapped onto it).
    pub(super) fn eval01(&self, u: f64, v: f64) -> Vec3 {
        match self {
            Field::Bezier(p) => p.eval(u, v),
            Field::Spline(s) => fairsurf::ParamSurface::eval_unit(s, u, v),
        }
    }
}

/// The normal-field term of `energy.normal_field` and `energy.sampling`
/// (the same rules for every surface kind): a Bézier field — or `spline`,
/// a B-spline scene's field on its own knots (its net already read from
/// the spec) — integrated exactly without sampling; with sampling, its
/// normals at the samples or `normal_samples`, and `normal_weights`.
/// Errors name the JSON path.
pub(crate) fn normal_field_term(
    normal_field: Option<&crate::NormalFieldSpec>,
    spline: Option<fairsurf::bspline::BSplineSurface>,
    sampling: Option<&crate::SamplingSpec>,
    grid: Option<SampleGrid>,
) -> Result<Option<NormalField>> {
    let field = match normal_field {
        Some(f) => {
            check_weight("energy.normal_field.weight", f.weight)?;
            match (&f.control_points, spline) {
                (_, Some(s)) => Some((f.weight, Some(Field::Spline(s)))),
                (Some(cp), None) => Some((f.weight, Some(Field::Bezier(normal_field_patch(cp, f.degree)?)))),
                (None, None) if sampling.is_some_and(|s| s.normal_samples.is_some()) => {
                    Some((f.weight, None))
                }
                (None, None) => {
                    return Err(Error::scene(
                        "energy.normal_field.control_points",
                        "required (the Bézier field N), unless energy.sampling.normal_samples gives the normals",
                    ))
                }
            }
        }
        None if sampling.is_some_and(|s| s.normal_samples.is_some()) => Some((1.0, None)),
        None => None,
    };
    if let (None, Some(s)) = (&field, sampling) {
        if s.normal_weights.is_some() {
            return Err(Error::scene(
                "energy.sampling.normal_weights",
                "needs energy.normal_field or energy.sampling.normal_samples",
            ));
        }
    }
    let Some((weight, patch)) = field else {
        return Ok(None);
    };
    let Some(g) = grid else {
        return Ok(Some(
            match patch.expect("without sampling the field has control points") {
                Field::Bezier(p) => NormalField::new(weight, p),
                Field::Spline(s) => NormalField::spline(weight, s),
            },
        ));
    };
    let s = sampling.expect("grid comes from sampling");
    let (np, mp) = g.size();
    let normals: Vec<Vec3> = match &s.normal_samples {
        Some(ns) => {
            let pts = parse_net(ns, "energy.sampling.normal_samples", (np, mp), false)?;
            pts.into_iter()
                .enumerate()
                .map(|(k, p)| {
                    let p = p.expect("no null");
                    if fairsurf::vector::norm(p) == 0.0 {
                        return Err(Error::scene(
                            format!(
                                "energy.sampling.normal_samples[{}][{}]",
                                k / (mp + 1),
                                k % (mp + 1)
                            ),
                            "is the zero vector and has no direction",
                        ));
                    }
                    Ok(p)
                })
                .collect::<Result<_>>()?
        }
        None => {
            let f = patch.expect("field given when samples are not");
            (0..g.len())
                .map(|k| {
                    let (u, v) = g.param(k);
                    let p = f.eval01(u, v);
                    if fairsurf::vector::normalize(p).is_none() {
                        return Err(Error::scene(
                            "energy.normal_field.control_points",
                            format!("N vanishes at sample (u, v) = ({u}, {v}), so it has no direction there"),
                        ));
                    }
                    Ok(p)
                })
                .collect::<Result<_>>()?
        }
    };
    let weights = parse_weights(
        s.normal_weights.as_ref(),
        "energy.sampling.normal_weights",
        (np, mp),
    )?;
    Ok(Some(NormalField::sampled(weight, g, normals, weights)))
}
