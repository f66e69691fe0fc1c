//! The handles of a scene's operator or constraint entry: points,
//! directions and planes the editor drags (`editor/API.md`,
//! `handles[].edit`).

use super::{vec3, Edit, Handle};
use fairsurf::vector::{add, dot, normalize, scale};
use fairsurf::Vec3;
use serde_json::Value;

/// An entry of the scene (an operator or a constraint) whose fields become
/// handles (see `editor/API.md`, `handles[].edit`).
pub(super) struct Field<'a> {
    /// The entry's JSON pointer (`/operators/2`).
    pub(super) prefix: String,
    pub(super) entry: &'a Value,
    /// Its name, or `operator 2`.
    pub(super) label: String,
    /// `operator` or `control_point` (the handle's colour).
    pub(super) kind: &'static str,
}

impl<'a> Field<'a> {
    /// The entries of the scene's list `list` (`operators`,
    /// `constraints`), unnamed ones called `noun k`.
    pub(super) fn entries(
        scene: &'a Value,
        list: &'static str,
        noun: &'static str,
    ) -> impl Iterator<Item = Field<'a>> {
        let kind = if list == "operators" {
            "operator"
        } else {
            "control_point"
        };
        scene[list]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate()
            .map(move |(k, entry)| Field {
                prefix: format!("/{list}/{k}"),
                entry,
                label: entry["name"]
                    .as_str()
                    .map_or(format!("{noun} {k}"), str::to_string),
                kind,
            })
    }

    pub(super) fn handle(&self, field: &str, position: Vec3, edit: Option<Edit>) -> Handle {
        Handle {
            edit,
            ..Handle::point(
                format!("{}/{field}", self.prefix),
                position,
                format!("{}: {field}", self.label),
                self.kind,
            )
        }
    }

    /// The point `field`: the handle is where the value is.
    pub(super) fn point(&self, handles: &mut Vec<Handle>, field: &str) {
        if let Some(p) = vec3(&self.entry[field]) {
            handles.push(self.handle(field, p, None));
        }
    }

    /// The direction `field`, drawn `length` from `anchor` along it.
    pub(super) fn direction(
        &self,
        handles: &mut Vec<Handle>,
        field: &str,
        anchor: Option<Vec3>,
        length: f64,
    ) {
        if let Some(h) = self.direction_handle(field, anchor, length, None) {
            handles.push(h);
        }
    }

    fn direction_handle(
        &self,
        field: &str,
        anchor: Option<Vec3>,
        length: f64,
        offset: Option<String>,
    ) -> Option<Handle> {
        let (anchor, d) = (anchor?, normalize(vec3(&self.entry[field])?)?);
        Some(self.handle(
            field,
            add(anchor, scale(d, length)),
            Some(Edit::Direction {
                anchor,
                length,
                offset,
            }),
        ))
    }

    /// The plane `normal`·x = `offset` as seen from the surface point `at`:
    /// a handle at the foot of `at` on the plane that moves the plane along
    /// its normal, and one for the normal that turns the plane about that
    /// foot.
    pub(super) fn plane(&self, handles: &mut Vec<Handle>, at: Option<Vec3>, length: f64) {
        let (Some(s), Some(n), Some(a)) = (
            at,
            vec3(&self.entry["normal"]),
            self.entry["offset"].as_f64(),
        ) else {
            return;
        };
        let nn = dot(n, n);
        if !(nn > 0.0 && nn.is_finite()) {
            return;
        }
        let foot = add(s, scale(n, (a - dot(n, s)) / nn));
        handles.push(self.handle(
            "offset",
            foot,
            Some(Edit::Offset {
                anchor: s,
                normal: n,
            }),
        ));
        let offset = Some(format!("{}/offset", self.prefix));
        if let Some(h) = self.direction_handle("normal", Some(foot), length, offset) {
            handles.push(h);
        }
    }
}
