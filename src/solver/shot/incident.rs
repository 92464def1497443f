//! One patch's shot gathered at the vertices of its zone: its shafts
//! culled, its rays cast from every receiving vertex (or from the vertices
//! its reception plan gathers at), and the rest of a dim shot interpolated
//! (`coarse_reception.rs`).

use crate::meshing::ShotPlaces;
use crate::rgb::Rgb;
use crate::scene::{ShadowCache, Visibility};
use crate::solver::layout::CulledZones;
use crate::solver::light::state::LightState;
use crate::solver::shot::cache_runs::{in_shadow_cache_runs, indices_in_shadow_cache_runs};
use crate::solver::shot::context::ShotContext;
use crate::solver::shot::patch_reception::ReceptionPlan;
use crate::solver::shot::scratch::{ShotMemory, ShotScratch};
use crate::solver::shot::shaft_culling::{ReceiverShafts, ReceivingBoxes, ShaftQuery};
use crate::solver::shot::shooter::{Gathered, Receiver, Shooter, ShotRadiosity};
use crate::solver::shot::visibility_memory::{Recall, VisibilityMemory};
use crate::solver::stats::SolveStats;

/// A patch's shot, as its gathering sees it.
pub(crate) struct PatchShot {
    /// The shooting patch's index.
    pub(crate) patch: usize,
    /// Its power, summed over the channels: what sets its samples.
    pub(crate) power: f64,
    /// Its power by channel when it may be received coarsely (a reflected
    /// shot); `None` for an emitter's.
    pub(crate) coarse: Option<Rgb>,
    /// The radiosity it shoots.
    pub(crate) radiosity: ShotRadiosity,
    /// The closed zone it lights alone, when the zones are culled.
    pub(crate) zone: Option<usize>,
}

/// The parts of a solver a shot works in and counts with.
pub(crate) struct ShotWork<'a> {
    pub(crate) scratch: &'a mut ShotScratch,
    pub(crate) memory: &'a mut ShotMemory,
    pub(crate) stats: &'a mut SolveStats,
}

/// A shot under way: its shooter, the BVH its rays traverse and where its
/// vertices keep their light.
pub(super) struct Shot<'a> {
    pub(super) context: ShotContext<'a>,
    /// The shooting patch's index.
    pub(super) patch: usize,
    /// The closed zone it lights, if culled.
    pub(super) zone: Option<usize>,
    pub(super) shooter: Shooter,
    /// The zone's BVH, or the scene's.
    pub(super) visibility: &'a Visibility,
    /// Where each receiving vertex keeps its light in `incident`.
    pub(super) places: ShotPlaces<'a>,
}

impl ShotContext<'_> {
    /// Irradiance at every vertex from `shot`, computed in parallel, into
    /// `incident` (cleared, then one value per vertex at its
    /// [`ShotPlaces`]): at the vertices of its closed zone only when it
    /// has one (the others get none, and have no place). When the shot may
    /// be received coarsely (a reflected shot), the patches it barely
    /// lights gather it at their sample vertices only (see
    /// [`ShotContext::reception_plan`]).
    pub(crate) fn incident_from(
        &self,
        shot: PatchShot,
        light: &LightState,
        work: ShotWork<'_>,
        incident: &mut Vec<Rgb>,
    ) {
        let PatchShot {
            patch: j,
            power,
            coarse,
            radiosity,
            zone,
        } = shot;
        let ShotWork {
            scratch,
            memory,
            stats,
        } = work;
        // Which vertices gather a reflected shot, and which interpolate it.
        let plan = coarse
            .filter(|_| self.settings.coarse_reception > 0.0)
            .map(|shot_power| {
                let reception = &mut memory.reception;
                self.reception_plan(j, shot_power, zone, &light.irradiance, scratch, reception)
            });
        let shot = Shot {
            context: *self,
            patch: j,
            zone,
            shooter: self.shooter(j, power, light.reference_power, radiosity),
            // A closed zone's rays traverse its own, smaller BVH.
            visibility: self.visibility_in(zone),
            places: ShotPlaces::new(zone, self.members()),
        };
        // The receiving patches that see all of the shooter cast no rays,
        // and those whose shafts hold a few triangles test those alone.
        let mut shafts = std::mem::take(&mut scratch.receiver_shafts);
        let reflected = coarse.is_some();
        shot.cull_shafts(reflected, &mut memory.receiving_boxes, &mut shafts, stats);
        // What each vertex saw of this patch at its last shot, for a
        // reflected shot.
        let remembering = reflected && self.settings.remember_visibility;
        let views = &mut memory.visibility_memory;
        views.refresh(self.mesh.vertices.len(), self.mesh.patches.len());
        // The shot's rays, from every receiving vertex or the plan's.
        let views = remembering.then_some(views);
        shot.gather(plan.as_ref(), &shafts, views, stats, incident);
        if let Some(plan) = plan {
            // The plan's other vertices, from their patches' samples.
            shot.interpolate(&plan, &memory.reception, incident, stats);
            scratch.reception_plan = plan;
        }
        scratch.receiver_shafts = shafts;
    }
}

