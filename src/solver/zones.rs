//! Closed zones: groups of surfaces that exchange light only among
//! themselves, such as the rooms of a building whose doors are shut.
//!
//! A shot from a patch in one closed zone cannot reach a vertex in another:
//! every shadow ray between them is blocked. Casting those rays is all the
//! work a building of separate rooms wastes, since each shot would otherwise
//! gather at every vertex of every room that faces it. The zones are found
//! once, before solving: every surface casts [`RAYS_PER_SURFACE`]
//! cosine-weighted rays from stratified points of its front, and two
//! surfaces are joined (union–find) when one of their rays lands on the
//! other's front. A ray that lands on a back joins nothing: backs are
//! black, so no light passes that way, and a ray that slipped through the
//! seam where two faces of a room meet lands on the back of the next room's
//! wall, or leaves the scene through the gap between two rooms. A group
//! at least [`MIN_ESCAPES`] of whose rays, and at least the share
//! [`MIN_ESCAPE_SHARE`] of them, leave the scene is open (seams leak a
//! few rays, openings a share), and all open groups are one zone: in the
//! open, two small plates that see each other may miss each other with
//! every ray, but neither then counts as closed.
//!
//! Each zone also gets a BVH of the surfaces within its bounds
//! ([`Visibility::of_surfaces`]), which its shots' shadow rays traverse: a
//! segment between two points of a zone's surfaces lies inside the box
//! around them, so only a surface that reaches into that box can block
//! it, and the answer is the same from a tree the size of one room as from
//! the building's. In a floor of 16 rooms the same rays cost about half as
//! much. The zone's own surfaces alone would not do: a closed box whose
//! faces turn inward, standing in the open, is a zone of its own (its
//! outside is black backs), yet it casts a shadow on the open ground.
//!
//! The cull is conservative where the rays are: surfaces that see each
//! other are joined unless every one of the many rays cast from both their
//! groups misses every surface of the other (an opening smaller than the
//! rays can find). A face that sees only backs (a table leg's top, hidden
//! under the table) is a zone of its own and receives nothing, as it
//! should; without the cull it may catch a little light through the seams,
//! which nobody sees. Everything else is exact: a vertex skipped would have
//! received nothing, so a solve with and without the cull gives the same
//! radiosity, bit for bit where no face is hidden so.

use glam::DVec3;
use rayon::prelude::*;

use crate::lighting::{SampleStream, stratified_points};
use crate::mesh::Mesh;
use crate::scene::{Scene, SurfaceBoxes, SurfaceId, Visibility};

/// Rays each surface casts to find what it sees: 16 stratified points, 4
/// cosine-weighted directions from each.
pub const RAYS_PER_SURFACE: usize = 64;

/// Points per surface the rays leave from.
const POINTS: usize = 16;

/// Rays of a group that must leave the scene for it to be open, at the
/// least: fewer slipped through a seam between a closed room's faces (a
/// ray that meets an edge shared by two triangles may hit neither).
const MIN_ESCAPES: usize = 4;

/// The share of a group's rays that must leave the scene for it to be
/// open, when that is more than [`MIN_ESCAPES`]. Seams leak a number of
/// rays that grows with the room's faces: the furnished offices of a
/// generated floor leak 1 to 9 of their 17,664 rays (0.05 % at most), the
/// shipped office 26 of its 245,248 (0.01 %), where an opening leaks a
/// share in proportion to what it subtends (a Cornell box's open front, a
/// quarter). A count alone joined every office that leaked four into the
/// one open zone, and with it their receivers and shots.
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

/// The closed zone of every surface, and each zone's shadow-ray BVH.
pub struct Zones {
    /// The zone of every surface.
    labels: ZoneLabels,
    /// Per zone, a BVH over the surfaces within its bounds, or None where
    /// that is every surface (empty while there is one zone): the scene's
    /// own BVH serves.
    visibility: Vec<Option<Visibility>>,
}

