//! glTF 2.0 (Khronos, <https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html>):
//! one mesh, one triangle primitive, one buffer; written as a binary `.glb`
//! container (§4.4) or as `.gltf` JSON with the buffer as a base64 data URI.

use crate::SurfaceMesh;
use fairsurf::colour::ColourMap;
use serde_json::{json, Value};
use std::io::Write;

const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const TRIANGLES: u32 = 4;

/// A glTF document and its one binary buffer. Every buffer view starts at a
/// multiple of 4 bytes (all components are 4 bytes wide), so the buffer
/// needs no padding and accessors are aligned as §3.6.2.4 requires.
pub(crate) struct Gltf {
    json: Value,
    bin: Vec<u8>,
}

/// Appends views and their accessors to a buffer.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    /// Adds `data` as a view with its accessor; returns the accessor's index.
    fn add_f32<const N: usize>(&mut self, data: &[[f32; N]], min_max: bool) -> usize {
        let offset = self.bin.len();
        for x in data.iter().flatten() {
            self.bin.extend_from_slice(&x.to_le_bytes());
        }
        let kind = match N {
            1 => "SCALAR",
            3 => "VEC3",
            _ => unreachable!("only SCALAR and VEC3 attributes are written"),
        };
        let mut acc = json!({
            "bufferView": self.view(offset, ARRAY_BUFFER),
            "componentType": FLOAT,
            "count": data.len(),
            "type": kind,
        });
        if min_max {
            let fold = |f: fn(f32, f32) -> f32, start: f32| {
                let v: Vec<f32> = (0..N)
                    .map(|c| data.iter().map(|x| x[c]).fold(start, f))
                    .collect();
                json!(v)
            };
            acc["min"] = fold(f32::min, f32::INFINITY);
            acc["max"] = fold(f32::max, f32::NEG_INFINITY);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    fn add_indices(&mut self, triangles: &[[u32; 3]]) -> usize {
        let offset = self.bin.len();
        for k in triangles.iter().flatten() {
            self.bin.extend_from_slice(&k.to_le_bytes());
        }
        let view = self.view(offset, ELEMENT_ARRAY_BUFFER);
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": UNSIGNED_INT,
            "count": 3 * triangles.len(),
            "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }

    fn view(&mut self, offset: usize, target: u32) -> usize {
        debug_assert_eq!(offset % 4, 0);
        self.views.push(json!({
            "buffer": 0,
            "byteOffset": offset,
            "byteLength": self.bin.len() - offset,
            "target": target,
        }));
        self.views.len() - 1
    }
}

impl Gltf {
    /// The document for `mesh`, colouring |H| over `range` = [lo, hi], lo < hi.
    pub(crate) fn new(mesh: &SurfaceMesh, range: [f64; 2]) -> Self {
        let m = mesh.mesh();
        let f32x3 = |v: &[fairsurf::Vec3]| -> Vec<[f32; 3]> {
            v.iter().map(|p| p.map(|c| c as f32)).collect()
        };
        let colours: Vec<[f32; 3]> = mesh
            .curvature()
            .iter()
            .map(|c| {
                let t = c.map_or(f64::NAN, |c| {
                    (c.mean.abs() - range[0]) / (range[1] - range[0])
                });
                ColourMap::Viridis.at(t).map(srgb_to_linear)
            })
            .collect();
        let h: Vec<[f32; 1]> = mesh
            .mean_curvature_filled()
            .iter()
            .map(|&h| [h as f32])
            .collect();
        let mut b = Builder::default();
        let position = b.add_f32(&f32x3(&m.positions), true);
        let normal = b.add_f32(&f32x3(&m.normals), false);
        let colour = b.add_f32(&colours, false);
        let mean = b.add_f32(&h, false);
        let indices = b.add_indices(&m.triangles);
        let json = json!({
            "asset": {
                "version": "2.0",
                "generator": format!("fairsurf {}", env!("CARGO_PKG_VERSION")),
            },
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "name": "surface"}],
            "meshes": [{
                "name": "surface",
                "primitives": [{
                    "attributes": {
                        "POSITION": position,
                        "NORMAL": normal,
                        "COLOR_0": colour,
                        "_MEAN_CURVATURE": mean,
                    },
                    "indices": indices,
                    "material": 0,
                    "mode": TRIANGLES,
                }],
            }],
            "materials": [{
                "name": "surface",
                "doubleSided": true,
                "pbrMetallicRoughness": {
                    "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                    "metallicFactor": 0.0,
                    "roughnessFactor": 0.6,
                },
            }],
            "accessors": b.accessors,
            "bufferViews": b.views,
            "buffers": [{"byteLength": b.bin.len()}],
        });
        Gltf { json, bin: b.bin }
    }

    /// The binary container: a 12-byte header, a JSON chunk padded with
    /// spaces and a BIN chunk padded with zeros, each to 4 bytes (§4.4).
    pub(crate) fn write_glb(&self, w: &mut dyn Write) -> std::io::Result<()> {
        let mut text = serde_json::to_vec(&self.json).map_err(std::io::Error::other)?;
        pad(&mut text, b' ');
        let mut bin = self.bin.clone();
        pad(&mut bin, 0);
        let total = 12 + 8 + text.len() + 8 + bin.len();
        let total = u32::try_from(total)
            .map_err(|_| std::io::Error::other("a .glb file cannot exceed 4 GiB"))?;
        w.write_all(b"glTF")?;
        w.write_all(&2u32.to_le_bytes())?;
        w.write_all(&total.to_le_bytes())?;
        for (chunk, kind) in [(&text, b"JSON"), (&bin, b"BIN\0")] {
            w.write_all(&(chunk.len() as u32).to_le_bytes())?;
            w.write_all(kind)?;
            w.write_all(chunk)?;
        }
        Ok(())
    }

    /// JSON with the buffer embedded as a base64 data URI.
    pub(crate) fn write_gltf(&self, w: &mut dyn Write) -> std::io::Result<()> {
        let mut doc = self.json.clone();
        doc["buffers"][0]["uri"] = json!(format!(
            "data:application/octet-stream;base64,{}",
            base64(&self.bin)
        ));
        serde_json::to_writer_pretty(&mut *w, &doc).map_err(std::io::Error::other)?;
        writeln!(w)
    }
}

