//! Scene files (TOML): an OBJ scene plus camera, solver and mesh settings.
//!
//! ```toml
//! obj = "cornell/cornell.obj"          # required, relative to this file
//! merge_coplanar = true                # default: merge adjacent coplanar faces
//! [camera]                             # optional: default frames the scene
//! position = [278.0, 273.0, -800.0]    # required in [camera]
//! look_at  = [278.0, 273.0, 0.0]       # required in [camera]
//! up       = [0.0, 1.0, 0.0]           # default [0, 1, 0]
//! vfov_deg = 39.3                      # default 40
//! width    = 512                       # default 512
//! height   = 512                       # default 512
//! [solver]                             # optional
//! tolerance = 0.01                     # stop when unshot power < 1 % of emitted
//! [mesh]                               # optional
//! kind = "contour"                     # "square" | "adaptive" | "contour"
//! max_edge = 50.0                      # longest element edge, scene units
//! elements_per_side = 10               # N × N grid on every quad
//! ```
//!
//! Unknown keys are errors (a typo must not be silently ignored).

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::Deserialize;

use crate::error::{Error, Result};

use super::loaded::LoadedScene;
use super::obj::load_obj_from;
use super::source::{Disk, SourceFiles};
use crate::scene::{Camera, SceneOptions};

/// The mesher kinds a scene file may name.
pub const MESH_KINDS: [&str; 3] = ["square", "adaptive", "contour"];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFileToml {
    obj: PathBuf,
    merge_coplanar: Option<bool>,
    camera: Option<CameraToml>,
    solver: Option<SolverToml>,
    mesh: Option<MeshToml>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraToml {
    position: [f64; 3],
    look_at: [f64; 3],
    up: Option<[f64; 3]>,
    vfov_deg: Option<f64>,
    width: Option<u32>,
    height: Option<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SolverToml {
    tolerance: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshToml {
    kind: Option<String>,
    max_edge: Option<f64>,
    elements_per_side: Option<usize>,
}

/// Loads a scene file and the OBJ scene it names. The scene's camera is the
/// file's `[camera]` (validated) if any; its `[solver]` and `[mesh]` settings
/// come back in [`LoadedScene::options`].
pub fn load_scene_file(path: &Path) -> Result<LoadedScene> {
    load_scene_file_from(path, &Disk, path.display().to_string())
}

/// [`load_scene_file`] reading every file from `files`; `source` names the
/// scene in messages.
pub(crate) fn load_scene_file_from(
    path: &Path,
    files: &dyn SourceFiles,
    source: String,
) -> Result<LoadedScene> {
    load_scene_file_with(path, files, source, true)
}

/// [`load_scene_file_from`], merging coplanar faces only when both
/// `merge_coplanar` and the file's `merge_coplanar` (default true) allow it.
pub(crate) fn load_scene_file_with(
    path: &Path,
    files: &dyn SourceFiles,
    source: String,
    merge_coplanar: bool,
) -> Result<LoadedScene> {
    // Parse the TOML; errors carry the line.
    let text = files.read_to_string(path)?;
    let file: SceneFileToml = toml::from_str(&text).map_err(|e| Error::SceneFile {
        path: path.to_path_buf(),
        message: toml_message(&text, &e),
    })?;
    let file_error = |message: String| Error::SceneFile {
        path: path.to_path_buf(),
        message,
    };
    // Settings and camera first: cheap to check.
    let options = scene_options(file.solver, file.mesh).map_err(file_error)?;
    let camera = file
        .camera
        .map(camera_from_toml)
        .transpose()
        .map_err(file_error)?;
    // The OBJ, relative to this file; an unreadable OBJ is this file's error.
    let obj_path = path.parent().unwrap_or(Path::new("")).join(&file.obj);
    let merge = merge_coplanar && file.merge_coplanar.unwrap_or(true);
    let mut scene = load_obj_from(&obj_path, files, merge).map_err(|e| match e {
        Error::Io { path: p, source } if p == obj_path => {
            file_error(format!("obj = {:?}: {}: {source}", file.obj, p.display()))
        }
        other => other,
    })?;
    scene.camera = camera;
    Ok(LoadedScene {
        scene,
        options,
        source,
    })
}

/// A toml error as "line N: what", on one line.
fn toml_message(text: &str, error: &toml::de::Error) -> String {
    let what = error.message().trim();
    match error.span() {
        Some(span) => {
            let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
            format!("line {line}: {what}")
        }
        None => what.to_owned(),
    }
}

/// The `[camera]` table, with defaults, checked by [`Camera::validate`].
fn camera_from_toml(c: CameraToml) -> Result<Camera, String> {
    let camera = Camera {
        position: DVec3::from_array(c.position),
        look_at: DVec3::from_array(c.look_at),
        up: c.up.map_or(DVec3::Y, DVec3::from_array),
        vfov_deg: c.vfov_deg.unwrap_or(40.0),
        width: c.width.unwrap_or(512),
        height: c.height.unwrap_or(512),
    };
    camera.validate().map_err(|e| format!("[camera]: {e}"))?;
    Ok(camera)
}

/// The `[solver]` and `[mesh]` tables, range-checked.
fn scene_options(
    solver: Option<SolverToml>,
    mesh: Option<MeshToml>,
) -> Result<SceneOptions, String> {
    let tolerance = solver.and_then(|s| s.tolerance);
    if let Some(t) = tolerance
        && !(t > 0.0 && t < 1.0)
    {
        return Err(format!("[solver] tolerance = {t} is not in (0, 1)"));
    }
    let mesh = mesh.unwrap_or(MeshToml {
        kind: None,
        max_edge: None,
        elements_per_side: None,
    });
    if let Some(kind) = &mesh.kind
        && !MESH_KINDS.contains(&kind.as_str())
    {
        return Err(format!(
            "[mesh] kind = {kind:?} is not one of {}",
            MESH_KINDS.join(", ")
        ));
    }
    if let Some(e) = mesh.max_edge
        && !(e > 0.0 && e.is_finite())
    {
        return Err(format!("[mesh] max_edge = {e} is not a positive length"));
    }
    if mesh.elements_per_side == Some(0) {
        return Err("[mesh] elements_per_side must be at least 1".into());
    }
    Ok(SceneOptions {
        tolerance,
        mesh_kind: mesh.kind,
        max_edge: mesh.max_edge,
        elements_per_side: mesh.elements_per_side,
    })
}