impl Zones {
    /// Finds the zones of `scene` by casting [`RAYS_PER_SURFACE`] rays from
    /// every surface, in parallel.
    #[must_use]
    pub fn new(scene: &Scene, visibility: &Visibility) -> Zones {
        let labels = ZoneLabels::new(scene, visibility);
        let visibility = if labels.count > 1 {
            let bounds = scene.bounds();
            let boxes = SurfaceBoxes::new(scene);
            // Shadow rays end lifted off their surfaces by the offset.
            let margin = 2.0 * visibility.surface_offset();
            labels
                .members()
                .par_iter()
                .map(|members| {
                    let (min, max) = members.iter().map(|&id| boxes.bounds(id)).fold(
                        (DVec3::INFINITY, DVec3::NEG_INFINITY),
                        |(min, max), (a, b)| (min.min(a), max.max(b)),
                    );
                    let within = boxes.near(min, max, margin);
                    (within.len() < scene.surfaces.len()).then(|| {
                        Visibility::of_listed_surfaces(
                            scene,
                            &within,
                            crate::scene::Box3::new(bounds.0, bounds.1),
                        )
                    })
                })
                .collect()
        } else {
            Vec::new()
        };
        Zones { labels, visibility }
    }

    /// The zone of every surface.
    #[must_use]
    pub fn labels(&self) -> &ZoneLabels {
        &self.labels
    }

    /// The shadow-ray BVH of the surfaces within zone `zone`'s bounds, if
    /// there is more than one zone and they are not all of the scene's.
    #[must_use]
    pub fn visibility(&self, zone: usize) -> Option<&Visibility> {
        self.visibility.get(zone)?.as_ref()
    }

    /// How many zones the surfaces fall into.
    #[must_use]
    pub fn count(&self) -> usize {
        self.labels.count
    }

    /// The zone of `surface`.
    #[must_use]
    pub fn of(&self, surface: SurfaceId) -> usize {
        self.labels.of(surface)
    }
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
        let reach = 2.0 * scene.diagonal();
        // What each surface's rays hit: a surface's front, a surface's
        // back, or nothing (the ray left the scene).
        let hits: Vec<Vec<Hit>> = scene
            .surfaces_with_ids()
            .collect::<Vec<_>>()
            .par_iter()
            .map(|&(id, surface)| {
                let frame = surface.frame();
                let normal = surface.normal();
                let mut random = SampleStream::new(u64::from(id), 0x20_4E5);
                let points =
                    stratified_points(&surface.plane_vertices(), POINTS, 0.01, &mut random);
                let mut hits = Vec::with_capacity(RAYS_PER_SURFACE);
                for (point, _) in points {
                    let origin = frame.to_world(point) + normal * visibility.surface_offset();
                    for _ in 0..RAYS_PER_SURFACE / POINTS {
                        let direction = cosine_direction(normal, &mut random);
                        let hit = match visibility.closest_hit(origin, direction, reach, id) {
                            None => Hit::Escaped,
                            Some((other, _))
                                if scene.surface(other).normal().dot(direction) < 0.0 =>
                            {
                                Hit::Front(other)
                            }
                            Some(_) => Hit::Back,
                        };
                        hits.push(hit);
                    }
                }
                hits
            })
            .collect();
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
        // A group whose rays leave the scene joins the open zone (index
        // `surfaces`), unless fewer than MIN_ESCAPES, or than the share
        // MIN_ESCAPE_SHARE of its rays, do: those slipped through seams of
        // a closed room's walls.
        let mut escapes = vec![0usize; surfaces + 1];
        let mut backs = vec![0usize; surfaces + 1];
        let mut rays = vec![0usize; surfaces + 1];
        for (k, surface_hits) in hits.iter().enumerate() {
            let root = find(&mut parents, k);
            rays[root] += surface_hits.len();
            for hit in surface_hits {
                if matches!(hit, Hit::Escaped) {
                    escapes[root] += 1;
                }
            }
            // A point whose rays all end on backs lies inside an object
            // standing on its surface (the board under a book), where no
            // light is: its backs lose nothing.
            for from_point in surface_hits.chunks(RAYS_PER_SURFACE / POINTS) {
                let on_backs = from_point.iter().filter(|h| matches!(h, Hit::Back)).count();
                if on_backs < from_point.len() {
                    backs[root] += on_backs;
                }
            }
        }
        let many = |count: usize, root: usize| {
            count >= MIN_ESCAPES && count as f64 >= MIN_ESCAPE_SHARE * rays[root] as f64
        };
        let open = |root: usize| many(escapes[root], root);
        // Before the open groups are joined: a closed group whose rays
        // land on backs (a one-sided plate seen from behind) loses light
        // there, as an open one loses it to the sky.
        let sees_backs: Vec<bool> = (0..surfaces)
            .map(|k| {
                let root = find(&mut parents, k);
                many(backs[root], root)
            })
            .collect();
        for k in 0..surfaces {
            let root = find(&mut parents, k);
            if open(root) {
                union(&mut parents, k, surfaces);
            }
        }
        let mut index = vec![u32::MAX; surfaces + 1];
        let mut count = 0;
        let zone: Vec<u32> = (0..surfaces)
            .map(|k| {
                let root = find(&mut parents, k);
                if index[root] == u32::MAX {
                    index[root] = count;
                    count += 1;
                }
                index[root]
            })
            .collect();
        let open_root = find(&mut parents, surfaces);
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

/// The vertices, elements and patches of a mesh, zone by zone, so that a
/// shot visits only its own zone's. Rebuilt after [`ZoneMembers::invalidate`]
/// (adaptive refinement renumbers the elements) or when the mesh's counts
/// changed since.
#[derive(Clone, Debug, Default)]
pub struct ZoneMembers {
    /// Vertex indices per zone.
    pub vertices: Vec<Vec<u32>>,
    /// Element indices per zone.
    pub elements: Vec<Vec<u32>>,
    /// Patch indices per zone.
    pub patches: Vec<Vec<u32>>,
    /// Each vertex's place in its zone's list of `vertices`: where a shot
    /// into that zone keeps its value.
    places: Vec<u32>,
    /// The mesh's vertex and element counts when these were listed.
    listed: (usize, usize),
}

impl ZoneMembers {
    /// Marks the lists stale: the mesh changed.
    pub fn invalidate(&mut self) {
        self.vertices.clear();
    }

