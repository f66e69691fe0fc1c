//! A solved B-spline scene as a result file: every control point filled, the
//! free ones listed, and the report.

use super::*;

impl SolvedBSplineScene {
    /// The solved surface.
    pub fn surface(&self) -> &BSplineSurface {
        &self.solution.surface
    }

    /// The result as a scene: every control point filled, the free ones
    /// listed (unless `fixed_rings` says which), and the report.
    pub fn result_scene(&self) -> BSplineScene {
        let mut out = self.scene.clone();
        let s = self.surface();
        let cv = s.counts().1;
        // A refined solve's result holds the refined degrees, knots and net.
        out.refine = None;
        out.surface.degree = [s.degree().0, s.degree().1];
        out.surface.knots = [s.knots().0.knots().to_vec(), s.knots().1.knots().to_vec()];
        if let Some(g) = out.energy.guide_surface.as_mut() {
            // A guide on its own knots or degree stays as given.
            let own = g.knots.is_some() || g.degree.is_some();
            if !own && (self.scene.refine.is_some() || g.control_points.is_none()) {
                // The guide as solved: on the (refined) knots.
                g.control_points = Some(
                    self.guide_points
                        .chunks(cv)
                        .map(|row| row.iter().map(|p| Some(p.to_vec())).collect())
                        .collect(),
                );
            }
        }
        out.surface.control_points = s
            .points()
            .chunks(cv)
            .map(|row| row.iter().map(|p| Some(p.to_vec())).collect())
            .collect();
        if out.fixed_rings.is_none() {
            out.free_points = Some(
                self.free
                    .iter()
                    .enumerate()
                    .filter(|(_, &f)| f)
                    .map(|(k, _)| [k / cv, k % cv])
                    .collect(),
            );
        }
        out.report = Some(self.report_json());
        out
    }

    /// What the result's reader should know: a fold.
    pub fn notes(&self) -> Vec<String> {
        self.normal_turn
            .filter(|t| t.is_fold())
            .map(|t| {
                format!(
                    "the surface folds: its normal turns by {:.1}° between neighbouring samples \
                     near (u, v) = ({:.3}, {:.3})",
                    t.angle.to_degrees(),
                    t.at.0,
                    t.at.1
                )
            })
            .into_iter()
            .collect()
    }

    /// The `"report"` object: the report of every tensor kind
    /// ([`crate::result::report_json`]) with the spans, the largest normal
    /// turn and the notes.
    pub fn report_json(&self) -> Value {
        let mut o = crate::result::report_json(&self.solution.report);
        let (ku, kv) = self.surface().knots();
        o["spans"] = json!([ku.spans().len(), kv.spans().len()]);
        o["max_normal_turn_deg"] = json!(self.normal_turn.map(|t| {
            crate::result::normal_turn_json(t.angle, json!([t.at.0, t.at.1]), t.is_fold())
        }));
        o["notes"] = json!(self.notes());
        o
    }
}
