//! The closed zone of every surface, found by rays from each surface's
//! front and joined by union–find (see the zones' module documentation).

use glam::DVec3;
use rayon::prelude::*;

use crate::lighting::{SampleStream, cosine_direction, stratified_points};
use crate::scene::{Scene, SurfaceId, Visibility};

/// Rays each surface casts to find what it sees: 16 stratified points, 4
/// cosine-weighted directions from each.
const RAYS_PER_SURFACE: usize = 64;

/// Points per surface the rays leave from.
const POINTS: usize = 16;

/// Rays of a group that must leave the scene for it to be open, at the
/// least: fewer slipped through a seam between a closed room's faces (a
/// ray that meets an edge shared by two triangles may hit neither).
const MIN_ESCAPES: usize = 4;

/// The share of a group's rays that must leave the scene for it to be
/// open, when that is more than [`MIN_ESCAPES`]. Seams leak a number of
/// rays that grows with the room's faces, a small fraction of a percent of
/// them, where an opening leaks a share in proportion to what it subtends
/// (a Cornell box's open front, a quarter): a count alone would join a
/// large closed room whose seams leak a few rays to the open zone.
const MIN_ESCAPE_SHARE: f64 = 1.0 / 256.0;

/// Where one of a surface's zone rays ended.
#[derive(Clone, Copy, Debug)]
enum Hit {
    /// On the front of this surface: the two exchange light.
    Front(SurfaceId),
    /// On the back of a surface, which is black.
    Back,
    /// Nowhere: it left the scene.
    Escaped,
}

/// The closed zone of every surface, without the zones' BVHs: what meshing
/// needs to pair each receiver only with the luminaires and occluders of
/// its own room.
#[derive(Clone, Debug)]
pub struct ZoneLabels {
    /// Zone index per surface.
    zone: Vec<u32>,
    /// How many zones there are (open ones counted as one).
    count: usize,
    /// Per zone, whether all the light its surfaces send lands on them
    /// (see [`ZoneLabels::is_lossless`]).
    lossless: Vec<bool>,
}

impl ZoneLabels {
    /// Finds the zones of `scene` by casting [`RAYS_PER_SURFACE`] rays from
    /// every surface, in parallel (see the module's documentation).
    #[must_use]
    pub fn new(scene: &Scene, visibility: &Visibility) -> ZoneLabels {
        let surfaces = scene.surfaces.len();
        // What each surface's rays hit.
        let hits = zone_rays(scene, visibility);
        // Join what sees what: a ray that lands on a surface's front joins
        // the two surfaces. A back is black: light does not pass it, and a
        // ray that slips through the seam where two faces of a room meet
        // lands on the back of the next room's wall, which must not join
        // the rooms.
        let mut parents: Vec<usize> = (0..=surfaces).collect();
        for (k, surface_hits) in hits.iter().enumerate() {
            for hit in surface_hits {
                if let Hit::Front(other) = hit {
                    union(&mut parents, k, other.index());
                }
            }
        }
        // How many of each group's rays escaped or landed on backs.
        let tally = RayTally::new(&hits, &mut parents);
        // Before the open groups are joined: a closed group whose rays
        // land on backs (a one-sided plate seen from behind) loses light
        // there, as an open one loses it to the sky.
        let sees_backs: Vec<bool> = (0..surfaces)
            .map(|k| {
                let root = find(&mut parents, k);
                tally.many(tally.backs[root], root)
            })
            .collect();
        // A group whose rays leave the scene joins the open zone (index
        // `surfaces`), unless fewer than MIN_ESCAPES, or than the share
        // MIN_ESCAPE_SHARE of its rays, do: those slipped through seams of
        // a closed room's walls.
        for k in 0..surfaces {
            let root = find(&mut parents, k);
            if tally.many(tally.escapes[root], root) {
                union(&mut parents, k, surfaces);
            }
        }
        // The groups numbered, and the lossless ones marked.
        ZoneLabels::numbered(&mut parents, &sees_backs)
    }

