//! Rendering triangles: the Gouraud rasterizer, tone mapping, and the EXR
//! and PNG files.
//!
//! The rasterizer sees only [`ShadedTriangle`]s (positions and vertex
//! radiance); it knows nothing of meshing or solving (a solution's triangles
//! come from `view.rs`). Images hold linear radiance, W/(m²·sr); only
//! [`write_png`] applies a [`ToneMap`].

mod edge_refinement;
mod image;
mod output;
mod rasterizer;
mod sampling;
mod setup;
mod shaded_triangle;
mod tone_map;

pub use image::Image;
pub use output::{read_exr, write_exr, write_png};
pub use rasterizer::{RenderSettings, rasterize};
pub use shaded_triangle::ShadedTriangle;
pub use tone_map::{ToneMap, auto_exposure, srgb_encode};
