//! isorad: progressive hierarchical radiosity with a radial contour-level mesher.

mod error;
mod scene;

pub use error::{Error, Result};
pub use scene::{
    Camera, CameraFrame, Material, PlaneFrame, Rgb, Scene, SceneOptions, Surface, Warning,
    newell_normal,
};
