//! Vertex-to-patch form factors by stratified, ray-traced source sampling.

mod mixed_kernel;
mod strata;
#[cfg(test)]
mod tests;

use std::sync::OnceLock;

use glam::{DVec2, DVec3};

use crate::lighting::SampleStream;
use crate::mesh::Cell;
use crate::radiometry::{disc_form_factor, polygon_form_factor};
use crate::rgb::Rgb;
use crate::scene::{ShadowCache, SurfaceId, Visibility};
use crate::solver::light::patch_field::{FieldScale, PatchField};
use crate::solver::settings::FormFactorKernel;
use strata::Strata;

/// Strata closer than ten stratum sizes (r² < NEAR_FIELD · A) use Lambert's
/// exact polygon factor instead of Wallace's disc term. The disc term's
/// relative bias is about A/(π r²) for a stratum seen off-axis, so beyond the
/// bound it stays under 1/(100π) ≈ 0.3 %; nearer, as in the corner where two
/// walls meet, the disc model fails and the exact factor is needed.
///
/// The same bound applies to the distances from each end to the other's
/// plane: a stratum less than ten of its sizes above the receiver's plane
/// (a lamp hung 2 cm from a wall) or a receiver as close to the source's
/// plane sees a cosine that varies across the stratum by more than a tenth,
/// and the disc term at one jittered point would leave blotches
/// (`tests/it/source_refinement.rs`).
const NEAR_FIELD: f64 = 100.0;

/// A shooting patch, prepared once per shot.
pub struct Shooter {
    /// The patch's shape.
    pub cell: Cell,
    /// Unit normal of its front.
    pub normal: DVec3,
    /// Its surface.
    pub surface: SurfaceId,
    /// Stratified subdivisions: `strata[m]` holds the m² cells for m samples
    /// per side and the radiosity each shoots, made when a receiver first
    /// needs them.
    strata: Vec<OnceLock<Strata>>,
    /// Fewest samples per side, from the shot's power.
    min_side: usize,
    /// What the patch shoots.
    radiosity: ShotRadiosity,
    /// How a field shot's ΔB read at a point becomes W
    /// ([`PatchField::exact_scale`]); `None` for a uniform shot.
    exact_scale: Option<FieldScale>,
}

/// The radiosity a shooter sends from each point of itself.
#[derive(Clone, Debug)]
pub enum ShotRadiosity {
    /// The same radiosity from every stratum: an emitter's emission, or the
    /// light a patch has shot in all (what new vertices of an adaptive mesh
    /// gather).
    Uniform(Rgb),
    /// The unshot radiosity of the elements under each stratum, scaled so
    /// the strata carry the patch's unshot power (see
    /// `PatchField::sampled`).
    Field(PatchField),
}

/// A receiving point: where it gathers, its normal, and a key for its jitter.
#[derive(Clone, Copy, Debug)]
pub struct Receiver<'a> {
    /// Position (already moved off the surface's boundary, if on it).
    pub position: DVec3,
    /// Unit normal of the front.
    pub normal: DVec3,
    /// Its surface.
    pub surface: SurfaceId,
    /// Identifies the receiver in the random streams.
    pub key: u64,
    /// Known to see all of the shooter: no triangle reaches into the shaft
    /// between them (`solver/shot/shaft_culling.rs`), or every ray of the
    /// shooter's last shot reached it (`solver/shot/visibility_memory.rs`), so
    /// its samples need no rays.
    pub clear: bool,
    /// The only triangles of the shot's `Visibility` that can block its
    /// rays to the shooter, when its shaft holds few
    /// (`solver/shot/shaft_culling.rs`): its rays test those alone.
    pub occluders: Option<&'a [u32]>,
}

/// The irradiance from a shooter and the number of shadow rays it took.
#[derive(Clone, Copy, Debug, Default)]
pub struct Gathered {
    /// Irradiance at the receiver from the shot, Σ_k W_k F_k: each stratum's
    /// radiosity times its point-to-stratum form factor, visibility included
    /// (W/m²).
    pub irradiance: Rgb,
    /// Shadow rays cast.
    pub rays: u32,
    /// Visibility samples taken without a ray, the receiver being clear.
    pub known_visible: u32,
    /// Shadow rays that were blocked.
    pub blocked: u32,
}

impl Shooter {
    /// Prepares a patch to shoot `radiosity` with between `min_side²` and
    /// `max_side²` samples.
    #[must_use]
    pub fn new(
        cell: Cell,
        normal: DVec3,
        surface: SurfaceId,
        min_side: usize,
        max_side: usize,
        radiosity: ShotRadiosity,
    ) -> Shooter {
        let max_side = max_side.max(1);
        let min_side = min_side.clamp(1, max_side);
        let strata = (0..=max_side).map(|_| OnceLock::new()).collect();
        let exact_scale = match &radiosity {
            ShotRadiosity::Field(field) => Some(field.exact_scale()),
            ShotRadiosity::Uniform(_) => None,
        };
        Shooter {
            cell,
            normal,
            surface,
            strata,
            min_side,
            radiosity,
            exact_scale,
        }
    }

    /// Samples per side a receiver at `distance` from the patch's centre
    /// takes: `density · √A / distance`, within the shot's bounds.
    #[must_use]
    pub fn side_at(&self, distance: f64, density: f64) -> usize {
        let distance = distance.max(f64::MIN_POSITIVE);
        let wanted = (density * self.cell.area.sqrt() / distance).ceil();
        if wanted.is_finite() {
            (wanted as usize).clamp(self.min_side, self.strata.len() - 1)
        } else {
            self.strata.len() - 1
        }
    }

