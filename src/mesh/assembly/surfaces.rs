//! Meshing a whole scene: every surface gets its square grid of patches,
//! re-triangulated where a contour layout is given or where another surface
//! stands on it (contact lines), with the hidden parts under objects dropped
//! and boundary vertices moved just inside their surface to gather.
//!
//! Every mesher's output passes through here ([`mesh_surfaces`]); the square
//! mesher is the assembly with no contour layouts ([`mesh_square`]).

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::contacts::{
    CONTACT_TOLERANCE, Contact, ContactDistances, contact_segments, gather_beside_covering_outlines,
};
use super::hidden::remove_hidden_elements;
use super::remesh::remesh_surface;
use crate::mesh::data::topology::Mesh;
use crate::mesh::meshers::contour::ContourLayout;
use crate::mesh::meshers::square::{SquareMeshSettings, square_grid};
use crate::phase::{Phase, PhaseCounter, PhaseReporter, silent};
use crate::scene::{Scene, Surface, SurfaceBoxes, SurfaceId, Visibility, surface_offset_for};

/// How far boundary vertices gather inside their surface, as a fraction of
/// the diagonal of the surface's room (its closed zone) or of the scene.
const RECEIVER_INSET: f64 = 1e-4;

/// The most a boundary vertex is moved inside, as a fraction of that
/// diagonal, unless two ray offsets of the scene are more (a cupboard's
/// inside in a building).
const MAX_RECEIVER_INSET: f64 = 1e-3;

/// The least a boundary vertex is moved inside, in shadow rays' surface
/// offsets ([`crate::scene::Visibility::surface_offset`], a fraction of the
/// scene's diagonal, 34 times the f32 rounding of the BVH's coordinates),
/// so that a ray from a vertex at a wall's foot starts clear of the wall
/// in a scene many times its room's size.
const INSET_IN_RAY_OFFSETS: f64 = 2.0;

/// The distance boundary vertices gather inside their surface, in the
/// scene (see [`ReceiverInset`]).
#[must_use]
pub fn receiver_inset(scene: &Scene) -> f64 {
    ReceiverInset::new(scene).within(None)
}

/// The distance boundary vertices gather inside their surface: a
/// ten-thousandth of the diagonal of the surface's room, or twice the
/// largest projection offset of a nearly planar face if larger, since a
/// neighbour's projected plane may cut that far across the corner it shares
/// with the vertex's surface (the Cornell box's red wall moves by 0.4 mm);
/// at least two shadow-ray offsets of the scene.
///
/// The room's diagonal, not the building's, as for the contact tolerance
/// ([`SurfaceGuides::contact_scale`]): a ten-thousandth of a large
/// building's diagonal moves boundary vertices centimetres inside, past a
/// shelf's front edge and a book's spine, and draws lines along a room's
/// edges; its room's (with reflected shots' shafts keeping a rim as wide,
/// `solver/shot/shaft_culling.rs`) keeps them within a millimetre. The projection offset stays the whole scene's
/// largest: one bent face anywhere moves every room's boundary
/// vertices as far, up to a thousandth of the room's diagonal.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ReceiverInset {
    /// Twice the largest projection offset of the scene's faces.
    projection: f64,
    /// The scene's diagonal.
    diagonal: f64,
}

impl ReceiverInset {
    /// The inset's rule for `scene`.
    pub(crate) fn new(scene: &Scene) -> ReceiverInset {
        let offset = scene
            .surfaces
            .iter()
            .map(Surface::projection_offset)
            .fold(0.0, f64::max);
        ReceiverInset {
            projection: 2.0 * offset,
            diagonal: scene.diagonal(),
        }
    }

    /// The inset in a room of diagonal `room` (`None`: the scene's).
    pub(crate) fn within(&self, room: Option<f64>) -> f64 {
        let scale = room.unwrap_or(self.diagonal).min(self.diagonal).max(0.0);
        let least = INSET_IN_RAY_OFFSETS * surface_offset_for(self.diagonal);
        self.projection
            .clamp(RECEIVER_INSET * scale, MAX_RECEIVER_INSET * scale)
            .max(least)
    }
}

