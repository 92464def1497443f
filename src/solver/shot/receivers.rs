//! The receivers of one shot: its closed zone's vertices and elements (or
//! the whole mesh's), and where each vertex keeps its light in the shot's
//! buffers.

use crate::meshing::ShotPlaces;

/// The vertices and elements a shot reaches, each list ascending.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShotReceivers<'a> {
    /// The receiving vertices: the k-th keeps its light at place k.
    pub(crate) vertices: &'a [u32],
    /// The receiving elements, whose corners are among `vertices`.
    pub(crate) elements: &'a [u32],
    /// Where each vertex keeps its light.
    pub(crate) places: ShotPlaces<'a>,
}
