//! Rendering a solution: the Gouraud rasterizer, tone mapping, and the EXR
//! and PNG writers; and the pictures that compare meshers: log–log plots
//! ([`write_loglog_plot`]) and meshes side by side ([`write_mesh_panels`]).
//!
//! The rasterizer sees only [`ShadedTriangle`]s (positions and vertex
//! radiance); it knows nothing of meshing or solving. The plot and panel
//! writers likewise take plain data (points, values, triangles). Images hold linear
//! radiance, W/(m²·sr); only [`write_png`] applies a [`ToneMap`].

mod font;
mod image;
mod mesh_image;
mod mesh_triangles;
mod output;
mod plot;
mod rasterizer;
mod setup;
mod tone_map;
mod view;

pub use image::Image;
pub use mesh_image::{MeshPanel, write_mesh_panels};
pub use mesh_triangles::mesh_triangles;
pub(crate) use output::write_atomically;
pub use output::{read_exr, write_exr, write_png};
pub use plot::{Series, write_loglog_plot};
pub use rasterizer::{RenderSettings, ShadedTriangle, rasterize};
pub use tone_map::{ToneMap, auto_exposure, srgb_encode};
