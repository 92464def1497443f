//! The ambient term room by room.
//!
//! The ambient term (`solver/ambient/rays.rs`) holds, while an image is made, each
//! vertex ray's hit and landing point (6 bytes) and the element under it
//! (8 more), 96 rays a vertex: 1.3 KB a vertex, most of what a building
//! needs at that moment. A closed room's rays land only in that room, and its
//! sweeps read only its own vertices and elements, so the term is made
//! room by room: each closed zone's vertices, elements and patches
//! ([`Room`]), with its rays, landing elements, estimates and sweeps, and
//! what lies outside every closed zone as one more room. A mesh of more
//! than [`KEPT_VERTEX_RAYS`] vertex rays casts each room's rays for the
//! image and drops them after, so that one room's rays are held at a
//! time, and the term's memory is that of the largest room, not of the
//! building, for the same image pixel for pixel.
//!
//! The rare ray that leaks out of a closed room through a seam (a zone
//! stays closed while under 1/256 of the rays that find it leave,
//! `meshing/zones/labels.rs`) reads the patch it lands on at patch resolution, its
//! unshot radiosity and the light it will still reflect (`solver/ambient/rays.rs`);
//! in the term of some rooms alone, made for readings inside them (a
//! view, probes, a calculation grid: [`crate::solver::ReadingPlace`],
//! [`crate::Ambient::For`]), its unshot radiosity
//! alone.

use crate::mesh::Mesh;
use crate::scene::SurfaceId;
use crate::solver::ambient::patch_rays::PatchRays;
use crate::solver::ambient::rays::VERTEX_RAYS;
use crate::solver::ambient::vertex_rays::VertexRays;

/// The most vertex rays kept from one image to the next: 2²⁴, about
/// 175,000 vertices' (96 MiB). A larger mesh's rooms cast theirs for each
/// image and drop them after: a preview costs the rays again, but the
/// term's memory stays that of one room.
pub(crate) const KEPT_VERTEX_RAYS: usize = 1 << 24;

/// The ambient term's rays kept between images: the patches' (64 a
/// patch), and each room's vertex rays while the mesh's are at most
/// [`KEPT_VERTEX_RAYS`].
#[derive(Clone, Debug, Default)]
pub(crate) struct AmbientCache {
    pub(crate) patches: PatchRays,
    /// Each kept room's vertex rays, the last image's rooms first, in its
    /// order, then the other rooms', found again by their vertex lists
    /// (none while the mesh is too large to keep them).
    pub(crate) rooms: Vec<VertexRays>,
}

impl AmbientCache {
    /// Whether a mesh of `vertices` vertices keeps its rooms' rays.
    #[must_use]
    pub(crate) fn keeps(vertices: usize) -> bool {
        vertices.saturating_mul(VERTEX_RAYS) <= KEPT_VERTEX_RAYS
    }
}

/// The vertices, elements and patches of one room (a closed zone, or
/// everything outside the closed zones), each list ascending.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Room {
    pub(crate) vertices: Vec<u32>,
    pub(crate) elements: Vec<u32>,
    pub(crate) patches: Vec<u32>,
}

impl Room {
    /// The mesh's rooms, by `room_of(surface)` (below `count`; `None`: in
    /// no room listed): each room's members, in the order of the rooms'
    /// indices; rooms without a vertex are left out. What lies in no room
    /// listed is not copied, so one room of a building costs a pass over
    /// the mesh and its own members.
    #[must_use]
    pub(crate) fn all(
        mesh: &Mesh,
        count: usize,
        room_of: &dyn Fn(SurfaceId) -> Option<usize>,
    ) -> Vec<Room> {
        let mut rooms = vec![Room::default(); count.max(1)];
        let mut list = |surfaces: &mut dyn Iterator<Item = SurfaceId>,
                        members: fn(&mut Room) -> &mut Vec<u32>| {
            for (k, surface) in surfaces.enumerate() {
                if let Some(room) = room_of(surface).and_then(|r| rooms.get_mut(r)) {
                    members(room).push(k as u32);
                }
            }
        };
        list(&mut mesh.vertices.iter().map(|v| v.surface), |r| {
            &mut r.vertices
        });
        list(&mut mesh.elements.iter().map(|e| e.surface), |r| {
            &mut r.elements
        });
        list(&mut mesh.patches.iter().map(|p| p.surface), |r| {
            &mut r.patches
        });
        rooms.retain(|room| !room.vertices.is_empty());
        rooms
    }

    /// The whole mesh as one room.
    #[must_use]
    pub(crate) fn whole(mesh: &Mesh) -> Room {
        Room::all(mesh, 1, &|_| Some(0)).pop().unwrap_or_default()
    }
}

/// A room whose members [`LocalIndex`] has entered: what the ambient term
/// reads of the room it is working on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RoomView<'a> {
    pub(crate) room: &'a Room,
    /// Each member's place in the room's lists.
    pub(crate) local: &'a LocalIndex,
}

