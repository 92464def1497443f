//! Scene files (TOML): an OBJ scene plus camera, solver and mesh settings.
//!
//! ```toml
//! obj = "cornell/cornell.obj"          # required, relative to this file
//! merge_coplanar = true                # default: merge adjacent coplanar faces
//! two_sided = ["WhitePaint"]           # optional: these materials' faces lit from both sides
//!                                      #   (`true`: every face; see `two_sided.rs`)
//! [camera]                             # optional: default frames the scene
//! position = [278.0, 273.0, -800.0]    # required in [camera]
//! look_at  = [278.0, 273.0, 0.0]       # required in [camera]
//! up       = [0.0, 1.0, 0.0]           # default [0, 1, 0]
//! vfov_deg = 39.3                      # default 40
//! width    = 512                       # default 512
//! height   = 512                       # default 512
//! [sky]                                # optional: daylight (see `sky_tables.rs`)
//! model = "cie_overcast"
//! [sun]                                # optional: the sun (see `sky_tables.rs`)
//! [glazing]                            # optional: materials made glazing by name
//! "Glass_Clear" = 0.78                 #   (see `glazing_table.rs`)
//! [solver]                             # optional; every key defaulted
//! tolerance = 0.01                     # stop when unshot power < 1 % of emitted
//! max_shots = 1000000                  # stop after this many shots
//! direct_samples = 64                  # samples per patch for the brightest shooters
//! max_samples = 256                    # most samples per patch and vertex (≤ 65536)
//! sample_density = 3.0                 # samples grow as (density · √A / r)²
//! kernel = "mixed"                     # "mixed" | "wallace" | "exact"
//! [mesh]                               # optional; every key defaulted
//! kind = "contour"                     # "square" (default) | "contour" | "adaptive"
//! max_edge = 50.0                      # longest element edge (default 1/40 of the diagonal)
//! patch_max_edge = { of_diagonal = 0.125 } # longest patch edge (default 1/8 of it)
//! elements_per_side = 10               # N × N grid on every quad, instead of max_edge
//! max_elements = 5000000               # refuse a larger mesh (counted before meshing)
//! max_shadow_boundaries = 256          # the most shadow boundaries one face gets
//! [mesh.contour]                       # the contour mesher
//! directions = 16                      # D rays from the light's maximum
//! levels = 8                           # K contour levels
//! [mesh.dominance]                     # which receivers get the contour mesher
//! min_share = 0.6                      # the luminaire's least share of the direct light
//! max_size_ratio = 0.25                # its largest radius / distance
//! sample_points = 16                   # points per receiver estimating the shares
//! shadow_rays = 4                      # shadow rays per luminaire polygon and point
//! [mesh.refinement]                    # the adaptive mesher
//! threshold = 1.0                      # split where gradient jump × size > this × radiosity
//! floor = 0.05                         # darker than this × the mean counts as this
//! max_levels = 3                       # halvings of a starting element (≤ 16)
//! coarsening = 1.0                     # starting elements this many times max_edge (≥ 1)
//! max_vertices = 2000000               # stop splitting at this many vertices
//! ```
//!
//! A length (`max_edge`, `patch_max_edge`) is a bare number in scene units,
//! or a fraction of the scene's bounding diagonal written
//! `{ of_diagonal = 0.025 }`. Sub-tables may also be written inline or
//! with dotted keys (`refinement.threshold = 0.5` under `[mesh]`).
//!
//! Unknown keys are errors (a typo must not be silently ignored). This
//! loader checks the top-level keys and the camera; the `[mesh]` and
//! `[solver]` tables are kept as written in [`LoadedScene::options`] and
//! read by `Settings::from_scene_options` (in the solver layer, which owns
//! those settings), whose errors name the file, the line and the field
//! path (`mesh.refinement.threshold`).

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::Deserialize;
use toml::Spanned;

use crate::error::{Error, Result};

use super::build::check_not_empty;
use super::glazing_table::{GlazingToml, apply_glazing};
use super::loaded::LoadedScene;
use super::luminaire_tables::{LuminaireTables, LuminaireToml};
use super::obj::load_obj_from;
use super::sky_tables::{SkyTables, SkyToml, SunToml};
use super::source::{Disk, SourceFiles, line_at};
use super::two_sided::{TwoSidedToml, apply_two_sided};
use crate::scene::{Camera, SceneOptions};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFileToml {
    obj: PathBuf,
    merge_coplanar: Option<bool>,
    two_sided: Option<Spanned<TwoSidedToml>>,
    camera: Option<CameraToml>,
    /// Read by the solver layer; here only checked to be a table.
    #[serde(rename = "solver")]
    _solver: Option<toml::Table>,
    /// Read by the solver layer; here only checked to be a table.
    #[serde(rename = "mesh")]
    _mesh: Option<toml::Table>,
    luminaire: Option<Vec<LuminaireToml>>,
    sky: Option<Spanned<SkyToml>>,
    glazing: Option<GlazingToml>,
    sun: Option<Spanned<SunToml>>,
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

/// Loads a scene file and the OBJ scene it names. The scene's camera is the
/// file's `[camera]` (validated) if any; its `[solver]` and `[mesh]` tables
/// come back, unread, in [`LoadedScene::options`].
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
    // The camera first: cheap to check.
    let camera = file
        .camera
        .map(camera_from_toml)
        .transpose()
        .map_err(file_error)?;
    // The OBJ, relative to this file; an unreadable OBJ is this file's error.
    let obj_path = path.parent().unwrap_or(Path::new("")).join(&file.obj);
    let merge = merge_coplanar && file.merge_coplanar.unwrap_or(true);
    let luminaire_tables = file.luminaire.unwrap_or_default();
    let lit_elsewhere = !luminaire_tables.is_empty() || file.sky.is_some() || file.sun.is_some();
    let mut scene = load_obj_from(&obj_path, files, merge, lit_elsewhere).map_err(|e| match e {
        Error::Io { path: p, source } if p == obj_path => {
            file_error(format!("obj = {:?}: {}: {source}", file.obj, p.display()))
        }
        other => other,
    })?;
    scene.camera = camera;
    if let Some(spec) = &file.two_sided {
        apply_two_sided(&mut scene, spec, path, &text)?;
        // Twins of emitting faces on many planes make bodies of their own.
        scene.join_emitting_bodies();
    }
    // The luminaires, each file read once (see `luminaire_tables`).
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut luminaires = LuminaireTables::new(path, &text, folder);
    for (k, table) in luminaire_tables.iter().enumerate() {
        scene.luminaires.push(luminaires.read(k + 1, table)?);
    }
    if let Some(glazing) = &file.glazing {
        apply_glazing(&mut scene, glazing, path, &text)?;
    }
    let sky_tables = SkyTables { path, text: &text };
    scene.daylight = sky_tables.read(file.sky.as_ref(), file.sun.as_ref())?;
    check_not_empty(&obj_path, &scene)?;
    Ok(LoadedScene {
        scene,
        options: SceneOptions::from_scene_file(path.to_path_buf(), text),
        source,
    })
}

/// A toml error as "line N: what", on one line.
fn toml_message(text: &str, error: &toml::de::Error) -> String {
    let what = error.message().trim();
    match error.span() {
        Some(span) => format!("line {}: {what}", line_at(text, span.start)),
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
