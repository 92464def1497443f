//! A mesh's vertices, elements and patches listed zone by zone, and where
//! a shot into one zone keeps each vertex's value.

use super::Zones;
use crate::mesh::Mesh;

/// The vertices, elements and patches of a mesh, zone by zone, so that a
/// shot visits only its own zone's. Rebuilt after [`ZoneMembers::invalidate`]
/// (adaptive refinement renumbers the elements) or when the mesh's counts
/// changed since.
#[derive(Clone, Debug, Default)]
pub struct ZoneMembers {
    /// Vertex indices per zone.
    pub vertices: Vec<Vec<u32>>,
    /// Element indices per zone.
    pub elements: Vec<Vec<u32>>,
    /// Patch indices per zone.
    pub patches: Vec<Vec<u32>>,
    /// Each vertex's place in its zone's list of `vertices`: where a shot
    /// into that zone keeps its value.
    places: Vec<u32>,
    /// The mesh's vertex and element counts when these were listed.
    listed: (usize, usize),
}

impl ZoneMembers {
    /// Marks the lists stale: the mesh changed.
    pub fn invalidate(&mut self) {
        self.vertices.clear();
    }

    /// Lists `mesh`'s members by zone again if they are stale or the mesh
    /// changed size since.
    pub fn refresh(&mut self, zones: &Zones, mesh: &Mesh) {
        let counts = (mesh.vertices.len(), mesh.elements.len());
        if counts == self.listed && !self.vertices.is_empty() {
            return;
        }
        self.vertices = vec![Vec::new(); zones.count().max(1)];
        self.elements = vec![Vec::new(); zones.count().max(1)];
        self.patches = vec![Vec::new(); zones.count().max(1)];
        self.places.clear();
        for (v, vertex) in mesh.vertices.iter().enumerate() {
            let list = &mut self.vertices[zones.of(vertex.surface)];
            self.places.push(list.len() as u32);
            list.push(v as u32);
        }
        for (e, element) in mesh.elements.iter().enumerate() {
            self.elements[zones.of(element.surface)].push(e as u32);
        }
        for (p, patch) in mesh.patches.iter().enumerate() {
            self.patches[zones.of(patch.surface)].push(p as u32);
        }
        self.listed = counts;
    }

    /// Each vertex's place in its zone's list of vertices.
    #[must_use]
    pub fn places(&self) -> &[u32] {
        &self.places
    }
}

/// Where a shot keeps each vertex's value in its buffers: at the vertex's
/// place in its closed zone's list when the shot lights one zone, so that
/// a shot in one room of a building holds that room's vertices alone, else
/// at the vertex's own index.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShotPlaces<'a>(pub(crate) Option<&'a [u32]>);

impl<'a> ShotPlaces<'a> {
    /// The places of a shot into closed zone `zone` (listed in `members`),
    /// or into every vertex.
    pub(crate) fn new(zone: Option<usize>, members: Option<&'a ZoneMembers>) -> ShotPlaces<'a> {
        ShotPlaces(zone.and(members).map(ZoneMembers::places))
    }

    /// Where vertex v's value is kept.
    pub(crate) fn of(self, v: u32) -> usize {
        match self.0 {
            Some(places) => places[v as usize] as usize,
            None => v as usize,
        }
    }
}
