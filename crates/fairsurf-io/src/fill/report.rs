//! Which holes a fill job fills (`--list`, `--hole`, the default), and what
//! it reports: per fill its size, sides, corners, W and solve, and the
//! surfaces written.

use super::*;
use fairsurf::fill::{largest_angle, other_seconds, Candidate};

/// The holes of a set of faces and which of them to fill.
#[derive(Clone, Debug)]
pub struct HoleChoice {
    /// Every hole, longest first.
    pub holes: Vec<Hole>,
    /// The indices to fill.
    pub chosen: Vec<usize>,
    /// The indices taken for outer rims (not filled unless asked): each
    /// open sheet's, and the loops that are not clearly holes (a pipe's
    /// ends).
    pub rims: Vec<usize>,
}

impl HoleChoice {
    /// The holes of `faces`; `asked` (indices) or, without it, every hole
    /// but the outer rims: the loops that bound their faces from outside
    /// ([`fairsurf::fill::Hole::bounds_from_outside`]; a closed shell's
    /// holes do not) — one per open sheet — and, beside other loops,
    /// those whose sense is unclear (a pipe's ends and a dome's rim run
    /// across their faces' normals; an interior hole whose sense is
    /// unclear is left too, and named a rim; a lone loop of unclear sense
    /// is a hole). When every loop is a rim (a sheet without holes, a
    /// file whose holes are all filled) none is chosen, and
    /// [`Self::fill`] says so.
    /// Errors: no hole, an index out of range (named as `holes[k]`).
    pub fn new(faces: &[BSplineSurface], asked: Option<&[usize]>) -> Result<HoleChoice> {
        Self::within(faces, asked, tolerance(faces))
    }

    /// [`new`](Self::new) for a read input (its stand-ins' tolerance).
    /// To fill the holes chosen, take [`FillInput::choose`], which also
    /// makes the stand-ins along a fan's sides one span each: without it a
    /// fan is cut at every knot of a stand-in (the rounded box's corners,
    /// `examples/cad/rounded_box.step`: fans of twelve patches, 1.2 s a
    /// corner against 35 ms).
    pub fn of(input: &FillInput, asked: Option<&[usize]>) -> Result<HoleChoice> {
        Self::where_(&input.faces, asked, input.hole_tolerance(), |k, e| {
            input.is_boundary(k, e)
        })
    }

    /// [`new`](Self::new) with boundary points within `tol` taken as one.
    pub fn within(
        faces: &[BSplineSurface],
        asked: Option<&[usize]>,
        tol: f64,
    ) -> Result<HoleChoice> {
        Self::where_(faces, asked, tol, |_, _| true)
    }

    /// [`within`](Self::within) over the boundaries that are edges of the
    /// model ([`fairsurf::fill::find_holes_where`]).
    fn where_(
        faces: &[BSplineSurface],
        asked: Option<&[usize]>,
        tol: f64,
        is_boundary: impl Fn(usize, Edge) -> bool,
    ) -> Result<HoleChoice> {
        let holes = find_holes_where(faces, tol, is_boundary)?;
        if holes.is_empty() {
            return Err(Error::Solve(fairsurf::Error::Fill {
                why: "there is no hole: every face boundary is shared by two faces".into(),
            }));
        }
        // The outer rims of open sheets: the loops that bound their faces
        // from outside (none on a closed shell with holes), and, beside
        // other loops, those whose sense is unclear (a pipe's ends, a
        // dome's rim: their faces run across the loop's area); a lone loop
        // of unclear sense is a hole (a sharp box without a face: its
        // sides meet the opening at right angles). Every loop may be a rim
        // (a sheet, a file whose holes are all filled): then none is
        // chosen.
        let n = holes.len();
        let rims: Vec<usize> = (0..n)
            .filter(|&k| match holes[k].bounds_from_outside(faces) {
                Some(outside) => outside,
                None => n > 1,
            })
            .collect();
        let chosen = match asked {
            Some(a) => {
                for (k, &h) in a.iter().enumerate() {
                    if h >= holes.len() {
                        return Err(Error::scene(
                            format!("holes[{k}]"),
                            format!(
                                "there is no hole {h}: the faces have {} (0 to {})",
                                holes.len(),
                                holes.len() - 1
                            ),
                        ));
                    }
                }
                // Each hole once, in the order first asked.
                let mut c: Vec<usize> = Vec::new();
                for &h in a {
                    if !c.contains(&h) {
                        c.push(h);
                    }
                }
                c
            }
            None => (0..n).filter(|h| !rims.contains(h)).collect(),
        };
        Ok(HoleChoice {
            holes,
            chosen,
            rims,
        })
    }

