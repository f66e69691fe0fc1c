//! The answer's parts as typed structs that mirror `editor/API.md`: the
//! view, table rows, handles and their edits, sliders, arrows, operator
//! markers, the method select, the net and the mesh.

use super::*;

/// A row of the table (`editor/API.md`, `table`).
#[derive(serde::Serialize)]
pub(super) struct Row {
    pub(super) label: String,
    pub(super) value: Cell,
}

/// A table cell: a number (null when absent or not finite) or text.
#[derive(serde::Serialize)]
#[serde(untagged)]
pub(super) enum Cell {
    Number(Option<f64>),
    Text(String),
}

impl From<f64> for Cell {
    fn from(x: f64) -> Self {
        Cell::Number(Some(x))
    }
}

impl From<Option<f64>> for Cell {
    fn from(x: Option<f64>) -> Self {
        Cell::Number(x)
    }
}

impl From<&str> for Cell {
    fn from(s: &str) -> Self {
        Cell::Text(s.into())
    }
}

impl From<String> for Cell {
    fn from(s: String) -> Self {
        Cell::Text(s)
    }
}

impl From<Value> for Cell {
    /// A measure of `analyse`: a number or its text.
    fn from(v: Value) -> Self {
        match v {
            Value::Number(n) => Cell::Number(n.as_f64()),
            Value::Null => Cell::Number(None),
            Value::String(s) => Cell::Text(s),
            other => Cell::Text(other.to_string()),
        }
    }
}

pub(super) fn row(label: impl Into<String>, value: impl Into<Cell>) -> Row {
    Row {
        label: label.into(),
        value: value.into(),
    }
}

/// A draggable handle: a JSON pointer into the scene and where it is
/// (`editor/API.md`, `handles`).
#[derive(serde::Serialize)]
pub(super) struct Handle {
    pub(super) pointer: String,
    pub(super) position: Vec3,
    pub(super) label: String,
    /// `control_point` or `operator` (its colour).
    pub(super) kind: &'static str,
    /// How a drag edits the value when it is not the position itself.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) edit: Option<Edit>,
}

impl Handle {
    /// A handle whose drag writes its position at `pointer`.
    pub(super) fn point(
        pointer: String,
        position: Vec3,
        label: String,
        kind: &'static str,
    ) -> Self {
        Handle {
            pointer,
            position,
            label,
            kind,
            edit: None,
        }
    }
}

/// What dragging a handle edits (`editor/API.md`, `handles[].edit`).
#[derive(serde::Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub(super) enum Edit {
    /// A unit direction drawn `length` from `anchor`; with `offset`, the
    /// pointer of a plane's offset kept through the foot while it turns.
    Direction {
        anchor: Vec3,
        length: f64,
        #[serde(skip_serializing_if = "Option::is_none")]
        offset: Option<String>,
    },
    /// A plane's offset, moved along its normal from the surface point
    /// `anchor`.
    Offset { anchor: Vec3, normal: Vec3 },
}

/// A weight or strength slider (`editor/API.md`, `sliders`).
#[derive(serde::Serialize)]
pub(super) struct Slider {
    pub(super) pointer: String,
    pub(super) label: String,
    pub(super) value: f64,
    pub(super) min: f64,
    pub(super) max: f64,
    pub(super) scale: &'static str,
}

/// An arrow: a guiding or prescribed normal.
#[derive(serde::Serialize)]
pub(super) struct Arrow {
    pub(super) at: Vec3,
    pub(super) dir: Vec3,
}

/// An operator's marker: where it acts on the surface and what it pulls
/// toward.
#[derive(serde::Serialize)]
pub(super) struct Marker {
    pub(super) name: String,
    pub(super) kind: String,
    pub(super) at: Option<Vec3>,
    pub(super) target: Option<Vec3>,
}

/// What the page draws and edits (`editor/API.md`, `POST /api/solve`),
/// the same fields for every kind of surface.
#[derive(serde::Serialize)]
pub(super) struct View<'a> {
    /// "tensor", "triangular" or "bspline".
    pub(super) kind: &'static str,
    /// Rows `{label, value}`.
    pub(super) table: Vec<Row>,
    /// The result file's content.
    pub(super) result: Scene,
    /// Positions, indices, colours by mean curvature and their legend.
    pub(super) mesh: MeshView,
    /// The control net.
    pub(super) net: Net<'a>,
    /// Boundary curves as polylines.
    pub(super) boundary: Vec<Vec<Vec3>>,
    /// Arrows of the guiding normals (`{at, dir}`).
    pub(super) normals: Vec<Arrow>,
    /// Operator markers.
    pub(super) operators: Vec<Marker>,
    /// Draggable handles (JSON pointers into the scene).
    pub(super) handles: Vec<Handle>,
    /// Weight sliders (JSON pointers into the scene).
    pub(super) sliders: Vec<Slider>,
    /// The construction method's select (tensor scenes), else null.
    pub(super) methods: Option<Methods>,
}

