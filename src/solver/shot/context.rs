//! What every shot reads and none changes: the scene, its mesh and
//! shadow-ray BVH, the solver's settings and the layout of its zones.

use crate::mesh::Mesh;
use crate::meshing::ZoneMembers;
use crate::scene::{Scene, Visibility};
use crate::solver::layout::{CulledZones, SolveLayout};
use crate::solver::settings::SolverSettings;

/// The solver's parts a shot reads, borrowed apart from those it changes
/// (the light, the shot's buffers and memory, the counters).
#[derive(Clone, Copy)]
pub(crate) struct ShotContext<'a> {
    pub(crate) scene: &'a Scene,
    pub(crate) mesh: &'a Mesh,
    /// The whole scene's shadow-ray BVH.
    pub(crate) visibility: &'a Visibility,
    pub(crate) settings: &'a SolverSettings,
    pub(crate) layout: &'a SolveLayout,
}

impl<'a> ShotContext<'a> {
    /// The BVH the rays of a shot into closed zone `zone` traverse: the
    /// zone's own, smaller one, or the scene's.
    pub(crate) fn visibility_in(&self, zone: Option<usize>) -> &'a Visibility {
        zone.zip(self.layout.zones.as_ref())
            .and_then(|(zone, CulledZones { zones, .. })| zones.visibility(zone))
            .unwrap_or(self.visibility)
    }

    /// The mesh's patches, elements and vertices zone by zone, when the
    /// closed zones are culled.
    pub(crate) fn members(&self) -> Option<&'a ZoneMembers> {
        self.layout
            .zones
            .as_ref()
            .map(|CulledZones { members, .. }| members)
    }
}
