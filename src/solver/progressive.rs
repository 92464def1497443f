//! The progressive shooting solver (Cohen, Chen, Wallace, Greenberg 1988).

use glam::DVec3;
use rayon::prelude::*;

use super::mesh_settings::MeshKind;
use super::refinement::{Refiner, elements_to_split};
use super::scene_mesh::{MeshAnalysis, SceneMesh, mesh_scene_in_zones};
use super::settings::{Settings, ShootFrom, SolverSettings};
use super::zones::{ShotPlaces, Zones};
use crate::freed_memory::give_back_freed_memory;
use crate::mesh::{Cell, ElementHierarchy, Mesh};
use crate::phase::{Phase, PhaseCounter, PhaseReporter, silent};
use crate::scene::{Rgb, Scene, ShadowCache, SurfaceId, Visibility};
use crate::solver::ambient::patch_shots::{PatchShotSummary, PatchShots};
use crate::solver::ambient::state::AmbientState;
use crate::solver::ambient::term::AmbientTerm;
use crate::solver::layout::{CulledZones, Layout};
use crate::solver::light::energy_balance::EnergyBalance;
use crate::solver::light::indexed_update;
use crate::solver::light::state::LightState;
use crate::solver::reading::request::{self, Ambient};
use crate::solver::reading::solution::Solution;
use crate::solver::shot::element_power;
use crate::solver::shot::patch_reception::ReceptionPlan;
use crate::solver::shot::scratch::{ShotMemory, ShotScratch};
use crate::solver::shot::shooter::{Gathered, Receiver, Shooter, ShotRadiosity};
use crate::solver::shot::visibility_memory::Recall;
use crate::solver::stats::SolveStats;

/// The least and the most a reflected shot's element powers in a closed zone
/// are scaled by to land whole (see [`Solver::landing_scale`]): the
/// offices' shots need 0.84 to 1.40, `scenes/room`'s 0.56 to 1.20.
const LANDING_SCALE: (f64, f64) = (0.5, 2.0);

/// How a shot's least samples fall with its share s of the strongest
/// emitter's power: `direct_samples` × s^0.75. Spreading a fixed number of
/// samples over the shots to least variance would give each in proportion
/// to its power (exponent 1), but a shot costs more than its samples (its
/// plan, its vertices' updates), so a dim shot's few more samples cost
/// little: at 0.75 a reflected shot of 5 % of a lamp's power takes 9
/// samples instead of 4. The ceilings of the offices, lit by the floors'
/// and desks' reflected shots, lost the blotches those shots' few samples
/// drew on them. Against Mitsuba's references (golden tests' metric,
/// `isorad render` at 256 px, 2026-12-05), exponent 1 → 0.75 → 0.625:
/// cluttered office 3.03 → 2.91 → 2.88 % per pixel for 20.9 → 22.3 →
/// 27.9 M rays (4.85 → 4.94 → 5.31 s in all); furnished office 1.55 →
/// 1.46 → 1.42 % (0.97 → 1.02 → 1.20 s); shipped office 3.83 → 3.76 →
/// 3.71 % (5.09 → 5.24 → 5.77 s); Cornell box 1.98 → 1.94 → 1.91 %. A path
/// tracer's time to an error goes as about its inverse square, so 0.75
/// gains at equal error in every scene, and 0.625 no more.
const SHARE_EXPONENT: f64 = 0.75;

/// A scene's mesh and the structures found with it, which a solver is made
/// of: the shadow-ray BVH, what meshing found, and the closed zones (None:
/// found by the solver if it culls them).
struct MeshedScene {
    mesh: Mesh,
    visibility: Visibility,
    analysis: MeshAnalysis,
    zones: Option<Zones>,
}

/// Radiosity at mesh vertices, solved by progressive refinement: the patch
/// with the most unshot power shoots it to every receiving vertex, until the
/// unshot power falls below the tolerance.
///
/// For every vertex v receiving from patch j: B_v += ρ_v Σ_k ΔB_j(x_k) F_{v→k},
/// the sum over the shooter's strata k of the unshot radiosity where each
/// lies (interpolated from the corners of the elements under it, scaled so
/// the strata carry the patch's unshot power Σ_e A_e ΔB̄_e exactly) times the
/// vertex's form factor to it; with [`ShootFrom::PatchMean`], or for an
/// emitter, ΔB_j(x_k) is the patch's mean ΔB_j and the sum is ΔB_j F_{v→j}.
/// Each element's corners then gain what their vertices reflected, ρ_v H_v,
/// and each patch's unshot radiosity the area-weighted mean of that over its
/// elements; a patch that shoots clears both.
///
/// The solver owns its scene, mesh and shadow-ray structure; drive it with
/// [`Solver::step`] or [`Solver::run_until`], and read it at any moment with
/// [`Solver::solution`].
///
/// # References
/// M. F. Cohen, S. E. Chen, J. R. Wallace, D. P. Greenberg, "A Progressive
/// Refinement Approach to Fast Radiosity Image Generation", SIGGRAPH 1988.
pub struct Solver {
    scene: Scene,
    mesh: Mesh,
    visibility: Visibility,
    settings: SolverSettings,
    /// Where things are: zones, reflectances, insets, patch areas.
    layout: Layout,
    /// The light shot and not yet shot, and the ledger's powers.
    light: LightState,
    /// The buffers a shot works in.
    scratch: ShotScratch,
    /// What shots remember of the mesh and of earlier shots.
    memory: ShotMemory,
    /// What the solve has done so far.
    stats: SolveStats,
    /// The ambient term's rays and the last run's patch shots.
    ambient: AmbientState,
    /// The element hierarchy of an adaptive solve.
    refiner: Option<Refiner>,
}

impl Solver {
    /// A solver for `scene`: checks the scene and settings, builds the
    /// shadow-ray BVH, meshes the scene as `settings.mesh` asks, and sets the
    /// emitters' radiosity, with nothing yet shot.
    ///
    /// Fails with the loaders' errors for a scene without surfaces or
    /// emitters or with a material out of range, and with
    /// [`crate::Error::InvalidSetting`] for settings out of range, and with
    /// [`crate::Error::MeshTooLarge`] when the mesh would have more than
    /// [`crate::MeshSettings::max_elements`] elements (counted before meshing).
    pub fn new(scene: Scene, settings: Settings) -> crate::Result<Self> {
        Self::new_with_progress(scene, settings, &silent)
    }

