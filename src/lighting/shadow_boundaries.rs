//! Shadow boundaries on a receiver: where an occluder's silhouette, seen
//! from a luminaire's corner, falls on the receiver's plane.
//!
//! Direct light changes its form across these lines: from a polygonal
//! luminaire, the outer and inner edges of every penumbra are pieces of the
//! shadows that the occluders cast from the luminaire's corners (the
//! vertex–edge events of discontinuity meshing). An element that straddles
//! one blurs the shadow over its whole width; with element edges along them,
//! the linear interpolation between vertices follows the penumbra instead.
//!
//! For each luminaire corner v in front of the receiver (a photometric
//! luminaire's centre counts as one corner) and each occluder
//! polygon in the shaft between them, every silhouette edge ab of the
//! occluder seen from v (an edge whose neighbour across it faces v the other
//! way, or that has none) is cut to the part in front of the receiver, below
//! v and in front of the luminaire, and projected centrally from v:
//! p ↦ v + (p − v) h_v / (h_v − h_p), with h the height over the receiver's
//! plane. The projected segment is clipped to the receiver's outline, and
//! to the parts of it where the event is real: where the receiver point
//! sees the edge point and the edge point sees v (shadow rays at
//! [`EVENT_SAMPLES`] + 1 points along the edge). An edge whose shadow falls
//! inside another occluder's umbra, or that v sees only through other
//! objects, bounds no penumbra there: a desk top's underside edges, a
//! chair's legs beneath its seat. Measured once by hand (`isorad info`,
//! `compare_images.py`, `isorad compare`): in the furnished office of
//! `bench/generate_building.py` the check takes a wall's boundaries from
//! 163 to 122 and the room's render from 1.84 % to 1.82 % off per pixel;
//! its floor keeps the cap of 256 (`isorad compare` on it: 3,299 vertices
//! for level lines at ε 8 % instead of 3,663, RMS error 0.046 instead of
//! 0.049).
//!
//! # References
//! P. Heckbert, "Discontinuity meshing for radiosity", Eurographics Workshop
//! on Rendering 1992; D. Lischinski, F. Tampieri, D. P. Greenberg,
//! "Discontinuity meshing for accurate radiosity", IEEE CG&A 12(6) 1992.

use std::hash::{Hash, Hasher};

use glam::{DVec2, DVec3};

use super::Luminaire;
use super::sample_stream::SampleStream;
use super::stratified::stratified_points;
use crate::fixed_hash::FixedMap;
use crate::scene::{
    PlaneFrame, Scene, ShadowCache, SurfaceId, Visibility, clip_segment_to_polygon,
    distance_to_boundary, distance_to_segment,
};

/// Corners of a luminaire's polygons used as projection centres, at most
/// (a disc's 64-gon is represented by 8 of its vertices, evenly spread).
const MAX_CORNERS_PER_POLYGON: usize = 8;

/// Heights within this fraction of the scene's diagonal count as on a plane.
const HEIGHT_TOLERANCE: f64 = 1e-3;

/// An edge is kept up to this fraction of its projection centre's height: a
/// point level with the corner would project to infinity.
const MAX_HEIGHT_FRACTION: f64 = 0.999;

/// Steps along an edge at which a boundary's event is checked by shadow
/// rays: a boundary is kept where the checks pass, to half a step beyond.
const EVENT_SAMPLES: usize = 8;

/// The surfaces that may shade a receiver within a box (its corners, min
/// and max): found by their bounding boxes (`SurfaceBoxes`), and only
/// those of the receiver's own closed room.
pub type OccludersIn<'a> = &'a (dyn Fn(DVec3, DVec3) -> Vec<SurfaceId> + Sync);

/// The boundaries a receiver keeps and what they may cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryLimits {
    /// Boundaries closer than this, and shorter ones, are merged or dropped:
    /// a feature the mesh cannot resolve. Scene units.
    pub min_feature: f64,
    /// The most boundaries one receiver keeps, longest first.
    pub max_per_receiver: usize,
}

/// The scene's polygon edges and the surfaces that share each one, for the
/// silhouette test: an edge whose neighbour across it faces a corner the
/// other way is on the occluder's silhouette from there.
pub struct EdgeNeighbours {
    quantum: f64,
    edges: FixedMap<EdgeKey, Vec<SurfaceId>>,
}

