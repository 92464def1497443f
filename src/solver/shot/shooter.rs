//! Vertex-to-patch form factors by stratified, ray-traced source sampling.

use std::sync::OnceLock;

use glam::DVec3;

use crate::lighting::SampleStream;
use crate::mesh::Cell;
use crate::radiometry::{disc_form_factor, polygon_form_factor};
use crate::scene::{Rgb, ShadowCache, SurfaceId, Visibility};
use crate::solver::light::unshot::{FieldScale, PatchField, SampledField, nearest_point_of};
use crate::solver::settings::FormFactorKernel;

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

/// One subdivision of a shooter: its cells and the radiosity each shoots,
/// read where a stratum's jittered sample falls.
struct Strata {
    cells: Vec<Cell>,
    radiosity: Vec<Rgb>,
    /// `sub` × `sub` values over each stratum's parameter square (see
    /// `PatchField::sampled`); empty for a uniform shot.
    sampled: Vec<Rgb>,
    /// Whether each sampled cell's centre found an element of the patch.
    found: Vec<bool>,
    /// For a field shot, each stratum's centre and the distance from it
    /// within which a receiver may stand closer to the stratum than its
    /// size (the farthest corner's distance plus the size).
    beside: Vec<(DVec3, f64)>,
    sub: usize,
}

/// How finely a shooting patch's unshot radiosity is read where a sample
/// falls: about this many cells per side of the patch, however few its
/// strata. A floor patch of 2 × 2 strata with a chair's base plate standing
/// on it then shoots nothing along the rays that start under the plate, and
/// shoots that power from the rest of the floor; read at each stratum's
/// centre, the plate's share of a stratum was lost on the plate's inside
/// (the office's floor patches lost up to 10 % of each shot, and its ceiling
/// came out 3 % dark). Eight per side recovers that to 0.4 %; sixteen
/// recover 0.3 % more but cost a fifth of the ray throughput.
pub(crate) const SAMPLED_PER_SIDE: usize = 8;

impl Strata {
    /// The radiosity stratum k shoots along a ray to its sample at
    /// parameters (u, v).
    fn at(&self, k: usize, uv: (f64, f64)) -> Rgb {
        if self.sampled.is_empty() {
            return self.radiosity[k];
        }
        self.sampled[self.cell_of(k, uv)]
    }

    /// Whether the sampled cell that parameters (u, v) of stratum k fall in
    /// read an element at its centre (always, for a uniform shot).
    fn found_at(&self, k: usize, uv: (f64, f64)) -> bool {
        self.found.is_empty() || self.found[self.cell_of(k, uv)]
    }

    /// The index of the sampled cell that parameters (u, v) of stratum k
    /// fall in.
    fn cell_of(&self, k: usize, uv: (f64, f64)) -> usize {
        k * self.sub * self.sub + sampled_cell(uv, self.sub)
    }
}