    /// [`Solver::new`], reporting to `report` the progress of finding the
    /// closed rooms, the shadow boundaries, the contour layouts and the
    /// mesh (see [`crate::phase`]), which take minutes for a building.
    pub fn new_with_progress(
        scene: Scene,
        settings: Settings,
        report: PhaseReporter,
    ) -> crate::Result<Self> {
        settings.validate()?;
        scene.validate()?;
        settings.mesh.check_budget(&scene)?;
        // What loading the scene freed (its file's text, its faces) is
        // given back before the solve's lists are made; so is what
        // finding the rooms and meshing free.
        give_back_freed_memory();
        let visibility = Visibility::new(&scene);
        // The closed zones, found once: meshing pairs each receiver with
        // its own room's lights and occluders, and the shots stay in theirs.
        let counter = PhaseCounter::start(Phase::ClosedRooms, 1, report);
        let zones = Zones::new(&scene, &visibility);
        counter.finish();
        give_back_freed_memory();
        let SceneMesh {
            mesh,
            analysis,
            receiver_insets,
        } = mesh_scene_in_zones(&scene, &visibility, &settings.mesh, Some(&zones), report);
        give_back_freed_memory();
        let refiner = (settings.mesh.kind == MeshKind::Adaptive)
            .then(|| Refiner::new(&mesh, settings.mesh.refinement.clone()));
        let parts = MeshedScene {
            mesh,
            visibility,
            analysis,
            zones: Some(zones),
        };
        let mut solver = Self::with_parts(scene, parts, settings.solver);
        solver.refiner = refiner;
        solver.layout.receiver_insets = receiver_insets;
        solver.layout.patch_edge = settings.mesh.square_for(&solver.scene).patch_max_edge;
        Ok(solver)
    }

    /// A solver for `scene` on a mesh the caller made (with [`crate::mesh::mesh_square`]
    /// or [`crate::solver::mesh_scene`], say), nothing yet shot. Probes and
    /// reflected shots' shafts take the scene's receiver inset
    /// (`mesh::receiver_inset`), as [`crate::mesh::mesh_square`]'s
    /// boundary vertices do; [`crate::solver::mesh_scene`]'s move each
    /// room's by a ten-thousandth of the room's diagonal, so in a building
    /// a probe within the scene's inset of an edge gathers a little
    /// further in than its vertices.
    pub fn with_mesh(scene: Scene, mesh: Mesh, settings: SolverSettings) -> crate::Result<Self> {
        settings.validate()?;
        scene.validate()?;
        let visibility = Visibility::new(&scene);
        let parts = MeshedScene {
            mesh,
            visibility,
            analysis: MeshAnalysis::default(),
            zones: None,
        };
        Ok(Self::with_parts(scene, parts, settings))
    }

    /// Emitters' radiosity set, nothing shot. The closed zones are found
    /// here unless given (and kept only if culled and more than one).
    fn with_parts(scene: Scene, parts: MeshedScene, settings: SolverSettings) -> Self {
        let MeshedScene {
            mesh,
            visibility,
            analysis,
            zones,
        } = parts;
        let mut layout = Layout::new(&scene, &mesh, &visibility, zones, &settings);
        layout.analysis = analysis;
        let light = LightState::new(&scene, &mesh, &layout, &settings);
        Solver {
            scene,
            mesh,
            visibility,
            settings,
            layout,
            light,
            scratch: ShotScratch::default(),
            memory: ShotMemory::default(),
            stats: SolveStats::default(),
            ambient: AmbientState::default(),
            refiner: None,
        }
    }

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

    /// Shoots the next photometric luminaire not yet shot, else the
    /// emitting patch with the most emission not yet shot, else the patch
    /// with the most unshot power (in a building of closed rooms, the last
    /// shot's room's strongest while it holds the share
    /// [`SolverSettings::zone_affinity`] of that: see `solver/light/unshot_by_zone.rs`).
    /// Returns false when nothing has any.
    ///
    /// Emission goes first because it is direct light: shot, it draws sharp
    /// shadows at every vertex; left unshot when the solve stops, only the
    /// ambient term's few rays per vertex would find it. A lamp split into
    /// small patches (the slivers of a many-sided disc) could otherwise
    /// carry less power per patch than the floor it lights, and wait.
    pub fn step(&mut self) -> bool {
        if let Some(k) = self.light.luminaire_shot.iter().position(|&shot| !shot) {
            // A shot changes the unshot power the patch shots were made of.
            self.ambient.patch_shots = None;
            self.shoot_luminaire(k);
            return true;
        }
        let power = |p: usize| self.light.unshot[p].element_sum() * self.layout.patch_areas[p];
        let pending = self
            .light
            .emission_pending
            .iter()
            .enumerate()
            .max_by(|a, b| power(*a.1 as usize).total_cmp(&power(*b.1 as usize)));
        let chosen = match pending {
            Some((k, &j)) => {
                self.light.emission_pending.swap_remove(k);
                Some((j as usize, power(j as usize)))
            }
            None => self
                .light
                .unshot_by_zone
                .next_shooter(self.settings.zone_affinity),
        };
        let Some((j, power)) = chosen else {
            return false;
        };
        if power.is_nan() || power <= 0.0 {
            return false;
        }
        self.ambient.patch_shots = None;
        let delta = std::mem::replace(&mut self.light.unshot[j], Rgb::ZERO);
        let shot_power = delta * self.mesh.patches[j].area;
        let surface = self.scene.surface(self.mesh.patches[j].surface);
        let is_emitter = self.scene.material_of(surface).is_emitter();
        let radiosity = if is_emitter || self.settings.shoot_from == ShootFrom::PatchMean {
            ShotRadiosity::Uniform(delta)
        } else {
            let patch = &self.mesh.patches[j];
            ShotRadiosity::Field(
                self.light
                    .unshot_corners
                    .field(&self.mesh, patch, shot_power),
            )
        };
        self.light.unshot_corners.clear(&self.mesh.patches[j]);
        // Only the shooter's closed zone can receive.
        let zone = self
            .layout
            .zones
            .as_mut()
            .map(|CulledZones { zones, members }| {
                members.refresh(zones, &self.mesh);
                zones.of(self.mesh.patches[j].surface)
            });
        let mut incident = std::mem::take(&mut self.scratch.incident);
        // Reflected light may be received patch by patch where it is dim.
        let coarse = (!is_emitter).then_some(shot_power);
        self.incident_from(j, (power, coarse), radiosity, zone, &mut incident);
        let lossless = self.layout.surface_lossless[self.mesh.patches[j].surface.index()];
        let lands_whole = (!is_emitter && lossless).then_some(shot_power);
        let emitter = is_emitter.then(|| {
            let patch = &self.mesh.patches[j];
            (patch.cell, self.scene.surface(patch.surface).normal())
        });
        self.receive(&incident, zone, emitter, lands_whole);
        self.recount_unshot(zone);
        self.scratch.incident = incident;
        self.light.shot_power += shot_power;
        self.light.shot[j] += delta;
        self.stats.shots += 1;
        // Shadow edges and highlights come from direct light: elements split
        // after the emitters' shots, and new vertices gather only those.
        if is_emitter {
            self.refine();
        }
        true
    }

