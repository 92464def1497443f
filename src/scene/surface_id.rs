//! The name of a surface: its index in the scene, as a type of its own.

use std::fmt;

/// A surface of a [`crate::Scene`]: its index in [`crate::Scene::surfaces`].
/// Four bytes, so that every mesh vertex and element can carry one.
/// [`crate::Scene::surface`] looks the surface up.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SurfaceId(u32);

impl SurfaceId {
    /// The surface at `index` in [`crate::Scene::surfaces`].
    ///
    /// # Panics
    /// When `index` does not fit in 32 bits (no scene holds 2³² surfaces).
    #[must_use]
    pub const fn new(index: usize) -> SurfaceId {
        assert!(
            index <= u32::MAX as usize,
            "a surface index fits in 32 bits"
        );
        SurfaceId(index as u32)
    }

    /// An id that no surface has: the end of a shadow ray at a point in
    /// free space (a work-plane point), which no surface must be ignored for.
    pub const NONE: SurfaceId = SurfaceId(u32::MAX);

    /// The index in [`crate::Scene::surfaces`].
    #[must_use]
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

/// The index, as a seed for a random stream.
impl From<SurfaceId> for u64 {
    fn from(id: SurfaceId) -> u64 {
        u64::from(id.0)
    }
}

/// The index, as a number.
impl fmt::Display for SurfaceId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_bytes_printed_as_the_index() {
        assert_eq!(std::mem::size_of::<SurfaceId>(), 4);
        let id = SurfaceId::new(42);
        assert_eq!(id.index(), 42);
        assert_eq!(id.to_string(), "42");
        assert_eq!(u64::from(id), 42);
        assert!(SurfaceId::new(3) < SurfaceId::new(4));
    }
}