/// An edge's two end points, rounded to the lattice, the lesser first.
/// Hashed as six words ([`FixedMap`]) and compared word by word: a
/// building's boundaries look one up per corner of every occluder near
/// every receiver, and SipHash over the 48 bytes took 3 % of the phase
/// (64 offices' boundaries take 1–2 % less time this way).
#[derive(Clone, Copy, Debug, Eq)]
struct EdgeKey([i64; 6]);

impl PartialEq for EdgeKey {
    fn eq(&self, other: &EdgeKey) -> bool {
        self.0.iter().zip(&other.0).all(|(a, b)| a == b)
    }
}

impl Hash for EdgeKey {
    fn hash<H: Hasher>(&self, state: &mut H) {
        for word in self.0 {
            state.write_u64(word as u64);
        }
    }
}

impl EdgeNeighbours {
    /// Indexes every surface's occluding polygon by its edges, end points
    /// rounded to a millionth of the scene's diagonal.
    #[must_use]
    pub fn new(scene: &Scene) -> EdgeNeighbours {
        let quantum = (1e-6 * scene.diagonal()).max(f64::MIN_POSITIVE);
        let mut neighbours = EdgeNeighbours {
            quantum,
            edges: FixedMap::default(),
        };
        for (id, surface) in scene.surfaces_with_ids() {
            let polygon = surface.occluder_vertices();
            for k in 0..polygon.len() {
                let key = neighbours.key(polygon[k], polygon[(k + 1) % polygon.len()]);
                neighbours.edges.entry(key).or_default().push(id);
            }
        }
        neighbours
    }

    fn key(&self, a: DVec3, b: DVec3) -> EdgeKey {
        let round = |p: DVec3| (p / self.quantum).round().as_i64vec3().to_array();
        let (a, b) = (round(a), round(b));
        let [[p, q, r], [x, y, z]] = if a <= b { [a, b] } else { [b, a] };
        EdgeKey([p, q, r, x, y, z])
    }

    /// The surfaces other than `surface` that have the edge ab.
    fn across(&self, surface: SurfaceId, a: DVec3, b: DVec3) -> impl Iterator<Item = SurfaceId> {
        self.edges
            .get(&self.key(a, b))
            .into_iter()
            .flatten()
            .copied()
            .filter(move |&other| other != surface)
    }
}

