//! Scenes: planar surfaces with diffuse materials, a camera, and loaders.

mod camera;
mod emitting_body;
pub(crate) mod geometry;
mod load;
mod luminaire;
mod material;
pub(crate) mod queries;
pub(crate) mod surface;
mod surface_id;

pub use camera::{Camera, CameraFrame};
pub use emitting_body::{
    BLEND_RADII, BODY_SAMPLES, BodySample, EmittingBody, MAX_EXACT_FACES, NEAR_RADII,
};
pub use geometry::Box3;
pub(crate) use geometry::{
    clip_segment_to_polygon, distance_to_boundary, distance_to_segment, polygon_contains,
    segment_parameter, triangulate_polygon,
};
pub use load::{
    LoadSettings, LoadedScene, MergeReport, ProbePoint, builtin_names, load_obj, load_probe_points,
    load_scene, load_scene_file, load_scene_with, merge_coplanar_faces, parse_probe_points,
};
pub use luminaire::{OPENING_SAMPLES, PhotometricLuminaire};
pub use material::Material;
pub(crate) use queries::surface_offset_for;
pub use queries::{ShadowCache, SurfaceBoxes, Visibility};
pub use surface::{PlaneFrame, Surface};
pub use surface_id::SurfaceId;

use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::daylight::Daylight;
use crate::rgb::Rgb;

/// Something a loader noticed and repaired or skipped, for the user to read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// What happened, naming the file and object.
    pub message: String,
}

/// A diffuse polygonal scene: surfaces, their materials, and an optional camera.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Planar one-sided polygons.
    pub surfaces: Vec<Surface>,
    /// Materials, indexed by [`Surface::material`].
    pub materials: Vec<Material>,
    /// The camera, if the scene defines one.
    pub camera: Option<Camera>,
    /// Luminaires from photometric files (a scene file's `[[luminaire]]`),
    /// lighting the scene besides its emitting faces.
    pub luminaires: Vec<PhotometricLuminaire>,
    /// The sky, sun and ground outside (a scene file's `[sky]` and
    /// `[sun]`), lighting the scene through its openings and glazing.
    pub daylight: Option<Daylight>,
    /// What the loader repaired or skipped.
    pub warnings: Vec<Warning>,
}

impl Scene {
    /// Axis-aligned bounds of all surfaces; zero for an empty scene.
    #[must_use]
    pub fn bounds(&self) -> Box3 {
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for p in self.surfaces.iter().flat_map(|s| s.vertices()) {
            min = min.min(*p);
            max = max.max(*p);
        }
        if min.x > max.x {
            Box3::new(DVec3::ZERO, DVec3::ZERO)
        } else {
            Box3::new(min, max)
        }
    }

    /// Length of the bounding box's diagonal: the scene's length scale.
    #[must_use]
    pub fn diagonal(&self) -> f64 {
        let Box3 { min, max } = self.bounds();
        (max - min).length()
    }

    /// The scene's camera, or one that frames the scene.
    #[must_use]
    pub fn camera_or_default(&self) -> Camera {
        self.camera.clone().unwrap_or_else(|| {
            let Box3 { min, max } = self.bounds();
            Camera::framing(min, max)
        })
    }

    /// The surface `id` names.
    ///
    /// # Panics
    /// When `id` is not a surface of this scene.
    #[must_use]
    pub fn surface(&self, id: SurfaceId) -> &Surface {
        &self.surfaces[id.index()]
    }

    /// Every surface with its id, in order.
    pub fn surfaces_with_ids(&self) -> impl ExactSizeIterator<Item = (SurfaceId, &Surface)> {
        self.surfaces
            .iter()
            .enumerate()
            .map(|(index, surface)| (SurfaceId::new(index), surface))
    }

    /// The first surface called `name`, if any.
    #[must_use]
    pub fn surface_named(&self, name: &str) -> Option<SurfaceId> {
        self.surfaces_with_ids()
            .find(|(_, surface)| surface.name == name)
            .map(|(id, _)| id)
    }

    /// The material of a surface.
    #[must_use]
    pub fn material_of(&self, surface: &Surface) -> &Material {
        &self.materials[surface.material]
    }

    /// Total emitted power Φ = Σ π L_e A over emitting surfaces, per channel
    /// (W when lengths are in metres and L_e in W/(m²·sr)).
    #[must_use]
    pub fn emitted_power(&self) -> Rgb {
        self.surfaces
            .iter()
            .map(|s| self.material_of(s).emitted_radiosity() * s.area())
            .sum()
    }
}

/// The settings a scene file carries, its `[mesh]` and `[solver]` tables,
/// as written. The scene layer knows nothing of the solver's settings, so it
/// keeps the file's path and text; [`crate::Settings::from_scene_options`]
/// reads the two tables from them, and its messages give the file, the line
/// and the setting's field path. The scene loader has already checked that
/// the file is TOML, that its top-level keys are known and that `[mesh]` and
/// `[solver]` are tables.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneOptions {
    /// The scene file and its text (a built-in scene's embedded file);
    /// `None` for an OBJ file, which carries no settings.
    file: Option<(PathBuf, String)>,
}

impl SceneOptions {
    /// The options of the scene file at `path`, whose text is `text`.
    #[must_use]
    pub(crate) fn from_scene_file(path: PathBuf, text: String) -> SceneOptions {
        SceneOptions {
            file: Some((path, text)),
        }
    }

    /// The scene file, if the scene came from one.
    #[must_use]
    pub fn path(&self) -> Option<&Path> {
        self.file.as_ref().map(|(path, _)| path.as_path())
    }

    /// The scene file's text (empty without a file: no settings).
    #[must_use]
    pub fn text(&self) -> &str {
        self.file.as_ref().map_or("", |(_, text)| text.as_str())
    }
}