/// The select of a tensor scene's `method`.
#[derive(serde::Serialize)]
pub(super) struct Methods {
    pub(super) pointer: &'static str,
    pub(super) value: fairsurf_io::Method,
    pub(super) options: [&'static str; 5],
}

impl Methods {
    pub(super) const OPTIONS: [&'static str; 5] = [
        "minimize",
        "harmonic",
        "biharmonic",
        "harmonic_mask",
        "biharmonic_mask",
    ];
}

/// Control points and the index pairs of the net's edges.
#[derive(serde::Serialize)]
pub(super) struct Net<'a> {
    pub(super) points: &'a [Vec3],
    pub(super) edges: Vec<[usize; 2]>,
}

/// The mesh as the page draws it (`editor/API.md`, `mesh`): kept in full
/// precision and written as the request asks ([`MeshEncoding`]) — JSON
/// lists of short decimals, or base64 text of little-endian arrays.
pub(super) struct MeshView {
    /// 3 per vertex.
    pub(super) positions: Vec<f64>,
    /// JSON lists give the positions to multiples of 10^digits.
    pub(super) digits: i32,
    /// 3 per triangle.
    pub(super) indices: Vec<u32>,
    /// (rows, columns) of vertices when the mesh is a uniform grid
    /// meshed as `TriMesh::from_patch` does: a base64 answer sends this
    /// instead of the indices.
    pub(super) grid: Option<(usize, usize)>,
    /// sRGB, 3 per vertex.
    pub(super) colors: Vec<f32>,
    pub(super) legend: Legend,
    pub(super) encoding: MeshEncoding,
}

/// How an answer writes its mesh's arrays (the request's `mesh_encoding`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum MeshEncoding {
    /// Lists of numbers: positions to 1e-7 of the mesh's extent, colours
    /// to 1e-4.
    #[default]
    Json,
    /// Base64 text (RFC 4648, padded) of little-endian arrays: float32
    /// positions, uint16 indices (uint32 past 65,536 vertices, as
    /// `index_type` says) — or, for a tensor or B-spline surface's grid, its size
    /// (`grid`) instead of indices —, uint8 sRGB colours (0–255, the
    /// legend's precision): a quarter of the bytes, no decimals to write or
    /// parse (what the editor's page asks for).
    Base64,
}

impl MeshEncoding {
    /// The request's name of the encoding.
    pub(crate) fn name(self) -> &'static str {
        match self {
            MeshEncoding::Json => "json",
            MeshEncoding::Base64 => "base64",
        }
    }

    /// The encoding of that name.
    pub(crate) fn from_name(name: &str) -> Option<Self> {
        [MeshEncoding::Json, MeshEncoding::Base64]
            .into_iter()
            .find(|e| e.name() == name)
    }
}

impl serde::Serialize for MeshView {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut m = s.serialize_struct("MeshView", 6)?;
        match self.encoding {
            MeshEncoding::Json => {
                let positions: Vec<f64> = self
                    .positions
                    .iter()
                    .map(|&x| super::decimal(x, self.digits))
                    .collect();
                let colors: Vec<f64> = self
                    .colors
                    .iter()
                    .map(|&x| super::decimal(x as f64, -4))
                    .collect();
                m.serialize_field("positions", &positions)?;
                m.serialize_field("indices", &self.indices)?;
                m.serialize_field("colors", &colors)?;
            }
            MeshEncoding::Base64 => {
                m.serialize_field("encoding", "base64")?;
                let positions: Vec<u8> = self
                    .positions
                    .iter()
                    .flat_map(|&x| (x as f32).to_le_bytes())
                    .collect();
                m.serialize_field("positions", &fairsurf_io::base64(&positions))?;
                if let Some(grid) = self.grid {
                    m.serialize_field("grid", &grid)?;
                } else {
                    // Two bytes an index while they fit.
                    let small = self.positions.len() / 3 <= 1 << 16;
                    m.serialize_field("index_type", if small { "uint16" } else { "uint32" })?;
                    let indices: Vec<u8> = if small {
                        self.indices
                            .iter()
                            .flat_map(|&i| (i as u16).to_le_bytes())
                            .collect()
                    } else {
                        self.indices.iter().flat_map(|i| i.to_le_bytes()).collect()
                    };
                    m.serialize_field("indices", &fairsurf_io::base64(&indices))?;
                }
                // sRGB in 0..255, as the legend's stops.
                let colors: Vec<u8> = self
                    .colors
                    .iter()
                    .map(|&c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
                    .collect();
                m.serialize_field("colors", &fairsurf_io::base64(&colors))?;
            }
        }
        m.serialize_field("legend", &self.legend)?;
        m.end()
    }
}

/// The colour legend of the mesh.
#[derive(serde::Serialize)]
pub(super) struct Legend {
    pub(super) name: &'static str,
    pub(super) min: f64,
    pub(super) max: f64,
    /// `[t in 0..1, CSS colour]`.
    pub(super) stops: Vec<(f64, String)>,
}
