//! Scenes: planar surfaces with diffuse materials, a camera, and loaders.

mod build;
mod camera;
mod load;
mod material;
pub(crate) mod plane_polygon;
pub(crate) mod polygon;
mod rgb;
pub(crate) mod surface;
mod surface_id;
pub(crate) mod triangulate;
mod visibility;

pub use camera::{Camera, CameraFrame};
pub use load::{
    LoadSettings, LoadedScene, MergeReport, ProbePoint, builtin_names, load_obj, load_probe_points,
    load_scene, load_scene_file, load_scene_with, merge_coplanar_faces, parse_probe_points,
};
pub use material::Material;
pub(crate) use plane_polygon::{distance_to_boundary, distance_to_segment, polygon_contains};
pub use polygon::PolygonPlane;
pub use rgb::Rgb;
pub use surface::{PlaneFrame, Surface};
pub use surface_id::SurfaceId;
pub(crate) use triangulate::triangulate_polygon;
pub use visibility::Visibility;

use glam::DVec3;

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
    /// What the loader repaired or skipped.
    pub warnings: Vec<Warning>,
}

impl Scene {
    /// Axis-aligned bounds (min, max) of all surfaces; zero for an empty scene.
    #[must_use]
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for p in self.surfaces.iter().flat_map(|s| s.vertices()) {
            min = min.min(*p);
            max = max.max(*p);
        }
        if min.x > max.x {
            (DVec3::ZERO, DVec3::ZERO)
        } else {
            (min, max)
        }
    }

    /// Length of the bounding box's diagonal: the scene's length scale.
    #[must_use]
    pub fn diagonal(&self) -> f64 {
        let (min, max) = self.bounds();
        (max - min).length()
    }

    /// The scene's camera, or one that frames the scene.
    #[must_use]
    pub fn camera_or_default(&self) -> Camera {
        self.camera.clone().unwrap_or_else(|| {
            let (min, max) = self.bounds();
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

/// Optional settings a scene file carries (its `[solver]` and `[mesh]`
/// tables). Each is `None` when the file leaves it out; the caller applies
/// its own defaults, then command-line flags.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneOptions {
    /// `[solver] tolerance`: stop when unshot power < tolerance × emitted power.
    pub tolerance: Option<f64>,
    /// `[mesh] kind`: "square", "adaptive" or "contour".
    pub mesh_kind: Option<String>,
    /// `[mesh] max_edge`: longest element edge, scene units.
    pub max_edge: Option<f64>,
    /// `[mesh] elements_per_side`: N for an N × N grid on every quad.
    pub elements_per_side: Option<usize>,
}
