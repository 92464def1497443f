//! Exporting a solution as a mesh with baked light, for other programs.
//!
//! Two formats, chosen by the file's extension ([`export_solution`]):
//!
//! - **PLY** (`.ply`, [`export_ply`]): binary little-endian, one vertex per
//!   mesh vertex with `x y z` (float), the flat surface normal `nx ny nz`
//!   (float), the HDR **radiance** `radiance_r radiance_g radiance_b` (float,
//!   W/(m²·sr), L = B/π, as in the EXR), and `red green blue` (uchar): the
//!   sRGB 8-bit colour the PNG shows, for viewers such as MeshLab. Faces are
//!   `vertex_indices` (list uchar uint), counter-clockwise seen from the front.
//! - **glTF 2.0 binary** (`.glb`, [`export_glb`]): one mesh, one triangle
//!   primitive with `POSITION` (with min/max), `NORMAL`, `COLOR_0` (float
//!   VEC3, *linear*, in [0, 1]) and `_RADIANCE` (float VEC3, the HDR radiance),
//!   indices as UNSIGNED_INT, and one material with `KHR_materials_unlit` and
//!   base colour 1, so a viewer shows `COLOR_0` as it is.
//!
//! In both, COLOR_0 and the 8-bit colour use the PNG's exposure: the linear
//! display value is clamp(L · 2^exposure, 0, 1) per channel (the glTF stores
//! it linear, the viewer applies the sRGB curve on output; the PLY stores it
//! sRGB-encoded, exactly as the PNG's pixels). Values above 1 are clipped,
//! with no other curve, like the PNG.
//!
//! Vertices are the solution's mesh vertices, unshared across surfaces (each
//! has its surface's normal, so light and shading stay discontinuous at
//! creases); triangles are the renderer's (a quad element is split along its
//! diagonal of closer radiosities). Coordinates are the scene's, unscaled
//! (glTF readers assume metres and +Y up).
//!
//! Files are written to a temporary file and renamed; a solution with a
//! non-finite position or radiosity is refused before anything is written.

mod gltf;
mod ply;

use std::path::Path;

use crate::error::{Error, Result};
use crate::render::ToneMap;
use crate::rgb::Rgb;
use crate::solver::Solution;

pub use gltf::{encode_glb, export_glb};
pub use ply::export_ply;

/// The file formats a solution can be exported to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ExportFormat {
    /// Stanford PLY, binary little-endian (`.ply`).
    Ply,
    /// glTF 2.0 binary (`.glb`).
    Glb,
}

impl ExportFormat {
    /// The format named by a path's extension (`.ply` or `.glb`, any case).
    ///
    /// # Errors
    ///
    /// [`Error::Output`] naming the path when the extension is neither.
    pub fn from_path(path: &Path) -> Result<ExportFormat> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("ply") => Ok(ExportFormat::Ply),
            Some("glb") => Ok(ExportFormat::Glb),
            _ => Err(export_error(
                path,
                "unknown export format: the extension must be .ply or .glb",
            )),
        }
    }
}

/// Exports `solution` to `path` in the format its extension names (see
/// [`ExportFormat::from_path`]), with colours exposed by `tone_map`.
///
/// # Errors
///
/// As [`export_ply`] and [`export_glb`], and [`Error::Output`] for an
/// unknown extension.
///
/// ```
/// use isorad::phase::silent;
/// use isorad::{Ambient, Settings, Solver, ToneMap, export_solution, load_scene, render::auto_exposure};
///
/// let mut solver = Solver::new(load_scene("cornell")?.scene, Settings::preview())?;
/// solver.run();
/// let solution = solver.solution(Ambient::Everywhere, &silent);
/// // The PNG's exposure, so the exported colours look as the image does.
/// let image = solution.render(&solver.scene().camera_or_default(), &Default::default());
/// let tone_map = ToneMap::new(auto_exposure(&image));
/// let dir = tempfile::tempdir().unwrap();
/// export_solution(&solution, &tone_map, &dir.path().join("cornell.glb"))?;
/// export_solution(&solution, &tone_map, &dir.path().join("cornell.ply"))?;
/// # Ok::<(), isorad::Error>(())
/// ```
pub fn export_solution(solution: &Solution<'_>, tone_map: &ToneMap, path: &Path) -> Result<()> {
    match ExportFormat::from_path(path)? {
        ExportFormat::Ply => export_ply(solution, tone_map, path),
        ExportFormat::Glb => export_glb(solution, tone_map, path),
    }
}

