//! The ambient term G_v made from a solver's parts: the rooms it is made
//! in, each patch's residual, and each room's vertices' light gathered
//! along their rays, swept and smoothed (`solver/ambient/rays.rs`,
//! `rooms.rs`, `sweeps.rs`, `smoothing.rs`).

use std::cell::OnceCell;
use std::sync::PoisonError;

use rayon::prelude::*;

use crate::freed_memory::give_back_freed_memory;
use crate::mesh::Mesh;
use crate::phase::{Phase, PhaseCounter, PhaseReporter};
use crate::rgb::Rgb;
use crate::scene::{Scene, SurfaceId, Visibility};
use crate::solver::ambient::irradiance::AmbientIrradiance;
use crate::solver::ambient::landing::LandingElement;
use crate::solver::ambient::patch_locator::PatchLocator;
use crate::solver::ambient::patch_rays::PatchRays;
use crate::solver::ambient::rays::{AmbientEstimate, PatchResidual};
use crate::solver::ambient::rooms::{AmbientCache, LocalIndex, Room, RoomView};
use crate::solver::ambient::smoothing;
use crate::solver::ambient::state::AmbientState;
use crate::solver::ambient::sweeps::{self, UnshotLight};
use crate::solver::ambient::vertex_rays::VertexRays;
use crate::solver::layout::{CulledZones, SolveLayout};
use crate::solver::light::patch_field::{FieldScale, PatchField};
use crate::solver::light::state::LightState;
use crate::solver::settings::SolverSettings;

/// The parts of a solver the ambient term reads (and the solution made
/// with it, `solver/reading/request.rs`), borrowed.
#[derive(Clone, Copy)]
pub(crate) struct AmbientTerm<'a> {
    pub(crate) scene: &'a Scene,
    pub(crate) mesh: &'a Mesh,
    pub(crate) visibility: &'a Visibility,
    pub(crate) layout: &'a SolveLayout,
    pub(crate) light: &'a LightState,
    pub(crate) settings: &'a SolverSettings,
    pub(crate) state: &'a AmbientState,
}

/// How a room's rays are found: cast, with the patch locator made on
/// first use, or kept from the last image; each room's progress counted.
struct RoomRays<'t, 'a> {
    term: &'t AmbientTerm<'a>,
    /// Where rays land, found only when some are cast.
    locator: OnceCell<PatchLocator>,
    counter: &'t PhaseCounter<'t>,
}

impl<'a> AmbientTerm<'a> {
    /// The ambient irradiance G_v of every vertex: the light the unshot
    /// radiosity will still give, gathered along rays (see
    /// `solver/ambient/rays.rs`), room by room (`solver/ambient/rooms.rs`),
    /// reporting its progress to `report`; only in zone `only`'s
    /// vertices where given (0 at the others, which it does not hold).
    pub(crate) fn irradiance(
        &self,
        only: Option<&[usize]>,
        report: PhaseReporter,
    ) -> AmbientIrradiance {
        let keep = AmbientCache::keeps(self.mesh.vertices.len());
        self.irradiance_keeping(keep, only, report)
    }

    /// [`AmbientTerm::irradiance`], the rooms' rays kept for the next
    /// image or, unless `keep`, cast room by room and dropped.
    pub(crate) fn irradiance_keeping(
        &self,
        keep: bool,
        only: Option<&[usize]>,
        report: PhaseReporter,
    ) -> AmbientIrradiance {
        // What the shots freed goes back before the term's lists are made.
        give_back_freed_memory();
        let (rooms, others) = self.rooms(only, keep);
        // Half a room's vertices count once their rays are cast (or kept),
        // the other half once their light is gathered.
        let total = rooms.iter().map(|room| room.vertices.len()).sum();
        let counter = PhaseCounter::start(Phase::AmbientTerm, total, report);
        let mut cache = self
            .state
            .rays
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        let room_rays = RoomRays {
            term: self,
            locator: OnceCell::new(),
            counter: &counter,
        };
        // The rooms' patches: the whole mesh's, or those of the rooms
        // asked for (a ray that leaks out of them reads the unshot light
        // where it lands, without its further bounces unless the patch
        // shots hold them).
        let within = only.is_some().then(|| patches_of(&rooms));
        let patches = self.patch_light(&mut cache.patches, within.as_deref(), &room_rays);
        // Kept rays serve again where their room's vertices are the same
        // (an adaptive mesh adds vertices to the rooms it refines).
        let kept = std::mem::take(&mut cache.rooms);
        if keep {
            cache.rooms = room_rays.kept_or_cast(kept, &rooms, &others);
        } else {
            drop(kept);
        }
        let term = self.gathered_in(&rooms, &cache.rooms, &patches, only.is_none(), &room_rays);
        counter.finish();
        term
    }

