//! Settings of the progressive shooting solver, and of a whole solve.

use serde::{Deserialize, Serialize};

use crate::meshing::MeshSettings;

/// How a vertex-to-patch form factor is estimated. Each kernel splits the
/// patch into m × m strata with one shadow ray each; they differ in what a
/// stratum contributes. In a scene file: `kernel = "mixed"`, `"wallace"` or
/// `"exact"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FormFactorKernel {
    /// Wallace's disc term A cosθ_r cosθ_s / (π r² + A) on far strata and
    /// Lambert's exact polygon factor on strata nearer than ten of their
    /// sizes, each times its own visibility. Accurate everywhere.
    #[default]
    Mixed,
    /// Wallace's disc term on every stratum (Wallace, Elmquist, Haines 1989;
    /// eq. 3.1 of Arquès et al. 2005). Fast; biased low near corners.
    Wallace,
    /// Lambert's exact factor of the whole patch times the fraction of
    /// strata whose shadow ray is unblocked. Exact when unoccluded.
    Exact,
}

/// Where on a shooting patch its unshot light leaves from. In a scene
/// file: `shoot_from = "elements"` or `"patch_mean"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShootFrom {
    /// Each stratum shoots the unshot radiosity of the elements under it,
    /// interpolated from their corners and scaled so the patch shoots its
    /// unshot power exactly: a floor patch half in a table's shadow shoots
    /// from its lit half, not into the table's underside from its dark one.
    #[default]
    Elements,
    /// Every stratum shoots the patch's mean unshot radiosity (Cohen et al.
    /// 1988 as first published). Kept for comparison.
    PatchMean,
}

