//! isorad: progressive hierarchical radiosity with a radial contour-level mesher.

mod error;
mod scene;

pub use error::{Error, Result};
pub use scene::{
    Camera, CameraFrame, CleanedPolygon, DEGENERATE_AREA_RATIO, LoadedScene, MESH_KINDS, Material,
    PLANARITY_TOLERANCE, PlaneFrame, PolygonPlane, Rgb, Scene, SceneOptions, Surface, Warning,
    best_fit_plane, builtin_names, clean_polygon, load_obj, load_scene, load_scene_file,
    newell_normal, polygon_diameter, project_onto_plane, remove_repeated_vertices, signed_area_2d,
    triangulate_polygon,
};
