//! Shaded triangles into a viewport with euc (a CPU rasterizer with a depth
//! buffer), supersampled and reduced to premultiplied RGBA.

use crate::camera::Camera;
use euc::buffer::Buffer2d;
use euc::rasterizer::{BackfaceCullingDisabled, Triangles};
use euc::{DepthStrategy, Pipeline};
use fairsurf::vector::{add, normalize, scale};
use fairsurf::Vec3;

/// A triangle soup with one unit normal and one base colour per vertex.
#[derive(Clone, Debug, Default)]
pub(crate) struct Soup {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub colours: Vec<[f32; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

/// A viewport's pixels: premultiplied RGBA in [0, 1], row-major, top row first.
pub(crate) struct Layer {
    pub width: usize,
    pub height: usize,
    pub rgba: Vec<[f32; 4]>,
    /// Nearest depth in [0, 1] per pixel (1 where nothing was drawn).
    pub depth: Vec<f32>,
}

impl Layer {
    /// Fraction of pixels the surface covers (alpha summed / pixel count).
    pub fn coverage(&self) -> f64 {
        let a: f64 = self.rgba.iter().map(|p| p[3] as f64).sum();
        a / (self.width * self.height).max(1) as f64
    }

    /// Whether a point at pixel (x, y) with depth z is in front of (or on)
    /// the surface drawn in the layer. Lenient near silhouettes: compared
    /// with the farthest depth among the 3×3 neighbouring pixels, plus a
    /// tolerance of 1% of the panel's depth range.
    pub fn visible(&self, x: f64, y: f64, z: f64) -> bool {
        let (xi, yi) = (x.floor() as i64, y.floor() as i64);
        let mut far = f32::NEG_INFINITY;
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (px, py) = (xi + dx, yi + dy);
                if px < 0 || py < 0 || px >= self.width as i64 || py >= self.height as i64 {
                    return true;
                }
                far = far.max(self.depth[py as usize * self.width + px as usize]);
            }
        }
        z as f32 <= far + 0.01
    }
}

#[derive(Clone, Copy)]
struct Vertex {
    pos: [f32; 4],
    normal: (f32, f32, f32),
    colour: (f32, f32, f32),
}

/// Stripes painted instead of the base colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Stripes {
    /// Reflection lines (zebra): bands of the angle between the reflected
    /// line of sight and a fixed axis.
    Reflection(u32),
    /// Isophotes: bands of the angle between the normal and the key light.
    Isophote(u32),
}

/// Fragment shading: two-sided Lambert + Blinn–Phong under one key light,
/// optionally stripes.
struct Shader {
    light: [f32; 3],
    half: [f32; 3],
    view: [f32; 3],
    /// Stripe count, axis, and whether the reflected ray (zebra) or the
    /// normal (isophotes) is measured against the axis.
    stripes: Option<(f32, [f32; 3], bool)>,
}