    /// The zones of the union–find `parents` (the open zone's root at the
    /// last index) numbered in the order of their first surface, each
    /// lossless unless it is the open one or one of its surfaces
    /// `sees_backs`.
    fn numbered(parents: &mut [usize], sees_backs: &[bool]) -> ZoneLabels {
        let surfaces = sees_backs.len();
        let mut index = vec![u32::MAX; surfaces + 1];
        let mut count = 0;
        let zone: Vec<u32> = (0..surfaces)
            .map(|k| {
                let root = find(parents, k);
                if index[root] == u32::MAX {
                    index[root] = count;
                    count += 1;
                }
                index[root]
            })
            .collect();
        let open_root = find(parents, surfaces);
        let open = index[open_root];
        let mut lossless = vec![true; count as usize];
        for (k, &z) in zone.iter().enumerate() {
            if z == open || sees_backs[k] {
                lossless[z as usize] = false;
            }
        }
        ZoneLabels {
            zone,
            count: count as usize,
            lossless,
        }
    }

    /// How many zones there are (open ones counted as one).
    #[must_use]
    pub fn count(&self) -> usize {
        self.count
    }

    /// Whether zone `zone` is closed and its surfaces' fronts see only
    /// fronts: all the light its surfaces send lands on its surfaces (none
    /// leaves the scene or falls on the black back of a one-sided
    /// surface), so each shot's power lands whole.
    #[must_use]
    pub fn is_lossless(&self, zone: usize) -> bool {
        self.lossless.get(zone).copied().unwrap_or(false)
    }

    /// Whether surfaces `a` and `b` are in the same zone, and so may
    /// exchange light.
    #[must_use]
    pub fn together(&self, a: SurfaceId, b: SurfaceId) -> bool {
        self.zone.get(a.index()) == self.zone.get(b.index())
    }

    /// The surfaces of each zone, by zone index.
    #[must_use]
    pub fn members(&self) -> Vec<Vec<SurfaceId>> {
        let mut members = vec![Vec::new(); self.count];
        for (k, &z) in self.zone.iter().enumerate() {
            members[z as usize].push(SurfaceId::new(k));
        }
        members
    }

    /// The zone of `surface`.
    #[must_use]
    pub fn of(&self, surface: SurfaceId) -> usize {
        self.zone.get(surface.index()).map_or(0, |&z| z as usize)
    }

    /// The closed zone a point of space stands in (a camera, a
    /// luminaire, a work plane's point): the zone that keeps all its light
    /// ([`ZoneLabels::is_lossless`]) on whose surfaces every one of
    /// [`ENCLOSURE_RAYS`] rays from `point`, spread over the sphere,
    /// lands, at least one on a front. A ray may land on the back of one
    /// of the zone's surfaces (a cable tray seen from below, the far side
    /// of a shelf's board that ends where the ray grazes it): backs are
    /// black, so no light comes that way, and the point still sees the
    /// zone alone. None where any ray leaves the scene or lands on another
    /// zone, or every ray on a back (the point lies inside an object, or
    /// outside the building).
    #[must_use]
    pub fn enclosing(&self, scene: &Scene, visibility: &Visibility, point: DVec3) -> Option<usize> {
        let reach = 2.0 * visibility.diagonal();
        let mut zone = None;
        let mut fronts = 0;
        for k in 0..ENCLOSURE_RAYS {
            let direction = sphere_direction(k, ENCLOSURE_RAYS);
            let (surface, _) = visibility.closest_hit(point, direction, reach, SurfaceId::NONE)?;
            let hit = self.of(surface);
            if !self.is_lossless(hit) || zone.is_some_and(|z| z != hit) {
                return None;
            }
            zone = Some(hit);
            fronts += usize::from(scene.surface(surface).normal().dot(direction) < 0.0);
        }
        zone.filter(|_| fronts > 0)
    }
}

/// Rays a point casts to find the closed zone it stands in.
const ENCLOSURE_RAYS: usize = 64;

