//! Adaptive stratified visibility of one source element from a probe point:
//! how much of the element's light gets past occluders, with the standard
//! error of that estimate, refined where the element is partly hidden.
//!
//! The element's parameter square is cut into m × m strata with one jittered
//! shadow ray each, plus one ray to each of the element's corners: a
//! *witness*, which counts only for telling whether a stratum's rays agree.
//! When all rays agree (the usual case: fully lit or fully hidden) the
//! element is settled and exact. Otherwise every stratum corner gets a
//! witness too, and the strata whose rays (their sample and their corners'
//! witnesses) disagree among themselves or with a neighbour's (8-connected,
//! across levels) form the *frontier*: each is split into 2 × 2 children
//! with two jittered rays each and witnesses at their corners, and the
//! children are checked in turn, so the refinement follows the shadow's edge
//! across the element. A straight occluder edge that crosses a stratum
//! separates its corners, so even a sliver thinner than the stratum, which
//! its jittered rays would miss, keeps it on the frontier.

use glam::{DVec2, DVec3};

use crate::fixed_hash::FixedMap;
use crate::lighting::SampleStream;
use crate::mesh::Cell;
use crate::scene::{SurfaceId, Visibility};

/// The deepest level of refinement below the base strata (m · 2⁸ strata per
/// side at most).
const MAX_LEVEL: u8 = 8;

/// Shadow rays per refined stratum: two, so each has a sample variance.
const RAYS_PER_CHILD: usize = 2;

/// A stratum's shadow rays: sums over its samples of the kernel
/// κ = cos θ_r cos θ_s / r² and of κ δ (δ = 1 when the ray is unblocked).
#[derive(Clone, Copy, Debug, Default)]
struct Stratum {
    /// Its share of the element's area (a fraction of 1).
    area: f64,
    /// Samples taken, rays cast (samples in front of the receiver), unblocked rays.
    samples: u32,
    cast: u32,
    unblocked: u32,
    /// Σ κ, Σ κ δ and Σ (κ δ)².
    kernel: f64,
    visible: f64,
    visible_squares: f64,
    /// Whether it disagrees with a neighbour (or its own rays disagree).
    frontier: bool,
}

impl Stratum {
    /// The variance of its estimate of ∫ κ δ dA (in units of the element's
    /// area): A_k² s²/n from the sample variance s² of κ δ, and for a
    /// frontier stratum at least the Bernoulli bound A_k² κ̄²/(4n), since its
    /// few rays may all have fallen on one side of a shadow edge.
    fn variance(&self) -> f64 {
        let n = f64::from(self.samples.max(1));
        let mean = self.visible / n;
        let sample_variance = if self.samples > 1 {
            ((self.visible_squares - n * mean * mean) / (n - 1.0)).max(0.0)
        } else {
            0.0
        };
        let bound = if self.frontier {
            (self.kernel / n).powi(2) / 4.0
        } else {
            0.0
        };
        self.area * self.area * sample_variance.max(bound) / n
    }
}

/// The corners of a grid cell, and its children, as offsets.
const CORNERS: [(u32, u32); 4] = [(0, 0), (1, 0), (0, 1), (1, 1)];

/// Where a stratum sits: its level below the base grid and its column and
/// row in that level's (m · 2^level)² grid over the element's parameters.
/// (Hashed as the tuple of its fields, in order.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Key {
    level: u8,
    i: u32,
    j: u32,
}

impl Key {
    const fn new(level: u8, i: u32, j: u32) -> Key {
        Key { level, i, j }
    }
}

/// The point a gather reads at: its position, the unit normal it faces
/// along, and its surface ([`SurfaceId::NONE`] in free space).
#[derive(Clone, Copy, Debug)]
pub struct GatherPoint {
    pub position: DVec3,
    pub normal: DVec3,
    pub surface: SurfaceId,
}

/// A source element a gather reads: its cell, its surface's front normal
/// and its surface.
#[derive(Clone, Copy, Debug)]
pub struct SourceElement {
    pub cell: Cell,
    pub normal: DVec3,
    pub surface: SurfaceId,
}