    /// Shoots photometric luminaire `k`: every vertex receives
    /// E = I(ω) cos θ / r² from its photometric centre, with one shadow ray.
    /// Inside a closed zone, only the zone's vertices receive it.
    fn shoot_luminaire(&mut self, k: usize) {
        let zone = self.layout.luminaire_zones[k];
        let vertices: Vec<u32> = match zone.zip(self.layout.zones.as_mut()) {
            Some((zone, CulledZones { zones, members })) => {
                members.refresh(zones, &self.mesh);
                members.vertices[zone].clone()
            }
            None => (0..self.mesh.vertices.len() as u32).collect(),
        };
        // In the zone's order: where the shot keeps its vertices' light.
        let incident = self.luminaire_light(k, &vertices);
        let samples = self.scene.luminaires[k].opening_samples().len();
        self.stats.rays += (vertices.len() * samples) as u64;
        self.receive(&incident, zone, None, None);
        self.recount_unshot(zone);
        self.light.shot_power += self.scene.luminaires[k].power();
        self.light.luminaire_shot[k] = true;
        self.stats.shots += 1;
        self.refine();
    }

    /// The irradiance photometric luminaire `k` gives each of `vertices`,
    /// in parallel: none, without rays, outside its closed zone, whose BVH
    /// the rays traverse.
    fn luminaire_light(&self, k: usize, vertices: &[u32]) -> Vec<Rgb> {
        let (scene, mesh) = (&self.scene, &self.mesh);
        let zone = self.layout.luminaire_zones[k].zip(
            self.layout
                .zones
                .as_ref()
                .map(|CulledZones { zones, .. }| zones),
        );
        let visibility = zone
            .and_then(|(zone, zones)| zones.visibility(zone))
            .unwrap_or(&self.visibility);
        let luminaire = &scene.luminaires[k];
        vertices
            .par_iter()
            .map(|&v| {
                let vertex = &mesh.vertices[v as usize];
                if zone.is_some_and(|(zone, zones)| zones.of(vertex.surface) != zone) {
                    return Rgb::ZERO;
                }
                let normal = scene.surface(vertex.surface).normal();
                luminaire.irradiance_at(
                    vertex.receiver_position(),
                    normal,
                    vertex.surface,
                    visibility,
                )
            })
            .collect()
    }