/// Settings of [`crate::Solver`]. Plain data: set the fields you need and
/// keep the defaults for the rest. A scene file's `[solver]` table is read
/// into this struct, field by field.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct SolverSettings {
    /// Stop when the unshot power falls below this fraction of the emitted
    /// power (5 %), and every emitter has shot its own light: what is left
    /// is reflected light, which the patch shots then carry
    /// ([`SolverSettings::patch_tolerance`]) and the ambient term gathers
    /// for images and probes. A closed zone's unshot power counts at
    /// [`SolverSettings::closed_zone_weight`]. 1 % takes about twice the
    /// time for a tenth of a point of per-pixel error against a path tracer
    /// (BENCHMARKS.md, (e)).
    pub tolerance: f64,
    /// Once the vertices' shots have converged to
    /// [`SolverSettings::tolerance`], the unshot power left is shot patch
    /// to patch until at most this fraction of the emitted power is left,
    /// every zone counted in full (0.0001; `solver/ambient/patch_shots.rs`): the
    /// dim reflected light carried at the coarsest level, patches, along
    /// a few rays a patch (2 to 32 a patch or cluster of small patches, by
    /// the power each will shoot: [`SolverSettings::patch_clusters`]),
    /// each sweep over a room's patches one addition a ray. The rays are
    /// most of the cost, so a ten-thousandth costs about
    /// what a hundredth does (16 closed offices: 0.10 s either way, eight
    /// sweeps a room). The ambient term then reads what each patch
    /// received as what it will still reflect. In (0, 1]; 1 shoots none
    /// (the ambient term then finds the further bounces itself, for the
    /// rooms it gathers).
    pub patch_tolerance: f64,
    /// The patch shots take a zone's small patches that stand side by side
    /// facing the same way as one cluster, which shoots their pooled power
    /// and receives for all of them (true; `solver/ambient/patch_clusters.rs`):
    /// patches of at most a sixteenth of a full patch's area, normals
    /// within about a degree, centres in one cube of the patch edge and
    /// one slab a quarter of it deep. The cluttered office's 1,309 small
    /// patches (books, the trays', chairs' and monitors' parts) shoot as
    /// 208 clusters, and its patch shots cast 4,971 rays instead of 8,987,
    /// for the same image to 0.05 % per pixel (BENCHMARKS.md, (e)).
    pub patch_clusters: bool,
    /// Stop after this many shots whatever the unshot power.
    pub max_shots: usize,
    /// Samples per shooting patch for the most powerful shooters (the
    /// emitters' first shots): they draw the shadows, whose penumbrae need
    /// many visibility samples. A shooter carrying a fraction f of that power
    /// gets about `direct_samples · f^0.75` samples, and never fewer than
    /// one (see `solver/shot/samples.rs`, `SHARE_EXPONENT`).
    pub direct_samples: usize,
    /// Upper bound on samples per shooting patch and receiver vertex.
    pub max_samples: usize,
    /// Samples grow as the shooter looks larger from the receiver: a patch of
    /// area A at distance r gets at least (sample_density · √A / r)² samples
    /// (Wallace et al. 1989, adaptive source sampling).
    pub sample_density: f64,
    /// How each vertex-to-patch form factor is estimated.
    pub kernel: FormFactorKernel,
    /// Where on a patch its unshot light leaves from (emitters always shoot
    /// uniformly).
    pub shoot_from: ShootFrom,
    /// Skip the receivers a shot cannot reach because they lie in another
    /// closed zone (a room whose doors are shut; see `meshing/zones/`):
    /// the same radiosity, without the shadow rays that would all be
    /// blocked (true).
    pub cull_closed_zones: bool,
    /// Skip the shadow rays of a shot to the receiving patches that see
    /// all of the shooter: those whose shaft to it (the convex region
    /// between the shooter's cell and the patch's receiving points) no
    /// other surface reaches into (Haines & Wallace 1991; see
    /// `solver/shot/shaft_culling.rs`). The same radiosity, with fewer rays,
    /// but that a clear vertex of an emitter's shot takes Lambert's exact
    /// factor, which its samples only estimate (true).
    pub cull_shafts: bool,
    /// A reflected shot from a patch that has shot before casts no rays
    /// from the vertices whose rays to it last time, four or more, were
    /// all unblocked or all blocked: they take all of it or none (see
    /// `solver/shot/visibility_memory.rs`; true).
    pub remember_visibility: bool,
    /// Scale the power each element of a closed zone takes from a
    /// reflected shot so that together they receive exactly the shot's
    /// power (true; vertices keep the irradiance they gathered). From any
    /// point of a closed zone the form factors to the zone sum to 1, so a
    /// shot's power lands whole; the elements' corner means of the sampled
    /// irradiance miss about 1 % of it (light falling off concavely into a
    /// junction), which compounded over the bounces and left furnished
    /// rooms 0.7–2 % dark against a path tracer. The ambient term's rays
    /// there that end on no front (a crack at a contact) are left out of
    /// their source's mean instead of counted as dark, where at least half
    /// of its rays land (`solver/ambient/rays.rs`).
    /// Zones that lose light for real (open to the sky, or showing the
    /// black back of a one-sided surface) are left alone.
    pub conserve_closed_zones: bool,
    /// A vertex takes a reflected shot interpolated from a few vertices of
    /// its patch (those nearest the patch's corners and centre) instead of
    /// gathering it where the most irradiance the shot can bring the patch,
    /// P / (π d²) for a shot of power P from d away (less where either
    /// patch sees the other at a slant), is at most this
    /// fraction of the irradiance the vertex has received so far (0.01),
    /// and those samples have received between half and twice its light:
    /// dim shots then cost rays per patch rather than per vertex
    /// (`solver/shot/patch_reception.rs`). 0 gathers every shot at every vertex.
    /// Emitters' shots are always gathered at every vertex.
    pub coarse_reception: f64,
    /// In a scene of several closed zones (rooms whose doors are shut),
    /// the last shot's zone goes on shooting while its strongest patch
    /// holds at least this share of the strongest unshot power of all
    /// (0.5), so that its data stays in the processor's caches: the zones
    /// exchange no light, and the order of their shots changes only which
    /// have shot more when the solve stops. 1 shoots the strongest of all
    /// at every shot: then the cull of closed zones gives the same
    /// radiosity as no cull, bit for bit. In (0, 1]; see
    /// `solver/light/unshot_by_zone.rs`.
    pub zone_affinity: f64,
    /// How much the unshot power of a closed zone that keeps all its light
    /// counts toward [`SolverSettings::tolerance`] (0.1: a closed room
    /// stops at half its emitted power unshot at the default, which in
    /// the offices is after their lamps' shots). There the ambient term
    /// places the residual where its rays land, swept at the vertices
    /// ([`SolverSettings::ambient_sweeps`]), and the zone receives it whole
    /// ([`SolverSettings::conserve_closed_zones`]); in the open, light
    /// leaves, the ambient term's guess of where the rest goes is poorer,
    /// and the unshot power counts in full. With the sweeps, closed rooms
    /// render at 0.1 about as well as at higher weights in a fraction of
    /// the time (BENCHMARKS.md, (e)). In (0, 1]; 1 holds every zone to the
    /// tolerance. Without `conserve_closed_zones` every zone counts in full.
    pub closed_zone_weight: f64,
    /// Average each vertex's ambient irradiance with its mesh neighbours',
    /// weighted by their distance over the harmonic mean distance of their
    /// rays (Ward, Rubinstein & Clear 1988) and by how far the estimates
    /// differ over their noise, vertices on a surface's outline left alone
    /// (true; see `solver/ambient/smoothing.rs`): the term's noise, seen
    /// pixel by pixel, falls by about three. The cluttered office stopped
    /// at 10 % (the term a tenth of its light) rendered at 2.81 % per pixel
    /// with it, 2.88 % without (BENCHMARKS.md, (e)); closed rooms now leave
    /// it half of their light.
    pub smooth_ambient: bool,
    /// At most this many Jacobi sweeps over the vertices take the ambient
    /// term's further bounces from where its rays land rather than from
    /// each patch's mean (16; they stop when the term changes by less than
    /// 0.5 % on average, after three to five in the offices; 0 keeps the
    /// patch-level estimate; at most 64; see `solver/ambient/sweeps.rs`).
    /// A patch half hidden behind furniture no longer sends what it will
    /// still reflect evenly from both halves: with 64 rays a vertex, the
    /// cluttered office solved from its lamps' shots alone rendered at
    /// 2.81 % per pixel with them, 3.50 % without (BENCHMARKS.md, (e)).
    pub ambient_sweeps: usize,
}

