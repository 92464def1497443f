//! The light of a solve: what each vertex has received, what each patch and
//! its elements' corners have not yet shot, the unshot power zone by zone,
//! what each patch has shot in all, and the ledger's powers.

use crate::mesh::Mesh;
use crate::rgb::Rgb;
use crate::scene::Scene;
use crate::solver::layout::SolveLayout;
use crate::solver::light::unshot::UnshotCorners;
use crate::solver::light::unshot_by_zone::UnshotByZone;
use crate::solver::light::vertex_irradiance::VertexIrradiance;
use crate::solver::settings::SolverSettings;

/// The light shot and not yet shot.
pub(crate) struct LightState {
    /// Irradiance H per vertex (light received), W/m². Its radiosity,
    /// B = E + ρ H, is found from it when asked.
    pub(crate) irradiance: VertexIrradiance,
    /// Unshot radiosity ΔB per patch: the area-weighted mean of its
    /// elements' corner means, the ledger's and the shooter choice's measure.
    pub(crate) unshot: Vec<Rgb>,
    /// Unshot radiosity at every element's corners: where on each patch the
    /// unshot light lies.
    pub(crate) unshot_corners: UnshotCorners,
    /// The unshot power ΔB_p A_p zone by zone: the strongest patch of
    /// each and their totals, counted again where a shot changed them.
    pub(crate) unshot_by_zone: UnshotByZone,
    /// Radiosity shot by each patch in all, Σ ΔB: what new vertices of an
    /// adaptive mesh gather.
    pub(crate) shot: Vec<Rgb>,
    /// The emitting patches whose emission has not been shot yet: they
    /// shoot before any patch that only reflects, and a solve has not
    /// converged while one is left.
    pub(crate) emission_pending: Vec<u32>,
    /// Whether each of the scene's photometric luminaires has shot.
    pub(crate) luminaire_shot: Vec<bool>,
    /// Whether the daylight has shot (true when the scene has none). Its
    /// power is what its shot landed: counted as emitted and shot then.
    pub(crate) daylight_shot: bool,
    /// The largest power a single patch or photometric luminaire emits (sum
    /// of channels): the scale for the number of samples a shot gets.
    pub(crate) reference_power: f64,
    /// Power emitted by the patches and the photometric luminaires.
    pub(crate) emitted_power: Rgb,
    /// Power shot so far.
    pub(crate) shot_power: Rgb,
    /// Power the elements received so far.
    pub(crate) received_power: Rgb,
    /// Σ (1 − ρ) P over the power P elements received: the ledger's absorbed
    /// power, counted as the received power is (see `element_power.rs`).
    pub(crate) absorbed_power: Rgb,
}

impl LightState {
    /// The emitters' radiosity set, nothing shot.
    pub(crate) fn new(
        scene: &Scene,
        mesh: &Mesh,
        layout: &SolveLayout,
        settings: &SolverSettings,
    ) -> LightState {
        // An emitting body's faces are shot by its luminaire.
        let emitted = |p: &crate::mesh::Patch| match layout.in_emitting_body[p.surface.index()] {
            true => Rgb::ZERO,
            false => scene
                .material_of(scene.surface(p.surface))
                .emitted_radiosity(),
        };
        let unshot: Vec<Rgb> = mesh.patches.iter().map(emitted).collect();
        let powers = mesh.patches.iter().zip(&unshot).map(|(p, b)| *b * p.area);
        let emitted_power =
            powers.clone().sum::<Rgb>() + scene.luminaires.iter().map(|l| l.power()).sum::<Rgb>();
        let emission_pending = (0..unshot.len() as u32)
            .filter(|&p| unshot[p as usize].element_sum() * mesh.patches[p as usize].area > 0.0)
            .collect();
        // Photometric luminaires count as emitters: a room lit only by them
        // scales its shots' samples by their power.
        let reference_power = powers
            .map(|p| p.element_sum())
            .chain(scene.luminaires.iter().map(|l| l.power().element_sum()))
            .fold(0.0, f64::max);
        // A closed zone's residual counts toward the tolerance at its weight.
        let weights = mesh
            .patches
            .iter()
            .map(|p| match layout.surface_lossless[p.surface.index()] {
                true => settings.closed_zone_weight,
                false => 1.0,
            })
            .collect();
        let areas = &layout.patch_areas[..];
        let unshot_by_zone = match layout.zones() {
            Some(zones) => {
                let zone_of = mesh.patches.iter().map(|p| zones.of(p.surface));
                UnshotByZone::new(zone_of, zones.count(), &unshot, areas, weights)
            }
            None => UnshotByZone::new(mesh.patches.iter().map(|_| 0), 1, &unshot, areas, weights),
        };
        LightState {
            irradiance: VertexIrradiance::zeros(mesh.vertices.len()),
            unshot_corners: UnshotCorners::new(mesh, &unshot),
            shot: vec![Rgb::ZERO; unshot.len()],
            unshot,
            unshot_by_zone,
            emission_pending,
            luminaire_shot: vec![false; scene.luminaires.len()],
            daylight_shot: layout.daylight.is_none(),
            reference_power,
            emitted_power,
            shot_power: Rgb::ZERO,
            received_power: Rgb::ZERO,
            absorbed_power: Rgb::ZERO,
        }
    }
}
