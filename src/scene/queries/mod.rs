//! Ray queries on a scene: shadow rays and closest hits over a BVH
//! ([`Visibility`]), the shadow cache, the shafts between two boxes and the
//! triangles that reach into them, and per-surface bounding boxes.

mod shadow_cache;
mod shaft;
mod shaft_queries;
mod surface_boxes;
mod visibility;

pub use shadow_cache::ShadowCache;
pub use surface_boxes::SurfaceBoxes;
pub use visibility::Visibility;
pub(crate) use visibility::surface_offset_for;
