//! Polygon geometry: planar polygons in 3D (cleaning, best-fit planes),
//! predicates and distances on plane polygons, their triangulation, and
//! axis-aligned boxes.

mod box3;
pub(crate) mod plane_polygon;
pub(crate) mod polygon;
pub(crate) mod repair;
pub(crate) mod triangulate;

pub use box3::Box3;
pub(crate) use plane_polygon::{
    clip_segment_to_polygon, distance_to_boundary, distance_to_segment, polygon_contains,
    segment_parameter,
};
pub(crate) use triangulate::triangulate_polygon;
