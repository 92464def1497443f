//! isorad: progressive hierarchical radiosity with a radial contour-level mesher.

mod error;
mod mesh;
mod radiometry;
mod render;
mod scene;
mod solver;

pub use error::{Error, Result};
pub use mesh::{Cell, Element, Mesh, MeshVertex, Patch, SquareMeshSettings, mesh_square};
pub use radiometry::{disc_form_factor, polygon_form_factor};
pub use render::{
    Image, RenderSettings, ShadedTriangle, ToneMap, auto_exposure, mesh_triangles, rasterize,
    read_exr, srgb_encode, write_exr, write_png,
};
pub use scene::{
    Camera, CameraFrame, LoadedScene, Material, PlaneFrame, PolygonPlane, Rgb, Scene, SceneOptions,
    Surface, Visibility, Warning, best_fit_plane, builtin_names, load_obj, load_scene,
    load_scene_file, newell_normal, triangulate_polygon,
};
pub use solver::{EnergyBalance, Solver, SolverSettings};
