//! Orthographic camera: a view direction, and framing that fits a set of
//! points into a viewport with a margin.

use crate::View;
use fairsurf::vector::{dot, sub};
use fairsurf::Vec3;

/// An orthonormal camera frame and the map from world points to viewport
/// pixels (x right, y down) and depth.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Camera {
    /// Screen right in world coordinates.
    pub right: Vec3,
    /// Screen up in world coordinates.
    pub up: Vec3,
    /// Direction of sight (from the eye into the scene).
    pub forward: Vec3,
    /// World point at the viewport centre.
    pub centre: Vec3,
    /// Pixels per world unit.
    pub scale: f64,
    /// Depth range [near, far] along `forward`, relative to `centre`.
    pub depth: (f64, f64),
    /// Viewport size in pixels.
    pub size: (f64, f64),
}

/// The camera frame for a view: (right, up, forward).
pub(crate) fn frame(view: View) -> (Vec3, Vec3, Vec3) {
    let (az, el) = (view.azimuth.to_radians(), view.elevation.to_radians());
    let eye = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
    let forward = [-eye[0], -eye[1], -eye[2]];
    // right = forward × z normalized, up = right × forward, in closed form so
    // that looking straight down or up (cos el = 0) needs no special case.
    let right = [-az.sin(), az.cos(), 0.0];
    let up = [-el.sin() * az.cos(), -el.sin() * az.sin(), el.cos()];
    (right, up, forward)
}

impl Camera {
    /// Frames `points` into a viewport of `size` pixels, leaving `margin`
    /// (a fraction of the smaller side) free around them.
    pub fn fit(view: View, points: &[Vec3], size: (f64, f64), margin: f64) -> Camera {
        let (right, up, forward) = frame(view);
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in points {
            let q = [dot(*p, right), dot(*p, up), dot(*p, forward)];
            for k in 0..3 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        if points.is_empty() {
            (lo, hi) = ([-1.0; 3], [1.0; 3]);
        }
        let mid = |k: usize| 0.5 * (lo[k] + hi[k]);
        let centre = [0, 1, 2].iter().fold([0.0; 3], |c, &k| {
            let axis = [right, up, forward][k];
            [
                c[0] + mid(k) * axis[0],
                c[1] + mid(k) * axis[1],
                c[2] + mid(k) * axis[2],
            ]
        });
        let (w, h) = ((hi[0] - lo[0]).max(1e-12), (hi[1] - lo[1]).max(1e-12));
        let usable = (size.0 - 2.0 * margin * size.0.min(size.1)).max(1.0);
        let usable_h = (size.1 - 2.0 * margin * size.0.min(size.1)).max(1.0);
        let scale = (usable / w).min(usable_h / h);
        let half_depth = (0.5 * (hi[2] - lo[2])).max(1e-9) * 1.05;
        Camera {
            right,
            up,
            forward,
            centre,
            scale,
            depth: (-half_depth, half_depth),
            size,
        }
    }

    /// Pixel coordinates (x right, y down, origin top left of the viewport)
    /// and depth in [0, 1] (0 nearest).
    pub fn project(&self, p: Vec3) -> (f64, f64, f64) {
        let d = sub(p, self.centre);
        let x = 0.5 * self.size.0 + self.scale * dot(d, self.right);
        let y = 0.5 * self.size.1 - self.scale * dot(d, self.up);
        let (near, far) = self.depth;
        let z = (dot(d, self.forward) - near) / (far - near);
        (x, y, z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fairsurf::vector::cross;

    fn close(a: Vec3, b: Vec3) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    #[test]
    fn frames_are_right_handed_and_presets_point_where_named() {
        for v in [View::ISO, View::TOP, View::FRONT, View::SIDE] {
            let (r, u, f) = frame(v);
            assert!(close(cross(r, u), [-f[0], -f[1], -f[2]]), "{v:?}");
        }
        let (r, u, f) = frame(View::TOP);
        assert!(
            close(r, [1.0, 0.0, 0.0]) && close(u, [0.0, 1.0, 0.0]),
            "{r:?} {u:?}"
        );
        assert!(close(f, [0.0, 0.0, -1.0]));
        let (r, u, _) = frame(View::FRONT);
        assert!(close(r, [1.0, 0.0, 0.0]) && close(u, [0.0, 0.0, 1.0]));
        let (r, u, _) = frame(View::SIDE);
        assert!(close(r, [0.0, 1.0, 0.0]) && close(u, [0.0, 0.0, 1.0]));
    }

    #[test]
    fn fit_centres_and_fills_the_viewport() {
        let pts = [[0.0, 0.0, 0.0], [2.0, 1.0, 0.0]];
        let cam = Camera::fit(View::TOP, &pts, (400.0, 400.0), 0.05);
        let (x0, y0, _) = cam.project(pts[0]);
        let (x1, y1, _) = cam.project(pts[1]);
        assert!((x0 - 20.0).abs() < 1e-9 && (x1 - 380.0).abs() < 1e-9);
        assert!((0.5 * (y0 + y1) - 200.0).abs() < 1e-9 && y1 < y0);
    }
}