/// The shadow boundaries that `luminaires` and the point sources at
/// `points` (photometric luminaires' centres, or their luminous openings'
/// corners) cast on `receiver` through the surfaces `occluders` finds in
/// the box around the receiver and each light's corners (the shaft
/// between them lies inside it: a silhouette point whose shadow falls on
/// the receiver lies on a segment from a corner to the receiver), in the
/// receiver's plane coordinates: merged
/// where closer than `limits.min_feature`, the longest
/// `limits.max_per_receiver` kept. Segments running along the receiver's
/// outline are left out (its edges are element edges already).
#[must_use]
pub fn shadow_boundaries(
    (scene, visibility): (&Scene, &Visibility),
    neighbours: &EdgeNeighbours,
    (receiver, occluders): (SurfaceId, OccludersIn<'_>),
    luminaires: &[Luminaire],
    points: &[DVec3],
    limits: BoundaryLimits,
) -> Vec<[DVec2; 2]> {
    let target = scene.surface(receiver);
    let frame = target.frame();
    let outline = target.plane_vertices();
    // The BVH keeps the scene's diagonal: `Scene::diagonal` visits every
    // vertex of the scene, once per receiver of a building.
    let tolerance = HEIGHT_TOLERANCE * visibility.diagonal();
    let mut found = Vec::new();
    for luminaire in luminaires {
        if luminaire.surfaces.contains(&receiver) {
            continue;
        }
        // The receiver must have some part in front of the luminaire.
        let lit = target
            .vertices()
            .iter()
            .any(|&p| (p - luminaire.centre).dot(luminaire.normal) > tolerance);
        if !lit {
            continue;
        }
        // The horizon only matters where the luminaire lights the receiver.
        let corners = luminaire_corners(scene, luminaire);
        let lights_front = corners.iter().any(|&v| frame.height(v) > tolerance);
        if let Some(horizon) = horizon(frame, &outline, luminaire).filter(|_| lights_front) {
            found.push(horizon);
        }
        let source = Source {
            corners,
            plane: Some((luminaire.centre, luminaire.normal)),
            surfaces: &luminaire.surfaces,
        };
        source.cast(
            (scene, visibility),
            neighbours,
            (receiver, occluders, tolerance),
            &mut found,
        );
    }
    for &point in points {
        let source = Source {
            corners: vec![point],
            plane: None,
            surfaces: &[],
        };
        source.cast(
            (scene, visibility),
            neighbours,
            (receiver, occluders, tolerance),
            &mut found,
        );
    }
    found.retain(|&[a, b]| {
        let along_outline = [a, b, a.lerp(b, 0.5)]
            .iter()
            .all(|&p| distance_to_boundary(&outline, p) <= limits.min_feature);
        a.distance(b) >= limits.min_feature && !along_outline
    });
    merge_boundaries(found, limits)
}

/// Receiver points [`light_reaches`] tries: a 4 × 4 stratification.
const REACH_POINTS: usize = 16;

/// Whether any of the points `from` (a luminaire's centre and corners)
/// sees some part of `receiver`: a shadow ray from one of 16 stratified
/// points of the receiver (lifted a surface offset off it) to one of them
/// (stopped that far short, so the luminaire's own surface `lamp` does not
/// count) is unblocked. A receiver in another closed room, or wholly in
/// the umbra, sees none, and casting shadow boundaries on it would only
/// add vertices where no direct light falls. A receiver lit only through a
/// gap narrower than the samples can be missed: its shadows are then
/// meshed as if there were no boundaries.
#[must_use]
pub fn light_reaches(
    scene: &Scene,
    visibility: &Visibility,
    receiver: SurfaceId,
    from: &[DVec3],
    lamp: SurfaceId,
) -> bool {
    let surface = scene.surface(receiver);
    let (frame, n) = (surface.frame(), surface.normal());
    let offset = visibility.surface_offset();
    let mut random = SampleStream::new(u64::from(receiver), 0x5EE5_11A7);
    let points = stratified_points(&surface.plane_vertices(), REACH_POINTS, 0.01, &mut random);
    let mut cache = ShadowCache::default();
    points.iter().any(|&(p, _)| {
        let x = frame.to_world(p) + n * offset;
        from.iter().any(|&y| {
            let d = y - x;
            n.dot(d) > 0.0 && {
                let end = y - d.normalize_or_zero() * offset;
                visibility.is_unblocked_cached(x, end, [receiver, lamp], &mut cache)
            }
        })
    })
}

/// A light that casts shadows: the corners they are cast from, the plane
/// in front of which it emits (none for a point source, which may light
/// every direction), and its own surfaces, which cast nothing.
struct Source<'a> {
    corners: Vec<DVec3>,
    plane: Option<(DVec3, DVec3)>,
    surfaces: &'a [SurfaceId],
}

