//! Axis-aligned boxes in world coordinates.

use glam::DVec3;

/// An axis-aligned box, from its least corner `min` to its greatest `max`:
/// a patch's receiving points, a lamp, the region a shaft joins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Box3 {
    /// The least corner.
    pub min: DVec3,
    /// The greatest corner.
    pub max: DVec3,
}

impl Box3 {
    /// The box from `min` to `max`.
    #[must_use]
    pub const fn new(min: DVec3, max: DVec3) -> Box3 {
        Box3 { min, max }
    }
}
