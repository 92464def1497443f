//! Rendering a solution: the Gouraud rasterizer, tone mapping, and the EXR
//! and PNG writers.
//!
//! The rasterizer sees only [`ShadedTriangle`]s (positions and vertex
//! radiance); it knows nothing of meshing or solving. Images hold linear
//! radiance, W/(m²·sr); only [`write_png`] applies a [`ToneMap`].

mod image;
mod mesh_triangles;
mod output;
mod rasterizer;
mod setup;
mod tone_map;

pub use image::Image;
pub use mesh_triangles::mesh_triangles;
pub use output::{read_exr, write_exr, write_png};
pub use rasterizer::{RenderSettings, ShadedTriangle, rasterize};
pub use tone_map::{ToneMap, auto_exposure, srgb_encode};