fn dot3(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Pipeline for Shader {
    type Vertex = Vertex;
    type VsOut = ((f32, f32, f32), (f32, f32, f32));
    type Pixel = [f32; 4];

    fn vert(&self, v: &Vertex) -> ([f32; 4], Self::VsOut) {
        (v.pos, (v.normal, v.colour))
    }

    fn frag(&self, &((nx, ny, nz), (r, g, b)): &Self::VsOut) -> [f32; 4] {
        let len = (nx * nx + ny * ny + nz * nz).sqrt().max(1e-20);
        let mut n = [nx / len, ny / len, nz / len];
        // Two-sided: turn the normal towards the eye (against the view).
        if dot3(n, self.view) > 0.0 {
            n = [-n[0], -n[1], -n[2]];
        }
        let mut base = [r, g, b];
        if let Some((stripes, axis, reflect)) = self.stripes {
            // Zebra: reflect the line of sight about the normal and band the
            // angle between the reflected ray and a fixed axis. Isophotes:
            // band the angle between the normal itself and the light.
            let ray = if reflect {
                let vn = dot3(self.view, n);
                [
                    self.view[0] - 2.0 * vn * n[0],
                    self.view[1] - 2.0 * vn * n[1],
                    self.view[2] - 2.0 * vn * n[2],
                ]
            } else {
                n
            };
            let t = dot3(ray, axis).clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
            let band = (t * stripes).floor() as i64;
            let shade = if band % 2 == 0 { 0.08 } else { 0.95 };
            base = [shade; 3];
        }
        let diffuse = dot3(n, self.light).max(0.0);
        let specular = dot3(n, self.half).max(0.0).powi(48);
        let k = 0.32 + 0.68 * diffuse;
        let c = |x: f32| (x * k + 0.2 * specular).min(1.0);
        [c(base[0]), c(base[1]), c(base[2]), 1.0]
    }

    fn get_depth_strategy(&self) -> DepthStrategy {
        DepthStrategy::IfLessWrite
    }
}

fn f32x3(v: Vec3) -> [f32; 3] {
    [v[0] as f32, v[1] as f32, v[2] as f32]
}

/// Rasterizes `soup` seen by `cam` into a layer of the camera's viewport
/// size, supersampled `ss`×`ss` and box-filtered down.
pub(crate) fn rasterize(soup: &Soup, cam: &Camera, ss: usize, stripes: Option<Stripes>) -> Layer {
    let (w, h) = (cam.size.0 as usize, cam.size.1 as usize);
    let (sw, sh) = (w * ss, h * ss);
    let eye = scale(cam.forward, -1.0);
    // Key light from the upper left, slightly in front of the viewer.
    let light = normalize(add(
        add(scale(eye, 0.75), scale(cam.up, 0.55)),
        scale(cam.right, -0.35),
    ))
    .unwrap_or(eye);
    let half = normalize(add(light, eye)).unwrap_or(eye);
    let shader = Shader {
        light: f32x3(light),
        half: f32x3(half),
        view: f32x3(cam.forward),
        stripes: stripes.map(|s| match s {
            Stripes::Reflection(k) => {
                let axis = normalize(add(cam.up, scale(cam.right, 0.35))).unwrap_or(cam.up);
                (k as f32, f32x3(axis), true)
            }
            Stripes::Isophote(k) => (k as f32, f32x3(light), false),
        }),
    };
    let ndc: Vec<[f32; 4]> = soup
        .positions
        .iter()
        .map(|&p| {
            let (x, y, z) = cam.project(p);
            [
                (2.0 * x / cam.size.0 - 1.0) as f32,
                (1.0 - 2.0 * y / cam.size.1) as f32,
                z.clamp(0.0, 1.0) as f32,
                1.0,
            ]
        })
        .collect();
    let mut verts = Vec::with_capacity(3 * soup.triangles.len());
    for t in &soup.triangles {
        let [a, b, c] = t.map(|k| ndc[k as usize]);
        // euc divides by the screen-space area: skip degenerate triangles
        // (collapsed patch edges, edge-on faces) that would give NaN weights.
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if area.abs() * (sw * sh) as f32 <= 1e-6 || !area.is_finite() {
            continue;
        }
        for &k in t {
            let k = k as usize;
            let [nx, ny, nz] = f32x3(soup.normals[k]);
            let [r, g, b] = soup.colours[k];
            verts.push(Vertex {
                pos: ndc[k],
                normal: (nx, ny, nz),
                colour: (r, g, b),
            });
        }
    }
    let mut colour = Buffer2d::new([sw, sh], [0.0f32; 4]);
    let mut depth = Buffer2d::new([sw, sh], 1.0f32);
    shader.draw::<Triangles<'_, Buffer2d<f32>, BackfaceCullingDisabled>, _>(
        &verts,
        &mut colour,
        Some(&mut depth),
    );
    let samples: &[[f32; 4]] = colour.as_ref();
    let norm = 1.0 / (ss * ss) as f32;
    let depths: &[f32] = depth.as_ref();
    let mut rgba = vec![[0.0f32; 4]; w * h];
    let mut near = vec![1.0f32; w * h];
    for y in 0..h {
        for x in 0..w {
            let mut acc = [0.0f32; 4];
            for dy in 0..ss {
                let row = (y * ss + dy) * sw;
                for dx in 0..ss {
                    let p = samples[row + x * ss + dx];
                    for c in 0..4 {
                        acc[c] += p[c];
                    }
                    near[y * w + x] = near[y * w + x].min(depths[row + x * ss + dx]);
                }
            }
            rgba[y * w + x] = acc.map(|v| v * norm);
        }
    }
    Layer {
        width: w,
        height: h,
        rgba,
        depth: near,
    }
}
