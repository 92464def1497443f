//! isorad: progressive hierarchical radiosity with a radial contour-level mesher.

mod error;
mod mesh;
mod radiometry;
mod scene;
mod solver;

pub use error::{Error, Result};
pub use mesh::{Cell, Element, Mesh, MeshVertex, Patch, SquareMeshSettings, mesh_square};
pub use radiometry::{disc_form_factor, polygon_form_factor};
pub use scene::{
    Camera, CameraFrame, Material, PlaneFrame, Rgb, Scene, SceneOptions, Surface, Visibility,
    Warning, newell_normal,
};
pub use solver::{EnergyBalance, Solver, SolverSettings};