    /// Irradiance at every vertex from patch j shooting `radiosity`,
    /// computed in parallel, into `incident` (cleared, then one value per
    /// vertex at its [`ShotPlaces`]): at the vertices of closed zone `zone`
    /// only when given (the others get none, and have no place). `power`
    /// is the shot's power as a sum of channels, and, when the shot may be
    /// received coarsely (a reflected shot), by channel: then the patches
    /// it barely lights gather it at their sample vertices only (see
    /// [`Solver::reception_plan`]).
    fn incident_from(
        &mut self,
        j: usize,
        (power, coarse): (f64, Option<Rgb>),
        radiosity: ShotRadiosity,
        zone: Option<usize>,
        incident: &mut Vec<Rgb>,
    ) {
        let plan = coarse
            .filter(|_| self.settings.coarse_reception > 0.0)
            .map(|shot_power| self.reception_plan(j, shot_power, zone));
        let patch = &self.mesh.patches[j];
        let shooter = self.shooter(j, power, radiosity);
        let (scene, mesh) = (&self.scene, &self.mesh);
        // A closed zone's rays traverse its own, smaller BVH.
        let visibility = zone
            .zip(self.layout.zones.as_ref())
            .and_then(|(zone, CulledZones { zones, .. })| zones.visibility(zone))
            .unwrap_or(&self.visibility);
        // The receiving patches that see all of the shooter cast no rays,
        // and those whose shafts hold a few triangles test those alone.
        let mut shafts = std::mem::take(&mut self.scratch.receiver_shafts);
        if self.settings.cull_shafts {
            self.memory.receiving_boxes.refresh(mesh);
            let receiving_patches = zone
                .zip(self.layout.zones.as_ref())
                .map(|(zone, CulledZones { members, .. })| &members.patches[zone][..]);
            // An emitter's shot reaches vertices on its shadow boundaries,
            // where an occluder's edge grazes the emitter's as seen from
            // them: its shafts keep the whole cell.
            let rim = match coarse {
                Some(_) => self
                    .layout
                    .receiver_insets
                    .get(patch.surface.index())
                    .copied()
                    .unwrap_or(0.0),
                None => 0.0,
            };
            let (tested, cleared) = self.memory.receiving_boxes.find_occluders(
                (scene, mesh, visibility),
                (&shooter, self.settings.sample_density, rim),
                receiving_patches,
                &mut shafts,
            );
            self.stats.shafts_tested += tested as u64;
            self.stats.shafts_clear += cleared as u64;
        } else {
            shafts.reset(mesh.vertices.len());
        }
        let (density, shot, kernel) = (
            self.settings.sample_density,
            self.stats.shots as u64,
            self.settings.kernel,
        );
        // What each vertex saw of this patch at its last shot, for a
        // reflected shot.
        let remembering = coarse.is_some() && self.settings.remember_visibility;
        let members = self
            .layout
            .zones
            .as_ref()
            .map(|CulledZones { members, .. }| members);
        let places = ShotPlaces::new(zone, members);
        self.memory
            .visibility_memory
            .refresh((mesh.vertices.len(), mesh.patches.len()));
        let memory = &self.memory.visibility_memory;
        let recall = |v: usize| {
            if remembering {
                memory.recall(j, places.of(v as u32))
            } else {
                Recall::Unknown
            }
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
            shooter.gather(&receiver, density, shot, kernel, (visibility, cache))
        };
        let zone_size = zone
            .zip(members)
            .map_or(mesh.vertices.len(), |(zone, members)| {
                members.vertices[zone].len()
            });
        incident.clear();
        incident.resize(zone_size, Rgb::ZERO);
        let vertices = match (&plan, zone.zip(self.layout.zones.as_ref())) {
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
            self.stats.rays += u64::from(g.rays);
            self.stats.known_visible += u64::from(g.known_visible);
            if shafts
                .occluders_of(v as usize)
                .is_some_and(|list| !list.is_empty())
            {
                self.stats.listed_rays += u64::from(g.rays);
            }
            self.stats.recalled_views += u64::from(recall(v as usize) != Recall::Unknown);
            incident[places.of(v)] = g.irradiance;
        }
        if remembering {
            self.memory
                .visibility_memory
                .remember((j, zone_size), places, (vertices, &gathered));
        }
        if let Some(plan) = plan {
            let shooter = &self.mesh.patches[j];
            let kernel = PointKernel {
                centre: shooter.cell.point(0.5, 0.5),
                normal: self.scene.surface(shooter.surface).normal(),
            };
            let (scene, mesh, reception) = (&self.scene, &self.mesh, &self.memory.reception);
            let at = |v: u32| {
                let vertex = &mesh.vertices[v as usize];
                kernel.at(
                    vertex.receiver_position(),
                    scene.surface(vertex.surface).normal(),
                )
            };
            let interpolate = |&v: &u32| {
                reception.weights_of(v).map(|weights| {
                    let (mut light, mut kernel_there) = (Rgb::ZERO, 0.0);
                    for &(s, w) in &weights {
                        light += incident[places.of(s)] * f64::from(w);
                        kernel_there += at(s) * f64::from(w);
                    }
                    light * curvature_factor(at(v), kernel_there)
                })
            };
            let values: Vec<Option<Rgb>> = plan
                .interpolated
                .par_iter()
                .with_min_len(INTERPOLATION_CHUNK)
                .map(interpolate)
                .collect();
            for (&v, value) in plan.interpolated.iter().zip(values) {
                if let Some(value) = value {
                    incident[places.of(v)] = value;
                }
            }
            let count = (plan.interpolated.len() + plan.gathered.len()) as u64;
            self.stats.interpolated_receptions += plan.interpolated.len() as u64;
            self.stats.receptions += count;
            self.scratch.reception_plan = plan;
        }
        self.scratch.receiver_shafts = shafts;
    }

    /// Which vertices of the receiving zone (`zone`, or the whole scene)
    /// gather a reflected shot of `shot_power` from patch j, and which are
    /// interpolated from their patch's samples: those whose irradiance so
    /// far is at least the shot's bound on their patches over
    /// [`SolverSettings::coarse_reception`], and whose samples agree with
    /// them (see `solver/shot/patch_reception.rs`).
    fn reception_plan(&mut self, j: usize, shot_power: Rgb, zone: Option<usize>) -> ReceptionPlan {
        self.memory.reception.refresh(&self.mesh);
        let mut plan = std::mem::take(&mut self.scratch.reception_plan);
        // Without zones, every patch and vertex, listed once per mesh size.
        let scratch = &mut self.scratch;
        if scratch.every_patch.len() != self.mesh.patches.len() {
            scratch.every_patch = (0..self.mesh.patches.len() as u32).collect();
        }
        if scratch.every_vertex.len() != self.mesh.vertices.len() {
            scratch.every_vertex = (0..self.mesh.vertices.len() as u32).collect();
        }
        let (patches, vertices): (&[u32], &[u32]) = match zone.zip(self.layout.zones.as_ref()) {
            Some((zone, CulledZones { members, .. })) => {
                (&members.patches[zone], &members.vertices[zone])
            }
            None => (&self.scratch.every_patch, &self.scratch.every_vertex),
        };
        let fraction = self.settings.coarse_reception;
        let never = Rgb::splat(f64::INFINITY);
        self.scratch
            .thresholds
            .resize(self.mesh.patches.len(), never);
        let reception = &self.memory.reception;
        let threshold =
            |&p: &u32| reception.interpolation_threshold((p as usize, j), shot_power, fraction);
        // A patch's bound costs about as much as a hundred vertices' updates.
        if patches.len() > indexed_update::SERIAL_PART / 64 {
            patches
                .par_iter()
                .map(threshold)
                .collect_into_vec(&mut self.scratch.patch_thresholds);
        } else {
            self.scratch.patch_thresholds.clear();
            self.scratch
                .patch_thresholds
                .extend(patches.iter().map(threshold));
        }
        for (&p, &t) in patches.iter().zip(&self.scratch.patch_thresholds) {
            self.scratch.thresholds[p as usize] = t;
        }
        self.memory.reception.plan(
            vertices,
            &self.scratch.thresholds,
            &self.light.irradiance,
            &mut plan,
        );
        for &p in patches {
            self.scratch.thresholds[p as usize] = never;
        }
        plan
    }

    /// Patch j prepared to shoot `radiosity`, of `power` in all (sum of
    /// channels): at least `direct_samples` × s^[`SHARE_EXPONENT`] samples
    /// for a shot of the share s of the strongest emitter's power.
    fn shooter(&self, j: usize, power: f64, radiosity: ShotRadiosity) -> Shooter {
        let patch = &self.mesh.patches[j];
        let surface = self.scene.surface(patch.surface);
        let share = (power / self.light.reference_power.max(f64::MIN_POSITIVE)).min(1.0);
        let max_side = (self.settings.max_samples as f64).sqrt().floor().max(1.0) as usize;
        let samples = self.settings.direct_samples as f64 * share.powf(SHARE_EXPONENT);
        let min_side = (samples.sqrt().round() as usize).clamp(1, max_side);
        Shooter::new(
            patch.cell,
            surface.normal(),
            patch.surface,
            (min_side, max_side),
            radiosity,
        )
    }

