//! How one light casts shadow boundaries on a receiver: every occluder's
//! silhouette edges, seen from each of the light's corners, projected onto
//! the receiver's plane where the event is real.

use glam::{DVec2, DVec3};

use super::super::AreaLight;
use super::ShadowReceiver;
use super::edges::EdgeNeighbours;
use crate::scene::{
    PlaneFrame, Scene, ShadowCache, SurfaceId, Visibility, clip_segment_to_polygon,
};

/// Corners of an area light's polygons used as projection centres, at most
/// (a disc's 64-gon is represented by 8 of its vertices, evenly spread).
const MAX_CORNERS_PER_POLYGON: usize = 8;

/// An edge is kept up to this fraction of its projection centre's height: a
/// point level with the corner would project to infinity.
const MAX_HEIGHT_FRACTION: f64 = 0.999;

/// Steps along an edge at which a boundary's event is checked by shadow
/// rays: a boundary is kept where the checks pass, to half a step beyond.
const EVENT_SAMPLES: usize = 8;

/// The part t ∈ [lo, hi] of an edge a + t (b − a) that casts a shadow.
#[derive(Clone, Copy, Debug, PartialEq)]
struct EdgeRange {
    lo: f64,
    hi: f64,
}

/// The surfaces an event's shadow rays may touch at their ends: the
/// receiver, the occluder whose edge it is, and the light's surface.
#[derive(Clone, Copy, Debug)]
struct EventEnds {
    receiver: SurfaceId,
    occluder: SurfaceId,
    lamp: SurfaceId,
}

/// A light that casts shadows: the corners they are cast from, the plane
/// in front of which it emits (none for a point source, which may light
/// every direction), and its own surfaces, which cast nothing.
pub(super) struct Source<'a> {
    pub(super) corners: Vec<DVec3>,
    pub(super) plane: Option<(DVec3, DVec3)>,
    pub(super) surfaces: &'a [SurfaceId],
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
    pub(super) fn cast(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        neighbours: &EdgeNeighbours,
        receiver: ShadowReceiver<'_>,
        tolerance: f64,
        found: &mut Vec<[DVec2; 2]>,
    ) {
        let ShadowReceiver {
            surface: receiver,
            occluders,
        } = receiver;
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
                    let whole = [range.lo, range.hi].map(|t| project(frame, v, a.lerp(b, t)));
                    if clip_segment_to_polygon(whole, &outline).is_none() {
                        continue;
                    }
                    let ends = EventEnds {
                        receiver,
                        occluder: id,
                        lamp,
                    };
                    for run in event_runs(scene, visibility, ends, v, [a, b], range) {
                        let segment = [run.lo, run.hi].map(|t| project(frame, v, a.lerp(b, t)));
                        if let Some(clipped) = clip_segment_to_polygon(segment, &outline) {
                            found.push(clipped);
                        }
                    }
                }
            }
        }
    }
}

/// The area light's horizon on the receiver: the line where the area light's
/// plane cuts the receiver's, clipped to its outline. Direct light falls to
/// zero there with a kink (as cos θ of the emitting side), and nothing
/// reaches beyond it.
pub(super) fn horizon(
    frame: &PlaneFrame,
    outline: &[DVec2],
    area_light: &AreaLight,
) -> Option<[DVec2; 2]> {
    // (p − c) · n over the receiver's plane is f0 + x (u · n) + y (v · n).
    let origin = frame.to_world(DVec2::ZERO);
    let f0 = (origin - area_light.centre).dot(area_light.normal);
    let gradient = DVec2::new(
        frame.u.dot(area_light.normal),
        frame.v.dot(area_light.normal),
    );
    if gradient.length() < 1e-6 {
        return None;
    }
    let foot = -gradient * (f0 / gradient.length_squared());
    let reach = outline.iter().map(|p| p.distance(foot)).fold(0.0, f64::max);
    let along = gradient.perp().normalize() * (2.0 * reach + 1.0);
    clip_segment_to_polygon([foot - along, foot + along], outline)
}

/// The corners an area light's shadows are cast from: its polygons' vertices,
/// at most [`MAX_CORNERS_PER_POLYGON`] of each, evenly spread.
pub(super) fn area_light_corners(scene: &Scene, area_light: &AreaLight) -> Vec<DVec3> {
    let mut corners: Vec<DVec3> = Vec::new();
    for &surface in &area_light.surfaces {
        let vertices = scene.surface(surface).vertices();
        let n = vertices.len();
        let take = n.min(MAX_CORNERS_PER_POLYGON);
        for k in 0..take {
            let v = vertices[k * n / take];
            if !corners
                .iter()
                .any(|c| c.distance(v) <= 1e-9 * area_light.radius)
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
) -> Option<EdgeRange> {
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
    (hi > lo).then_some(EdgeRange { lo, hi })
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
/// `ends` are the surfaces the rays may touch). Each run reaches half a step beyond its outer passing
/// points, where the change lies somewhere between samples.
fn event_runs(
    scene: &Scene,
    visibility: &Visibility,
    ends: EventEnds,
    v: DVec3,
    [a, b]: [DVec3; 2],
    range: EdgeRange,
) -> Vec<EdgeRange> {
    let EventEnds {
        receiver,
        occluder,
        lamp,
    } = ends;
    let EdgeRange { lo, hi } = range;
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
        runs.push(EdgeRange { lo: t0, hi: t1 });
        k += 1;
    }
    runs
}