    /// Irradiance from this patch at a receiver (Wallace, Elmquist, Haines
    /// 1989): the patch is split into m × m strata, m growing with the
    /// patch's apparent size (`density · √A / r`); each stratum k contributes
    /// its radiosity W_k times its disc-kernel factor (or, when near, its
    /// exact polygon factor) if a shadow ray to a jittered point in it is
    /// unblocked:
    ///
    /// ```text
    ///   H ≈ Σ_k W_k δ_k · A_k cosθ_r cosθ_s / (π r_k² + A_k)
    /// ```
    ///
    /// W_k is the patch's unshot radiosity where stratum k lies (see
    /// [`ShotRadiosity`]), so a patch half in shadow shoots from its lit half.
    ///
    /// # References
    /// J. R. Wallace, K. A. Elmquist, E. A. Haines, "A Ray Tracing Algorithm
    /// for Progressive Radiosity", SIGGRAPH 1989; M. F. Cohen, S. E. Chen,
    /// J. R. Wallace, D. P. Greenberg, "A Progressive Refinement Approach to
    /// Fast Radiosity Image Generation", SIGGRAPH 1988.
    ///
    /// The shadow rays go through `cache` ([`Visibility::is_unblocked_cached`]).
    #[must_use]
    pub fn gather(
        &self,
        receiver: &Receiver,
        density: f64,
        shot: u64,
        kernel: FormFactorKernel,
        visibility: &Visibility,
        cache: &mut ShadowCache,
    ) -> Gathered {
        let x = receiver.position;
        let n = receiver.normal;
        // One-sided source and receiver: nothing unless each faces the other.
        let centre = self.cell.centre();
        if self.normal.dot(x - centre) <= 0.0
            || self.cell.polygon().iter().all(|&p| n.dot(p - x) <= 0.0)
        {
            return Gathered::default();
        }
        let side = self.side_at((centre - x).length(), density);
        // A receiver that sees all of a uniform shooter (an emitter, or a
        // reflected shot from the patch mean) needs no samples: its
        // irradiance is W times Lambert's exact factor, which the strata's
        // sum only estimates where they are far (their disc terms; near
        // ones already sum to it).
        if receiver.clear
            && kernel != FormFactorKernel::Wallace
            && let ShotRadiosity::Uniform(radiosity) = self.radiosity
        {
            let factor = polygon_form_factor(x, n, self.cell.polygon()).max(0.0);
            return Gathered {
                irradiance: radiosity * factor,
                known_visible: (side * side) as u32,
                ..Gathered::default()
            };
        }
        let strata = self.strata[side].get_or_init(|| self.stratify(side));
        let mut random = SampleStream::new(receiver.key, shot);
        if kernel == FormFactorKernel::Mixed {
            return self.gather_mixed(receiver, strata, &mut random, visibility, cache);
        }
        let mut gathered = Gathered::default();
        // Each stratum: an unoccluded factor (or, for `Exact`, a weight), and
        // a shadow ray to a jittered point of it.
        let mut total_weight = 0.0;
        let mut visible = Rgb::ZERO;
        for (k, stratum) in strata.cells.iter().enumerate() {
            let uv = DVec2::new(random.next_f64(), random.next_f64());
            let y = stratum.point(uv.x, uv.y);
            let radiosity = strata.at(k, uv);
            let Some((factor, target)) = self.stratum_factor(x, n, stratum, y, kernel) else {
                continue;
            };
            total_weight += factor;
            gathered.rays += u32::from(!receiver.clear);
            gathered.known_visible += u32::from(receiver.clear);
            let seen = receiver.clear || self.is_visible(receiver, target, visibility, cache);
            gathered.blocked += u32::from(!seen);
            if seen {
                visible += radiosity * factor;
            }
        }
        gathered.irradiance = if kernel == FormFactorKernel::Exact {
            // Lambert's factor of the whole patch times the unoccluded,
            // radiosity-weighted fraction.
            if total_weight > 0.0 {
                visible * (polygon_form_factor(x, n, self.cell.polygon()) / total_weight)
            } else {
                Rgb::ZERO
            }
        } else {
            visible
        };
        gathered
    }

    /// Whether a shadow ray from the receiver reaches `target` on this patch,
    /// both ends lifted off their surfaces.
    // Inlined into the strata loops always: called out of line, it slowed
    // the solve by a few percent.
    #[inline(always)]
    fn is_visible(
        &self,
        receiver: &Receiver,
        target: DVec3,
        visibility: &Visibility,
        cache: &mut ShadowCache,
    ) -> bool {
        let offset = visibility.surface_offset();
        let (from, to) = (
            receiver.position + receiver.normal * offset,
            target + self.normal * offset,
        );
        match receiver.occluders {
            Some(occluders) => visibility.is_unblocked_among(from, to, occluders),
            None => {
                visibility.is_unblocked_cached(from, to, [receiver.surface, self.surface], cache)
            }
        }
    }

    /// A stratum's unoccluded factor and the point to test visibility
    /// against. For the `Exact` kernel the factor is only a weight: the
    /// stratum's area, when its sample lies above the receiver's plane.
    fn stratum_factor(
        &self,
        x: DVec3,
        n: DVec3,
        stratum: &Cell,
        y: DVec3,
        kernel: FormFactorKernel,
    ) -> Option<(f64, DVec3)> {
        let d = y - x;
        if kernel == FormFactorKernel::Exact {
            return (n.dot(d) > 0.0).then_some((stratum.area, y));
        }
        let r2 = d.length_squared();
        let r = r2.sqrt();
        let factor = disc_form_factor(stratum.area, n.dot(d) / r, -self.normal.dot(d) / r, r2);
        (factor > 0.0).then_some((factor, y))
    }
}