    /// The factor, channel by channel, by which the elements of a reflected
    /// shot's closed zone (or the whole scene) scale the power they took
    /// from the shot's irradiance, `received` in all, so that together they
    /// receive exactly the shot's power P (`shot_power`):
    ///
    /// ```text
    ///   s = P / Σ_e A_e mean_corners(H),
    /// ```
    ///
    /// Σ over the elements [`Solver::receive`] gives power to. In a closed
    /// zone the form factors from any point of the shooter to the zone sum
    /// to 1 (the summation relation of form factors: Cohen & Wallace 1993),
    /// so all of P lands; the corners' mean over an element misses some of
    /// it where light falls off concavely into a junction, and counts some
    /// twice where a stratum's kernel peaks beside a vertex. Most shots land
    /// within a few percent of P (the cluttered office of
    /// `bench/generate_building.py`: half within 2 %, nine in ten within
    /// 7 %, 1.1 % short on average weighted by power), and the shortfall,
    /// compounded over the bounces, left the furnished offices 0.7–2 %
    /// dark against a path tracer. Only the elements' powers (what their
    /// patches shoot next, and the energy ledger) are scaled: the vertices
    /// keep the irradiance they gathered, the point values that images
    /// show. Scaling those as well brightened the offices a little more but
    /// spread each shot's local errors over its whole zone (`scenes/room`
    /// 1.65 % → 2.13 % off per pixel). The factor is held to
    /// [`LANDING_SCALE`]: a shooter whose light falls mostly where no
    /// element is keeps the rest as escaped power. Only zones whose
    /// surfaces' fronts see fronts are scaled ([`ZoneLabels::is_lossless`]):
    /// light that falls on the black back of a one-sided plate is lost for
    /// real. Shots of emitting patches are left alone, reflected light
    /// included, and so is the light new vertices of an adaptive mesh
    /// gather ([`Solver::refine`] books the difference in the ledger).
    ///
    /// # References
    /// M. F. Cohen, J. R. Wallace, *Radiosity and Realistic Image
    /// Synthesis*, Academic Press 1993.
    fn landing_scale(shot_power: Rgb, received: Rgb) -> Rgb {
        let scale = |shot: f64, got: f64| {
            if got > 0.0 {
                (shot / got).clamp(LANDING_SCALE.0, LANDING_SCALE.1)
            } else {
                1.0
            }
        };
        Rgb::new(
            scale(shot_power.r, received.r),
            scale(shot_power.g, received.g),
            scale(shot_power.b, received.b),
        )
    }

    /// Adds a shot's irradiance to vertices, and what elements reflect to
    /// their corners' and their patches' unshot radiosity: over the
    /// elements of closed zone `zone` only when given (no other receives).
    /// For the shot of an emitting patch (its polygon and normal), the
    /// elements' received power takes the curvature of its unoccluded field
    /// (see `solver/shot/element_power.rs`); otherwise it is the corners' mean times the
    /// area, scaled to land whole when `lands_whole` gives the shot's power
    /// (see [`Solver::landing_scale`]). The vertices, the elements' powers
    /// and their corners are updated in parallel, the sums in order, so
    /// that a solve is the same on any number of threads.
    fn receive(
        &mut self,
        incident: &[Rgb],
        zone: Option<usize>,
        emitter: Option<(Cell, DVec3)>,
        lands_whole: Option<Rgb>,
    ) {
        // The zone's lists, taken out of `self` while its fields change.
        let members = zone.and_then(|zone| Some((zone, self.layout.zones.take()?)));
        let (all_vertices, all_elements): (Vec<u32>, Vec<u32>);
        let (vertices, elements): (&[u32], &[u32]) = match &members {
            Some((zone, CulledZones { members, .. })) => {
                (&members.vertices[*zone], &members.elements[*zone])
            }
            None => {
                all_vertices = (0..self.mesh.vertices.len() as u32).collect();
                all_elements = (0..self.mesh.elements.len() as u32).collect();
                (&all_vertices, &all_elements)
            }
        };
        // The k-th of `vertices` keeps its light at place k.
        let places = ShotPlaces::new(
            zone,
            members
                .as_ref()
                .map(|(_, CulledZones { members, .. })| members),
        );
        let at = |v: u32| incident[places.of(v)];
        let (mesh, reflectances) = (&self.mesh, &self.layout.surface_reflectance);
        let reflectance_of = |surface: SurfaceId| reflectances[surface.index()];
        self.light.irradiance.add_at(vertices, incident);
        let mut powers = std::mem::take(&mut self.scratch.element_powers);
        match emitter {
            Some((cell, normal)) => {
                let emitter = (cell.polygon(), normal);
                let zone = (vertices, elements);
                let values = (incident, places);
                powers =
                    element_power::emitter_shot_powers(&self.scene, mesh, emitter, values, zone);
            }
            None => {
                let power = |&e: &u32| {
                    let element = &mesh.elements[e as usize];
                    element.corner_mean(at) * element.area
                };
                if elements.len() > indexed_update::SERIAL_PART {
                    elements.par_iter().map(power).collect_into_vec(&mut powers);
                } else {
                    powers.clear();
                    powers.extend(elements.iter().map(power));
                }
            }
        }
        let scale = lands_whole.map_or(Rgb::ONE, |shot_power| {
            Solver::landing_scale(shot_power, powers.iter().copied().sum())
        });
        for (&e, &power) in elements.iter().zip(&powers) {
            let incident_power = power * scale;
            if incident_power == Rgb::ZERO {
                continue;
            }
            let element = &mesh.elements[e as usize];
            self.light.received_power += incident_power;
            let patch = element.patch as usize;
            let reflectance = reflectance_of(element.surface);
            self.light.unshot[patch] +=
                reflectance * incident_power / self.layout.patch_areas[patch];
            self.light.absorbed_power += (Rgb::ONE - reflectance) * incident_power;
        }
        self.light
            .unshot_corners
            .add_shot(mesh, elements, |element, v| {
                reflectance_of(element.surface) * scale * at(v)
            });
        self.scratch.element_powers = powers;
        if let Some((_, zones)) = members {
            self.layout.zones = Some(zones);
        }
    }