/// One source element seen from one receiving point.
pub struct AdaptiveVisibility<'a> {
    cell: Cell,
    /// The receiver: position, normal, surface.
    x: DVec3,
    n: DVec3,
    receiver: SurfaceId,
    /// The source: normal, surface.
    source_normal: DVec3,
    source: SurfaceId,
    visibility: &'a Visibility,
    random: SampleStream,
    /// The witness rays at strata corners, by lattice point of the finest
    /// level's grid (none when the point is behind the receiver).
    witnesses: FixedMap<(u32, u32), Option<bool>>,
    /// Base strata per side.
    base: u32,
    /// The strata that are leaves, and the frontier of the finest level.
    strata: FixedMap<Key, Stratum>,
    frontier: Vec<Key>,
    /// The estimate of an element whose base rays all agree, which needs
    /// no strata kept.
    settled: Option<(f64, f64)>,
    /// Shadow rays cast so far.
    pub rays: usize,
}

impl<'a> AdaptiveVisibility<'a> {
    /// Samples the `source` element from the point `at` with `base` ×
    /// `base` strata of one jittered ray each. `corner_witnesses` are the
    /// shadow rays to the element's corners in polygon order (none where no
    /// ray could be cast), which the caller casts once for all the elements
    /// that share a corner.
    #[must_use]
    pub fn new(
        source: SourceElement,
        at: GatherPoint,
        base: usize,
        corner_witnesses: [Option<bool>; 4],
        visibility: &'a Visibility,
        random: SampleStream,
    ) -> Self {
        let SourceElement {
            cell,
            normal: source_normal,
            surface: source,
        } = source;
        let GatherPoint {
            position: x,
            normal: n,
            surface: receiver,
        } = at;
        let base = base.max(1) as u32;
        let mut this = AdaptiveVisibility {
            cell,
            x,
            n,
            receiver,
            source_normal,
            source,
            visibility,
            random,
            witnesses: FixedMap::default(),
            base,
            strata: FixedMap::default(),
            frontier: Vec::new(),
            settled: None,
            rays: 0,
        };
        let keys: Vec<Key> = (0..base)
            .flat_map(|j| (0..base).map(move |i| Key::new(0, i, j)))
            .collect();
        let strata: Vec<Stratum> = keys.iter().map(|&key| this.sample(key, 1)).collect();
        // The usual case, wholly lit or wholly hidden: every ray cast and all agreeing.
        let agreed = corner_witnesses[0].filter(|&unblocked| {
            corner_witnesses[1..this.cell.polygon().len()]
                .iter()
                .all(|&w| w == Some(unblocked))
                && strata.iter().all(|stratum| {
                    stratum.cast == stratum.samples
                        && stratum.unblocked == if unblocked { stratum.cast } else { 0 }
                })
        });
        if agreed.is_some() {
            let (mut kernel, mut visible) = (0.0, 0.0);
            for stratum in &strata {
                kernel += stratum.area * stratum.kernel;
                visible += stratum.area * stratum.visible;
            }
            this.settled = Some(if kernel > 0.0 && kernel.is_finite() {
                ((visible / kernel).clamp(0.0, 1.0), 0.0)
            } else {
                (1.0, 0.0)
            });
            return this;
        }
        for (&key, stratum) in keys.iter().zip(strata) {
            this.strata.insert(key, stratum);
        }
        // The element's corners, then, if it is partly hidden, every base corner.
        // Parameters (0, 0), (1, 0), (1, 1), (0, 1) are a quad's corners in
        // order; a triangle's square is folded, so (1, 1) is its first corner.
        let polygon_corners = if this.cell.polygon().len() == 3 {
            [0, 1, 0, 2]
        } else {
            [0, 1, 2, 3]
        };
        for ((i, j), k) in [(0, 0), (base, 0), (base, base), (0, base)]
            .into_iter()
            .zip(polygon_corners)
        {
            let point = this.lattice(Key::new(0, i, j));
            this.witnesses.insert(point, corner_witnesses[k]);
        }
        this.mark_frontier(&keys);
        if !this.frontier.is_empty() {
            for &Key { level, i, j } in &keys {
                for (di, dj) in CORNERS {
                    this.witness(Key::new(level, i + di, j + dj));
                }
            }
            this.mark_frontier(&keys);
        }
        this
    }

