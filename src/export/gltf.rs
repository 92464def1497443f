//! glTF 2.0 binary (.glb) with baked vertex colours and an unlit material.
//!
//! Layout: a 12-byte header, a JSON chunk (padded with spaces to 4 bytes) and
//! a BIN chunk (padded with zeros) holding five tightly packed buffer views:
//! POSITION, NORMAL, COLOR_0, _RADIANCE (float VEC3 each) and the indices
//! (UNSIGNED_INT).
//!
//! # References
//!
//! Khronos Group, *glTF 2.0 Specification*, §3.7.2 (meshes: COLOR_0 is
//! linear and multiplies the base colour; POSITION needs min and max;
//! application-specific attributes start with an underscore), §4.4 (GLB);
//! *KHR_materials_unlit*.

use std::io::Write;
use std::path::Path;

use serde_json::{Value, json};

use super::{BakedMesh, export_error};
use crate::error::Result;
use crate::fs::write_atomically;
use crate::render::ToneMap;
use crate::solver::Solution;

/// "glTF", the GLB magic number.
const GLB_MAGIC: u32 = 0x4654_6C67;
/// "JSON", the JSON chunk's type.
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// "BIN\0", the binary chunk's type.
const CHUNK_BIN: u32 = 0x004E_4942;
/// Accessor component types and buffer-view targets.
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Writes `solution` to `path` as a glTF 2.0 binary file: one mesh, one
/// triangle primitive with POSITION, NORMAL, COLOR_0 (linear
/// clamp(L · 2^exposure, 0, 1) with `tone_map`'s exposure) and _RADIANCE
/// (HDR radiance L = B/π, W/(m²·sr)), and one `KHR_materials_unlit` material
/// of base colour 1, so that viewers show the baked light as the PNG does.
///
/// # Errors
///
/// [`crate::Error::Output`] when a position or radiosity is not finite or the
/// mesh is empty; [`crate::Error::Io`] when the file cannot be written. The
/// target is then left untouched.
pub fn export_glb(solution: &Solution<'_>, tone_map: &ToneMap, path: &Path) -> Result<()> {
    let bytes = encode_glb(solution, tone_map, path)?;
    write_atomically(path, |writer| {
        writer.write_all(&bytes).map_err(|e| export_error(path, e))
    })
}

/// The .glb file [`export_glb`] writes, in memory: for a program that sends
/// it rather than writing it (the viewer's export button). `name` only
/// names the file in errors.
///
/// # Errors
///
/// [`crate::Error::Output`] when a position or radiosity is not finite or the
/// mesh is empty.
pub fn encode_glb(solution: &Solution<'_>, tone_map: &ToneMap, name: &Path) -> Result<Vec<u8>> {
    let baked = BakedMesh::new(solution, tone_map, name)?;
    glb_bytes(&baked, tone_map.exposure, name)
}

/// The binary chunk and the JSON describing it.
struct Layout {
    bin: Vec<u8>,
    buffer_views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Layout {
    /// Appends `data` as a buffer view for `target`, and `accessor` (all but
    /// its buffer view) over it; returns the accessor's index.
    fn push(&mut self, data: &[u8], target: u32, accessor: Value) -> usize {
        let view = self.buffer_views.len();
        self.buffer_views.push(json!({
            "buffer": 0,
            "byteOffset": self.bin.len(),
            "byteLength": data.len(),
            "target": target,
        }));
        self.bin.extend_from_slice(data);
        let mut accessor = accessor;
        accessor["bufferView"] = json!(view);
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// A float VEC3 attribute; with `bounds`, its min and max.
    fn push_vec3(&mut self, values: &[[f32; 3]], bounds: bool) -> usize {
        let data: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let mut accessor = json!({"componentType": FLOAT, "count": values.len(), "type": "VEC3"});
        if bounds {
            let (min, max) = vec3_bounds(values);
            accessor["min"] = json!(min);
            accessor["max"] = json!(max);
        }
        self.push(&data, ARRAY_BUFFER, accessor)
    }
}

/// The whole .glb file (`path` only names it in errors).
fn glb_bytes(baked: &BakedMesh, exposure: f64, path: &Path) -> Result<Vec<u8>> {
    // Binary data: vertex attributes, then indices; every view is a
    // multiple of 4 bytes, so all stay aligned.
    let mut layout = Layout {
        bin: Vec::new(),
        buffer_views: Vec::new(),
        accessors: Vec::new(),
    };
    let position = layout.push_vec3(&baked.positions, true);
    let normal = layout.push_vec3(&baked.normals, false);
    let color = layout.push_vec3(&baked.display, false);
    let radiance = layout.push_vec3(&baked.radiance, false);
    let index_bytes: Vec<u8> = baked
        .triangles
        .iter()
        .flatten()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    let indices = layout.push(
        &index_bytes,
        ELEMENT_ARRAY_BUFFER,
        json!({"componentType": UNSIGNED_INT, "count": 3 * baked.triangles.len(), "type": "SCALAR"}),
    );
    let document = json!({
        "asset": {
            "version": "2.0",
            "generator": concat!("isorad ", env!("CARGO_PKG_VERSION")),
            "extras": {
                "COLOR_0": "linear display radiance clamp(L * 2^exposure, 0, 1)",
                "_RADIANCE": "linear radiance L = B/pi, W/(m^2 sr)",
                "exposure_stops": exposure,
            },
        },
        "extensionsUsed": ["KHR_materials_unlit"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "isorad solution"}],
        "meshes": [{
            "name": "isorad solution",
            "primitives": [{
                "attributes": {
                    "POSITION": position,
                    "NORMAL": normal,
                    "COLOR_0": color,
                    "_RADIANCE": radiance,
                },
                "indices": indices,
                "material": 0,
                "mode": 4,
            }],
        }],
        "materials": [{
            "name": "baked radiosity (unlit)",
            "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 1.0,
            },
            "extensions": {"KHR_materials_unlit": {}},
        }],
        "buffers": [{"byteLength": layout.bin.len()}],
        "bufferViews": layout.buffer_views,
        "accessors": layout.accessors,
    });
    let mut json_chunk = serde_json::to_vec(&document).map_err(|e| export_error(path, e))?;
    pad(&mut json_chunk, b' ');
    let mut bin_chunk = layout.bin;
    pad(&mut bin_chunk, 0);
    // Header, then the two chunks, each with its length and type.
    let total = 12 + 8 + json_chunk.len() + 8 + bin_chunk.len();
    let total_u32 = u32::try_from(total)
        .map_err(|_| export_error(path, format!("{total} bytes is beyond GLB's 4 GiB limit")))?;
    let mut bytes = Vec::with_capacity(total);
    for word in [GLB_MAGIC, 2, total_u32] {
        bytes.extend_from_slice(&word.to_le_bytes());
    }
    for (chunk, kind) in [(&json_chunk, CHUNK_JSON), (&bin_chunk, CHUNK_BIN)] {
        bytes.extend_from_slice(&(chunk.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&kind.to_le_bytes());
        bytes.extend_from_slice(chunk);
    }
    Ok(bytes)
}

/// Pads `chunk` with `byte` to a multiple of 4 bytes, as GLB chunks must be.
fn pad(chunk: &mut Vec<u8>, byte: u8) {
    while !chunk.len().is_multiple_of(4) {
        chunk.push(byte);
    }
}

/// Component-wise minimum and maximum of a non-empty list of vectors.
fn vec3_bounds(values: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    for v in values {
        for k in 0..3 {
            min[k] = min[k].min(v[k]);
            max[k] = max[k].max(v[k]);
        }
    }
    (min, max)
}