impl Shot<'_> {
    /// Finds what each receiving vertex's shaft to the shooter holds, into
    /// `shafts` (all unknown when the settings do not cull shafts). An
    /// emitter's shot reaches vertices on its shadow boundaries, where an
    /// occluder's edge grazes the emitter's as seen from them: its shafts
    /// keep the whole cell; a `reflected` shot's leave out a rim as wide
    /// as its surface's receivers' inset.
    fn cull_shafts(
        &self,
        reflected: bool,
        boxes: &mut ReceivingBoxes,
        shafts: &mut ReceiverShafts,
        stats: &mut SolveStats,
    ) {
        let ShotContext {
            scene,
            mesh,
            settings,
            layout,
            ..
        } = self.context;
        if !settings.cull_shafts {
            shafts.reset(mesh.vertices.len());
            return;
        }
        boxes.refresh(mesh);
        let receiving_patches = self
            .zone
            .zip(layout.zones.as_ref())
            .map(|(zone, CulledZones { members, .. })| &members.patches[zone][..]);
        let patch = &mesh.patches[self.patch];
        let rim = match reflected {
            true => layout
                .receiver_insets
                .get(patch.surface.index())
                .copied()
                .unwrap_or(0.0),
            false => 0.0,
        };
        let query = ShaftQuery {
            scene,
            mesh,
            visibility: self.visibility,
            shooter: &self.shooter,
            density: settings.sample_density,
            rim,
        };
        let (tested, cleared) = boxes.find_occluders(&query, receiving_patches, shafts);
        stats.shafts_tested += tested as u64;
        stats.shafts_clear += cleared as u64;
    }

    /// Gathers the shot at the `plan`'s gathering vertices, or at every
    /// vertex of its zone (of the mesh), in parallel, into `incident`
    /// (cleared to the zone's size), counting its rays. With the
    /// visibility `memory` (a reflected shot's, when remembered), what each
    /// vertex saw of the shooter at its last shot spares its rays, and
    /// what it sees now is remembered.
    fn gather(
        &self,
        plan: Option<&ReceptionPlan>,
        shafts: &ReceiverShafts,
        memory: Option<&mut VisibilityMemory>,
        stats: &mut SolveStats,
        incident: &mut Vec<Rgb>,
    ) {
        let ShotContext {
            scene,
            mesh,
            settings,
            layout,
            ..
        } = self.context;
        let (j, zone, places) = (self.patch, self.zone, self.places);
        let patch = &mesh.patches[j];
        let (density, shot, kernel) =
            (settings.sample_density, stats.shots as u64, settings.kernel);
        let remembered = memory.as_deref();
        let recall = |v: usize| match remembered {
            Some(memory) => memory.recall(j, places.of(v as u32)),
            None => Recall::Unknown,
        };
        let gather = |index: usize, cache: &mut ShadowCache| {
            let vertex = &mesh.vertices[index];
            // Nothing on the shooter's own plane receives from it.
            if vertex.surface == patch.surface {
                return Default::default();
            }
            let recalled = recall(index);
            if recalled == Recall::Hidden {
                return Default::default();
            }
            let receiver = Receiver {
                position: vertex.receiver_position(),
                normal: scene.surface(vertex.surface).normal(),
                surface: vertex.surface,
                key: index as u64,
                clear: shafts.is_clear(index) || recalled == Recall::Visible,
                occluders: shafts.occluders_of(index),
            };
            let visibility = self.visibility;
            self.shooter
                .gather(&receiver, density, shot, kernel, visibility, cache)
        };
        let members = self.context.members();
        let zone_size = zone
            .zip(members)
            .map_or(mesh.vertices.len(), |(zone, members)| {
                members.vertices[zone].len()
            });
        incident.clear();
        incident.resize(zone_size, Rgb::ZERO);
        let vertices = match (plan, zone.zip(layout.zones.as_ref())) {
            (Some(plan), _) => Some(&plan.gathered[..]),
            (None, Some((zone, CulledZones { members, .. }))) => Some(&members.vertices[zone][..]),
            (None, None) => None,
        };
        let every_vertex: Vec<u32>;
        let (vertices, gathered): (&[u32], Vec<Gathered>) = match vertices {
            Some(vertices) => (
                vertices,
                in_shadow_cache_runs(vertices, |&v, cache| gather(v as usize, cache)),
            ),
            None => {
                every_vertex = (0..mesh.vertices.len() as u32).collect();
                (
                    &every_vertex,
                    indices_in_shadow_cache_runs(mesh.vertices.len(), gather),
                )
            }
        };
        for (&v, g) in vertices.iter().zip(&gathered) {
            stats.rays += u64::from(g.rays);
            stats.known_visible += u64::from(g.known_visible);
            if shafts
                .occluders_of(v as usize)
                .is_some_and(|list| !list.is_empty())
            {
                stats.listed_rays += u64::from(g.rays);
            }
            stats.recalled_views += u64::from(recall(v as usize) != Recall::Unknown);
            incident[places.of(v)] = g.irradiance;
        }
        if let Some(memory) = memory {
            memory.remember(j, zone_size, places, vertices, &gathered);
        }
    }
}