    /// The source element.
    #[must_use]
    pub fn cell(&self) -> &Cell {
        &self.cell
    }

    /// Whether more refinement could change the estimate.
    #[must_use]
    pub fn is_settled(&self) -> bool {
        self.frontier.is_empty()
    }

    /// The most rays the next refinement would cast: each frontier stratum's
    /// children's samples and the five new corners among them.
    #[must_use]
    pub fn next_rays(&self) -> usize {
        self.frontier.len() * (4 * RAYS_PER_CHILD + 5)
    }

    /// The visible share of the element, weighted by the kernel,
    /// f = ∫ κ δ dA / ∫ κ dA, and the variance of that estimate; (1, 0)
    /// when no ray could be cast (the element lies behind the receiver).
    ///
    /// Each stratum k estimates its integrals by the means of its samples
    /// times its area A_k; the variance is Σ_k Var_k / (Σ_k A_k κ̄_k)², the
    /// stratified estimator's, with the kernel's integral taken as exact.
    #[must_use]
    pub fn estimate(&self) -> (f64, f64) {
        if let Some(estimate) = self.settled {
            return estimate;
        }
        let (mut kernel, mut visible, mut variance) = (0.0, 0.0, 0.0);
        for stratum in self.strata.values() {
            let n = f64::from(stratum.samples.max(1));
            kernel += stratum.area * stratum.kernel / n;
            visible += stratum.area * stratum.visible / n;
            variance += stratum.variance();
        }
        if kernel <= 0.0 || !kernel.is_finite() {
            return (1.0, 0.0);
        }
        (
            (visible / kernel).clamp(0.0, 1.0),
            variance / (kernel * kernel),
        )
    }

    /// Splits every frontier stratum into 2 × 2 children of two rays each
    /// and finds the children's frontier. At the deepest level the element
    /// is settled as it stands.
    pub fn refine(&mut self) {
        let frontier = std::mem::take(&mut self.frontier);
        if frontier.first().is_some_and(|key| key.level >= MAX_LEVEL) {
            return;
        }
        let mut children = Vec::with_capacity(4 * frontier.len());
        for Key { level, i, j } in frontier {
            self.strata.remove(&Key::new(level, i, j));
            for (di, dj) in CORNERS {
                let key = Key::new(level + 1, 2 * i + di, 2 * j + dj);
                let stratum = self.sample(key, RAYS_PER_CHILD);
                self.strata.insert(key, stratum);
                for (ci, cj) in CORNERS {
                    self.witness(Key::new(key.level, key.i + ci, key.j + cj));
                }
                children.push(key);
            }
        }
        self.mark_frontier(&children);
    }

    /// Marks which of `keys` (all of one level) disagree with a neighbour
    /// or within themselves, and makes them the frontier.
    fn mark_frontier(&mut self, keys: &[Key]) {
        let mut frontier = Vec::new();
        for &key in keys {
            let share = self.unblocked_share(key);
            let mixed = share.is_some_and(|s| s > 0.0 && s < 1.0);
            let disagrees = mixed
                || neighbours(key, self.base).any(|other| {
                    let other = self.leaf_over(other).and_then(|k| self.unblocked_share(k));
                    matches!((share, other), (Some(a), Some(b)) if a != b)
                });
            if disagrees {
                frontier.push(key);
            }
        }
        for key in &frontier {
            if let Some(stratum) = self.strata.get_mut(key) {
                stratum.frontier = true;
            }
        }
        self.frontier = frontier;
    }

