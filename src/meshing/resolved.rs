//! The mesh settings resolved once against a scene: every length in scene
//! units, ready for the meshers, the shadow boundaries and the element
//! budget.

use super::layouts::{LAYOUT_EXTRA_POINTS, MAX_LAYOUT_GRID_RATIO};
use super::settings::{MeshKind, MeshSettings};
use crate::error::Result;
use crate::lighting::{BoundaryLimits, DominanceSettings};
use crate::mesh::{
    ContourSettings, SquareMeshSettings, check_element_budget, estimate_contour_elements,
    estimate_square_elements,
};
use crate::scene::Scene;

/// Shadow boundaries closer than this fraction (3/16) of the element
/// spacing are one: the mesh cannot tell them apart. A table leg's shadow
/// is a strip whose edges converge towards the leg's foot; merged at a
/// quarter of an element, the strip kept one edge over most of its length,
/// and the triangles from that edge's dark vertices across the lit side
/// left a dark wedge beside each leg's shadow. Finer merging costs
/// vertices for little.
const BOUNDARY_MIN_FEATURE: f64 = 0.1875;

/// [`MeshSettings`] resolved against one scene ([`MeshSettings::resolve`]):
/// the lengths given as fractions of the scene's diagonal are scene units
/// here, so everything that meshes the scene reads the same numbers.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct ResolvedMeshSettings {
    /// Square, contour or adaptive.
    pub kind: MeshKind,
    /// The square mesher's settings, lengths in scene units: for adaptive
    /// meshing the elements start `refinement.coarsening` times longer, and
    /// patches are never shorter than elements.
    pub square: SquareMeshSettings,
    /// D and K of the contour mesher.
    pub contour: ContourSettings,
    /// What makes a receiver qualify for the contour mesher.
    pub dominance: DominanceSettings,
    /// The shadow boundaries a receiver keeps (merged closer than 3/16 of
    /// an element, at most `max_shadow_boundaries`), or `None` where the
    /// settings ask for none.
    pub shadow_boundaries: Option<BoundaryLimits>,
    /// The most elements [`ResolvedMeshSettings::check_budget`] allows.
    pub max_elements: usize,
}

impl ResolvedMeshSettings {
    /// `settings` resolved against `scene`.
    #[must_use]
    pub fn new(settings: &MeshSettings, scene: &Scene) -> ResolvedMeshSettings {
        let square = settings.square_for(scene);
        let shadow_boundaries = settings.shadow_boundaries.then_some(BoundaryLimits {
            min_feature: BOUNDARY_MIN_FEATURE * square.max_edge,
            max_per_receiver: settings.max_shadow_boundaries,
        });
        ResolvedMeshSettings {
            kind: settings.kind,
            square,
            contour: settings.contour.clone(),
            dominance: settings.dominance.clone(),
            shadow_boundaries,
            max_elements: settings.max_elements,
        }
    }

    /// The elements [`super::mesh_scene`] would make at most (see
    /// `mesh/meshers/budget.rs`): the square grid's count, plus for the contour
    /// meshers the triangles of the largest layouts they keep on every
    /// receiver.
    #[must_use]
    pub fn estimate_elements(&self, scene: &Scene) -> f64 {
        let square = estimate_square_elements(scene, &self.square);
        let contour = match self.kind {
            // Adaptive meshing starts from the square grid; its splits stop
            // at `refinement.max_vertices`.
            MeshKind::Square | MeshKind::Adaptive => 0.0,
            MeshKind::Contour => {
                estimate_contour_elements(scene, square, MAX_LAYOUT_GRID_RATIO, LAYOUT_EXTRA_POINTS)
            }
        };
        square + contour
    }

    /// Refuses settings that would mesh `scene` into more than
    /// `max_elements` elements, with an error that says how to ask for
    /// fewer or allow more.
    pub fn check_budget(&self, scene: &Scene) -> Result<()> {
        check_element_budget(
            scene,
            self.estimate_elements(scene),
            self.max_elements,
            &self.square,
        )
    }
}

impl MeshSettings {
    /// These settings resolved against `scene`: every length in scene
    /// units, the shadow boundaries' limits set (see
    /// [`ResolvedMeshSettings`]).
    #[must_use]
    pub fn resolve(&self, scene: &Scene) -> ResolvedMeshSettings {
        ResolvedMeshSettings::new(self, scene)
    }

    /// The elements [`super::mesh_scene`] would make at most (see
    /// [`ResolvedMeshSettings::estimate_elements`]).
    #[must_use]
    pub fn estimate_elements(&self, scene: &Scene) -> f64 {
        self.resolve(scene).estimate_elements(scene)
    }

    /// Refuses settings that would mesh `scene` into more than
    /// [`MeshSettings::max_elements`] elements, with an error that says how
    /// to ask for fewer or allow more. [`crate::Solver::new`] calls it before
    /// meshing; call it before [`super::mesh_scene`] when meshing yourself.
    pub fn check_budget(&self, scene: &Scene) -> Result<()> {
        self.resolve(scene).check_budget(scene)
    }
}