/// The most ambient sweeps a solve may ask for: each costs about as much
/// as the first gather, and a room whose reflectances near 1 would need
/// hundreds to converge.
const MAX_AMBIENT_SWEEPS: usize = 64;

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            tolerance: 0.05,
            patch_tolerance: 0.0001,
            patch_clusters: true,
            max_shots: 1_000_000,
            direct_samples: 64,
            max_samples: 256,
            sample_density: 3.0,
            kernel: FormFactorKernel::default(),
            shoot_from: ShootFrom::default(),
            cull_closed_zones: true,
            cull_shafts: true,
            remember_visibility: true,
            conserve_closed_zones: true,
            coarse_reception: 0.01,
            zone_affinity: 0.5,
            closed_zone_weight: 0.1,
            smooth_ambient: true,
            ambient_sweeps: 16,
        }
    }
}

impl SolverSettings {
    /// Quick, noisier images: 10 % tolerance (closed rooms stop once their
    /// emitters have shot), fewer shadow samples.
    #[must_use]
    pub fn preview() -> Self {
        SolverSettings {
            tolerance: 0.1,
            direct_samples: 16,
            max_samples: 64,
            ..Self::default()
        }
    }

    /// Converged, smooth images: 0.1 % tolerance, held in full by closed
    /// rooms too (`closed_zone_weight` 1), more shadow samples.
    #[must_use]
    pub fn final_quality() -> Self {
        SolverSettings {
            tolerance: 0.001,
            direct_samples: 256,
            max_samples: 1024,
            closed_zone_weight: 1.0,
            ..Self::default()
        }
    }