    /// The share of a stratum's rays, its sample's and its corners'
    /// witnesses, that are unblocked; none when no ray was cast.
    fn unblocked_share(&self, key: Key) -> Option<f64> {
        let stratum = &self.strata[&key];
        let (mut rays, mut unblocked) = (stratum.cast, stratum.unblocked);
        for (di, dj) in CORNERS {
            let corner = self.lattice(Key::new(key.level, key.i + di, key.j + dj));
            if let Some(&Some(witness)) = self.witnesses.get(&corner) {
                rays += 1;
                unblocked += u32::from(witness);
            }
        }
        (rays > 0).then(|| f64::from(unblocked) / f64::from(rays))
    }

    /// The leaf stratum covering a grid cell: the cell itself or the
    /// nearest coarser stratum that holds it.
    fn leaf_over(&self, mut key: Key) -> Option<Key> {
        loop {
            if self.strata.contains_key(&key) {
                return Some(key);
            }
            if key.level == 0 {
                return None;
            }
            key = Key::new(key.level - 1, key.i / 2, key.j / 2);
        }
    }

    /// A corner of a level's grid as a point of the finest level's lattice.
    fn lattice(&self, key: Key) -> (u32, u32) {
        let Key { level, i, j } = key;
        (i << (MAX_LEVEL - level), j << (MAX_LEVEL - level))
    }

    /// Casts the witness ray to a grid corner (once), a thousandth of a
    /// finest stratum inside the element where the corner is on its edge.
    fn witness(&mut self, corner: Key) {
        let point = self.lattice(corner);
        if self.witnesses.contains_key(&point) {
            return;
        }
        let side = f64::from(self.base << MAX_LEVEL);
        let inside = 1e-3 / side;
        let parameter = |k: u32| (f64::from(k) / side).clamp(inside, 1.0 - inside);
        let ray = self.ray(DVec2::new(parameter(point.0), parameter(point.1)));
        self.witnesses
            .insert(point, ray.map(|(_, unblocked)| unblocked));
    }

    /// The shadow ray to the element's point at parameters `st` = (s, t):
    /// its kernel κ and whether it is unblocked; none when the point is
    /// behind the receiver or the receiver behind the source.
    fn ray(&mut self, st: DVec2) -> Option<(f64, bool)> {
        let y = self.cell.point(st.x, st.y);
        let d = y - self.x;
        let r2 = d.length_squared();
        let kernel = self.n.dot(d) * -self.source_normal.dot(d) / (r2 * r2);
        if !(kernel > 0.0 && kernel.is_finite()) {
            return None;
        }
        self.rays += 1;
        let offset = self.visibility.surface_offset();
        let unblocked = self.visibility.is_unblocked(
            self.x + self.n * offset,
            y + self.source_normal * offset,
            [self.receiver, self.source],
        );
        Some((kernel, unblocked))
    }

    /// `count` jittered shadow rays into a stratum.
    fn sample(&mut self, key: Key, count: usize) -> Stratum {
        let Key { level, i, j } = key;
        let side = f64::from(self.base << level);
        let mut stratum = Stratum {
            area: 1.0 / (side * side),
            ..Stratum::default()
        };
        for _ in 0..count {
            let st = DVec2::new(
                (f64::from(i) + self.random.next_f64()) / side,
                (f64::from(j) + self.random.next_f64()) / side,
            );
            stratum.samples += 1;
            let Some((kernel, unblocked)) = self.ray(st) else {
                continue;
            };
            stratum.cast += 1;
            stratum.kernel += kernel;
            if unblocked {
                stratum.unblocked += 1;
                stratum.visible += kernel;
                stratum.visible_squares += kernel * kernel;
            }
        }
        stratum
    }
}

/// The up-to-eight neighbours of a grid cell within its level's grid.
fn neighbours(key: Key, base: u32) -> impl Iterator<Item = Key> {
    let Key { level, i, j } = key;
    let side = i64::from(base << level);
    (-1i64..=1)
        .flat_map(|dj| (-1i64..=1).map(move |di| (di, dj)))
        .filter(|&d| d != (0, 0))
        .filter_map(move |(di, dj)| {
            let (p, q) = (i64::from(i) + di, i64::from(j) + dj);
            ((0..side).contains(&p) && (0..side).contains(&q))
                .then_some(Key::new(level, p as u32, q as u32))
        })
}
