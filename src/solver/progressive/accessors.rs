//! What a solver tells of itself: how much light is left unshot, whether
//! emission is pending, and its parts and counters.

use crate::mesh::{ElementHierarchy, Mesh};
use crate::meshing::MeshAnalysis;
use crate::rgb::Rgb;
use crate::scene::{Scene, Visibility};
use crate::solver::layout::CulledZones;
use crate::solver::progressive::Solver;
use crate::solver::settings::SolverSettings;
use crate::solver::stats::SolveStats;

impl Solver {
    /// How many closed zones the scene's surfaces fall into (rooms that
    /// exchange no light; open space counts as one); 1 when the cull is off
    /// ([`SolverSettings::cull_closed_zones`]).
    #[must_use]
    pub fn closed_zones(&self) -> usize {
        self.layout
            .zones
            .as_ref()
            .map_or(1, |CulledZones { zones, .. }| zones.count())
    }

    /// Whether some emission (a photometric luminaire, or an emitting
    /// patch's first shot) has not been shot yet: a solve is not converged
    /// before it has.
    #[must_use]
    pub fn emission_pending(&self) -> bool {
        !self.light.emission_pending.is_empty()
            || self.light.luminaire_shot.contains(&false)
            || !self.light.daylight_shot
    }

    /// Unshot power over emitted power (sums of channels), after the patch
    /// shots what they left ([`Solver::shoot_patches`]); 0 for a dark
    /// scene.
    #[must_use]
    pub fn unshot_fraction(&self) -> f64 {
        let emitted = self.light.emitted_power.element_sum();
        if emitted > 0.0 {
            self.unshot_power().element_sum() / emitted
        } else {
            0.0
        }
    }

    /// The unshot fraction [`SolverSettings::tolerance`] is held to: the
    /// unshot power the vertices' shots leave, with each closed zone's
    /// counted at [`SolverSettings::closed_zone_weight`], over the emitted
    /// power (sums of channels); 0 for a dark scene. The patch shots do not
    /// change it: after them [`Solver::unshot_fraction`] reads less, and
    /// the next shot takes that back to what the vertices' shots leave.
    #[must_use]
    pub fn convergence_fraction(&self) -> f64 {
        let emitted = self.light.emitted_power.element_sum();
        if emitted > 0.0 {
            (self.light.unshot_by_zone.weighted_total() + self.unshot_luminaires().element_sum())
                / emitted
        } else {
            0.0
        }
    }

    /// The power not yet shot: what the patch shots left, if the last run
    /// made them, or what the vertices' shots left.
    pub(super) fn unshot_power(&self) -> Rgb {
        let unshot = match &self.ambient.patch_shots {
            Some(shots) => shots.left,
            None => self.light.unshot_by_zone.total(),
        };
        unshot + self.unshot_luminaires()
    }

    /// The power of the photometric luminaires that have not shot yet.
    fn unshot_luminaires(&self) -> Rgb {
        self.scene
            .luminaires
            .iter()
            .zip(&self.light.luminaire_shot)
            .filter(|(_, shot)| !**shot)
            .map(|(l, _)| l.power())
            .sum()
    }

    /// The element hierarchy of an adaptive solve ([`crate::MeshKind::Adaptive`]),
    /// whose leaves are the mesh's elements; `None` for other meshes.
    #[must_use]
    pub fn hierarchy(&self) -> Option<&ElementHierarchy> {
        self.refiner.as_ref().map(|r| &r.hierarchy)
    }

    /// What the solve has done so far: shots, shadow rays, and what shaft
    /// culling, the visibility memory and coarse reception saved.
    #[must_use]
    pub fn stats(&self) -> SolveStats {
        self.stats
    }

    /// The scene's daylight with the portals it comes in through, if the
    /// scene has a sky.
    #[must_use]
    pub fn daylight(&self) -> Option<&crate::lighting::DaylightSource> {
        self.layout.daylight.as_ref()
    }

    /// The settings in use.
    #[must_use]
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// The scene being solved.
    #[must_use]
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The mesh whose vertices receive light.
    #[must_use]
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The shadow-ray structure over the scene.
    #[must_use]
    pub fn visibility(&self) -> &Visibility {
        &self.visibility
    }

    /// What meshing found: luminaires, receivers' analyses, contour-meshed
    /// surfaces (empty for square meshing or a caller's mesh).
    #[must_use]
    pub fn mesh_analysis(&self) -> &MeshAnalysis {
        &self.layout.analysis
    }
}
