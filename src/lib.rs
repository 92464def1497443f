//! isorad: progressive hierarchical radiosity with a radial contour-level mesher.

mod error;
mod render;
mod scene;

pub use error::{Error, Result};
pub use render::{
    Image, RenderSettings, ShadedTriangle, ToneMap, auto_exposure, rasterize, read_exr,
    srgb_encode, write_exr, write_png,
};
pub use scene::{
    Camera, CameraFrame, Material, PlaneFrame, Rgb, Scene, SceneOptions, Surface, Warning,
    newell_normal,
};