    /// Each patch's residual and value ([`AmbientTerm::patch_residual`]),
    /// its rays cast first on the patches `within` (all, by `None`) that
    /// lack them, unless patch shots hold the further bounces.
    fn patch_light(
        &self,
        rays: &mut PatchRays,
        within: Option<&[u32]>,
        room_rays: &RoomRays<'_, 'a>,
    ) -> PatchResidual {
        // After patch shots the patches' further bounces are theirs; else
        // the term finds them along its patches' rays.
        let uncast = match &self.state.patch_shots {
            Some(_) => Vec::new(),
            None => rays.uncast(self.mesh, within),
        };
        if !uncast.is_empty() {
            rays.cast(
                self.scene,
                self.mesh,
                &uncast,
                room_rays.locator(),
                &|surface| self.visibility_of(surface),
            );
        }
        self.patch_residual(rays, within)
    }

    /// Each room's term in turn, its rays `kept` (in the rooms' order)
    /// or cast for it: every vertex's by index (`everywhere`), or the
    /// rooms' vertices' alone.
    fn gathered_in(
        &self,
        rooms: &[Room],
        kept: &[VertexRays],
        patches: &PatchResidual,
        everywhere: bool,
        room_rays: &RoomRays<'_, 'a>,
    ) -> AmbientIrradiance {
        let mut local = LocalIndex::new(self.mesh);
        // Every vertex's term by index, or the rooms' vertices' alone.
        let mut everywhere = everywhere.then(|| vec![Rgb::ZERO; self.mesh.vertices.len()]);
        let mut in_rooms = Vec::new();
        for (r, room) in rooms.iter().enumerate() {
            let cast_now;
            let rays = match kept.get(r) {
                Some(kept) => kept,
                None => {
                    cast_now = room_rays.cast(room);
                    &cast_now
                }
            };
            local.enter(room);
            let view = RoomView {
                room,
                local: &local,
            };
            let room_ambient = self.room_ambient(view, rays, patches);
            match &mut everywhere {
                Some(values) => {
                    for (&v, g) in room.vertices.iter().zip(room_ambient) {
                        values[v as usize] = g;
                    }
                }
                None => in_rooms.extend(room.vertices.iter().copied().zip(room_ambient)),
            }
            local.leave(room);
            room_rays.counter.add(halves(room).1);
        }
        match everywhere {
            Some(values) => AmbientIrradiance::Everywhere(values),
            None => AmbientIrradiance::of_rooms(in_rooms),
        }
    }