    /// Gives back the buffers a shot works in, kept from shot to shot: a
    /// shot's irradiance per vertex of its zone (24 bytes) and its power
    /// per element (24, about 1.25 elements a vertex), which hold nothing
    /// between shots. In a scene of one zone, the ambient term's memory
    /// would stand on theirs once a run stops; the next shot makes them
    /// again.
    pub(crate) fn release_shot_buffers(&mut self) {
        self.scratch.incident = Vec::new();
        self.scratch.element_powers = Vec::new();
    }

    /// Counts the unshot power of closed zone `zone`'s patches again after
    /// a shot changed them, or of every patch.
    fn recount_unshot(&mut self, zone: Option<usize>) {
        let counts = (&self.light.unshot[..], &self.layout.patch_areas[..]);
        match zone {
            Some(zone) => self.light.unshot_by_zone.shot_in(zone, counts),
            None => self.light.unshot_by_zone.recount_all(counts),
        }
    }

    /// Whether some emission (a photometric luminaire, or an emitting
    /// patch's first shot) has not been shot yet: a solve is not converged
    /// before it has.
    #[must_use]
    pub fn emission_pending(&self) -> bool {
        !self.light.emission_pending.is_empty() || self.light.luminaire_shot.contains(&false)
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
    fn unshot_power(&self) -> Rgb {
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

    /// Radiosity per vertex (W/m²) from the light shot so far, B = E + ρ H
    /// with the emission E and reflectance ρ of each vertex's surface: a
    /// new list, 24 bytes a vertex (the solver keeps H alone).
    #[must_use]
    pub fn radiosity(&self) -> Vec<Rgb> {
        self.solution(Ambient::Omitted, &silent).radiosity()
    }

    /// Irradiance per vertex (W/m²) from the light shot so far, as a new
    /// list (the solver keeps it in `f32`: `solver/light/vertex_irradiance.rs`).
    #[must_use]
    pub fn irradiance(&self) -> Vec<Rgb> {
        self.light.irradiance.to_vec()
    }

    /// Vertex `v`'s irradiance (W/m²) from the light shot so far.
    ///
    /// # Panics
    /// If `v` is not a vertex of the mesh.
    #[must_use]
    pub fn irradiance_at(&self, v: usize) -> Rgb {
        self.light.irradiance.at(v)
    }

    /// The solution from the light shot so far with the `ambient` term
    /// asked for (see [`Ambient`]), reporting the term's progress to
    /// `report` ([`crate::Phase::AmbientTerm`]; `&isorad::phase::silent`
    /// for none).
    #[must_use]
    pub fn solution(&self, ambient: Ambient<'_>, report: PhaseReporter) -> Solution<'_> {
        request::solution(&self.ambient_term(), ambient, report)
    }

    /// The parts of the solver the ambient term reads, borrowed.
    pub(crate) fn ambient_term(&self) -> AmbientTerm<'_> {
        AmbientTerm {
            scene: &self.scene,
            mesh: &self.mesh,
            visibility: &self.visibility,
            layout: &self.layout,
            light: &self.light,
            settings: &self.settings,
            state: &self.ambient,
        }
    }

    /// Shoots the unshot power the vertices' shots left patch to patch
    /// (`solver/ambient/patch_shots.rs`), until at most
    /// [`SolverSettings::patch_tolerance`] of the emitted power is left,
    /// every zone counted in full; [`Solver::run_until`] does when it
    /// converges. The vertices keep the light of their own shots
    /// ([`Solver::solution`]); each patch keeps the irradiance the patch
    /// shots brought it, which the ambient term gathers at the vertices
    /// an image, a probe or an export reads. Nothing is shot while
    /// emission is pending, or when no more than the tolerance is left.
    /// The next shot drops them: they are made again from its unshot
    /// power.
    pub fn shoot_patches(&mut self) {
        self.ambient.patch_shots = None;
        let emitted = self.light.emitted_power.element_sum();
        let unshot = self.light.unshot_by_zone.total().element_sum();
        let tolerance = self.settings.patch_tolerance;
        // A NaN unshot power (a broken material) would stop every sweep.
        let finite = unshot.is_finite() && emitted.is_finite();
        if self.emission_pending() || !finite || emitted <= 0.0 || unshot <= tolerance * emitted {
            return;
        }
        self.release_shot_buffers();
        give_back_freed_memory();
        let shots = PatchShots::shoot_from(&self.ambient_term(), tolerance * emitted / unshot);
        self.ambient.patch_shots = Some(shots);
    }

    /// What the last run's patch shots did ([`Solver::shoot_patches`]), or
    /// `None` if it made none (or a shot came after).
    #[must_use]
    pub fn patch_shot_summary(&self) -> Option<PatchShotSummary> {
        let shots = self.ambient.patch_shots.as_ref()?;
        Some(shots.summary(self.light.emitted_power))
    }

    /// The energy ledger; see [`EnergyBalance`].
    #[must_use]
    pub fn energy_balance(&self) -> EnergyBalance {
        let (absorbed, escaped) = self
            .ambient
            .patch_shots
            .as_ref()
            .map_or((Rgb::ZERO, Rgb::ZERO), |s| (s.absorbed, s.escaped));
        EnergyBalance {
            emitted: self.light.emitted_power,
            absorbed: self.light.absorbed_power + absorbed,
            unshot: self.unshot_power(),
            escaped: self.light.shot_power - self.light.received_power + escaped,
        }
    }

    /// The element hierarchy of an adaptive solve ([`MeshKind::Adaptive`]),
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

impl Solver {
    /// Splits the elements whose vertices disagree (see [`elements_to_split`]),
    /// level by level until none does, and gives every new vertex the light
    /// of all shots so far by gathering it (see [`Solver::gather_shot_light`]).
    ///
    /// The energy ledger stays closed: where the finer elements estimate a
    /// patch's incident power differently, the difference ΔP moves from the
    /// escaped power to the received power, and ρ ΔP to the patch's unshot
    /// power. The new elements' unshot corners carry that ρ ΔP where it was
    /// found (see [`UnshotCorners::after_split`]).
    pub(crate) fn refine(&mut self) {
        let Some(mut refiner) = self.refiner.take() else {
            return;
        };
        loop {
            if self.mesh.vertices.len() >= refiner.settings.max_vertices {
                break;
            }
            let split = elements_to_split(
                &self.mesh,
                &refiner.hierarchy,
                &self.radiosity(),
                &refiner.settings,
            );
            if split.is_empty() {
                break;
            }
            let before = self.incident_power_per_patch();
            let corners_before = self.light.unshot_corners.by_vertices(&self.mesh);
            let added = refiner.hierarchy.split(&mut self.mesh, &split);
            let gathered = self.gather_shot_light(&added);
            for (&v, irradiance) in added.iter().zip(gathered) {
                debug_assert_eq!(v as usize, self.light.irradiance.len());
                self.light.irradiance.push(irradiance);
            }
            self.carry_unshot_corners(&refiner.hierarchy, &corners_before);
            let after = self.incident_power_per_patch();
            for (p, (old, new)) in before.into_iter().zip(after).enumerate() {
                let change = new - old;
                let patch = &self.mesh.patches[p];
                if patch.area > 0.0 {
                    let reflectance = self
                        .scene
                        .material_of(self.scene.surface(patch.surface))
                        .reflectance;
                    self.light.unshot[p] += reflectance * change / patch.area;
                    self.light.received_power += change;
                    self.light.absorbed_power += (Rgb::ONE - reflectance) * change;
                }
            }
            self.recount_unshot(None);
        }
        self.refiner = Some(refiner);
        // The mesh changed: its members are listed by zone again, and its
        // patches' samples found again.
        if let Some(CulledZones { members, .. }) = &mut self.layout.zones {
            members.invalidate();
        }
        self.memory.reception.invalidate();
    }

    /// The unshot corners of the mesh's new elements after a split (see
    /// [`UnshotCorners::after_split`]), from `before`, the corners of the
    /// elements before it by their vertex arrays.
    fn carry_unshot_corners(
        &mut self,
        hierarchy: &ElementHierarchy,
        before: &std::collections::HashMap<[u32; 4], [Rgb; 4]>,
    ) {
        let (scene, mesh) = (&self.scene, &self.mesh);
        let parent_of = |e: usize| {
            let parent = hierarchy.leaf(e).parent?;
            hierarchy.node(parent).map(|node| node.element)
        };
        let reflectance = |element: &crate::mesh::Element| {
            scene
                .material_of(scene.surface(element.surface))
                .reflectance
        };
        self.light.unshot_corners.after_split(
            mesh,
            parent_of,
            before,
            &self.light.irradiance,
            reflectance,
        );
    }

    /// Σ over each patch's elements of the mean irradiance of the element's
    /// corners times its area: the incident power the ledger counts.
    fn incident_power_per_patch(&self) -> Vec<Rgb> {
        let mut power = vec![Rgb::ZERO; self.mesh.patches.len()];
        for element in &self.mesh.elements {
            let mean = element.corner_mean(|v| self.light.irradiance.at(v as usize));
            power[element.patch as usize] += mean * element.area;
        }
        power
    }

    /// The irradiance of new vertices from every shot so far: for each patch
    /// p that has shot radiosity S_p in all, H_v = Σ_p S_p F_{v→p}, with the
    /// form factors of the solver's kernel and sampling. Parallel over vertices.
    fn gather_shot_light(&mut self, vertices: &[u32]) -> Vec<Rgb> {
        let shooters: Vec<Shooter> = self
            .light
            .shot
            .iter()
            .enumerate()
            .filter(|(_, s)| s.element_sum() > 0.0)
            .map(|(p, &s)| {
                let power = s.element_sum() * self.mesh.patches[p].area;
                self.shooter(p, power, ShotRadiosity::Uniform(s))
            })
            .collect();
        let (scene, mesh, visibility) = (&self.scene, &self.mesh, &self.visibility);
        let zones = self
            .layout
            .zones
            .as_ref()
            .map(|CulledZones { zones, .. }| zones);
        let (density, kernel, shot) = (
            self.settings.sample_density,
            self.settings.kernel,
            self.stats.shots as u64,
        );
        let gathered: Vec<(Rgb, u64)> = in_shadow_cache_runs(vertices, |&v, cache| {
            let vertex = &mesh.vertices[v as usize];
            // Only the vertex's own closed zone's shooters reach it.
            let elsewhere = |shooter: &Shooter| {
                zones.is_some_and(|zones| zones.of(shooter.surface) != zones.of(vertex.surface))
            };
            let receiver = Receiver {
                position: vertex.receiver_position(),
                normal: scene.surface(vertex.surface).normal(),
                surface: vertex.surface,
                key: u64::from(v),
                clear: false,
                occluders: None,
            };
            let mut irradiance = Rgb::ZERO;
            let mut rays = 0;
            for shooter in &shooters {
                if shooter.surface == vertex.surface || elsewhere(shooter) {
                    continue;
                }
                let g = shooter.gather(&receiver, density, shot, kernel, (visibility, &mut *cache));
                irradiance += g.irradiance;
                rays += u64::from(g.rays);
            }
            (irradiance, rays)
        });
        self.stats.rays += gathered.iter().map(|g| g.1).sum::<u64>();
        let mut light: Vec<Rgb> = gathered.into_iter().map(|g| g.0).collect();
        for k in 0..self.scene.luminaires.len() {
            if self.light.luminaire_shot[k] {
                let direct = self.luminaire_light(k, vertices);
                self.stats.rays += vertices.len() as u64;
                for (h, d) in light.iter_mut().zip(direct) {
                    *h += d;
                }
            }
        }
        light
    }
}

/// Receivers in one run of a shot's shadow rays through one [`ShadowCache`].
/// Runs of a fixed length make the cache's answers, and so the solve, the
/// same however rayon spreads the runs over its threads; each run's first
/// blocked ray pays a traversal to fill its cache.
const SHADOW_CACHE_RUN: usize = 256;

/// Interpolated vertices per parallel task.
const INTERPOLATION_CHUNK: usize = 2048;

/// A shooting patch seen as a point at its centre: the kernel
/// cos θ_x cos θ_s / r² of a receiving point x with normal n_x, which
/// carries how a shot's irradiance bends across a receiving patch (falling
/// off as the inverse square of the distance and with both cosines).
struct PointKernel {
    centre: DVec3,
    normal: DVec3,
}

impl PointKernel {
    /// cos θ_x cos θ_s / r² at x facing `normal` (0 behind either plane).
    fn at(&self, x: DVec3, normal: DVec3) -> f64 {
        let d = self.centre - x;
        let r2 = d.length_squared();
        if r2 <= 0.0 {
            return 0.0;
        }
        normal.dot(d).max(0.0) * self.normal.dot(-d).max(0.0) / (r2 * r2)
    }
}

/// How much a shot's irradiance interpolated from a patch's samples is
/// scaled at a vertex: the shooter's point kernel there over the same
/// interpolation of the kernel at the samples, within [1/2, 2]; 1 where
/// either is 0. Linear interpolation of a field that bends (a shot falls
/// off as 1/r² and with the cosines) misses its curvature: a receiving
/// patch under a shooter, where the field peaks, took too little.
fn curvature_factor(here: f64, interpolated: f64) -> f64 {
    if here > 0.0 && interpolated > 0.0 {
        (here / interpolated).clamp(0.5, 2.0)
    } else {
        1.0
    }
}

/// `f` of each item, in parallel over runs of [`SHADOW_CACHE_RUN`] items,
/// each run with a fresh [`ShadowCache`]; in the items' order.
fn in_shadow_cache_runs<T: Sync, R: Send + Default>(
    items: &[T],
    f: impl Fn(&T, &mut ShadowCache) -> R + Sync,
) -> Vec<R> {
    indices_in_shadow_cache_runs(items.len(), |k, cache| f(&items[k], cache))
}

/// `f` of each index below `count`, as [`in_shadow_cache_runs`] does it.
fn indices_in_shadow_cache_runs<R: Send + Default>(
    count: usize,
    f: impl Fn(usize, &mut ShadowCache) -> R + Sync,
) -> Vec<R> {
    let mut results: Vec<R> = std::iter::repeat_with(R::default).take(count).collect();
    results
        .par_chunks_mut(SHADOW_CACHE_RUN)
        .enumerate()
        .for_each(|(run, results)| {
            let mut cache = ShadowCache::default();
            for (k, result) in results.iter_mut().enumerate() {
                *result = f(run * SHADOW_CACHE_RUN + k, &mut cache);
            }
        });
    results
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::test_scenes::two_closed_rooms;

    /// A shot into one of two closed rooms keeps its buffers at that
    /// room's size, for the next shot, and a run gives them back when it
    /// stops.
    #[test]
    fn a_run_gives_back_its_shot_buffers_when_it_stops() {
        let mut settings = Settings::default();
        settings.mesh.max_edge = crate::Length::Absolute(0.5);
        let mut solver = Solver::new(two_closed_rooms(), settings).expect("a valid scene");
        assert!(solver.step());
        let held = |s: &Solver| s.scratch.incident.capacity() + s.scratch.element_powers.capacity();
        assert!(held(&solver) > 0, "a shot keeps its buffers for the next");
        let CulledZones { zones, members } =
            solver.layout.zones.as_ref().expect("two closed rooms");
        let room = zones.of(solver.mesh.patches[0].surface);
        let room_size = (members.vertices[room].len(), members.elements[room].len());
        assert!(
            2 * room_size.0 <= solver.mesh.vertices.len() + 1,
            "{room_size:?}"
        );
        assert_eq!(
            (
                solver.scratch.incident.len(),
                solver.scratch.element_powers.len()
            ),
            room_size
        );
        let until = crate::Until::default().total_shots(3);
        solver.run_until(&until, |_| {});
        assert_eq!((solver.stats().shots, held(&solver)), (3, 0));
    }

    /// Each run of receivers starts with a fresh shadow cache at the same
    /// receivers, however many threads share the runs: the cache's answers,
    /// and so a solve, cannot depend on rayon's scheduling.
    #[test]
    fn shadow_cache_runs_start_fresh_at_fixed_receivers_on_any_pool() {
        let items: Vec<usize> = (0..1000).collect();
        let expected: Vec<bool> = items.iter().map(|i| i % SHADOW_CACHE_RUN == 0).collect();
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let fresh: Vec<bool> = pool.install(|| {
                in_shadow_cache_runs(&items, |_, cache| {
                    let fresh = cache.is_fresh();
                    cache.fill_for_test();
                    fresh
                })
            });
            assert_eq!(fresh, expected, "{threads} threads");
        }
    }

    /// Under a small shooter the shot's irradiance is its point kernel
    /// times a constant: interpolated linearly between two samples either
    /// side of the peak it falls short, and the curvature factor restores
    /// it; a vertex behind either plane keeps the interpolation.
    #[test]
    fn the_curvature_factor_restores_a_point_shooters_peak() {
        let kernel = PointKernel {
            centre: DVec3::new(0.0, 2.0, 0.0),
            normal: DVec3::NEG_Y,
        };
        let up = DVec3::Y;
        let field = |x: f64| 7.0 * kernel.at(DVec3::new(x, 0.0, 0.0), up);
        let (left, right) = (field(-0.5), field(0.5));
        let linear = 0.5 * (left + right);
        assert!(linear < 0.9 * field(0.0), "{linear} against {}", field(0.0));
        let interpolated_kernel = 0.5
            * (kernel.at(DVec3::new(-0.5, 0.0, 0.0), up)
                + kernel.at(DVec3::new(0.5, 0.0, 0.0), up));
        let here = kernel.at(DVec3::ZERO, up);
        let restored = linear * curvature_factor(here, interpolated_kernel);
        assert!((restored / field(0.0) - 1.0).abs() < 1e-12, "{restored}");
        // Facing away from the shooter: no kernel, no change.
        let behind = kernel.at(DVec3::ZERO, DVec3::NEG_Y);
        assert_eq!(behind, 0.0);
        assert_eq!(curvature_factor(behind, interpolated_kernel), 1.0);
        // Far off the peak the factor is held within [1/2, 2].
        assert_eq!(curvature_factor(1.0, 0.01), 2.0);
    }
}
