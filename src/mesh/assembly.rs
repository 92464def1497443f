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
    Contact, contact_segments, gather_beside_covering_outlines, remesh_surface,
    remove_hidden_elements,
};
use super::contour::ContourLayout;
use super::square::{SquareMeshSettings, square_grid};
use super::topology::Mesh;
use crate::phase::{Phase, PhaseCounter, PhaseReporter, silent};
use crate::scene::{Scene, Surface, SurfaceBoxes, SurfaceId};

/// How close to a plane, as a fraction of the scene's diagonal, another
/// surface's edge must lie to stand on it.
pub(crate) const CONTACT_TOLERANCE: f64 = 1e-3;

/// How far boundary vertices gather inside their surface, as a fraction of
/// the scene's diagonal: at least ten times the shadow rays' surface offset,
/// so a ray from a vertex at a wall's foot starts clear of the wall.
const RECEIVER_INSET: f64 = 1e-4;

/// The most a boundary vertex is moved inside, as a fraction of the diagonal.
const MAX_RECEIVER_INSET: f64 = 1e-3;

/// The distance boundary vertices gather inside their surface: the base
/// inset, or twice the largest projection offset of a nearly planar face if
/// larger, since a neighbour's projected plane may cut that far across the
/// corner it shares with the vertex's surface (the Cornell box's red wall
/// moves by 0.4 mm).
#[must_use]
pub fn receiver_inset(scene: &Scene) -> f64 {
    let diagonal = scene.diagonal();
    let offset = scene
        .surfaces
        .iter()
        .map(Surface::projection_offset)
        .fold(0.0, f64::max);
    (2.0 * offset).clamp(RECEIVER_INSET * diagonal, MAX_RECEIVER_INSET * diagonal)
}

/// Meshes every surface of the scene uniformly. Where another surface
/// stands on one (a block on a floor), the grid is re-triangulated with
/// element edges along the contact lines, and the elements hidden under the
/// object are dropped (see `mesh/contacts.rs`).
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
    /// The length the contact tolerance is a thousandth of: the diagonal
    /// of the surface's room (its closed zone), or, where `None`, of the
    /// whole scene. A building's
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
    mesh_surfaces_counted(scene, settings, guides, &silent)
}

/// [`mesh_surfaces`], reporting its progress surface by surface, and one
/// unit more once the hidden parts are dropped.
pub(crate) fn mesh_surfaces_counted(
    scene: &Scene,
    settings: &SquareMeshSettings,
    guides: &(dyn Fn(SurfaceId) -> SurfaceGuides + Sync),
    report: PhaseReporter,
) -> Mesh {
    let counter = PhaseCounter::start(Phase::Meshing, scene.surfaces.len() + 1, report);
    let diagonal = scene.diagonal();
    let inset = receiver_inset(scene);
    let boxes = SurfaceBoxes::new(scene);
    let mut mesh = Mesh::default();
    let mut touched = Vec::new();
    let mut covering = Vec::new();
    // A batch of surfaces at a time, so that the surfaces' own meshes
    // never all wait beside the whole.
    let ids: Vec<SurfaceId> = scene.surfaces_with_ids().map(|(id, _)| id).collect();
    for batch in ids.chunks(MESHING_BATCH) {
        let meshed: Vec<MeshedSurface> = batch
            .par_iter()
            .map(|&id| {
                let guides = guides(id);
                let tolerance = CONTACT_TOLERANCE * guides.contact_scale.unwrap_or(diagonal);
                let scales = (tolerance, inset);
                let meshed = mesh_surface(scene, &boxes, (id, &guides), scales, settings);
                counter.add(1);
                meshed
            })
            .collect();
        for (&id, surface) in batch.iter().zip(meshed) {
            mesh.append(surface.mesh);
            if surface.touched {
                touched.push((id, surface.tolerance));
            }
            if !surface.covering.is_empty() {
                covering.push((id, surface.covering));
            }
        }
    }
    if !touched.is_empty() {
        remove_hidden_elements(&mut mesh, scene, &touched);
    }
    mesh.inset_boundary_receivers(inset);
    gather_beside_covering_outlines(&mut mesh, scene, &covering, settings.max_edge);
    mesh.shrink_to_fit();
    counter.finish();
    mesh
}

/// Surfaces meshed in parallel before their meshes join the whole.
const MESHING_BATCH: usize = 1024;

/// One surface's mesh, before the hidden parts are dropped, and what the
/// whole mesh's passes need of its contacts.
struct MeshedSurface {
    mesh: Mesh,
    /// Another surface stands on it, or covers it: its hidden elements are
    /// looked for, at `tolerance`.
    touched: bool,
    tolerance: f64,
    /// The contact lines of surfaces standing clear of it (its vertices
    /// along them gather beside).
    covering: Vec<Contact>,
}

/// Meshes surface `id` alone: its square grid, re-triangulated along its
/// contact lines and `guides`' boundaries or layout; contacts are found at
/// `tolerance` and boundary points inset by `inset`.
fn mesh_surface(
    scene: &Scene,
    boxes: &SurfaceBoxes,
    (id, guides): (SurfaceId, &SurfaceGuides),
    (tolerance, inset): (f64, f64),
    settings: &SquareMeshSettings,
) -> MeshedSurface {
    let surface = scene.surface(id);
    let contacts = contact_segments(scene, boxes, id, (tolerance, inset), settings.max_edge);
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
        tolerance,
        covering,
    }
}