fn pad(bytes: &mut Vec<u8>, with: u8) {
    while bytes.len() % 4 != 0 {
        bytes.push(with);
    }
}

/// The sRGB transfer function inverted: glTF vertex colours are linear RGB
/// (§3.7.2.1), the colour map's values are sRGB.
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Standard base64 (RFC 4648 §4) with `=` padding: what a glTF data URI
/// holds, and the editor's binary meshes.
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let symbol = |n: u32, k: u32| ALPHABET[(n >> (18 - 6 * k)) as usize & 63];
    let mut out = vec![b'='; bytes.len().div_ceil(3) * 4];
    let whole = bytes.chunks_exact(3);
    let rest = whole.remainder();
    let mut quads = out.chunks_exact_mut(4);
    for (c, o) in whole.zip(&mut quads) {
        let n = (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2]);
        o.copy_from_slice(&[symbol(n, 0), symbol(n, 1), symbol(n, 2), symbol(n, 3)]);
    }
    if let Some(o) = quads.next() {
        // 1 or 2 bytes left: their 2 or 3 symbols, then '='.
        let n = rest
            .iter()
            .enumerate()
            .fold(0, |n, (k, &b)| n | u32::from(b) << (16 - 8 * k));
        for (k, o) in o.iter_mut().enumerate().take(rest.len() + 1) {
            *o = symbol(n, k as u32);
        }
    }
    String::from_utf8(out).expect("the base64 alphabet is ASCII")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc_4648_test_vectors() {
        let cases = [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ];
        // All 64 symbols, in order.
        let bytes: Vec<u8> = (0u32..16)
            .flat_map(|k| {
                let n = (4 * k) << 18 | (4 * k + 1) << 12 | (4 * k + 2) << 6 | (4 * k + 3);
                [(n >> 16) as u8, (n >> 8) as u8, n as u8]
            })
            .collect();
        assert_eq!(
            base64(&bytes),
            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/"
        );
        for (plain, coded) in cases {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
    }

    #[test]
    fn srgb_round_trip_ends() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
    }

    #[test]
    fn glb_chunks_are_aligned_and_lengths_add_up() {
        let p = fairsurf::TensorPatch::from_fn(2, 3, |i, j| [i as f64, j as f64, (i * j) as f64]);
        let doc = Gltf::new(&SurfaceMesh::from_patch(&p, 3, 5), [0.0, 1.0]);
        let mut out = Vec::new();
        doc.write_glb(&mut out).unwrap();
        let u32_at = |k: usize| u32::from_le_bytes(out[k..k + 4].try_into().unwrap()) as usize;
        assert_eq!(&out[0..4], b"glTF");
        assert_eq!(u32_at(8), out.len());
        let json_len = u32_at(12);
        assert_eq!((json_len % 4, &out[16..20]), (0, &b"JSON"[..]));
        let bin_at = 20 + json_len;
        assert_eq!(
            (u32_at(bin_at) % 4, &out[bin_at + 4..bin_at + 8]),
            (0, &b"BIN\0"[..])
        );
        assert_eq!(bin_at + 8 + u32_at(bin_at), out.len());
        let json: Value = serde_json::from_slice(&out[20..bin_at]).unwrap();
        for v in json["bufferViews"].as_array().unwrap() {
            assert_eq!(v["byteOffset"].as_u64().unwrap() % 4, 0);
        }
        // 4 × 6 vertices; positions, normals, colours (12 bytes), H (4), indices 30 × 3 × 4.
        assert_eq!(json["buffers"][0]["byteLength"], 24 * 40 + 30 * 12);
    }
}
