//! The progressive shooting solver (Cohen, Chen, Wallace, Greenberg 1988):
//! `Solver` as a driver of its parts. It chooses each shot and hands it to
//! `shot/` (gathering, reception) and `light/` (the unshot light and the
//! ledger), refines an adaptive mesh after direct light, and runs until a
//! stop criterion (`stop.rs`) is met.

mod accessors;
mod run_loop;

use super::refinement::{Refiner, elements_to_split};
use super::settings::{Settings, ShootFrom, SolverSettings};
use crate::freed_memory::give_back_freed_memory;
use crate::mesh::Mesh;
use crate::meshing::{MeshAnalysis, MeshKind, SceneMesh, Zones, mesh_scene_in_zones};
use crate::phase::{Phase, PhaseCounter, PhaseReporter, silent};
use crate::rgb::Rgb;
use crate::scene::{Scene, Visibility};
use crate::solver::ambient::patch_shots::{PatchShotSummary, PatchShots};
use crate::solver::ambient::state::AmbientState;
use crate::solver::ambient::term::AmbientTerm;
use crate::solver::layout::{CulledZones, SolveLayout};
use crate::solver::light::energy_balance::EnergyBalance;
use crate::solver::light::state::LightState;
use crate::solver::reading::request::{self, Ambient};
use crate::solver::reading::solution::Solution;
use crate::solver::shot::context::ShotContext;
use crate::solver::shot::element_power::Emitter;
use crate::solver::shot::incident::{PatchShot, ShotWork};
use crate::solver::shot::scratch::{ShotMemory, ShotScratch};
use crate::solver::shot::shooter::ShotRadiosity;
use crate::solver::stats::SolveStats;

/// The parts of a solver every shot reads ([`ShotContext`]), borrowed field
/// by field so that the parts a shot changes can be borrowed beside them.
macro_rules! shot_context {
    ($solver:expr) => {
        ShotContext {
            scene: &$solver.scene,
            mesh: &$solver.mesh,
            visibility: &$solver.visibility,
            settings: &$solver.settings,
            layout: &$solver.layout,
        }
    };
}

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
    layout: SolveLayout,
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
        // The mesh settings resolved against the scene once, for the
        // budget, the meshers and the patch clusters' extent.
        let mesh_settings = settings.mesh.resolve(&scene);
        mesh_settings.check_budget(&scene)?;
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
        } = mesh_scene_in_zones(&scene, &visibility, &mesh_settings, Some(&zones), report);
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
        solver.layout.patch_edge = mesh_settings.square.patch_max_edge;
        Ok(solver)
    }

    /// A solver for `scene` on a mesh the caller made (with [`crate::mesh::mesh_square`]
    /// or [`crate::meshing::mesh_scene`], say), nothing yet shot. Probes and
    /// reflected shots' shafts take the scene's receiver inset
    /// (`mesh::receiver_inset`), as [`crate::mesh::mesh_square`]'s
    /// boundary vertices do; [`crate::meshing::mesh_scene`]'s move each
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
        let mut layout = SolveLayout::new(&scene, &mesh, &visibility, zones, &settings);
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
        if !self.light.daylight_shot {
            self.ambient.patch_shots = None;
            self.shoot_daylight();
            return true;
        }
        // The shooter: pending emission first, else the most unshot power.
        let areas = &self.layout.patch_areas;
        let chosen = self.light.next_shooter(areas, self.settings.zone_affinity);
        let Some((j, power)) = chosen else {
            return false;
        };
        if power.is_nan() || power <= 0.0 {
            return false;
        }
        self.ambient.patch_shots = None;
        // What it shoots: its unshot radiosity, uniform or as a field.
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
        // Its irradiance at the zone's vertices; reflected light may be
        // received patch by patch where it is dim.
        let mut incident = std::mem::take(&mut self.scratch.incident);
        let shot = PatchShot {
            patch: j,
            power,
            coarse: (!is_emitter).then_some(shot_power),
            radiosity,
            zone,
        };
        let work = ShotWork {
            scratch: &mut self.scratch,
            memory: &mut self.memory,
            stats: &mut self.stats,
        };
        shot_context!(self).incident_from(shot, &self.light, work, &mut incident);
        // Received by the zone's elements, whole where the zone keeps it.
        let lossless = self.layout.surface_lossless[self.mesh.patches[j].surface.index()];
        let lands_whole = (!is_emitter && lossless).then_some(shot_power);
        let emitter = is_emitter.then(|| {
            let patch = &self.mesh.patches[j];
            let normal = self.scene.surface(patch.surface).normal();
            Emitter::Patch {
                cell: patch.cell,
                normal,
            }
        });
        self.receive(&incident, zone, emitter, lands_whole);
        self.scratch.incident = incident;
        // The ledger and the counters.
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
        let incident = shot_context!(self).luminaire_light(k, &vertices);
        let samples = self.scene.luminaires[k].opening_samples().len();
        self.stats.rays += (vertices.len() * samples) as u64;
        self.receive(&incident, zone, Some(Emitter::Luminaire(k)), None);
        self.light.shot_power += self.scene.luminaires[k].power();
        self.light.luminaire_shot[k] = true;
        self.stats.shots += 1;
        self.refine();
    }

    /// Shoots the daylight: every vertex receives the sky, the ground and
    /// the sun through the portals ([`crate::lighting::DaylightSource`]).
    /// Its power is the power its shot landed, counted as emitted and
    /// shot: the ledger's escaped power does not change.
    fn shoot_daylight(&mut self) {
        let vertices: Vec<u32> = (0..self.mesh.vertices.len() as u32).collect();
        let (incident, rays) = shot_context!(self).daylight_light(&vertices);
        self.stats.rays += rays;
        let before = self.light.received_power;
        self.receive(&incident, None, None, None);
        let landed = self.light.received_power - before;
        self.light.emitted_power += landed;
        self.light.shot_power += landed;
        self.light.reference_power = self.light.reference_power.max(landed.element_sum());
        self.light.daylight_shot = true;
        self.stats.shots += 1;
        self.refine();
    }

    /// A shot's `incident` irradiance received by closed zone `zone`'s
    /// vertices and elements, or every one (see [`ShotContext::receive`]),
    /// and the unshot power counted again where it changed.
    fn receive(
        &mut self,
        incident: &[Rgb],
        zone: Option<usize>,
        emitter: Option<Emitter>,
        lands_whole: Option<Rgb>,
    ) {
        let powers = &mut self.scratch.element_powers;
        shot_context!(self).receive(
            &mut self.light,
            incident,
            zone,
            emitter,
            lands_whole,
            powers,
        );
        self.light.recount_unshot(zone, &self.layout.patch_areas);
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
}