    /// Fills the chosen holes: one patch for 4 sides, a fan of triangular
    /// patches otherwise. Errors when none is chosen and every loop is a
    /// rim (nothing asked for and nothing left: a file whose holes are all
    /// filled); none asked for otherwise is no fill. Errors too when a
    /// chosen hole's loop and another bound one ring, either inside the
    /// other ([`fairsurf::fill::Hole::ring_with`]).
    pub fn fill(&self, faces: &[BSplineSurface], options: &FillOptions) -> Result<Vec<HoleFill>> {
        if self.chosen.is_empty() && !self.holes.is_empty() && self.rims.len() == self.holes.len() {
            let rims: Vec<String> = self.rims.iter().map(usize::to_string).collect();
            return Err(Error::Solve(fairsurf::Error::Fill {
                why: format!(
                    "no hole to fill: every free loop is taken for an outer rim (hole{} {}: \
                     loops that bound their faces from outside or run across their normals, \
                     as a pipe's ends); asked for by its index, one is filled",
                    if rims.len() == 1 { "" } else { "s" },
                    rims.join(", ")
                ),
            }));
        }
        // A loop inside another, the missing face leaving each towards the
        // other: it is a ring between them, which no fill of one loop
        // makes — a disc over the outer loop would cover the inner loop's
        // faces (a fillet round a boss left out: a disc through the boss,
        // the boss left open).
        for &h in &self.chosen {
            let ring = (0..self.holes.len()).filter(|&j| j != h).find_map(|j| {
                let (outer, inner) = (&self.holes[h], &self.holes[j]);
                let height = outer
                    .ring_with(faces, inner)
                    .or_else(|| inner.ring_with(faces, outer))?;
                Some((j, height))
            });
            if let Some((j, height)) = ring {
                return Err(Error::Solve(fairsurf::Error::Fill {
                    why: format!(
                        "hole {h}: the missing face is a ring between its loop and hole {j}'s \
                         (one inside the other seen along the outer's normal, {height:.3e} from \
                         its plane, the missing face leaving each loop towards the other); a \
                         fill of one loop does not make it (it would cover the inner loop's \
                         faces)"
                    ),
                }));
            }
        }
        self.chosen
            .iter()
            .map(|&h| {
                HoleFill::new(faces, &self.holes[h], options).map_err(|e| match e {
                    fairsurf::Error::Fill { why } => fairsurf::Error::Fill {
                        why: format!("hole {h}: {why}"),
                    },
                    e => e,
                })
            })
            .collect::<fairsurf::Result<_>>()
            .map_err(Error::Solve)
    }

    /// The `--list` table: index, sides, length, faces, and whether it is
    /// filled by default.
    pub fn list_json(&self) -> Value {
        Value::Array(
            self.holes
                .iter()
                .enumerate()
                .map(|(k, h)| {
                    json!({
                        "index": k,
                        "sides": h.sides.len(),
                        "length": h.length,
                        "faces": h.faces(),
                        "rim": self.rims.contains(&k),
                        "chosen": self.chosen.contains(&k),
                    })
                })
                .collect(),
        )
    }
}