/// A solution flattened for the writers: f32 vertex attributes and
/// triangle indices, checked finite.
struct BakedMesh {
    /// Vertex positions.
    positions: Vec<[f32; 3]>,
    /// Each vertex's surface normal (unit).
    normals: Vec<[f32; 3]>,
    /// Radiance L = B/π per vertex, W/(m²·sr).
    radiance: Vec<[f32; 3]>,
    /// Linear display colour per vertex, clamp(L · 2^exposure, 0, 1).
    display: Vec<[f32; 3]>,
    /// The PNG's 8-bit sRGB colour per vertex ([`ToneMap::map_channel`]).
    srgb: Vec<[u8; 3]>,
    /// Triangles, counter-clockwise seen from the front.
    triangles: Vec<[u32; 3]>,
}

impl BakedMesh {
    /// Flattens `solution`, or fails naming `path` when a value is not
    /// finite or there is nothing to export.
    fn new(solution: &Solution<'_>, tone_map: &ToneMap, path: &Path) -> Result<BakedMesh> {
        let (scene, mesh) = (solution.scene, solution.mesh);
        let radiosity = solution.radiosity();
        // Refuse non-finite values before anything is written.
        for (index, (vertex, b)) in mesh.vertices.iter().zip(&radiosity).enumerate() {
            if !vertex.position.is_finite() || !b.is_finite() {
                return Err(export_error(
                    path,
                    format!("vertex {index} has a non-finite position or radiosity"),
                ));
            }
        }
        // The renderer's triangles (Solution::triangles), as indices.
        let triangles = solution.triangle_indices();
        if triangles.is_empty() {
            return Err(export_error(path, "the mesh has no triangles to export"));
        }
        let to_f32 = |v: glam::DVec3| v.as_vec3().to_array();
        let scale = tone_map.exposure.exp2();
        let radiance: Vec<Rgb> = radiosity
            .iter()
            .map(|b| *b / std::f64::consts::PI)
            .collect();
        Ok(BakedMesh {
            positions: mesh.vertices.iter().map(|v| to_f32(v.position)).collect(),
            normals: mesh
                .vertices
                .iter()
                .map(|v| to_f32(scene.surface(v.surface).normal()))
                .collect(),
            display: radiance
                .iter()
                .map(|l| (*l * scale).clamp(Rgb::ZERO, Rgb::ONE).to_f32_array())
                .collect(),
            srgb: radiance
                .iter()
                .map(|l| l.to_array().map(|c| tone_map.map_channel(c)))
                .collect(),
            radiance: radiance.into_iter().map(Rgb::to_f32_array).collect(),
            triangles,
        })
    }
}

/// [`Error::Output`] naming `path`.
fn export_error(path: &Path, message: impl ToString) -> Error {
    Error::Output {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::phase::silent;
    use crate::solver::AmbientIrradiance;
    use crate::{Ambient, Length, Settings, Solver, load_scene};

    /// A vertex whose radiosity is not finite is named, and neither format
    /// writes a file, nor leaves a temporary one.
    #[test]
    fn non_finite_radiosity_is_refused_and_nothing_is_written() {
        let scene = load_scene("cornell").expect("the bundled scene").scene;
        let mut settings = Settings::default();
        settings.mesh.max_edge = Length::OfDiagonal(0.15);
        let mut solver = Solver::new(scene, settings).expect("a valid scene");
        assert!(solver.step());
        let mut solution = solver.solution(Ambient::Omitted, &silent);
        let mut ambient = vec![Rgb::ZERO; solver.mesh().vertices.len()];
        ambient[7].g = f64::NAN;
        solution.ambient = AmbientIrradiance::Everywhere(ambient);
        let dir = tempfile::tempdir().expect("a temporary folder");
        for name in ["bad.glb", "bad.ply"] {
            let path = dir.path().join(name);
            let error = export_solution(&solution, &ToneMap::new(-2.0), &path).unwrap_err();
            assert!(matches!(error, Error::Output { .. }), "{error}");
            assert!(error.to_string().contains("vertex 7"), "{error}");
            assert!(!path.exists());
        }
        let left = std::fs::read_dir(dir.path()).map(Iterator::count);
        assert_eq!(left.ok(), Some(0), "no temporary file left");
    }
}
