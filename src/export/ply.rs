//! Binary little-endian PLY with per-vertex radiance.

use std::io::Write;
use std::path::Path;

use super::{BakedMesh, export_error};
use crate::error::Result;
use crate::fs::write_atomically;
use crate::render::ToneMap;
use crate::solver::Solution;

/// Writes `solution` to `path` as a binary little-endian PLY file: per
/// vertex `x y z nx ny nz radiance_r radiance_g radiance_b` (float; radiance
/// L = B/π in W/(m²·sr)) and `red green blue` (uchar, the sRGB colour the PNG
/// shows with `tone_map`); per face `vertex_indices` (list uchar uint), the
/// renderer's triangles, counter-clockwise seen from the front. The header's
/// comments give the units and the exposure.
///
/// # Errors
///
/// [`crate::Error::Output`] when a position or radiosity is not finite or the
/// mesh is empty; [`crate::Error::Io`] when the file cannot be written. The
/// target is then left untouched.
pub fn export_ply(solution: &Solution<'_>, tone_map: &ToneMap, path: &Path) -> Result<()> {
    let baked = BakedMesh::new(solution, tone_map, path)?;
    let bytes = ply_bytes(&baked, tone_map.exposure);
    write_atomically(path, |writer| {
        writer.write_all(&bytes).map_err(|e| export_error(path, e))
    })
}

/// The whole file: ASCII header, then the binary vertex and face records.
fn ply_bytes(baked: &BakedMesh, exposure: f64) -> Vec<u8> {
    let header = format!(
        "ply\n\
         format binary_little_endian 1.0\n\
         comment isorad radiosity solution\n\
         comment radiance_*: linear radiance L = B/pi, W/(m^2 sr)\n\
         comment red/green/blue: sRGB 8-bit colour at exposure {exposure:+.4} stops, as the PNG\n\
         element vertex {}\n\
         property float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         property float radiance_r\nproperty float radiance_g\nproperty float radiance_b\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\n\
         element face {}\n\
         property list uchar uint vertex_indices\n\
         end_header\n",
        baked.positions.len(),
        baked.triangles.len()
    );
    let vertex_size = 9 * 4 + 3;
    let face_size = 1 + 3 * 4;
    let mut bytes = Vec::with_capacity(
        header.len() + vertex_size * baked.positions.len() + face_size * baked.triangles.len(),
    );
    bytes.extend_from_slice(header.as_bytes());
    // Vertex records.
    for k in 0..baked.positions.len() {
        for value in [baked.positions[k], baked.normals[k], baked.radiance[k]]
            .iter()
            .flatten()
        {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
        bytes.extend_from_slice(&baked.srgb[k]);
    }
    // Face records.
    for triangle in &baked.triangles {
        bytes.push(3);
        for index in triangle {
            bytes.extend_from_slice(&index.to_le_bytes());
        }
    }
    bytes
}