pub(crate) fn edge_name(e: Edge) -> &'static str {
    match e {
        Edge::U0 => "u0",
        Edge::U1 => "u1",
        Edge::V0 => "v0",
        Edge::V1 => "v1",
    }
}

/// One side's fit as JSON, `face` the neighbour's index in the output.
pub(crate) fn side_json(f: &SideFit, face: usize) -> Value {
    json!({
        "face": face,
        "edge": edge_name(f.side.edge),
        "reversed": f.side.reversed,
        "range": f.side.range,
        "gap": f.gap,
        "angle_deg": f.angle.to_degrees(),
        "samples": f.samples,
        "singular": f.singular,
        "exact": f.exact,
    })
}

/// The fields a fill and a blend report alike: size, sides, corners, W,
/// the solve and the time.
pub(crate) fn patch_json(
    surface: &BSplineSurface,
    sides: Vec<Value>,
    fits: &[SideFit],
    corners: &CornerMismatch,
    curvature: &TotalCurvature,
    willmore: &[f64],
    normal_weight: f64,
    s: &fairsurf::SolveReport,
    seconds: &FillSeconds,
) -> Value {
    let (ku, kv) = surface.knots();
    json!({
        "degree": surface.degree(),
        "control_points": surface.counts(),
        "spans": [ku.spans().len(), kv.spans().len()],
        "sides": sides,
        "max_gap": fits.iter().map(|f| f.gap).fold(0.0, f64::max),
        "max_angle_deg": largest_angle(fits).to_degrees(),
        "corners": {
            "position": corners.position,
            "tangent": corners.tangent,
            "twist": corners.twist,
        },
        "curvature_w": curvature.value,
        "curvature_w_error": curvature.error,
        "willmore_w": willmore,
        "normal_weight": normal_weight,
        "solve": crate::result::report_json(s),
        "seconds": {
            "setup": seconds.setup,
            "solve": seconds.solve,
            "measure": seconds.measure,
            "total": seconds.total(),
        },
    })
}

/// One fill's report (`"kind"`: `"patch"` or `"fan"`): the surface's
/// size, per side the gap and normal angle measured on it, the corner
/// mismatches, W, the solve's figures and the time.
pub fn fill_json(hole: usize, fill: &HoleFill) -> Value {
    match fill {
        HoleFill::Patch(f) => patch_fill_json(hole, f),
        HoleFill::Fan(f) => fan_fill_json(hole, f),
    }
}

/// A fan's report (one triangular patch for a 3-sided hole when that is
/// fairer: `"patches": 1`): as a patch's, with the fan's own G¹ (the largest
/// normal angle between its patches, the conditions kept and dropped) and
/// the triangular solve's check.
pub(super) fn fan_fill_json(hole: usize, fan: &FanFill) -> Value {
    let r = &fan.report;
    let s = &r.solve;
    let sides: Vec<Value> = r.sides.iter().map(|f| side_json(f, f.side.face)).collect();
    json!({
        "hole": hole,
        "kind": "fan",
        "patches": fan.surface.patch_count(),
        "degree": fan.surface.degree(),
        "control_points": fan.surface.point_count(),
        "sides": sides,
        "max_gap": r.sides.iter().map(|f| f.gap).fold(0.0, f64::max),
        "max_angle_deg": largest_angle(&r.sides).to_degrees(),
        "inner_angle_deg": r.inner_angle.to_degrees(),
        "corners": {
            "position": r.corners.position,
            "tangent": r.corners.tangent,
            "twist": r.corners.twist,
        },
        "curvature_w": r.curvature.value,
        "curvature_w_error": r.curvature.error,
        "willmore_w": r.willmore,
        "descent_note": r.descent_note,
        "solve": crate::tri_result::tri_report_json(s),
        "seconds": {
            "setup": r.seconds.setup,
            "solve": r.seconds.solve,
            "measure": r.seconds.measure,
            "other_candidates": other_seconds(&r.others),
            "total": r.seconds.total_with(&r.others),
        },
        "others": others_json(&r.others),
    })
}