/// Each vertex's, element's and patch's index in the room being worked on
/// ([`LocalIndex::enter`]), or none: what lies outside it.
///
/// Each is kept plus one, zero outside: the lists start as zeroed memory,
/// which the system maps only where rooms write. The term of one office of
/// a building then holds a few pages of them, not 4 bytes for each of the
/// building's vertices, elements and patches (165 MB for a million quads).
#[derive(Clone, Debug)]
pub(crate) struct LocalIndex {
    vertex: Vec<u32>,
    element: Vec<u32>,
    patch: Vec<u32>,
}

/// Not in the room.
const OUTSIDE: u32 = 0;

impl LocalIndex {
    /// Nothing entered yet, for a mesh as large as `mesh`.
    #[must_use]
    pub(crate) fn new(mesh: &Mesh) -> LocalIndex {
        LocalIndex {
            vertex: vec![OUTSIDE; mesh.vertices.len()],
            element: vec![OUTSIDE; mesh.elements.len()],
            patch: vec![OUTSIDE; mesh.patches.len()],
        }
    }

    /// Indexes `room`'s members by their places in its lists.
    pub(crate) fn enter(&mut self, room: &Room) {
        let number = |index: &mut [u32], members: &[u32]| {
            for (i, &m) in members.iter().enumerate() {
                index[m as usize] = i as u32 + 1;
            }
        };
        number(&mut self.vertex, &room.vertices);
        number(&mut self.element, &room.elements);
        number(&mut self.patch, &room.patches);
    }

    /// Forgets `room`'s members (the one entered last), in the time of its
    /// size, not the mesh's.
    pub(crate) fn leave(&mut self, room: &Room) {
        let clear = |index: &mut [u32], members: &[u32]| {
            for &m in members {
                index[m as usize] = OUTSIDE;
            }
        };
        clear(&mut self.vertex, &room.vertices);
        clear(&mut self.element, &room.elements);
        clear(&mut self.patch, &room.patches);
    }

    /// Vertex v's index in the room entered, if it belongs to it.
    pub(crate) fn vertex(&self, v: usize) -> Option<usize> {
        Self::local(&self.vertex, v)
    }

    /// Element e's index in the room entered, if it belongs to it.
    pub(crate) fn element(&self, e: usize) -> Option<usize> {
        Self::local(&self.element, e)
    }

    /// Patch p's index in the room entered, if it belongs to it.
    pub(crate) fn patch(&self, p: usize) -> Option<usize> {
        Self::local(&self.patch, p)
    }

    fn local(index: &[u32], k: usize) -> Option<usize> {
        index
            .get(k)
            .filter(|&&i| i != OUTSIDE)
            .map(|&i| i as usize - 1)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    /// Two unit quads on surfaces 0 and 1, one patch each.
    fn two_quads() -> Mesh {
        let mut mesh = Mesh::default();
        for s in 0..2 {
            let x = s as f64 * 2.0;
            let corners = [
                DVec3::new(x, 0.0, 0.0),
                DVec3::new(x + 1.0, 0.0, 0.0),
                DVec3::new(x + 1.0, 1.0, 0.0),
                DVec3::new(x, 1.0, 0.0),
            ];
            let surface = SurfaceId::new(s);
            let v: Vec<u32> = corners
                .iter()
                .map(|&c| mesh.add_vertex(c, surface))
                .collect();
            let cell = crate::mesh::Cell::quad(corners[0], corners[1], corners[2], corners[3]);
            let patch = mesh.add_patch(surface, cell);
            mesh.add_element(&[v[0], v[1], v[2], v[3]], patch);
        }
        mesh
    }

    #[test]
    fn rooms_list_their_members_and_the_index_forgets_them() {
        let mesh = two_quads();
        let rooms = Room::all(&mesh, 3, &|s| Some(2 * s.index()));
        // Room 1 holds nothing and is left out.
        assert_eq!(rooms.len(), 2);
        assert_eq!(rooms[1].vertices, vec![4, 5, 6, 7]);
        assert_eq!(
            (rooms[1].elements.clone(), rooms[1].patches.clone()),
            (vec![1], vec![1])
        );
        let mut local = LocalIndex::new(&mesh);
        local.enter(&rooms[1]);
        assert_eq!(local.vertex(6), Some(2));
        assert_eq!(
            (local.vertex(0), local.element(1), local.patch(0)),
            (None, Some(0), None)
        );
        local.leave(&rooms[1]);
        assert_eq!(
            (local.vertex(6), local.element(1), local.vertex(99)),
            (None, None, None)
        );
        assert_eq!(Room::whole(&mesh).vertices.len(), 8);
        // A room listed alone: the other surfaces' members are in none.
        let picked = Room::all(&mesh, 1, &|s| (s.index() == 1).then_some(0));
        assert_eq!(picked, vec![rooms[1].clone()]);
    }
}