/// Meshes every surface of the scene uniformly. Where another surface
/// stands on one (a block on a floor), the grid is re-triangulated with
/// element edges along the contact lines, and the elements hidden under the
/// object are dropped (see `mesh/assembly/contacts.rs`).
#[must_use]
pub fn mesh_square(scene: &Scene, settings: &SquareMeshSettings) -> Mesh {
    mesh_surfaces(scene, settings, &|_| SurfaceGuides::default())
}

/// What a mesher adds to one surface's square grid, in the surface's plane
/// coordinates.
#[derive(Clone, Debug, Default)]
pub struct SurfaceGuides {
    /// A contour layout, whose points and pieces replace the grid's points.
    pub layout: Option<ContourLayout>,
    /// Lines that element edges follow: the shadow boundaries the lights
    /// cast on the surface (see `lighting::shadow_boundaries`).
    pub boundaries: Vec<[DVec2; 2]>,
    /// The length the contact tolerance is a thousandth of, and the
    /// boundary vertices' inset a ten-thousandth (`ReceiverInset`): the
    /// diagonal of the surface's room (its closed zone), or, where `None`,
    /// of the whole scene. A building's
    /// rooms are then meshed as each would be alone: at a thousandth of a
    /// floor's diagonal, 65 mm for 64 offices, the books' millimetre slots
    /// and their 2 cm from the wall counted as contacts.
    pub contact_scale: Option<f64>,
}

/// Meshes every surface: a contour layout where `guides` gives one, the
/// square grid elsewhere, with element edges along the shadow boundaries it
/// gives, and contact lines and hidden parts handled as [`mesh_square`]
/// does. Patches are the square grid's blocks either way. Surfaces are
/// meshed in parallel and appended in the scene's order, so the mesh is
/// the same on any number of threads.
#[must_use]
pub fn mesh_surfaces(
    scene: &Scene,
    settings: &SquareMeshSettings,
    guides: &(dyn Fn(SurfaceId) -> SurfaceGuides + Sync),
) -> Mesh {
    mesh_surfaces_counted(scene, None, settings, guides, &silent).0
}

/// [`mesh_surfaces`], reporting its progress surface by surface, and one
/// unit more once the hidden parts are dropped; with how far each
/// surface's boundary vertices gather inside it (by surface index:
/// [`ReceiverInset`] in its room, `guides`' contact scale). The hidden
/// parts are found through the scene's BVH ([`Visibility::new`]) when it
/// is given, else through one built for them.
pub(crate) fn mesh_surfaces_counted(
    scene: &Scene,
    visibility: Option<&Visibility>,
    settings: &SquareMeshSettings,
    guides: &(dyn Fn(SurfaceId) -> SurfaceGuides + Sync),
    report: PhaseReporter,
) -> (Mesh, Vec<f64>) {
    let counter = PhaseCounter::start(Phase::Meshing, scene.surfaces.len() + 1, report);
    let diagonal = scene.diagonal();
    let rule = ReceiverInset::new(scene);
    let boxes = SurfaceBoxes::new(scene);
    let mut mesh = Mesh::default();
    let mut touched = Vec::new();
    let mut covering = Vec::new();
    let mut insets = Vec::with_capacity(scene.surfaces.len());
    // A batch of surfaces at a time, so that the surfaces' own meshes
    // never all wait beside the whole.
    let ids: Vec<SurfaceId> = scene.surfaces_with_ids().map(|(id, _)| id).collect();
    for batch in ids.chunks(MESHING_BATCH) {
        let meshed: Vec<MeshedSurface> = batch
            .par_iter()
            .map(|&id| {
                let guides = guides(id);
                let distances = ContactDistances {
                    tolerance: CONTACT_TOLERANCE * guides.contact_scale.unwrap_or(diagonal),
                    inset: rule.within(guides.contact_scale),
                };
                let meshed = mesh_surface(scene, &boxes, id, &guides, distances, settings);
                counter.add(1);
                meshed
            })
            .collect();
        for (&id, surface) in batch.iter().zip(meshed) {
            mesh.append(surface.mesh);
            insets.push(surface.inset);
            if surface.touched {
                touched.push((id, surface.tolerance));
            }
            if !surface.covering.is_empty() {
                covering.push((id, surface.covering));
            }
        }
    }
    if !touched.is_empty() {
        let built;
        let visibility = match visibility {
            Some(visibility) => visibility,
            None => {
                built = Visibility::new(scene);
                &built
            }
        };
        remove_hidden_elements(&mut mesh, scene, visibility, &touched);
    }
    let scene_inset = rule.within(None);
    mesh.inset_boundary_receivers_by(&|surface| {
        insets.get(surface.index()).copied().unwrap_or(scene_inset)
    });
    gather_beside_covering_outlines(&mut mesh, scene, &covering, settings.max_edge);
    mesh.shrink_to_fit();
    counter.finish();
    (mesh, insets)
}