    /// Checks every field is in range; returns the first problem, an
    /// [`crate::Error::InvalidSetting`] named by its field (`tolerance`;
    /// [`Settings::validate`] puts it under `solver.`).
    pub fn validate(&self) -> crate::Result<()> {
        let invalid = |name: &str, message: String| crate::Error::InvalidSetting {
            name: name.into(),
            message,
        };
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(invalid(
                "tolerance",
                format!("{} is not in (0, 1)", self.tolerance),
            ));
        }
        if !(self.patch_tolerance > 0.0 && self.patch_tolerance <= 1.0) {
            return Err(invalid(
                "patch_tolerance",
                format!("{} is not in (0, 1]", self.patch_tolerance),
            ));
        }
        if self.direct_samples == 0 {
            return Err(invalid("direct_samples", "0 is not at least 1".into()));
        }
        if !(1..=65_536).contains(&self.max_samples) {
            let message = format!("{} is not in 1..=65536", self.max_samples);
            return Err(invalid("max_samples", message));
        }
        if !(self.sample_density > 0.0 && self.sample_density.is_finite()) {
            return Err(invalid(
                "sample_density",
                format!("{} is not positive", self.sample_density),
            ));
        }
        if !(0.0..1.0).contains(&self.coarse_reception) {
            return Err(invalid(
                "coarse_reception",
                format!("{} is not in [0, 1)", self.coarse_reception),
            ));
        }
        if !(self.zone_affinity > 0.0 && self.zone_affinity <= 1.0) {
            return Err(invalid(
                "zone_affinity",
                format!("{} is not in (0, 1]", self.zone_affinity),
            ));
        }
        if !(self.closed_zone_weight > 0.0 && self.closed_zone_weight <= 1.0) {
            return Err(invalid(
                "closed_zone_weight",
                format!("{} is not in (0, 1]", self.closed_zone_weight),
            ));
        }
        if self.ambient_sweeps > MAX_AMBIENT_SWEEPS {
            return Err(invalid(
                "ambient_sweeps",
                format!("{} is more than {MAX_AMBIENT_SWEEPS}", self.ambient_sweeps),
            ));
        }
        Ok(())
    }
}

/// Everything [`crate::Solver::new`] needs: how to mesh the scene and how
/// to shoot. Plain data with named presets.
///
/// ```
/// let mut settings = isorad::Settings::preview();
/// settings.solver.tolerance = 0.02;
/// assert!(settings.validate().is_ok());
/// ```
///
/// A scene file's `[mesh]` and `[solver]` tables are read into it by
/// [`Settings::from_scene_options`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct Settings {
    /// How the scene is meshed.
    pub mesh: MeshSettings,
    /// How light is shot.
    pub solver: SolverSettings,
}

impl Settings {
    /// Quick, noisier images: coarser elements, 10 % tolerance, fewer
    /// shadow samples.
    #[must_use]
    pub fn preview() -> Self {
        Settings {
            mesh: MeshSettings::preview(),
            solver: SolverSettings::preview(),
        }
    }

    /// Converged, smooth images: finer elements, 0.1 % tolerance (closed
    /// rooms' too), more shadow samples.
    #[must_use]
    pub fn final_quality() -> Self {
        Settings {
            mesh: MeshSettings::final_quality(),
            solver: SolverSettings::final_quality(),
        }
    }

    /// Checks every field is in range; returns the first problem, an
    /// [`crate::Error::InvalidSetting`] named by its field path
    /// (`mesh.max_edge`, `solver.tolerance`, `mesh.refinement.threshold`).
    pub fn validate(&self) -> crate::Result<()> {
        self.mesh.validate().map_err(|e| e.within("mesh"))?;
        self.solver.validate().map_err(|e| e.within("solver"))
    }
}