/// The cell, row by row, of a `sub` × `sub` grid over a parameter square
/// that parameters (u, v) fall in: where a sample reads the values of
/// [`PatchField::sampled`].
pub(crate) fn sampled_cell((u, v): (f64, f64), sub: usize) -> usize {
    let cell = |w: f64| ((w * sub as f64) as usize).min(sub - 1);
    cell(v) * sub + cell(u)
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
        (min_side, max_side): (usize, usize),
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
        (visibility, cache): (&Visibility, &mut ShadowCache),
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
        // ones already sum to it). On the 16 cluttered offices of
        // `bench/generate_building.py`, whose lamps' shots see 44 % of
        // their samples clear, the solve went from 3.5 to 3.0 s and the
        // golden scenes' images moved by 0.004 points or less.
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
            return self.gather_mixed(receiver, strata, &mut random, (visibility, cache));
        }
        let mut gathered = Gathered::default();
        // Each stratum: an unoccluded factor (or, for `Exact`, a weight), and
        // a shadow ray to a jittered point of it.
        let mut total_weight = 0.0;
        let mut visible = Rgb::ZERO;
        for (k, stratum) in strata.cells.iter().enumerate() {
            let uv = (random.next_f64(), random.next_f64());
            let y = stratum.point(uv.0, uv.1);
            let radiosity = strata.at(k, uv);
            let Some((factor, target)) = self.stratum_factor(x, n, stratum, y, kernel) else {
                continue;
            };
            total_weight += factor;
            gathered.rays += u32::from(!receiver.clear);
            gathered.known_visible += u32::from(receiver.clear);
            let seen = receiver.clear || self.is_visible(receiver, target, (visibility, cache));
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

    /// The m × m strata of the patch and the radiosity each shoots.
    fn stratify(&self, side: usize) -> Strata {
        let mut cells = Vec::with_capacity(side * side);
        self.cell.subdivide(side, &mut cells);
        let sub = SAMPLED_PER_SIDE.div_ceil(side.max(1));
        let (radiosity, sampled, found, beside) = match &self.radiosity {
            ShotRadiosity::Uniform(b) => {
                (vec![*b; cells.len()], Vec::new(), Vec::new(), Vec::new())
            }
            ShotRadiosity::Field(field) => {
                let SampledField { sampled, found } = field.sampled(&cells, sub);
                let share = 1.0 / (sub * sub) as f64;
                let means = sampled
                    .chunks(sub * sub)
                    .map(|values| values.iter().copied().sum::<Rgb>() * share)
                    .collect();
                let beside = cells
                    .iter()
                    .map(|cell| {
                        let centre = cell.centre();
                        let reach = cell
                            .polygon()
                            .iter()
                            .map(|p| p.distance_squared(centre))
                            .fold(0.0, f64::max)
                            .sqrt();
                        (centre, reach + cell.area.sqrt())
                    })
                    .collect();
                (means, sampled, found, beside)
            }
        };
        Strata {
            cells,
            radiosity,
            sampled,
            found,
            beside,
            sub,
        }
    }

    /// The `Mixed` kernel: Wallace's disc term on far strata, Lambert's exact
    /// factor on near ones, each times its own shadow ray.
    ///
    /// Lambert's factor is additive over the strata, which tile the patch:
    /// Σ_near F_k = F_patch − Σ_far F_k. So the near strata's visible share is
    /// summed either directly over the visible ones or, when fewer factors
    /// are needed that way, as F_patch less the far and the hidden near
    /// strata's factors. A fully visible patch seen from nearby then costs
    /// one polygon factor instead of one per stratum; the result is the same
    /// sum, up to rounding. When the strata shoot different radiosities W_k
    /// ([`ShotRadiosity::Field`]), the complement gives the visible near
    /// strata's total factor F, which is shared among them in proportion to
    /// their disc terms g_k: H_near = F · Σ W_k g_k / Σ g_k (exact for a
    /// uniform shot; the direct sum when that is cheaper). That direct sum
    /// takes each visible near stratum's field by a control variate,
    /// W̄_k F_k + A_k k(y_k) (W(y_k) − W̄_k), with W̄_k the stratum's mean
    /// radiosity and k the point kernel cosθ_r cosθ_s / (π r²) at its
    /// sample: unbiased for ∫ ΔB k over the stratum, where W(y_k) F_k would
    /// weight ΔB evenly over a stratum seen from nearby (a whole patch,
    /// for a dim shot's one stratum) and light the receivers beside its dark
    /// part as if it were bright.
    ///
    /// The complement's share is biased where W varies across strata the
    /// receiver stands beside: the disc terms weigh the stratum under the
    /// receiver far less than its exact factor does. In the corner of a
    /// floor and a wall, the floor's ΔB rising from 1 at the wall to 4 a
    /// patch's width away, a wall point 1 % of that width up receives twice
    /// the integral (one stratum; +55 % with 3 × 3, +5 % at 20 % up), and
    /// a third too little if ΔB falls away from the wall. Rooms'
    /// junctions are dim, so their vertices come out bright: the lines
    /// along the tops of the walls. The exact integral was built (strata
    /// beside the receiver split until each piece is farther than its
    /// size, W read from the elements): it matched a 1000 × 1000 sum to
    /// 0.2 %, but every office and the Cornell box came out darker and
    /// further from the path tracer (furnished office 1.46 % → 1.63 % per
    /// pixel, mean radiance ×0.997 → ×0.994; cluttered 2.91 % → 3.81 %),
    /// since the bias offsets what the corners' interpolation loses where
    /// light falls off concavely into a junction; and it took 2–3 times as
    /// long. Taking out of the share only the strata the receiver stands
    /// beside (each its exact factor, with ΔB at its point nearest the
    /// receiver as the control variate's baseline) did the same on a
    /// smaller scale: Cornell box 1.88 → 1.90 %, furnished office
    /// 1.447 → 1.466 %, mean radiance ×0.9975 → ×0.9962.
    fn gather_mixed(
        &self,
        receiver: &Receiver,
        strata: &Strata,
        random: &mut SampleStream,
        (visibility, cache): (&Visibility, &mut ShadowCache),
    ) -> Gathered {
        let (x, n) = (receiver.position, receiver.normal);
        let mut gathered = Gathered::default();
        let mut far_visible = Rgb::ZERO;
        // Which strata were near and visible, near and hidden, far.
        let mut kinds = [(); 3].map(|()| StrataSet::new(strata.cells.len()));
        let (mut near_visible, mut near_hidden, mut far) = (0, 0, 0);
        // The visible near strata's Σ W_k g_k and Σ g_k, g_k their disc terms:
        // how W varies over them, to share out their exact total factor.
        let (mut near_shape, mut near_weight, mut near_radiosity) = (Rgb::ZERO, 0.0, Rgb::ZERO);
        // The visible near strata and the radiosity each shoots at its sample.
        let mut near_samples = Vec::new();
        // The element of a field shot's patch that the last near sample fell in.
        let mut field_hint = 0;
        // The receiver's height above the source's plane, the same for every stratum.
        let receiver_height = self.normal.dot(x - self.cell.corners[0]);
        for (k, stratum) in strata.cells.iter().enumerate() {
            // The random numbers are drawn for every stratum, in order.
            let uv = (random.next_f64(), random.next_f64());
            let y = stratum.point(uv.0, uv.1);
            let d = y - x;
            let r2 = d.length_squared();
            let nearest = r2
                .min(n.dot(d).powi(2))
                .min(receiver_height * receiver_height);
            if nearest < NEAR_FIELD * stratum.area {
                // Aim at a part of the stratum above the receiver's plane.
                let Some((target, target_uv)) = near_target(x, n, stratum, (y, uv)) else {
                    continue;
                };
                gathered.rays += u32::from(!receiver.clear);
                gathered.known_visible += u32::from(receiver.clear);
                let seen =
                    receiver.clear || self.is_visible(receiver, target, (visibility, &mut *cache));
                gathered.blocked += u32::from(!seen);
                if seen {
                    kinds[NEAR_VISIBLE].insert(k);
                    near_visible += 1;
                    let w =
                        self.radiosity_at_target(strata, k, (target, target_uv), &mut field_hint);
                    // The point kernel at the jittered sample, times the
                    // stratum's area (zero behind either plane).
                    let point_factor = {
                        let (r2, cos_r) = (d.length_squared(), n.dot(d));
                        let cos_s = -self.normal.dot(d);
                        if cos_r > 0.0 && cos_s > 0.0 && r2 > 0.0 {
                            stratum.area * cos_r * cos_s / (std::f64::consts::PI * r2 * r2)
                        } else {
                            0.0
                        }
                    };
                    near_samples.push((k, w, point_factor));
                    let d = target - x;
                    let r2 = d.length_squared();
                    let r = r2.sqrt();
                    let g =
                        disc_form_factor(stratum.area, n.dot(d) / r, -self.normal.dot(d) / r, r2)
                            .max(0.0);
                    near_shape += w * g;
                    near_weight += g;
                    near_radiosity += w;
                } else {
                    kinds[NEAR_HIDDEN].insert(k);
                    near_hidden += 1;
                }
            } else {
                kinds[FAR].insert(k);
                far += 1;
                let r = r2.sqrt();
                let factor =
                    disc_form_factor(stratum.area, n.dot(d) / r, -self.normal.dot(d) / r, r2);
                if factor > 0.0 {
                    gathered.rays += u32::from(!receiver.clear);
                    gathered.known_visible += u32::from(receiver.clear);
                    let seen =
                        receiver.clear || self.is_visible(receiver, y, (visibility, &mut *cache));
                    gathered.blocked += u32::from(!seen);
                    if seen {
                        far_visible += strata.at(k, uv) * factor;
                    }
                }
            }
        }
        let in_set = |set: usize| {
            let kinds = &kinds;
            strata
                .cells
                .iter()
                .enumerate()
                .filter(move |(k, _)| kinds[set].contains(*k))
        };
        let lambert = |set: usize| -> f64 {
            in_set(set)
                .map(|(_, stratum)| polygon_form_factor(x, n, stratum.polygon()))
                .sum()
        };
        let near_visible_irradiance = if near_visible == 0 {
            Rgb::ZERO
        } else if near_visible <= 1 + far + near_hidden {
            // Each visible near stratum's Σ_y ΔB(y) F(x, dy) by a control
            // variate: its mean radiosity W̄ times its exact factor, plus the
            // deviation at the jittered sample weighted by the point kernel,
            //   W̄ F_k + A_k k(y) (W(y) − W̄),
            // whose expectation is ∫ W k over the stratum. W(y) F_k alone
            // would weight ΔB evenly over a stratum seen from nearby, and
            // shift light from the patch's bright part to receivers beside
            // its dark part.
            //
            // A_k k(y) estimates F_k, which no stratum's factor exceeds: a
            // sample with A_k k(y) > 1 lies in the kernel's 1/r² spike right
            // beside the receiver, where the correction's variance is
            // unbounded. One a millimetre from the vertex in the corner of
            // a bookcase's board and side gave it a radiosity of 17 where
            // the shelf round it has 0.4, and lit the shelf; capped at 1,
            // the offices' images are otherwise unchanged.
            //
            // Beside the stratum (closer than its size), the spike holds most
            // of ∫ k and the cap drops most of the correction, so the
            // baseline is W where the spike stands, at the stratum's point
            // nearest the receiver, rather than the mean: beside an object
            // standing on the patch, whose footprint the mean counts dark,
            // the mean lost a fifth of the light.
            near_samples
                .iter()
                .map(|&(k, w, point_factor)| {
                    let stratum = &strata.cells[k];
                    let baseline = self
                        .spike_radiosity(strata, k, x, &mut field_hint)
                        .unwrap_or(strata.radiosity[k]);
                    let exact = polygon_form_factor(x, n, stratum.polygon());
                    (baseline * exact + (w - baseline) * point_factor.min(1.0)).max(Rgb::ZERO)
                })
                .sum()
        } else {
            let far_factor = if far > 0 { lambert(FAR) } else { 0.0 };
            let hidden_factor = if near_hidden > 0 {
                lambert(NEAR_HIDDEN)
            } else {
                0.0
            };
            let total =
                (polygon_form_factor(x, n, self.cell.polygon()) - far_factor - hidden_factor)
                    .max(0.0);
            let mean_radiosity = if near_weight > 0.0 {
                near_shape / near_weight
            } else {
                near_radiosity / f64::from(near_visible)
            };
            mean_radiosity * total
        };
        gathered.irradiance = near_visible_irradiance + far_visible;
        gathered
    }

    /// The radiosity a near stratum k shoots at its aimed point: the value
    /// of the sampled cell it falls in, unless that cell's centre found no
    /// element on a field shot, when ΔB is interpolated from the element
    /// under the point itself (nothing if none is). A cell's value is ΔB at
    /// its centre, and where an object stands on the patch a cell whose
    /// centre is under it reads nothing, though part of it is lit: a
    /// receiver on the object's side, just above the patch, sees mostly the
    /// patch within a few of its heights, and lost a twelfth of its light
    /// there (the Cornell box's tall block, 8 % dark at its foot).
    // Kept out of `gather_mixed`'s loop, whose far strata are the hot path:
    // inlined, this and `spike_radiosity` slowed the cluttered office's
    // solve by 2–3 %.
    #[inline(never)]
    fn radiosity_at_target(
        &self,
        strata: &Strata,
        k: usize,
        (target, uv): (DVec3, (f64, f64)),
        hint: &mut usize,
    ) -> Rgb {
        match (&self.radiosity, self.exact_scale) {
            (ShotRadiosity::Field(field), Some(scale)) if !strata.found_at(k, uv) => field
                .unshot_at(target, hint)
                .map_or(Rgb::ZERO, |unshot| scale.apply(unshot)),
            _ => strata.at(k, uv),
        }
    }

    /// A field shot's radiosity at the point of stratum k nearest the
    /// receiver at x, when x is closer to the stratum than the stratum's
    /// size and an element lies under that point; `None` otherwise, or for
    /// a uniform shot.
    #[inline(never)]
    fn spike_radiosity(
        &self,
        strata: &Strata,
        k: usize,
        x: DVec3,
        hint: &mut usize,
    ) -> Option<Rgb> {
        let (ShotRadiosity::Field(field), Some(scale)) = (&self.radiosity, self.exact_scale) else {
            return None;
        };
        let stratum = &strata.cells[k];
        // Most near strata are several sizes away: rule them out by the
        // sphere round the stratum before looking for its nearest point.
        let (centre, beside) = strata.beside[k];
        if centre.distance_squared(x) >= beside * beside {
            return None;
        }
        let nearest = nearest_point_of(stratum, x);
        if (nearest - x).length_squared() >= stratum.area {
            return None;
        }
        field
            .unshot_at(nearest, hint)
            .map(|unshot| scale.apply(unshot))
    }

    /// Whether a shadow ray from the receiver reaches `target` on this patch,
    /// both ends lifted off their surfaces.
    // Inlined into the strata loops always: called out of line (as the
    // compiler chose after unrelated changes), the 16 offices' solve took
    // about 5 % longer (measured on top of the other two fixes of that
    // day: `Cell::point` and `Visibility`'s traversal).
    #[inline(always)]
    fn is_visible(
        &self,
        receiver: &Receiver,
        target: DVec3,
        (visibility, cache): (&Visibility, &mut ShadowCache),
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

/// The sets of strata a `Mixed` gather sorts into (strata wholly behind the
/// receiver's plane are in none): near with an unblocked shadow ray, near
/// with a blocked one, and far (disc term, already counted).
const NEAR_VISIBLE: usize = 0;
const NEAR_HIDDEN: usize = 1;
const FAR: usize = 2;

/// A set of stratum indices, one bit each, on the stack up to 256 strata.
struct StrataSet {
    small: [u64; 4],
    large: Vec<u64>,
}

impl StrataSet {
    fn new(len: usize) -> StrataSet {
        let large = if len > 256 {
            vec![0; len.div_ceil(64)]
        } else {
            Vec::new()
        };
        StrataSet {
            small: [0; 4],
            large,
        }
    }

    fn insert(&mut self, k: usize) {
        let words = if self.large.is_empty() {
            &mut self.small[..]
        } else {
            &mut self.large[..]
        };
        words[k / 64] |= 1 << (k % 64);
    }

    fn contains(&self, k: usize) -> bool {
        let words = if self.large.is_empty() {
            &self.small[..]
        } else {
            &self.large[..]
        };
        words[k / 64] & (1 << (k % 64)) != 0
    }
}

/// The point of a near stratum a shadow ray aims at, and its parameters in
/// the stratum: its jittered sample `y` (at `uv`) if above the receiver's
/// plane, else its centre or a corner that is; none when the whole stratum
/// is behind the plane (its factor is then zero). The stratum's radiosity
/// is read there too: a sample behind the plane may lie under the object
/// the receiver belongs to, where the shooter has no light.
fn near_target(
    x: DVec3,
    n: DVec3,
    stratum: &Cell,
    (y, uv): (DVec3, (f64, f64)),
) -> Option<(DVec3, (f64, f64))> {
    let above = |p: &DVec3| n.dot(*p - x) > 0.0;
    if above(&y) {
        return Some((y, uv));
    }
    let corners: &[(f64, f64)] = if stratum.is_triangle {
        &[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]
    } else {
        &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    };
    let centre_uv = if stratum.is_triangle {
        (1.0 / 3.0, 1.0 / 3.0)
    } else {
        (0.5, 0.5)
    };
    std::iter::once((stratum.centre(), centre_uv))
        .chain(
            stratum
                .polygon()
                .iter()
                .copied()
                .zip(corners.iter().copied()),
        )
        .find(|(p, _)| above(p))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Material, Scene};

    /// A 1 m square lamp 3 m over a 6 m floor, facing it: an empty scene,
    /// so every ray is unblocked. From the floor its strata are far
    /// (`NEAR_FIELD`), and the samples sum Wallace's disc terms.
    fn lamp_over_floor() -> (Scene, Shooter) {
        let mut scene = Scene::new();
        let grey = scene
            .add_material(Material::diffuse("grey", Rgb::splat(0.5)))
            .unwrap();
        let at = DVec3::new;
        scene
            .add_polygon(
                "floor",
                grey,
                &[
                    at(-2.0, 0.0, -2.0),
                    at(-2.0, 0.0, 2.0),
                    at(2.0, 0.0, 2.0),
                    at(2.0, 0.0, -2.0),
                ],
            )
            .unwrap();
        let lamp = [
            at(-0.5, 3.0, -0.5),
            at(0.5, 3.0, -0.5),
            at(0.5, 3.0, 0.5),
            at(-0.5, 3.0, 0.5),
        ];
        scene.add_polygon("lamp", grey, &lamp).unwrap();
        let cell = Cell::quad(lamp[0], lamp[1], lamp[2], lamp[3]);
        let shooter = Shooter::new(
            cell,
            DVec3::NEG_Y,
            SurfaceId::new(1),
            (8, 16),
            ShotRadiosity::Uniform(Rgb::splat(2.0)),
        );
        (scene, shooter)
    }

    fn gather(
        (shooter, visibility): (&Shooter, &Visibility),
        x: DVec3,
        (clear, key): (bool, u64),
        kernel: FormFactorKernel,
    ) -> Gathered {
        let receiver = Receiver {
            position: x,
            normal: DVec3::Y,
            surface: SurfaceId::new(0),
            key,
            clear,
            occluders: None,
        };
        shooter.gather(
            &receiver,
            3.0,
            1,
            kernel,
            (visibility, &mut ShadowCache::default()),
        )
    }

    /// A receiver known to see all of a uniform shooter takes W times
    /// Lambert's exact factor, without samples; the samples of one that
    /// casts its rays estimate the same value. Wallace's kernel keeps its
    /// samples' sum, rays or none.
    #[test]
    fn a_clear_receiver_of_a_uniform_shot_takes_the_exact_factor() {
        let (scene, shooter) = lamp_over_floor();
        let visibility = Visibility::new(&scene);
        for x in [
            DVec3::ZERO,
            DVec3::new(0.7, 0.0, 0.2),
            DVec3::new(1.9, 0.0, -1.5),
        ] {
            let exact = 2.0 * polygon_form_factor(x, DVec3::Y, shooter.cell.polygon());
            let clear = gather(
                (&shooter, &visibility),
                x,
                (true, 0),
                FormFactorKernel::Mixed,
            );
            assert_eq!(clear.irradiance.g, exact, "at {x}");
            assert_eq!((clear.rays, clear.blocked), (0, 0));
            assert!(clear.known_visible >= 64);
            let trials = 64;
            let sampled: f64 = (0..trials)
                .map(|key| {
                    let g = gather(
                        (&shooter, &visibility),
                        x,
                        (false, key),
                        FormFactorKernel::Mixed,
                    );
                    assert!(g.rays >= 64 && g.blocked == 0);
                    g.irradiance.g
                })
                .sum::<f64>()
                / f64::from(trials as u32);
            assert!(
                (sampled / exact - 1.0).abs() < 0.01,
                "{sampled} against {exact} at {x}"
            );
            let wallace = |clear| {
                gather(
                    (&shooter, &visibility),
                    x,
                    (clear, 3),
                    FormFactorKernel::Wallace,
                )
                .irradiance
            };
            assert_eq!(wallace(true), wallace(false));
        }
    }
}