/// Direction `k` of `count` spread evenly over the unit sphere (a
/// Fibonacci spiral), turned by half a step about its axis so that none
/// lies in a plane of the axes: a work plane at the height of a desk's
/// top would otherwise send one ray along the top, through the desk's
/// near edge and onto the back of its far one.
fn sphere_direction(k: usize, count: usize) -> DVec3 {
    let z = 1.0 - (2.0 * k as f64 + 1.0) / count as f64;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = (k as f64 + 0.5) * std::f64::consts::PI * (3.0 - 5f64.sqrt());
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// What each surface's rays hit, by surface index: a surface's front, a
/// surface's back, or nothing (the ray left the scene). Each surface casts
/// [`RAYS_PER_SURFACE`] cosine-weighted rays from [`POINTS`] stratified
/// points of its front, in parallel.
fn zone_rays(scene: &Scene, visibility: &Visibility) -> Vec<Vec<Hit>> {
    let reach = 2.0 * scene.diagonal();
    scene
        .surfaces_with_ids()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&(id, surface)| {
            let frame = surface.frame();
            let normal = surface.normal();
            let mut random = SampleStream::new(u64::from(id), 0x20_4E5);
            let points = stratified_points(&surface.plane_vertices(), POINTS, 0.01, &mut random);
            let mut hits = Vec::with_capacity(RAYS_PER_SURFACE);
            for (point, _) in points {
                let origin = frame.to_world(point) + normal * visibility.surface_offset();
                for _ in 0..RAYS_PER_SURFACE / POINTS {
                    let direction = cosine_direction(normal, &mut random);
                    let hit = match visibility.closest_hit(origin, direction, reach, id) {
                        None => Hit::Escaped,
                        Some((other, _)) if scene.surface(other).normal().dot(direction) < 0.0 => {
                            Hit::Front(other)
                        }
                        Some(_) => Hit::Back,
                    };
                    hits.push(hit);
                }
            }
            hits
        })
        .collect()
}

/// Per union–find root, how many of its group's rays were cast, left the
/// scene, and landed on backs.
struct RayTally {
    rays: Vec<usize>,
    escapes: Vec<usize>,
    backs: Vec<usize>,
}

impl RayTally {
    /// Counts `hits` by the root of each surface's group in `parents`.
    fn new(hits: &[Vec<Hit>], parents: &mut [usize]) -> RayTally {
        let roots = parents.len();
        let mut tally = RayTally {
            rays: vec![0; roots],
            escapes: vec![0; roots],
            backs: vec![0; roots],
        };
        for (k, surface_hits) in hits.iter().enumerate() {
            let root = find(parents, k);
            tally.rays[root] += surface_hits.len();
            for hit in surface_hits {
                if matches!(hit, Hit::Escaped) {
                    tally.escapes[root] += 1;
                }
            }
            // A point whose rays all end on backs lies inside an object
            // standing on its surface (the board under a book), where no
            // light is: its backs lose nothing.
            for from_point in surface_hits.chunks(RAYS_PER_SURFACE / POINTS) {
                let on_backs = from_point.iter().filter(|h| matches!(h, Hit::Back)).count();
                if on_backs < from_point.len() {
                    tally.backs[root] += on_backs;
                }
            }
        }
        tally
    }

    /// Whether `count` of group `root`'s rays are many: at least
    /// [`MIN_ESCAPES`] and at least the share [`MIN_ESCAPE_SHARE`] of them.
    fn many(&self, count: usize, root: usize) -> bool {
        count >= MIN_ESCAPES && count as f64 >= MIN_ESCAPE_SHARE * self.rays[root] as f64
    }
}

fn find(parents: &mut [usize], mut k: usize) -> usize {
    while parents[k] != k {
        parents[k] = parents[parents[k]];
        k = parents[k];
    }
    k
}

fn union(parents: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parents, a), find(parents, b));
    if ra != rb {
        // The open zone (the largest index) stays a root.
        let (low, high) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parents[low] = high;
    }
}