/// Surfaces meshed in parallel before their meshes join the whole: a
/// batch waits for its slowest surface (a floor under many contacts), so
/// batches are large enough that a building's cores stay busy.
const MESHING_BATCH: usize = 16_384;

/// One surface's mesh, before the hidden parts are dropped, and what the
/// whole mesh's passes need of its contacts.
struct MeshedSurface {
    mesh: Mesh,
    /// Another surface stands on it, or covers it: its hidden elements are
    /// looked for, at `tolerance`.
    touched: bool,
    tolerance: f64,
    /// How far its boundary vertices gather inside it.
    inset: f64,
    /// The contact lines of surfaces standing clear of it (its vertices
    /// along them gather beside).
    covering: Vec<Contact>,
}

/// Meshes surface `id` alone: its square grid, re-triangulated along its
/// contact lines and `guides`' boundaries or layout; contacts are found at
/// the `distances`' tolerance and boundary points inset by their inset.
fn mesh_surface(
    scene: &Scene,
    boxes: &SurfaceBoxes,
    id: SurfaceId,
    guides: &SurfaceGuides,
    distances: ContactDistances,
    settings: &SquareMeshSettings,
) -> MeshedSurface {
    let surface = scene.surface(id);
    let contacts = contact_segments(scene, boxes, id, distances, settings.max_edge);
    let frame = surface.frame();
    let marks: Vec<DVec3> = contacts.marks.iter().map(|&m| frame.to_world(m)).collect();
    let grid = square_grid(surface, id, settings, &marks);
    let covering = contacts
        .lines
        .iter()
        .filter(|c| c.clearance > 0.0)
        .copied()
        .collect();
    let touched = !contacts.lines.is_empty() || contacts.covered;
    let mesh =
        if contacts.lines.is_empty() && guides.layout.is_none() && guides.boundaries.is_empty() {
            grid
        } else {
            remesh_surface(
                surface,
                &grid,
                &contacts.lines,
                &guides.boundaries,
                settings.max_edge,
                guides.layout.as_ref(),
            )
        };
    MeshedSurface {
        mesh,
        touched,
        tolerance: distances.tolerance,
        inset: distances.inset,
        covering,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_inset_follows_the_room_down_to_two_ray_offsets() {
        // A building 190 m across, of offices 8.3 m across.
        let rule = ReceiverInset {
            projection: 0.0,
            diagonal: 190.0,
        };
        assert!((rule.within(None) - 0.019).abs() < 1e-12);
        assert!((rule.within(Some(8.3)) - 8.3e-4).abs() < 1e-12);
        // A cupboard's inside: two ray offsets of the building, 0.76 mm.
        assert!((rule.within(Some(0.5)) - 7.6e-4).abs() < 1e-12);
        // A room no larger than the scene; a bent face's projection wins.
        assert!((rule.within(Some(1e4)) - 0.019).abs() < 1e-12);
        let bent = ReceiverInset {
            projection: 0.004,
            ..rule
        };
        assert!((bent.within(Some(8.3)) - 0.004).abs() < 1e-12);
    }
}