    /// Lists `mesh`'s members by zone again if they are stale or the mesh
    /// changed size since.
    pub fn refresh(&mut self, zones: &Zones, mesh: &Mesh) {
        let counts = (mesh.vertices.len(), mesh.elements.len());
        if counts == self.listed && !self.vertices.is_empty() {
            return;
        }
        self.vertices = vec![Vec::new(); zones.count().max(1)];
        self.elements = vec![Vec::new(); zones.count().max(1)];
        self.patches = vec![Vec::new(); zones.count().max(1)];
        self.places.clear();
        for (v, vertex) in mesh.vertices.iter().enumerate() {
            let list = &mut self.vertices[zones.of(vertex.surface)];
            self.places.push(list.len() as u32);
            list.push(v as u32);
        }
        for (e, element) in mesh.elements.iter().enumerate() {
            self.elements[zones.of(element.surface)].push(e as u32);
        }
        for (p, patch) in mesh.patches.iter().enumerate() {
            self.patches[zones.of(patch.surface)].push(p as u32);
        }
        self.listed = counts;
    }

    /// Each vertex's place in its zone's list of vertices.
    #[must_use]
    pub fn places(&self) -> &[u32] {
        &self.places
    }
}

/// Where a shot keeps each vertex's value in its buffers: at the vertex's
/// place in its closed zone's list when the shot lights one zone, so that
/// a shot in one room of a building holds that room's vertices alone, else
/// at the vertex's own index.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShotPlaces<'a>(pub(crate) Option<&'a [u32]>);

impl<'a> ShotPlaces<'a> {
    /// The places of a shot into closed zone `zone` (listed in `members`),
    /// or into every vertex.
    pub(crate) fn new(zone: Option<usize>, members: Option<&'a ZoneMembers>) -> ShotPlaces<'a> {
        ShotPlaces(zone.and(members).map(ZoneMembers::places))
    }

    /// Where vertex v's value is kept.
    pub(crate) fn of(self, v: u32) -> usize {
        match self.0 {
            Some(places) => places[v as usize] as usize,
            None => v as usize,
        }
    }
}

/// A cosine-weighted direction about the unit `normal` (Malley's method:
/// a uniform point of the unit disc lifted onto the hemisphere).
pub(super) fn cosine_direction(normal: DVec3, random: &mut SampleStream) -> DVec3 {
    cosine_direction_at(normal, (random.next_f64(), random.next_f64()))
}

/// The cosine-weighted direction about the unit `normal` of the unit
/// square's point (u₁, u₂): radius √u₁ and angle 2π u₂ on the disc, lifted.
/// Strata of the square are strata of the projected solid angle.
pub(super) fn cosine_direction_at(normal: DVec3, (u1, u2): (f64, f64)) -> DVec3 {
    let (radius, angle) = (u1.sqrt(), std::f64::consts::TAU * u2);
    let tangent = normal.any_orthonormal_vector();
    let bitangent = normal.cross(tangent);
    (tangent * (radius * angle.cos())
        + bitangent * (radius * angle.sin())
        + normal * (1.0 - u1).max(0.0).sqrt())
    .normalize()
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
