//! The progressive shooting solver (Cohen, Chen, Wallace, Greenberg 1988):
//! `Solver` as a driver of its parts. It chooses each shot and hands it to
//! `shot/` (gathering, reception) and `light/` (the unshot light and the
//! ledger), refines an adaptive mesh after direct light, and runs until a
//! stop criterion (`run.rs`) is met.

mod accessors;
mod run_loop;

use rayon::prelude::*;

use super::refinement::{Refiner, elements_to_split};
use super::settings::{Settings, ShootFrom, SolverSettings};
use crate::freed_memory::give_back_freed_memory;
use crate::mesh::Mesh;
use crate::meshing::{MeshAnalysis, MeshKind, SceneMesh, Zones, mesh_scene_in_zones};
use crate::phase::{Phase, PhaseCounter, PhaseReporter, silent};
use crate::scene::{Camera, Rgb, Scene, SurfaceId, Visibility};
use crate::solver::ambient::irradiance::AmbientIrradiance;
use crate::solver::ambient::patch_shots::{PatchShotInput, PatchShotSummary, PatchShots};
use crate::solver::ambient::rays::{
    AmbientEstimate, LandingElement, PatchLocator, PatchRays, VertexRays,
};
use crate::solver::ambient::rooms::{AmbientCache, LocalIndex, ReadingPlace, Room, zones_read};
use crate::solver::ambient::smoothing;
use crate::solver::ambient::state::AmbientState;
use crate::solver::ambient::sweeps::{self, UnshotLight};
use crate::solver::layout::{CulledZones, Layout};
use crate::solver::light::energy_balance::EnergyBalance;
use crate::solver::light::state::LightState;
use crate::solver::light::unshot::{FieldScale, PatchField};
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
            Emitter {
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
        self.receive(&incident, zone, None, None);
        self.light.shot_power += self.scene.luminaires[k].power();
        self.light.luminaire_shot[k] = true;
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

    fn reflectance(&self, vertex: usize) -> Rgb {
        self.layout.surface_reflectance[self.mesh.vertices[vertex].surface.index()]
    }

    /// Radiosity per vertex (W/m²) from the light shot so far, B = E + ρ H
    /// with the emission E and reflectance ρ of each vertex's surface: a
    /// new list, 24 bytes a vertex (the solver keeps H alone).
    #[must_use]
    pub fn radiosity(&self) -> Vec<Rgb> {
        self.solution().radiosity()
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

    /// Radiosity per vertex with the ambient term added: the light not yet
    /// shot, gathered where it will land, B_v + ρ_v G_v. For intermediate
    /// images.
    #[must_use]
    pub fn radiosity_with_ambient(&self) -> Vec<Rgb> {
        self.solution_with_ambient().radiosity()
    }

    /// The ambient irradiance G_v of every vertex: the light the unshot
    /// radiosity will still give, gathered along rays (see
    /// `solver/ambient/rays.rs`), room by room (`solver/ambient/rooms.rs`),
    /// reporting its progress to `report`; only in zone `only`'s
    /// vertices where given (0 at the others, which it does not hold).
    fn ambient_irradiance(
        &self,
        only: Option<&[usize]>,
        report: PhaseReporter,
    ) -> AmbientIrradiance {
        let keep = AmbientCache::keeps(self.mesh.vertices.len());
        self.ambient_irradiance_keeping(keep, only, report)
    }

    /// [`Solver::ambient_irradiance`], the rooms' rays kept for the next
    /// image or, unless `keep`, cast room by room and dropped.
    fn ambient_irradiance_keeping(
        &self,
        keep: bool,
        only: Option<&[usize]>,
        report: PhaseReporter,
    ) -> AmbientIrradiance {
        // What the shots freed goes back before the term's lists are made.
        give_back_freed_memory();
        let zones = self
            .layout
            .zones
            .as_ref()
            .map(|CulledZones { zones, .. }| zones);
        let (rooms, others) = self.ambient_rooms(only, keep);
        // Half a room's vertices count once their rays are cast (or kept),
        // the other half once their light is gathered.
        let total = rooms.iter().map(|room| room.vertices.len()).sum();
        let counter = PhaseCounter::start(Phase::AmbientTerm, total, report);
        let halves = |room: &Room| {
            let n = room.vertices.len();
            (n / 2, n - n / 2)
        };
        let mut cache = self
            .ambient
            .rays
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        // A zone's rays traverse the BVH of what lies within its bounds,
        // as its shots' do: a ray that leaves them (through a seam) lands
        // on no front of its zone either way.
        let visibility_of = |surface: SurfaceId| {
            zones
                .and_then(|zones| zones.visibility(zones.of(surface)))
                .unwrap_or(&self.visibility)
        };
        // The rooms' patches: the whole mesh's, or those of the rooms
        // asked for (a ray that leaks out of them reads the unshot light
        // where it lands, without its further bounces unless the patch
        // shots hold them).
        let within = only.is_some().then(|| {
            let mut patches: Vec<u32> = rooms
                .iter()
                .flat_map(|r| r.patches.iter().copied())
                .collect();
            patches.sort_unstable();
            patches
        });
        // Where rays land, found only when some are cast.
        let locator = std::cell::OnceCell::new();
        let locator = || locator.get_or_init(|| PatchLocator::new(&self.scene, &self.mesh));
        // After patch shots the patches' further bounces are theirs; else
        // the term finds them along its patches' rays.
        let uncast = match &self.ambient.patch_shots {
            Some(_) => Vec::new(),
            None => cache.patches.uncast(&self.mesh, within.as_deref()),
        };
        if !uncast.is_empty() {
            let parts = (&self.scene, &self.mesh);
            cache
                .patches
                .cast(parts, &uncast, locator(), &visibility_of);
        }
        let (residual, patch_value) = self.patch_residual(&cache.patches, within.as_deref());
        let cast = |room: &Room| {
            let rays = VertexRays::cast(
                &self.scene,
                &self.mesh,
                room.vertices.clone(),
                locator(),
                &visibility_of,
            );
            counter.add(halves(room).0);
            rays
        };
        // Kept rays serve again where their room's vertices are the same
        // (an adaptive mesh adds vertices to the rooms it refines).
        let mut kept = std::mem::take(&mut cache.rooms);
        if keep {
            let mut reuse = |room: &Room| {
                let same = kept
                    .iter()
                    .position(|rays| rays.vertices() == room.vertices);
                same.map(|k| {
                    counter.add(halves(room).0);
                    kept.swap_remove(k)
                })
            };
            cache.rooms = rooms
                .iter()
                .map(|room| reuse(room).unwrap_or_else(|| cast(room)))
                .collect();
            // After the rooms' own, in any order: looked up by vertices.
            kept.retain(|rays| others.iter().any(|room| rays.vertices() == room.vertices));
            cache.rooms.append(&mut kept);
        }
        kept.clear();
        let mut local = LocalIndex::new(&self.mesh);
        // Every vertex's term by index, or the rooms' vertices' alone.
        let mut everywhere = only
            .is_none()
            .then(|| vec![Rgb::ZERO; self.mesh.vertices.len()]);
        let mut in_rooms = Vec::new();
        for (r, room) in rooms.iter().enumerate() {
            let cast_now;
            let rays = match cache.rooms.get(r) {
                Some(kept) => kept,
                None => {
                    cast_now = cast(room);
                    &cast_now
                }
            };
            local.enter(room);
            let room_ambient = self.room_ambient((room, &local), rays, (&residual, &patch_value));
            match &mut everywhere {
                Some(values) => {
                    for (&v, g) in room.vertices.iter().zip(room_ambient) {
                        values[v as usize] = g;
                    }
                }
                None => in_rooms.extend(room.vertices.iter().copied().zip(room_ambient)),
            }
            local.leave(room);
            counter.add(halves(room).1);
        }
        counter.finish();
        match everywhere {
            Some(values) => AmbientIrradiance::Everywhere(values),
            None => AmbientIrradiance::of_rooms(in_rooms),
        }
    }

    /// The rooms whose ambient term is made (the mesh's closed zones and
    /// the rest, see [`Room::all`]; only the zones `only` lists where
    /// given), and, if `listing_others`, the others.
    fn ambient_rooms(
        &self,
        only: Option<&[usize]>,
        listing_others: bool,
    ) -> (Vec<Room>, Vec<Room>) {
        let Some(CulledZones { zones, .. }) = &self.layout.zones else {
            return (vec![Room::whole(&self.mesh)], Vec::new());
        };
        let count = zones.count();
        let every = |s: SurfaceId| Some(zones.of(s));
        let Some(only) = only else {
            return (Room::all(&self.mesh, count, &every), Vec::new());
        };
        let mut wanted = vec![false; count];
        for &zone in only {
            if let Some(w) = wanted.get_mut(zone) {
                *w = true;
            }
        }
        let is_wanted = |zone: usize| wanted.get(zone).copied().unwrap_or(false);
        if !listing_others {
            let picked = |s: SurfaceId| Some(zones.of(s)).filter(|&z| is_wanted(z));
            return (Room::all(&self.mesh, count, &picked), Vec::new());
        }
        let zone_of = |room: &Room| {
            let v = room.vertices.first().map(|&v| v as usize);
            v.and_then(|v| self.mesh.vertices.get(v))
                .map(|vertex| zones.of(vertex.surface))
        };
        Room::all(&self.mesh, count, &every)
            .into_iter()
            .partition(|room| zone_of(room).is_some_and(is_wanted))
    }

    /// Each patch's residual A_h, the unshot light's further bounces at
    /// patch resolution, and ΔB_h + A_h, what a vertex ray reads where it
    /// lands on no element of its room. After patch shots A_h is ρ_h
    /// times the irradiance they brought h (`solver/ambient/patch_shots.rs`);
    /// otherwise it is found along the patches' `rays`
    /// ([`PatchRays::residual`], zero until they are cast), on the patches
    /// `within` (all, by `None`).
    fn patch_residual(&self, rays: &PatchRays, within: Option<&[u32]>) -> (Vec<Rgb>, Vec<Rgb>) {
        let residual = match &self.ambient.patch_shots {
            Some(shots) => (0..self.mesh.patches.len())
                .into_par_iter()
                .map(|p| {
                    let surface = self.mesh.patches[p].surface.index();
                    self.layout.surface_reflectance[surface] * shots.irradiance(p)
                })
                .collect(),
            None => {
                let (reflectance, lossless): (Vec<Rgb>, Vec<bool>) = self
                    .mesh
                    .patches
                    .iter()
                    .map(|p| {
                        let surface = self.scene.surface(p.surface);
                        let reflectance = self.scene.material_of(surface).reflectance;
                        (reflectance, self.layout.surface_lossless[p.surface.index()])
                    })
                    .unzip();
                rays.residual((&self.light.unshot, &reflectance, &lossless), within)
            }
        };
        let patch_value = self
            .light
            .unshot
            .iter()
            .zip(&residual)
            .map(|(u, a)| *u + *a)
            .collect();
        (residual, patch_value)
    }

    /// G_v of `room`'s vertices, in its order (`local` has entered it),
    /// from its vertices' `rays` and each patch's residual A_h and
    /// ΔB_h + A_h (see `solver/ambient/rays.rs`).
    fn room_ambient(
        &self,
        (room, local): (&Room, &LocalIndex),
        rays: &VertexRays,
        (residual, patch_value): (&[Rgb], &[Rgb]),
    ) -> Vec<Rgb> {
        let mesh = &self.mesh;
        // Each of the room's patches' unshot field over its elements, at
        // the scale that carries its power, for the rays to read where
        // they land.
        let fields: Vec<(PatchField, FieldScale)> = room
            .patches
            .par_iter()
            .map(|&p| {
                let patch = &mesh.patches[p as usize];
                let power = self.light.unshot[p as usize] * patch.area;
                let field = self.light.unshot_corners.field(mesh, patch, power);
                let scale = field.exact_scale();
                (field, scale)
            })
            .collect();
        // The element under each ray's landing point, found once for the
        // first gather and every sweep; none outside the room.
        let landed = rays.landing_elements(&|p, (s, t), hint| {
            let (field, _) = &fields[local.patch(p)?];
            let patch = &mesh.patches[p];
            field
                .locate(patch.cell.point(s, t), hint)
                .map(|(k, st)| LandingElement::new(patch.elements[k], st))
        });
        let corners: Vec<[Rgb; 4]> = room
            .elements
            .par_iter()
            .map(|&e| {
                let corners = self.light.unshot_corners.of(e as usize);
                let patch = mesh.elements[e as usize].patch as usize;
                local
                    .patch(patch)
                    .map_or(corners, |i| corners.map(|c| fields[i].1.apply(c)))
            })
            .collect();
        let unshot_at = |k: usize| {
            let landed = landed[k];
            let i = local.element(landed.element()?)?;
            landed.value(mesh, |_| corners[i])
        };
        let lossless = |surface: SurfaceId| self.layout.surface_lossless[surface.index()];
        let gathered = rays.irradiance(mesh, (residual, patch_value), &unshot_at, &lossless);
        let distances = rays.harmonic_distances(mesh);
        let around = self
            .settings
            .smooth_ambient
            .then(|| smoothing::Neighbourhood::new(mesh, room, local));
        let smooth = |gathered: &[AmbientEstimate]| -> Vec<Rgb> {
            match &around {
                Some(around) => smoothing::smoothed(mesh, (room, around), gathered, &distances),
                None => gathered.iter().map(|g| g.irradiance).collect(),
            }
        };
        let first = smooth(&gathered);
        let vertex_reflectance: Vec<Rgb> = room
            .vertices
            .iter()
            .map(|&v| self.reflectance(v as usize))
            .collect();
        let unshot = UnshotLight {
            landed: &landed,
            corners: &corners,
            per_patch: &self.light.unshot,
            outside: patch_value,
        };
        sweeps::swept(
            (rays, mesh),
            (room, local),
            (first, self.settings.ambient_sweeps),
            (&unshot, &vertex_reflectance),
            &lossless,
            &smooth,
        )
    }

    /// The solution from the light shot so far, without the ambient term.
    #[must_use]
    pub fn solution(&self) -> Solution<'_> {
        self.solution_from(AmbientIrradiance::Nowhere)
    }

    /// The solution with the ambient term for the light not yet shot added:
    /// B_v + ρ_v G_v and H_v + G_v, G_v the unshot light gathered along
    /// rays (a coarse final gather of what remains; see
    /// `solver/ambient/rays.rs`). What images and probes show.
    #[must_use]
    pub fn solution_with_ambient(&self) -> Solution<'_> {
        self.solution_with_ambient_progress(&silent)
    }

    /// [`Solver::solution_with_ambient`], reporting the ambient term's
    /// progress to `report` ([`crate::Phase::AmbientTerm`]), which takes
    /// minutes for a building; nothing is reported when no light is left
    /// unshot (there is no ambient term).
    #[must_use]
    pub fn solution_with_ambient_progress(&self, report: PhaseReporter) -> Solution<'_> {
        self.solution_with_ambient_in(None, report)
    }

    /// The solution an image from `camera` needs: where the camera stands
    /// inside a closed room (a zone that keeps its light, whose walls hide
    /// the rest: [`Solution::triangles_seen_from`]), the ambient term is
    /// made for that room's vertices alone, and the other rooms hold the
    /// light shot so far; elsewhere it is
    /// [`Solver::solution_with_ambient_progress`]. A view from one office
    /// of a building then costs that office's term (a second, where the
    /// building's is minutes). It is
    /// [`Solver::solution_with_ambient_for`] the camera's position, and
    /// its probes are refused outside the camera's room.
    #[must_use]
    pub fn solution_with_ambient_seen_from(
        &self,
        camera: &Camera,
        report: PhaseReporter,
    ) -> Solution<'_> {
        self.solution_with_ambient_for(&[ReadingPlace::InSpace(camera.position)], report)
    }

    /// The solution that readings at `places` need (probes on surfaces,
    /// a calculation grid's points, a camera): where every place lies in
    /// a closed room (a zone that keeps its light, so that what is read
    /// there comes from that room alone), the ambient term is made for
    /// those rooms' vertices alone, and every other room holds the light
    /// shot so far. Where any place lies in no closed room, or no place
    /// is given, it is the whole term
    /// ([`Solver::solution_with_ambient_progress`]). A
    /// calculation grid on one office's work plane then costs that
    /// office's term, not the building's. Read the returned solution
    /// only at these places: elsewhere it lacks the light not yet shot,
    /// and [`Solution::probe`] refuses a point outside its rooms.
    #[must_use]
    pub fn solution_with_ambient_for(
        &self,
        places: &[ReadingPlace],
        report: PhaseReporter,
    ) -> Solution<'_> {
        let rooms = self
            .layout
            .zones
            .as_ref()
            .and_then(|CulledZones { zones, .. }| {
                let labels = zones.labels();
                (labels.count() > 1)
                    .then(|| zones_read(labels, (&self.scene, &self.visibility), places))
                    .flatten()
            });
        self.solution_with_ambient_in(rooms.as_deref(), report)
    }

    /// The solution with the ambient term made in the vertices of the
    /// zones `only` lists, or in all by `None`.
    fn solution_with_ambient_in(
        &self,
        only: Option<&[usize]>,
        report: PhaseReporter,
    ) -> Solution<'_> {
        if self.light.unshot.iter().all(|b| *b == Rgb::ZERO) {
            return self.solution();
        }
        let ambient = self.ambient_irradiance(only, report);
        let mut solution = self.solution_from(ambient);
        if solution.zones.is_some() {
            solution.ambient_zones = only.map(<[usize]>::to_vec);
        }
        solution
    }

    /// A [`Solution`] of this solver's scene, mesh and light shot, with
    /// the `ambient` term added.
    fn solution_from(&self, ambient: AmbientIrradiance) -> Solution<'_> {
        Solution {
            scene: &self.scene,
            mesh: &self.mesh,
            visibility: &self.visibility,
            luminaires_shot: self.light.luminaire_shot.clone(),
            shot_irradiance: &self.light.irradiance,
            ambient,
            receiver_insets: &self.layout.receiver_insets,
            zones: self
                .layout
                .zones
                .as_ref()
                .map(|CulledZones { zones, .. }| zones.labels())
                .filter(|labels| labels.count() > 1),
            ambient_zones: None,
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
        let zones = self
            .layout
            .zones
            .as_ref()
            .map(|CulledZones { zones, .. }| zones);
        let visibility_of = |surface: SurfaceId| {
            zones
                .and_then(|zones| zones.visibility(zones.of(surface)))
                .unwrap_or(&self.visibility)
        };
        let locator = PatchLocator::new(&self.scene, &self.mesh);
        let input = PatchShotInput {
            scene: &self.scene,
            mesh: &self.mesh,
            zones: self.light.unshot_by_zone.zone_patches(),
            unshot: &self.light.unshot,
            areas: &self.layout.patch_areas,
            reflectance: &self.layout.surface_reflectance,
            lossless: &self.layout.surface_lossless,
            locator: &locator,
            surface_zone: &self.layout.surface_zone,
            cluster_edge: self
                .settings
                .patch_clusters
                .then_some(self.layout.patch_edge),
            visibility_of: &visibility_of,
        };
        let shots = PatchShots::shoot(&input, tolerance * emitted / unshot);
        self.ambient.patch_shots = Some(shots);
    }

    /// What the last run's patch shots did ([`Solver::shoot_patches`]), or
    /// `None` if it made none (or a shot came after).
    #[must_use]
    pub fn patch_shot_summary(&self) -> Option<PatchShotSummary> {
        let shots = self.ambient.patch_shots.as_ref()?;
        let emitted = self.light.emitted_power.element_sum();
        let fraction = |power: Rgb| {
            if emitted > 0.0 {
                power.element_sum() / emitted
            } else {
                0.0
            }
        };
        Some(PatchShotSummary {
            unshot_before: fraction(shots.before),
            unshot_after: fraction(shots.left),
            sweeps: shots.sweeps,
            rays: shots.rays,
            clusters: shots.clusters,
            clustered_patches: shots.clustered_patches,
        })
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
    use glam::DVec3;

    use super::*;
    use crate::scene::surface::newell_normal;
    use crate::scene::{Material, ProbePoint, Surface};
    use crate::solver::ProbeMode;

    /// Two closed 4 × 3 × 4 m rooms 5 m apart, each with a lamp under its
    /// ceiling and a block on its floor, every face towards the room; the
    /// second room's lamp twice as bright as the first's.
    fn two_closed_rooms() -> Scene {
        let mut scene = Scene::default();
        let materials = [
            ("wall", 0.6, 0.0),
            ("lamp", 0.0, 10.0),
            ("bright", 0.0, 20.0),
        ];
        for (name, reflectance, radiance) in materials {
            scene.materials.push(Material {
                name: name.into(),
                reflectance: Rgb::splat(reflectance),
                emitted_radiance: Rgb::splat(radiance),
            });
        }
        // A quad of a box's face, turned to face `towards`.
        let mut add = |material: usize, mut quad: Vec<DVec3>, towards: DVec3| {
            let centre = quad.iter().copied().sum::<DVec3>() / 4.0;
            if newell_normal(&quad).dot(towards - centre) < 0.0 {
                quad.reverse();
            }
            scene
                .surfaces
                .push(Surface::new("face", material, quad).expect("a valid quad"));
        };
        // The faces of the box [lo, hi], each facing `inwards` or out.
        let box_faces = |lo: DVec3, hi: DVec3| {
            (0..3).flat_map(move |axis| {
                [0.0, 1.0].map(move |side| {
                    let corner = |s: f64, t: f64| {
                        let mut w = [0.0; 3];
                        w[axis] = side;
                        w[(axis + 1) % 3] = s;
                        w[(axis + 2) % 3] = t;
                        lo + (hi - lo) * DVec3::from_array(w)
                    };
                    vec![
                        corner(0.0, 0.0),
                        corner(1.0, 0.0),
                        corner(1.0, 1.0),
                        corner(0.0, 1.0),
                    ]
                })
            })
        };
        for (x, lamp) in [(0.0, 1), (5.0, 2)] {
            let (lo, hi) = (DVec3::new(x, 0.0, 0.0), DVec3::new(x + 4.0, 3.0, 4.0));
            for quad in box_faces(lo, hi) {
                add(0, quad, (lo + hi) / 2.0);
            }
            let (block_lo, block_hi) = (
                lo + DVec3::new(1.0, 0.0, 1.0),
                lo + DVec3::new(2.0, 0.8, 2.0),
            );
            // The block's faces but its bottom (the third), facing out.
            let centre = (block_lo + block_hi) / 2.0;
            for (k, quad) in box_faces(block_lo, block_hi).enumerate() {
                let outwards = quad.iter().copied().sum::<DVec3>() / 2.0 - centre;
                if k != 2 {
                    add(0, quad, outwards);
                }
            }
            let corners = [(1.7, 1.7), (2.3, 1.7), (2.3, 2.3), (1.7, 2.3)]
                .map(|(u, w)| lo + DVec3::new(u, 2.99, w))
                .to_vec();
            add(lamp, corners, lo + DVec3::new(2.0, 0.0, 2.0));
        }
        scene
    }

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

    /// A gather inside a closed room, on its floor or in its air, tries
    /// that room's elements alone, and reads what a gather over every
    /// element of the building reads: the other room's are all hidden.
    #[test]
    fn a_gather_in_a_closed_room_reads_what_one_over_every_element_reads() {
        let mut settings = Settings::default();
        settings.mesh.max_edge = crate::Length::Absolute(0.5);
        let mut solver = Solver::new(two_closed_rooms(), settings).expect("a valid scene");
        solver.run();
        let zoned = solver.solution_with_ambient();
        assert!(zoned.zones.is_some());
        let mut everywhere = solver.solution_from(zoned.ambient.clone());
        everywhere.zones = None;
        for x in [0.0, 5.0] {
            let floor = ProbePoint {
                position: DVec3::new(x + 3.1, 0.0, 0.6),
                normal: Some(DVec3::Y),
                line: 1,
            };
            // Each gather finds its room, the floor's and the air's alike.
            let air = DVec3::new(x + 0.6, 1.5, 3.2);
            let room = zoned.gathered_zone(air, SurfaceId::NONE);
            assert!(room.is_some());
            let on_floor = zoned.probe(&floor, ProbeMode::Mesh);
            let surface = on_floor.expect("a point on the floor").surface;
            assert_eq!(zoned.gathered_zone(floor.position, surface), room);
            let [a, b] = [&zoned, &everywhere].map(|solution| {
                let probe = solution.probe(&floor, ProbeMode::Gather);
                probe.expect("a point on the floor").irradiance
            });
            assert!(
                a.g > 0.0 && (a.g - b.g).abs() <= 1e-9 * b.g,
                "{a:?} against {b:?}"
            );
            let [a, b] = [&zoned, &everywhere].map(|s| s.irradiance_in_space(air, DVec3::X).0);
            assert!(
                a.g > 0.0 && (a.g - b.g).abs() <= 1e-9 * b.g,
                "{a:?} against {b:?}"
            );
        }
    }

    /// The ambient term made room by room is the same whether the rooms'
    /// rays are kept between images or cast for each and dropped, and
    /// each room's rays stay in it: the second room, lit twice as
    /// brightly, gets twice the first's light within the rays' noise.
    #[test]
    fn rooms_kept_or_cast_again_give_the_same_ambient_term() {
        let mut settings = Settings::default();
        settings.mesh.max_edge = crate::Length::Absolute(0.5);
        let mut solver = Solver::new(two_closed_rooms(), settings).expect("a valid scene");
        assert!(solver.closed_zones() >= 2, "{}", solver.closed_zones());
        // Both lamps' shots: half the rooms' light is still unshot.
        solver.step();
        solver.step();
        let streamed = solver.ambient_irradiance_keeping(false, None, &silent);
        let kept = solver.ambient_irradiance_keeping(true, None, &silent);
        let again = solver.ambient_irradiance_keeping(true, None, &silent);
        assert!(streamed == kept, "kept and streamed rays differ");
        assert!(kept == again, "the kept rays changed");
        let kept = kept.at_every(solver.mesh.vertices.len());
        // Σ A G over the elements of the room from x0 to x0 + 4.
        let room_total = |x0: f64| -> f64 {
            let mesh = &solver.mesh;
            let in_room = |x: f64| (x0 - 0.1..=x0 + 4.1).contains(&x);
            mesh.elements
                .iter()
                .filter(|e| in_room(mesh.vertices[e.vertices[0] as usize].position.x))
                .map(|e| e.corner_mean(|v| kept[v as usize]).element_sum() * e.area)
                .sum()
        };
        let (a, b) = (room_total(0.0), room_total(5.0));
        assert!(a > 0.0 && (2.0 * a - b).abs() < 0.01 * b, "{a} against {b}");
    }

    /// A term made in one room between two made in all keeps the other
    /// rooms' rays and changes nothing: the rays found again by their
    /// vertices, the patches' rays cast for the one room kept with the
    /// rest.
    #[test]
    fn one_rooms_term_keeps_the_other_rooms_rays() {
        let mut settings = Settings::default();
        settings.mesh.max_edge = crate::Length::Absolute(0.5);
        let mut solver = Solver::new(two_closed_rooms(), settings.clone()).expect("a valid scene");
        solver.step();
        solver.step();
        let zones = solver
            .layout
            .zones
            .as_ref()
            .map(|culled| culled.zones.labels().clone());
        let zones = zones.expect("closed zones");
        let zone_of = |v: usize| zones.of(solver.mesh.vertices[v].surface);
        let room = zone_of(0);
        let one = solver.ambient_irradiance_keeping(true, Some(&[room]), &silent);
        let rays = |s: &Solver| s.ambient.rays.lock().map(|c| c.rooms.len()).unwrap_or(0);
        assert_eq!(rays(&solver), 1, "one room's rays cast");
        let all = solver.ambient_irradiance_keeping(true, None, &silent);
        let kept = rays(&solver);
        let one_again = solver.ambient_irradiance_keeping(true, Some(&[room]), &silent);
        assert_eq!(rays(&solver), kept, "the other rooms' rays dropped");
        let all_again = solver.ambient_irradiance_keeping(true, None, &silent);
        assert!(all == all_again && one == one_again);
        let count = solver.mesh.vertices.len();
        let (one_at, all_at) = (one.at_every(count), all.at_every(count));
        for (v, g) in one_at.iter().enumerate() {
            if zone_of(v) == room {
                assert!((*g - all_at[v]).abs().max_element() <= 1e-6 * all_at[v].max_element());
            } else {
                assert_eq!(*g, Rgb::ZERO);
            }
        }
        assert!(
            matches!(one, AmbientIrradiance::At { .. }),
            "one room's term alone"
        );
        // The whole term is the one a solver that never drew one room
        // makes, streamed or kept: the rays do not depend on the order.
        let mut fresh = Solver::new(two_closed_rooms(), settings).expect("a valid scene");
        fresh.step();
        fresh.step();
        assert!(all == fresh.ambient_irradiance_keeping(false, None, &silent));
        assert!(all == fresh.ambient_irradiance_keeping(true, None, &silent));
    }

    /// An adaptive mesh's rooms keep the rays of the rooms whose vertices
    /// stay as they were and cast those of the rooms refinement grows: the
    /// term is what rays all cast afresh give.
    #[test]
    fn refined_rooms_cast_their_new_vertices_rays() {
        let mut settings = Settings::default();
        settings.mesh.max_edge = crate::Length::Absolute(0.5);
        settings.mesh.kind = MeshKind::Adaptive;
        let mut solver = Solver::new(two_closed_rooms(), settings).expect("a valid scene");
        let before = solver.mesh.vertices.len();
        let _ = solver.ambient_irradiance_keeping(true, None, &silent);
        for _ in 0..4 {
            solver.step();
        }
        assert!(
            solver.mesh.vertices.len() > before,
            "{before} vertices, none added"
        );
        let kept = solver.ambient_irradiance_keeping(true, None, &silent);
        let streamed = solver.ambient_irradiance_keeping(false, None, &silent);
        assert!(
            kept == streamed,
            "kept and streamed rays differ after refinement"
        );
        let count = solver.mesh.vertices.len();
        assert!(kept.at_every(count).iter().any(|g| g.element_sum() > 0.0));
    }
}