    /// The BVH a ray from `surface` traverses: that of what lies within
    /// its closed zone's bounds, as its shots' do (a ray that leaves them
    /// through a seam lands on no front of its zone either way), or the
    /// scene's.
    pub(crate) fn visibility_of(&self, surface: SurfaceId) -> &'a Visibility {
        self.layout
            .zones
            .as_ref()
            .map(|CulledZones { zones, .. }| zones)
            .and_then(|zones| zones.visibility(zones.of(surface)))
            .unwrap_or(self.visibility)
    }

    /// The rooms whose ambient term is made (the mesh's closed zones and
    /// the rest, see [`Room::all`]; only the zones `only` lists where
    /// given), and, if `listing_others`, the others.
    fn rooms(&self, only: Option<&[usize]>, listing_others: bool) -> (Vec<Room>, Vec<Room>) {
        let Some(CulledZones { zones, .. }) = &self.layout.zones else {
            return (vec![Room::whole(self.mesh)], Vec::new());
        };
        let count = zones.count();
        let every = |s: SurfaceId| Some(zones.of(s));
        let Some(only) = only else {
            return (Room::all(self.mesh, count, &every), Vec::new());
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
            return (Room::all(self.mesh, count, &picked), Vec::new());
        }
        let zone_of = |room: &Room| {
            let v = room.vertices.first().map(|&v| v as usize);
            v.and_then(|v| self.mesh.vertices.get(v))
                .map(|vertex| zones.of(vertex.surface))
        };
        Room::all(self.mesh, count, &every)
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
    fn patch_residual(&self, rays: &PatchRays, within: Option<&[u32]>) -> PatchResidual {
        let residual = match &self.state.patch_shots {
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
                rays.residual(&self.light.unshot, &reflectance, &lossless, within)
            }
        };
        let value = self
            .light
            .unshot
            .iter()
            .zip(&residual)
            .map(|(u, a)| *u + *a)
            .collect();
        PatchResidual { residual, value }
    }

    /// G_v of `room`'s vertices, in its order, from its vertices' `rays`
    /// and each patch's residual A_h and ΔB_h + A_h (see
    /// `solver/ambient/rays.rs`).
    fn room_ambient(
        &self,
        room: RoomView<'_>,
        rays: &VertexRays,
        patches: &PatchResidual,
    ) -> Vec<Rgb> {
        let mesh = self.mesh;
        let RoomView {
            room: members,
            local,
        } = room;
        let (landed, corners) = self.unshot_in(room, rays);
        let unshot_at = |k: usize| {
            let landed = landed[k];
            let i = local.element(landed.element()?)?;
            landed.value(mesh, |_| corners[i])
        };
        let lossless = |surface: SurfaceId| self.layout.surface_lossless[surface.index()];
        let gathered = rays.irradiance(mesh, patches, &unshot_at, &lossless);
        let distances = rays.harmonic_distances(mesh);
        let around = self
            .settings
            .smooth_ambient
            .then(|| smoothing::Neighbourhood::new(mesh, members, local));
        let smooth = |gathered: &[AmbientEstimate]| -> Vec<Rgb> {
            match &around {
                Some(around) => smoothing::smoothed(mesh, members, around, gathered, &distances),
                None => gathered.iter().map(|g| g.irradiance).collect(),
            }
        };
        let first = smooth(&gathered);
        let vertex_reflectance: Vec<Rgb> = members
            .vertices
            .iter()
            .map(|&v| self.layout.surface_reflectance[mesh.vertices[v as usize].surface.index()])
            .collect();
        let unshot = UnshotLight {
            landed: &landed,
            corners: &corners,
            per_patch: &self.light.unshot,
            outside: &patches.value,
        };
        sweeps::swept(
            rays,
            mesh,
            room,
            first,
            self.settings.ambient_sweeps,
            &unshot,
            &vertex_reflectance,
            &lossless,
            &smooth,
        )
    }

    /// What `room`'s rays read of the unshot light: the element under each
    /// ray's landing point, and the room's elements' corners' unshot
    /// radiosity (in its order) at the scale that carries its patch's
    /// power.
    fn unshot_in(
        &self,
        room: RoomView<'_>,
        rays: &VertexRays,
    ) -> (Vec<LandingElement>, Vec<[Rgb; 4]>) {
        let mesh = self.mesh;
        let RoomView {
            room: members,
            local,
        } = room;
        // Each of the room's patches' unshot field over its elements, at
        // the scale that carries its power, for the rays to read where
        // they land.
        let fields: Vec<(PatchField, FieldScale)> = members
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
        let landed = rays.landing_elements(&|p, st, hint| {
            let (field, _) = &fields[local.patch(p)?];
            let patch = &mesh.patches[p];
            field
                .locate(patch.cell.point(st.x, st.y), hint)
                .map(|(k, st)| LandingElement::new(patch.elements[k], st.into()))
        });
        let corners: Vec<[Rgb; 4]> = members
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
        (landed, corners)
    }
}

impl<'a> RoomRays<'_, 'a> {
    /// The patch locator, made on first use.
    fn locator(&self) -> &PatchLocator {
        self.locator
            .get_or_init(|| PatchLocator::new(self.term.scene, self.term.mesh))
    }

    /// `room`'s vertex rays, cast now.
    fn cast(&self, room: &Room) -> VertexRays {
        let term = self.term;
        let rays = VertexRays::cast(
            term.scene,
            term.mesh,
            room.vertices.clone(),
            self.locator(),
            &|surface| term.visibility_of(surface),
        );
        self.counter.add(halves(room).0);
        rays
    }

    /// The rays to keep for the next image: each of `rooms`' taken from
    /// `kept` where its vertices are the same, or cast; then those of
    /// `kept` that belong to the `others`, in any order (looked up by
    /// vertices).
    fn kept_or_cast(
        &self,
        mut kept: Vec<VertexRays>,
        rooms: &[Room],
        others: &[Room],
    ) -> Vec<VertexRays> {
        let mut reuse = |room: &Room| {
            let same = kept
                .iter()
                .position(|rays| rays.vertices() == room.vertices);
            same.map(|k| {
                self.counter.add(halves(room).0);
                kept.swap_remove(k)
            })
        };
        let mut rays: Vec<VertexRays> = rooms
            .iter()
            .map(|room| reuse(room).unwrap_or_else(|| self.cast(room)))
            .collect();
        // After the rooms' own, in any order: looked up by vertices.
        kept.retain(|rays| others.iter().any(|room| rays.vertices() == room.vertices));
        rays.append(&mut kept);
        rays
    }
}

/// A room's vertices in two halves: the first counted once their rays
/// are cast (or kept), the second once their light is gathered.
fn halves(room: &Room) -> (usize, usize) {
    let n = room.vertices.len();
    (n / 2, n - n / 2)
}

/// The patches of `rooms`, ascending.
fn patches_of(rooms: &[Room]) -> Vec<u32> {
    let mut patches: Vec<u32> = rooms
        .iter()
        .flat_map(|r| r.patches.iter().copied())
        .collect();
    patches.sort_unstable();
    patches
}
