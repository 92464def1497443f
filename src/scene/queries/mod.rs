//! Ray queries on a scene: shadow rays over a BVH ([`Visibility`]), the
//! shafts between two segments, and per-surface bounding boxes.

mod shaft;
mod shaft_queries;
mod surface_boxes;
mod visibility;

pub use surface_boxes::SurfaceBoxes;
pub(crate) use visibility::surface_offset_for;
pub use visibility::{ShadowCache, Visibility};