impl Source<'_> {
    /// Whether `p` lies where the source sends light.
    fn in_front(&self, p: DVec3, tolerance: f64) -> bool {
        self.plane
            .is_none_or(|(centre, normal)| (p - centre).dot(normal) > tolerance)
    }

    /// Pushes onto `found` the receiver-plane shadows of every occluder's
    /// silhouette edges from each of the source's corners in front of the
    /// receiver, where the event is real ([`event_runs`]), clipped to its
    /// outline. The occluders are those in the box around the receiver and
    /// those corners.
    fn cast(
        &self,
        (scene, visibility): (&Scene, &Visibility),
        neighbours: &EdgeNeighbours,
        (receiver, occluders, tolerance): (SurfaceId, OccludersIn<'_>, f64),
        found: &mut Vec<[DVec2; 2]>,
    ) {
        let target = scene.surface(receiver);
        let frame = target.frame();
        let outline = target.plane_vertices();
        let corners: Vec<DVec3> = self
            .corners
            .iter()
            .copied()
            .filter(|&v| frame.height(v) > tolerance)
            .collect();
        if corners.is_empty() {
            return;
        }
        let highest = corners.iter().map(|&v| frame.height(v)).fold(0.0, f64::max);
        let shaft = target.vertices().iter().chain(&corners);
        let low = shaft.clone().fold(DVec3::INFINITY, |m, &p| m.min(p));
        let high = shaft.fold(DVec3::NEG_INFINITY, |m, &p| m.max(p));
        let margin = DVec3::splat(tolerance);
        for id in occluders(low - margin, high + margin) {
            if id == receiver || self.surfaces.contains(&id) {
                continue;
            }
            let occluder = scene.surface(id);
            let polygon = occluder.occluder_vertices();
            let between = polygon.iter().any(|&p| {
                let h = frame.height(p);
                h > tolerance && h < highest
            }) && polygon.iter().any(|&p| self.in_front(p, tolerance));
            if !between || !in_shaft(frame, &outline, &corners, polygon, tolerance) {
                continue;
            }
            let normal = occluder.normal();
            let faces = |surface: SurfaceId, v: DVec3| {
                let s = scene.surface(surface);
                s.normal().dot(v - s.vertices()[0]) > 0.0
            };
            let lamp = self.surfaces.first().copied().unwrap_or(id);
            // The faces across each edge, looked up once for all corners.
            let across: Vec<Vec<SurfaceId>> = (0..polygon.len())
                .map(|k| {
                    let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
                    neighbours.across(id, a, b).collect()
                })
                .collect();
            for &v in &corners {
                let facing = normal.dot(v - polygon[0]) > 0.0;
                for k in 0..polygon.len() {
                    let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
                    let silhouette =
                        across[k].is_empty() || (facing && across[k].iter().any(|&n| !faces(n, v)));
                    if !silhouette {
                        continue;
                    }
                    let Some(range) = edge_range(frame, self.plane, v, [a, b]) else {
                        continue;
                    };
                    // The runs' shadows lie on the whole range's: where that
                    // misses the receiver, so do they, and no rays are cast.
                    let whole = [range.0, range.1].map(|t| project(frame, v, a.lerp(b, t)));
                    if clip_segment_to_polygon(whole, &outline).is_none() {
                        continue;
                    }
                    let ends = (receiver, id, lamp);
                    for (t0, t1) in event_runs((scene, visibility), ends, v, [a, b], range) {
                        let segment = [t0, t1].map(|t| project(frame, v, a.lerp(b, t)));
                        if let Some(clipped) = clip_segment_to_polygon(segment, &outline) {
                            found.push(clipped);
                        }
                    }
                }
            }
        }
    }
}

/// The luminaire's horizon on the receiver: the line where the luminaire's
/// plane cuts the receiver's, clipped to its outline. Direct light falls to
/// zero there with a kink (as cos θ of the emitting side), and nothing
/// reaches beyond it.
fn horizon(frame: &PlaneFrame, outline: &[DVec2], luminaire: &Luminaire) -> Option<[DVec2; 2]> {
    // (p − c) · n over the receiver's plane is f0 + x (u · n) + y (v · n).
    let origin = frame.to_world(DVec2::ZERO);
    let f0 = (origin - luminaire.centre).dot(luminaire.normal);
    let gradient = DVec2::new(frame.u.dot(luminaire.normal), frame.v.dot(luminaire.normal));
    if gradient.length() < 1e-6 {
        return None;
    }
    let foot = -gradient * (f0 / gradient.length_squared());
    let reach = outline.iter().map(|p| p.distance(foot)).fold(0.0, f64::max);
    let along = gradient.perp().normalize() * (2.0 * reach + 1.0);
    clip_segment_to_polygon([foot - along, foot + along], outline)
}

/// The corners a luminaire's shadows are cast from: its polygons' vertices,
/// at most [`MAX_CORNERS_PER_POLYGON`] of each, evenly spread.
fn luminaire_corners(scene: &Scene, luminaire: &Luminaire) -> Vec<DVec3> {
    let mut corners: Vec<DVec3> = Vec::new();
    for &surface in &luminaire.surfaces {
        let vertices = scene.surface(surface).vertices();
        let n = vertices.len();
        let take = n.min(MAX_CORNERS_PER_POLYGON);
        for k in 0..take {
            let v = vertices[k * n / take];
            if !corners
                .iter()
                .any(|c| c.distance(v) <= 1e-9 * luminaire.radius)
            {
                corners.push(v);
            }
        }
    }
    corners
}