impl Solver {
    /// Splits the elements whose vertices disagree (see [`elements_to_split`]),
    /// level by level until none does, and gives every new vertex the light
    /// of all shots so far by gathering it (see
    /// [`ShotContext::gather_shot_light`]).
    ///
    /// The energy ledger stays closed: where the finer elements estimate a
    /// patch's incident power differently, the difference ΔP moves from the
    /// escaped power to the received power, and ρ ΔP to the patch's unshot
    /// power. The new elements' unshot corners carry that ρ ΔP where it was
    /// found (see `UnshotCorners::after_split`).
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
            let before = self.light.incident_power_per_patch(&self.mesh);
            let corners_before = self.light.unshot_corners.by_vertices(&self.mesh);
            let added = refiner.hierarchy.split(&mut self.mesh, &split);
            // The new vertices gather the light of every shot so far.
            let context = shot_context!(self);
            let gathered = context.gather_shot_light(&self.light, &mut self.stats, &added);
            self.light.add_vertices(&added, gathered);
            let (scene, mesh) = (&self.scene, &self.mesh);
            let hierarchy = &refiner.hierarchy;
            (self.light).carry_unshot_corners(scene, mesh, hierarchy, &corners_before);
            // The difference in incident power the finer elements found.
            let after = self.light.incident_power_per_patch(&self.mesh);
            self.light
                .book_split(&self.scene, &self.mesh, before, after);
            self.light.recount_unshot(None, &self.layout.patch_areas);
        }
        self.refiner = Some(refiner);
        // The mesh changed: its members are listed by zone again, and its
        // patches' samples found again.
        if let Some(CulledZones { members, .. }) = &mut self.layout.zones {
            members.invalidate();
        }
        self.memory.reception.invalidate();
    }
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
}
