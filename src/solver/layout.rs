//! What a solve knows of where things are, fixed for its whole run: the
//! closed zones and each surface's, which zones keep all their light, each
//! surface's reflectance and boundary inset, each patch's area, and the
//! zone each photometric luminaire lights, and the daylight's portals.

use crate::lighting::DaylightSource;
use crate::mesh::{Mesh, receiver_inset};
use crate::meshing::MeshAnalysis;
use crate::meshing::{ZoneLabels, ZoneMembers, Zones};
use crate::rgb::Rgb;
use crate::scene::{Scene, Visibility};
use crate::solver::settings::SolverSettings;

/// The closed zones a shot need not reach beyond, with the mesh's members
/// listed zone by zone.
pub(crate) struct CulledZones {
    /// The zones, their labels and each one's BVH.
    pub(crate) zones: Zones,
    /// The mesh's patches, elements and vertices zone by zone.
    pub(crate) members: ZoneMembers,
}

/// Where things are, for the solver's parts to look up by index.
pub(crate) struct SolveLayout {
    /// The closed zones (None: not culled).
    pub(crate) zones: Option<CulledZones>,
    /// Per surface, whether its zone keeps all its light: its patches'
    /// reflected shots are scaled to land whole, and its ambient rays that
    /// end on no front are left out of their source's mean
    /// ([`SolverSettings::conserve_closed_zones`]).
    pub(crate) surface_lossless: Vec<bool>,
    /// Per surface, the closed zone it lies in (all 0 when the zones were
    /// not found): a patch cluster keeps to one.
    pub(crate) surface_zone: Vec<u32>,
    /// Each surface's reflectance, side by side: every shot reads it at
    /// every element it reaches.
    pub(crate) surface_reflectance: Vec<Rgb>,
    /// How far each surface's boundary vertices gather inside it, by
    /// surface index: a ten-thousandth of its room's diagonal when the
    /// solver meshed the scene, the scene's (`mesh::receiver_inset`) when
    /// the caller brought the mesh.
    pub(crate) receiver_insets: Vec<f64>,
    /// Each patch's area, side by side: ΔB_p A_p is the unshot power.
    pub(crate) patch_areas: Vec<f64>,
    /// The longest patch edge: the mesh settings' `patch_max_edge` when
    /// the solver meshed the scene, the mesh's longest patch edge when the
    /// caller brought it. It bounds a patch cluster's extent.
    pub(crate) patch_edge: f64,
    /// The closed zone each photometric luminaire stands in, whose
    /// vertices alone its light can reach (None: it is not culled).
    pub(crate) luminaire_zones: Vec<Option<usize>>,
    /// Whether each surface is a face of an emitting body, by surface
    /// index: its emission is the body's luminaire's light, not its own
    /// patches' ([`Scene::join_emitting_bodies`]).
    pub(crate) in_emitting_body: Vec<bool>,
    /// What meshing found (empty when the caller brought the mesh).
    pub(crate) analysis: MeshAnalysis,
    /// The scene's daylight with its portals, if it has a sky.
    pub(crate) daylight: Option<DaylightSource>,
}

impl SolveLayout {
    /// The layout of `scene` meshed as `mesh`. The closed zones are found
    /// here unless given (and kept only if culled and more than one).
    pub(crate) fn new(
        scene: &Scene,
        mesh: &Mesh,
        visibility: &Visibility,
        zones: Option<Zones>,
        settings: &SolverSettings,
    ) -> SolveLayout {
        let surface_reflectance = scene
            .surfaces
            .iter()
            .map(|surface| scene.material_of(surface).reflectance)
            .collect();
        let zones = match zones {
            None if settings.cull_closed_zones => Some(Zones::new(scene, visibility)),
            zones => zones,
        };
        // Without the cull, the zones' labels alone (no BVH per zone).
        let built;
        let labels = match &zones {
            Some(zones) => Some(zones.labels()),
            None if settings.conserve_closed_zones => {
                built = ZoneLabels::new(scene, visibility);
                Some(&built)
            }
            None => None,
        };
        let surface_lossless = match labels {
            Some(labels) if settings.conserve_closed_zones => scene
                .surfaces_with_ids()
                .map(|(id, _)| labels.is_lossless(labels.of(id)))
                .collect(),
            _ => vec![false; scene.surfaces.len()],
        };
        let surface_zone = match labels {
            Some(labels) => scene
                .surfaces_with_ids()
                .map(|(id, _)| labels.of(id) as u32)
                .collect(),
            None => vec![0; scene.surfaces.len()],
        };
        let zones = zones
            .filter(|zones| settings.cull_closed_zones && zones.count() > 1)
            .map(|zones| CulledZones {
                zones,
                members: ZoneMembers::default(),
            });
        // A luminaire inside a closed room lights that room alone. Its
        // photometric centre may lie on the ceiling (a recessed fitting):
        // the zone is found a little way along its aim. An emitting body
        // lights the zone its faces face.
        let luminaire_zones = scene
            .luminaires
            .iter()
            .map(|luminaire| {
                let zones = &zones.as_ref()?.zones;
                if let Some(body) = &luminaire.body {
                    return Some(zones.of(body.surfaces[0]));
                }
                let inside =
                    luminaire.position + luminaire.aim * (16.0 * visibility.surface_offset());
                zones.labels().enclosing(scene, visibility, inside)
            })
            .collect();
        SolveLayout {
            zones,
            surface_lossless,
            surface_zone,
            surface_reflectance,
            // The scene's inset, until `Solver::new` gives each room's.
            receiver_insets: vec![receiver_inset(scene); scene.surfaces.len()],
            patch_areas: mesh.patches.iter().map(|p| p.area).collect(),
            patch_edge: mesh.longest_patch_edge(),
            luminaire_zones,
            in_emitting_body: scene.in_emitting_body(),
            analysis: MeshAnalysis::default(),
            daylight: DaylightSource::of_scene(scene),
        }
    }

    /// The closed zones' labels when more than one zone is culled.
    pub(crate) fn zones(&self) -> Option<&Zones> {
        self.zones.as_ref().map(|culled| &culled.zones)
    }
}