/// Whether any corner's shadow of the occluder's polygon can reach the
/// receiver: the bounding box of the polygon's projections (from every
/// corner, of the points below it) overlaps the outline's.
fn in_shaft(
    frame: &PlaneFrame,
    outline: &[DVec2],
    corners: &[DVec3],
    polygon: &[DVec3],
    tolerance: f64,
) -> bool {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for &p in outline {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    for &v in corners {
        let hv = frame.height(v);
        let (mut a, mut b) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for &p in polygon {
            let hp = frame.height(p).max(0.0);
            if hp >= MAX_HEIGHT_FRACTION * hv {
                // A point level with the corner throws its shadow anywhere.
                return true;
            }
            let q = frame.to_plane(v + (p - v) * (hv / (hv - hp)));
            a = a.min(q);
            b = b.max(q);
        }
        let margin = DVec2::splat(tolerance);
        if a.cmple(hi + margin).all() && b.cmpge(lo - margin).all() {
            return true;
        }
    }
    false
}

/// The parameters t ∈ [lo, hi] of the part of edge ab that casts a shadow
/// from corner v on the receiver's plane: in front of the receiver, below
/// v and in front of the source's `plane` (centre, normal) if it has one.
/// `None` when no part is.
fn edge_range(
    frame: &PlaneFrame,
    plane: Option<(DVec3, DVec3)>,
    v: DVec3,
    [a, b]: [DVec3; 2],
) -> Option<(f64, f64)> {
    let hv = frame.height(v);
    // Keep t ∈ [lo, hi] where each of the linear functions f(t) ≥ 0.
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let mut keep = |fa: f64, fb: f64| {
        if fa < 0.0 && fb < 0.0 {
            hi = -1.0;
        } else if fa < 0.0 {
            lo = lo.max(fa / (fa - fb));
        } else if fb < 0.0 {
            hi = hi.min(fa / (fa - fb));
        }
    };
    let (ha, hb) = (frame.height(a), frame.height(b));
    keep(ha, hb);
    keep(MAX_HEIGHT_FRACTION * hv - ha, MAX_HEIGHT_FRACTION * hv - hb);
    if let Some((centre, normal)) = plane {
        keep((a - centre).dot(normal), (b - centre).dot(normal));
    }
    (hi > lo).then_some((lo, hi))
}

/// The central projection from v of point p onto the receiver's plane:
/// v + (p − v) h_v / (h_v − h_p), in plane coordinates.
fn project(frame: &PlaneFrame, v: DVec3, p: DVec3) -> DVec2 {
    let (hv, hp) = (frame.height(v), frame.height(p).max(0.0));
    frame.to_plane(v + (p - v) * (hv / (hv - hp)))
}

/// The runs of edge ab's parameter range where its shadow from corner v is
/// a real event: at each of [`EVENT_SAMPLES`] + 1 points q of the range,
/// the receiver point it projects to sees q, and q sees v (shadow rays
/// lifted off the receiver and stopped a surface offset short of q and v;
/// `ends` are the receiver, the occluder and the light's surface, which the
/// rays may touch). Each run reaches half a step beyond its outer passing
/// points, where the change lies somewhere between samples.
fn event_runs(
    (scene, visibility): (&Scene, &Visibility),
    (receiver, occluder, lamp): (SurfaceId, SurfaceId, SurfaceId),
    v: DVec3,
    [a, b]: [DVec3; 2],
    (lo, hi): (f64, f64),
) -> Vec<(f64, f64)> {
    let target = scene.surface(receiver);
    let (frame, normal) = (target.frame(), target.normal());
    let offset = visibility.surface_offset();
    let step = (hi - lo) / EVENT_SAMPLES as f64;
    // Neighbouring samples' rays are nearly parallel: one shadow cache for
    // the rays to the receiver, one for those to the light.
    let (mut to_receiver, mut to_light) = (ShadowCache::default(), ShadowCache::default());
    let mut real = |k: usize| {
        let q = a.lerp(b, lo + step * k as f64);
        let x = frame.to_world(project(frame, v, q)) + normal * offset;
        let short = |from: DVec3, to: DVec3| to + (from - to).normalize_or_zero() * offset;
        visibility.is_unblocked_cached(x, short(x, q), [receiver, occluder], &mut to_receiver)
            && visibility.is_unblocked_cached(
                short(v, q),
                short(q, v),
                [occluder, lamp],
                &mut to_light,
            )
    };
    let passing: Vec<bool> = (0..=EVENT_SAMPLES).map(&mut real).collect();
    let mut runs = Vec::new();
    let mut k = 0;
    while k <= EVENT_SAMPLES {
        if !passing[k] {
            k += 1;
            continue;
        }
        let first = k;
        while k < EVENT_SAMPLES && passing[k + 1] {
            k += 1;
        }
        let t0 = (lo + step * (first as f64 - 0.5)).max(lo);
        let t1 = (lo + step * (k as f64 + 0.5)).min(hi);
        runs.push((t0, t1));
        k += 1;
    }
    runs
}

/// Keeps the longest boundaries first, leaving out any that lies within
/// `min_feature` of one already kept along its whole length (its ends and
/// middle), up to `max_per_receiver`. A kept boundary stands for the
/// cluster of those it covers; where that cluster is at least `min_feature`
/// wide across (the offsets of its members' middles from the kept line, on
/// both sides), its two outermost members are kept instead: the edge of the
/// umbra and the outer edge of the penumbra, which one line in between
/// left without vertices. Keeping the outermost two renders the cluttered
/// office of `bench/generate_building.py` at 2.68 % per pixel instead of
/// 2.76 %, the furnished one at 1.51 % instead
/// of 1.53 %, for 1.5 % more vertices; the shipped `scenes/office` (4.42 %
/// against 4.43 %) and the golden scenes render as before. The two count
/// against `max_per_receiver` like any others. It does not mend the
/// penumbra under that office's whiteboard, whose 2 cm ledge casts two
/// dozen boundaries over 4.5 cm of wall: 3 cm below the ledge the mesh
/// still reads 0.77 of a gather.
fn merge_boundaries(mut found: Vec<[DVec2; 2]>, limits: BoundaryLimits) -> Vec<[DVec2; 2]> {
    found.retain(|s| s.iter().all(|p| p.is_finite()));
    found.sort_by(|a, b| b[0].distance(b[1]).total_cmp(&a[0].distance(a[1])));
    let mut clusters: Vec<Cluster> = Vec::new();
    for segment in found {
        if clusters.len() >= limits.max_per_receiver {
            break;
        }
        let middle = segment[0].lerp(segment[1], 0.5);
        let covering = clusters.iter_mut().find(|cluster| {
            let [a, b] = cluster.kept;
            [segment[0], segment[1], middle]
                .iter()
                .all(|&p| distance_to_segment(p, a, b) < limits.min_feature)
        });
        match covering {
            Some(cluster) => cluster.add(segment),
            None => clusters.push(Cluster::new(segment)),
        }
    }
    clusters
        .into_iter()
        .flat_map(|cluster| cluster.kept_lines(limits.min_feature))
        .take(limits.max_per_receiver)
        .collect()
}

/// A kept shadow boundary and the outermost of those it covers on each
/// side: their middles' signed offsets from its line, and the boundaries.
struct Cluster {
    kept: [DVec2; 2],
    low: (f64, [DVec2; 2]),
    high: (f64, [DVec2; 2]),
}

impl Cluster {
    fn new(kept: [DVec2; 2]) -> Cluster {
        Cluster {
            kept,
            low: (0.0, kept),
            high: (0.0, kept),
        }
    }

    fn add(&mut self, segment: [DVec2; 2]) {
        let [a, b] = self.kept;
        let middle = segment[0].lerp(segment[1], 0.5);
        let offset = (b - a).normalize_or_zero().perp_dot(middle - a);
        if offset < self.low.0 {
            self.low = (offset, segment);
        }
        if offset > self.high.0 {
            self.high = (offset, segment);
        }
    }

    /// The kept boundary, or the two outermost when the cluster is at least
    /// `min_feature` wide.
    fn kept_lines(self, min_feature: f64) -> Vec<[DVec2; 2]> {
        if self.high.0 - self.low.0 >= min_feature {
            vec![self.low.1, self.high.1]
        } else {
            vec![self.kept]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lighting::luminaires;
    use crate::scene::{Material, Rgb, SurfaceBoxes};

    /// A 10 × 10 floor at y = 0, a 0.2 m square lamp facing down at
    /// `lamp_height` over the origin, and an occluder given by its polygons.
    fn scene_with(occluder: &[Vec<DVec3>], lamp_height: f64) -> Scene {
        let mut scene = Scene::new();
        let grey = scene
            .add_material(Material::diffuse("grey", Rgb::splat(0.5)))
            .unwrap();
        let lamp = scene
            .add_material(Material::emitter("lamp", Rgb::splat(10.0)))
            .unwrap();
        let floor = [(-5.0, -5.0), (-5.0, 5.0), (5.0, 5.0), (5.0, -5.0)];
        let floor: Vec<DVec3> = floor.iter().map(|&(x, z)| DVec3::new(x, 0.0, z)).collect();
        scene.add_polygon("floor", grey, &floor).unwrap();
        let h = lamp_height;
        let square = [(-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1)];
        let lamp_polygon: Vec<DVec3> = square.iter().map(|&(x, z)| DVec3::new(x, h, z)).collect();
        scene.add_polygon("lamp", lamp, &lamp_polygon).unwrap();
        for polygon in occluder {
            scene.add_polygon("occluder", grey, polygon).unwrap();
        }
        scene
    }

    /// Parallel boundaries 2 m long at heights `ys`, the one at `longest`
    /// a little longer (kept first).
    fn parallel_lines(ys: &[f64], longest: f64) -> Vec<[DVec2; 2]> {
        ys.iter()
            .map(|&y| {
                let end = if y == longest { 2.01 } else { 2.0 };
                [DVec2::new(0.0, y), DVec2::new(end, y)]
            })
            .collect()
    }

    #[test]
    fn a_cluster_wider_than_the_feature_size_keeps_its_outermost_boundaries() {
        let limits = BoundaryLimits {
            min_feature: 0.04,
            max_per_receiver: 100,
        };
        let heights = |kept: Vec<[DVec2; 2]>| {
            let mut ys: Vec<f64> = kept.iter().map(|s| s[0].y).collect();
            ys.sort_by(f64::total_cmp);
            ys
        };
        // A ledge's penumbra 4 cm wide: its two edges, not its middle.
        let wide = parallel_lines(&[0.855, 0.865, 0.875, 0.885, 0.895], 0.875);
        assert_eq!(heights(merge_boundaries(wide, limits)), [0.855, 0.895]);
        // Narrower than the feature size: one line.
        let narrow = parallel_lines(&[0.865, 0.875, 0.885], 0.875);
        assert_eq!(heights(merge_boundaries(narrow, limits)), [0.875]);
    }

    fn limits() -> BoundaryLimits {
        BoundaryLimits {
            min_feature: 1e-3,
            max_per_receiver: 1000,
        }
    }

    fn boundaries_on_floor(scene: &Scene) -> Vec<[DVec2; 2]> {
        let neighbours = EdgeNeighbours::new(scene);
        let lights = luminaires(scene);
        let boxes = SurfaceBoxes::new(scene);
        let occluders = |low, high| boxes.near(low, high, 0.0);
        shadow_boundaries(
            (scene, &Visibility::new(scene)),
            &neighbours,
            (SurfaceId::new(0), &occluders),
            &lights,
            &[],
            limits(),
        )
    }

    /// A horizontal plate, 1 m wide, at height 1, facing up (or down).
    fn plate(up: bool) -> Vec<DVec3> {
        let mut p = vec![
            DVec3::new(0.5, 1.0, -0.5),
            DVec3::new(-0.5, 1.0, -0.5),
            DVec3::new(-0.5, 1.0, 0.5),
            DVec3::new(0.5, 1.0, 0.5),
        ];
        if !up {
            p.reverse();
        }
        p
    }

    #[test]
    fn a_plate_casts_each_edge_from_each_lamp_corner_at_its_central_projection() {
        // Lamp at 2 m, plate at 1 m: from corner (cx, cz), the plate's edge
        // x = 0.5 falls at x = cx + (0.5 − cx) · 2 / (2 − 1).
        for up in [true, false] {
            let scene = scene_with(&[plate(up)], 2.0);
            let frame = *scene.surface(SurfaceId::new(0)).frame();
            let found = boundaries_on_floor(&scene);
            // 4 corners × 4 edges, none closer than a millimetre to another.
            assert_eq!(found.len(), 16, "{found:?}");
            for cx in [-0.1, 0.1] {
                for cz in [-0.1, 0.1] {
                    for (edge_x, edge_z) in [(0.5, cz), (-0.5, cz), (cx, 0.5), (cx, -0.5)] {
                        let x = cx + (edge_x - cx) * 2.0;
                        let z = cz + (edge_z - cz) * 2.0;
                        let expected = frame.to_plane(DVec3::new(x, 0.0, z));
                        let hit = found
                            .iter()
                            .any(|&[a, b]| distance_to_segment(expected, a, b) < 1e-9);
                        assert!(hit, "no boundary through {expected} (corner {cx}, {cz})");
                    }
                }
            }
        }
    }

    /// A square plate of half-size `r` centred over (x, z) at height `h`,
    /// facing up.
    fn plate_at(r: f64, (x, h, z): (f64, f64, f64)) -> Vec<DVec3> {
        [(r, -r), (-r, -r), (-r, r), (r, r)]
            .iter()
            .map(|&(dx, dz)| DVec3::new(x + dx, h, z + dz))
            .collect()
    }

    #[test]
    fn a_plate_in_another_plates_umbra_casts_no_boundary() {
        // Lamp at 3 m (corners at ±0.1), a 2 m plate at 2 m whose umbra on
        // the floor reaches |x| < 2.6, and a 0.5 m plate at 1 m whose shadow
        // (within 0.6 of the centre) falls wholly inside it: every shadow
        // ray from the small plate's shadow to its edges, or from them to
        // the lamp, is blocked by the big plate, so only the big plate's 16
        // (4 edges from 4 lamp corners) remain. (The small plate is off
        // centre: a ray through the big plate's diagonal, the seam of its
        // two triangles, may slip through in f32.)
        let big = plate_at(1.0, (0.0, 2.0, 0.0));
        let scene = scene_with(&[big, plate_at(0.25, (0.1, 1.0, 0.05))], 3.0);
        let found = boundaries_on_floor(&scene);
        assert_eq!(found.len(), 16, "{found:?}");
        for [a, b] in found {
            for p in [a, b] {
                assert!(p.x.abs().max(p.y.abs()) > 2.5, "{p}");
            }
        }
    }

    #[test]
    fn a_box_casts_only_its_silhouette_edges() {
        // A closed 1 m cube from 0.5 to 1.5 m high: seen from a lamp corner
        // above it, only the top face's outline and the vertical edges on the
        // far side are silhouettes; the bottom face's edges are hidden behind
        // the sides, so fewer boundaries than edges × corners.
        let (lo, hi) = (DVec3::new(-0.5, 0.5, -0.5), DVec3::new(0.5, 1.5, 0.5));
        let corner = |x: bool, y: bool, z: bool| {
            DVec3::new(
                if x { hi.x } else { lo.x },
                if y { hi.y } else { lo.y },
                if z { hi.z } else { lo.z },
            )
        };
        let faces: Vec<Vec<DVec3>> = [
            [(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)], // top, +y
            [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)], // bottom, −y
            [(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)], // −z
            [(1, 0, 1), (1, 1, 1), (0, 1, 1), (0, 0, 1)], // +z
            [(0, 0, 1), (0, 1, 1), (0, 1, 0), (0, 0, 0)], // −x
            [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)], // +x
        ]
        .iter()
        .map(|face| {
            face.iter()
                .map(|&(x, y, z)| corner(x == 1, y == 1, z == 1))
                .collect()
        })
        .collect();
        let scene = scene_with(&faces, 3.0);
        let found = boundaries_on_floor(&scene);
        // From above the top face (the lamp is within the cube's footprint),
        // the silhouette is the top face's outline: 4 edges per corner.
        assert_eq!(found.len(), 16, "{found:?}");
        // Each lies outside the cube's footprint, none is the bottom's
        // outline (the shadow is wider than the cube).
        for [a, b] in found {
            for p in [a, b] {
                assert!(p.x.abs().max(p.y.abs()) > 0.5 + 1e-6, "{p}");
            }
        }
    }

    #[test]
    fn nothing_above_the_lamp_or_behind_the_floor_casts_a_boundary() {
        // A plate above the lamp (lamp at 0.5 m), and one under the floor.
        let below: Vec<DVec3> = plate(true)
            .iter()
            .map(|p| DVec3::new(p.x, -1.0, p.z))
            .collect();
        let scene = scene_with(&[plate(true), below], 0.5);
        assert!(boundaries_on_floor(&scene).is_empty());
    }
}