/// The candidates tried and not kept: kind, and the largest normal angle
/// to the neighbours (degrees) with W, or the refusal; seconds.
fn others_json(others: &[Candidate]) -> Value {
    others
        .iter()
        .map(|c| match &c.outcome {
            Ok((angle, w)) => json!({
                "kind": c.kind,
                "max_angle_deg": angle.to_degrees(),
                "curvature_w": w,
                "seconds": c.seconds,
            }),
            Err(e) => json!({"kind": c.kind, "refused": e, "seconds": c.seconds}),
        })
        .collect()
}

/// A 4-sided fill's report.
pub(super) fn patch_fill_json(hole: usize, fill: &Fill) -> Value {
    let r = &fill.report;
    let sides = r.sides.iter().map(|f| side_json(f, f.side.face)).collect();
    let mut out = patch_json(
        &fill.surface,
        sides,
        &r.sides,
        &r.corners,
        &r.curvature,
        &r.willmore,
        r.normal_weight,
        &r.solve,
        &r.seconds,
    );
    out["hole"] = json!(hole);
    out["kind"] = json!("patch");
    out["alpha"] = json!(r.alpha);
    out["others"] = others_json(&r.others);
    out["seconds"]["other_candidates"] = json!(other_seconds(&r.others));
    out["seconds"]["total"] = json!(r.seconds.total_with(&r.others));
    out
}

/// The whole report of a fill job: the number of faces, every hole (as
/// `--list` gives them), each fill's report ([`fill_json`]) with the sides
/// measured beyond `tolerance` ([`sides_beyond`],
/// `sides_beyond_tolerances`), and the tolerances (`tolerances`: `gap`,
/// `angle_deg`).
pub fn fill_report_json(
    faces: usize,
    choice: &HoleChoice,
    fills: &[HoleFill],
    tolerance: FitTolerance,
) -> Value {
    json!({
        "faces": faces,
        "holes": choice.list_json(),
        "fills": choice
            .chosen
            .iter()
            .zip(fills)
            .map(|(&h, f)| {
                let mut out = fill_json(h, f);
                out["sides_beyond_tolerances"] = json!(sides_beyond(f, tolerance));
                out
            })
            .collect::<Vec<_>>(),
        "tolerances": {"gap": tolerance.position, "angle_deg": tolerance.angle.to_degrees()},
        "fairsurf_version": env!("CARGO_PKG_VERSION"),
    })
}

/// The sides (in the fill report's order: a fan's as cut into pieces)
/// where the fill was measured farther from its neighbour than `tolerance`
/// allows, in gap or in normal angle.
pub fn sides_beyond(fill: &HoleFill, tolerance: FitTolerance) -> Vec<usize> {
    fill.sides()
        .iter()
        .enumerate()
        .filter(|(_, s)| !(s.gap <= tolerance.position && s.angle <= tolerance.angle))
        .map(|(k, _)| k)
        .collect()
}

/// The input faces followed by the fills (a fan as its patches), for the
/// CAD writers; a face that stands in for a rational one (`rational`, per
/// face, as [`FillOptions::rational_faces`]) is written as that. (A read
/// input with trimmed faces: [`FillInput::surfaces`].)
pub fn fill_surfaces(
    faces: &[BSplineSurface],
    rational: &[Option<Arc<RationalSurface>>],
    fills: &[HoleFill],
) -> Vec<CadSurface> {
    let patches: Vec<BSplineSurface> = fills.iter().flat_map(HoleFill::patches).collect();
    let own =
        faces
            .iter()
            .enumerate()
            .map(|(k, f)| match rational.get(k).and_then(Option::as_deref) {
                Some(r) => CadSurface::from(r),
                None => CadSurface::from(f),
            });
    own.chain(patches.iter().map(CadSurface::from)).collect()
}
