//! Shaft culling of a shot: the receiving patches that see all of the
//! shooter, whose vertices need no shadow rays, and the few triangles that
//! alone can block the rays of the others.
//!
//! Before a shot, the solver asks, for each patch of the receiving zone,
//! whether any triangle reaches into the shaft between the shooter's cell
//! and the box of the patch's receiving points (Haines & Wallace 1991;
//! `Visibility::shaft_occluders`). Where none does, every shadow ray from
//! those points to the shooter is unblocked, and the shot is gathered at
//! them with no rays: a reflected shot with the same samples and factors,
//! a uniform shooter (an emitter) with Lambert's exact factor, which its
//! samples only estimate (`Shooter::gather`). A vertex on the border of two
//! patches is clear when either patch is, since its receiving point lies
//! in both boxes.
//!
//! A shaft costs about what fifteen rays cost, so only patches whose
//! vertices would cast at least [`MIN_RAYS`] rays are tested, and the
//! elements of a blocked patch (one by one) only when each would cast
//! [`ELEMENT_RAYS`]: an emitter's shot, whose vertices cast 64 each.
//!
//! A shaft that is not clear often holds only a few triangles: a desk's
//! top between a lamp and the floor under it, a chair's seat. On an
//! emitter's shot, the patch's traversal lists its triangles (up to
//! [`PATCH_OCCLUDERS`]), each element's shaft, which lies within the
//! patch's, picks its own from them (up to [`MOST_OCCLUDERS`]), and the
//! rays of the element's vertices test those alone instead of traversing
//! the BVH: each ray lies in the shaft, so nothing else can block it (the
//! candidate lists of Haines & Wallace). The answers are the BVH's but for
//! a triangle met within the surface offset of a ray's start, which the
//! lists leave out and the BVH's f32 boxes mostly do
//! (`Visibility::is_unblocked_among`). Lists are made only where the
//! shafts keep the whole shooter; a vertex takes the shortest of its
//! elements'. Longer element lists lose more to the traversal than they
//! save, and a patch's list used for its elements' rays, in place of
//! theirs, gains nothing.
//!
//! The irradiance is the rays' own but for one thing: a reflected shot's
//! shafts leave out a rim of the shooter as wide as its surface's
//! receivers' inset (a ten-thousandth of its room's diagonal,
//! `mesh/assembly/surfaces.rs`), so that a wall meeting a ceiling patch at its edge
//! does not touch every shaft of it. A ray aimed into that rim and grazing
//! something there is then taken as unblocked.
//! Emitters' shafts keep the whole cell: their shadow boundaries are
//! meshed, and a vertex on one sees an occluder's edge line up with the
//! emitter's.
//!
//! # References
//! E. A. Haines, J. R. Wallace, "Shaft Culling for Efficient Ray-Traced
//! Radiosity", Eurographics Workshop on Rendering, 1991.

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::Mesh;
use crate::scene::{Box3, Scene, SurfaceId, Visibility};
use crate::solver::shot::shooter::Shooter;

/// A patch is tested only when its vertices would cast at least this many
/// shadow rays to the shooter in all (vertices times samples per vertex).
const MIN_RAYS: usize = 64;

/// A blocked patch's elements are tested one by one only when each would
/// cast at least this many rays: an element stands for about one vertex
/// (its four corners are each shared with three more), so this is the
/// samples per vertex.
const ELEMENT_RAYS: usize = 64;

/// What each vertex's shaft to one shot's shooter holds: nothing (the
/// vertex sees all of the shooter), a few triangles (its rays need test
/// only those), or unknown. Only the vertices given a verdict are reset
/// before the next shot, so that a shot in one room of a building touches
/// that room's vertices alone.
#[derive(Clone, Debug, Default)]
pub(crate) struct ReceiverShafts {
    /// Per vertex: [`UNKNOWN`], [`CLEAR`], or 1 + the index of its list
    /// in `lists`.
    verdicts: Vec<u32>,
    /// The vertices given a verdict.
    set: Vec<u32>,
    /// Each list's start and length in `occluders`.
    lists: Vec<(u32, u32)>,
    /// The lists' triangles (indices into the shot's `Visibility`).
    occluders: Vec<u32>,
}

/// A vertex whose shaft was not tested, or held too much.
const UNKNOWN: u32 = 0;

/// A vertex whose shaft holds nothing.
const CLEAR: u32 = u32::MAX;

impl ReceiverShafts {
    /// Forgets every verdict, for a mesh of `vertices` vertices.
    pub(crate) fn reset(&mut self, vertices: usize) {
        for &v in &self.set {
            if let Some(verdict) = self.verdicts.get_mut(v as usize) {
                *verdict = UNKNOWN;
            }
        }
        self.set.clear();
        self.lists.clear();
        self.occluders.clear();
        self.verdicts.resize(vertices, UNKNOWN);
    }

    /// Marks vertex `v` clear (a vertex beyond the mesh is ignored).
    fn mark(&mut self, v: u32) {
        if let Some(verdict) = self.verdicts.get_mut(v as usize) {
            if *verdict == UNKNOWN {
                self.set.push(v);
            }
            *verdict = CLEAR;
        }
    }

    /// Gives vertex `v` list `list` unless it is clear or has a shorter
    /// list already.
    fn offer(&mut self, v: u32, list: u32) {
        let length = |verdict: u32| self.lists[verdict as usize - 1].1;
        let Some(&verdict) = self.verdicts.get(v as usize) else {
            return;
        };
        if verdict == CLEAR || (verdict != UNKNOWN && length(verdict) <= length(list + 1)) {
            return;
        }
        if verdict == UNKNOWN {
            self.set.push(v);
        }
        self.verdicts[v as usize] = list + 1;
    }

    /// Takes one patch's verdicts: its clear vertices, and its lists
    /// offered to theirs.
    fn take(&mut self, found: &PatchShafts) {
        for &v in &found.clear {
            self.mark(v);
        }
        // A shot's lists are its zone's elements' at most, eight
        // triangles each: far under 2³² − 2 (`CLEAR` and `UNKNOWN`).
        debug_assert!(self.occluders.len() + found.occluders.len() < CLEAR as usize);
        debug_assert!(self.lists.len() + found.lists.len() < (CLEAR - 1) as usize);
        let base = self.occluders.len() as u32;
        self.occluders.extend_from_slice(&found.occluders);
        for &((first, count), (start, length)) in &found.lists {
            let list = self.lists.len() as u32;
            self.lists.push((base + start, length));
            for &v in &found.listed[first as usize..(first + count) as usize] {
                self.offer(v, list);
            }
        }
    }

    /// Whether vertex `v` sees all of the shooter.
    #[must_use]
    pub(crate) fn is_clear(&self, v: usize) -> bool {
        self.verdicts.get(v) == Some(&CLEAR)
    }

    /// The only triangles that can block vertex `v`'s rays to the shooter,
    /// when its shaft held few (empty when it is clear).
    #[must_use]
    pub(crate) fn occluders_of(&self, v: usize) -> Option<&[u32]> {
        match self.verdicts.get(v).copied().unwrap_or(UNKNOWN) {
            UNKNOWN => None,
            CLEAR => Some(&[]),
            list => {
                let (start, length) = self.lists[list as usize - 1];
                Some(&self.occluders[start as usize..(start + length) as usize])
            }
        }
    }
}

/// The most triangles a shaft's list holds: beyond, its rays traverse the
/// BVH. Eight triangle tests cost about what a traversal does.
const MOST_OCCLUDERS: usize = 8;

/// The most triangles a patch's shaft to an emitter lists for its
/// elements' shafts to pick theirs from; beyond, each element's shaft
/// traverses the BVH. Shorter or longer lists solve a building of
/// furnished offices more slowly, with the same image.
const PATCH_OCCLUDERS: usize = 128;

/// What one receiving patch's shafts found: the vertices clear, and the
/// lists of the others (each its vertices and triangles).
#[derive(Default)]
struct PatchShafts {
    tested: usize,
    cleared: usize,
    clear: Vec<u32>,
    /// Per list: its vertices' range in `listed` and its triangles' range
    /// in `occluders`.
    lists: Vec<((u32, u32), (u32, u32))>,
    listed: Vec<u32>,
    occluders: Vec<u32>,
}

impl PatchShafts {
    /// Records a shaft's verdict for `vertices`: clear when `occluders`
    /// past `start` is empty, their list otherwise.
    fn record(&mut self, vertices: &[u32], start: usize) {
        if self.occluders.len() == start {
            self.cleared += 1;
            self.clear.extend_from_slice(vertices);
        } else {
            let first = self.listed.len() as u32;
            self.listed.extend_from_slice(vertices);
            self.lists.push((
                (first, vertices.len() as u32),
                (start as u32, (self.occluders.len() - start) as u32),
            ));
        }
    }
}

/// The box of each patch's receiving points, kept while the mesh keeps its
/// vertices and elements.
#[derive(Clone, Debug, Default)]
pub(crate) struct ReceivingBoxes {
    /// Per patch: the box round its elements' vertices' receiving points,
    /// and how many vertices it has.
    boxes: Vec<(DVec3, DVec3, usize)>,
    /// The mesh's vertex and element counts the boxes were made for.
    made_for: (usize, usize),
}

impl ReceivingBoxes {
    /// Makes the boxes again if the mesh has changed.
    pub(crate) fn refresh(&mut self, mesh: &Mesh) {
        let size = (mesh.vertices.len(), mesh.elements.len());
        if self.made_for == size && self.boxes.len() == mesh.patches.len() {
            return;
        }
        self.boxes = mesh
            .patches
            .par_iter()
            .map(|patch| {
                let mut min = DVec3::INFINITY;
                let mut max = DVec3::NEG_INFINITY;
                let mut count: usize = 0;
                for &e in &patch.elements {
                    for &v in mesh.elements[e as usize].corners() {
                        let p = mesh.vertices[v as usize].receiver_position();
                        min = min.min(p);
                        max = max.max(p);
                        count += 1;
                    }
                }
                // Corners are counted once per element: about four times
                // a quad grid's vertices.
                (min, max, count.div_ceil(4))
            })
            .collect();
        self.made_for = size;
    }

    /// Finds, for the vertices of the `patches` (all when `None`), what
    /// their shafts to the query's shooter hold, into `shafts` (reset for
    /// the mesh's vertices), counting every triangle of the query's
    /// `visibility` but the shooter's and the patch's own surfaces'. Each
    /// patch's shaft to its receiving points is tested for being clear;
    /// where it is not but its elements would each cast [`ELEMENT_RAYS`]
    /// rays or more (an emitter's shot), each element's shaft is, picking
    /// its triangles from the patch's list when that held at most
    /// [`PATCH_OCCLUDERS`], and is listed when it holds at most
    /// [`MOST_OCCLUDERS`] and the rim is zero. A vertex takes the shortest
    /// verdict of its patch's and elements' shafts. A rim of the shooter
    /// `rim` wide is left out of the shafts (see [`ShaftTest::new`]).
    /// Returns how many shafts were tested and how many of them were clear.
    pub(crate) fn find_occluders(
        &self,
        query: &ShaftQuery<'_>,
        patches: Option<&[u32]>,
        shafts: &mut ReceiverShafts,
    ) -> (usize, usize) {
        let mesh = query.mesh;
        shafts.reset(mesh.vertices.len());
        let test = ShaftTest::new(query, &self.boxes);
        let indices: Vec<usize> = match patches {
            Some(patches) => patches.iter().map(|&p| p as usize).collect(),
            None => (0..mesh.patches.len()).collect(),
        };
        let results: Vec<PatchShafts> = indices.into_par_iter().map(|p| test.patch(p)).collect();
        let (mut tested, mut cleared) = (0, 0);
        for found in results {
            tested += found.tested;
            cleared += found.cleared;
            shafts.take(&found);
        }
        (tested, cleared)
    }
}

/// One shot's shafts, as [`ReceivingBoxes::find_occluders`] tests them.
pub(crate) struct ShaftQuery<'a> {
    /// The scene, for the receiving surfaces' normals.
    pub(crate) scene: &'a Scene,
    /// The mesh whose vertices receive.
    pub(crate) mesh: &'a Mesh,
    /// The BVH the shot's rays traverse, whose triangles the shafts hold.
    pub(crate) visibility: &'a Visibility,
    /// The shooting patch.
    pub(crate) shooter: &'a Shooter,
    /// The settings' sample density, which sets how many rays a receiver
    /// casts ([`Shooter::side_at`]).
    pub(crate) density: f64,
    /// How wide a rim of the shooter the shafts leave out.
    pub(crate) rim: f64,
}

/// A shot's shafts, ready to be tested patch by patch.
struct ShaftTest<'a> {
    query: &'a ShaftQuery<'a>,
    /// Per patch: its receiving points' box and vertex count.
    boxes: &'a [(DVec3, DVec3, usize)],
    /// How far the shafts' ends are lifted off their surfaces.
    offset: f64,
    /// The shooter's end of every shaft.
    source: Box3,
    /// The shooter's centre.
    centre: DVec3,
}

impl<'a> ShaftTest<'a> {
    /// The shafts of `query`'s shot to patches with receiving `boxes`.
    ///
    /// Their source is the shooter's box less a rim as wide as its
    /// receivers' inset (or none), so that a wall meeting the shooter at
    /// its edge, which no ray to it crosses, does not touch the shaft. Rays
    /// aimed at that rim are answered by the shaft as if they were inside;
    /// a triangle would have to reach into the rim's sliver of the hull
    /// alone to tell, as an occluder does whose edge lines up with the
    /// shooter's as seen from a vertex on a shadow boundary.
    fn new(query: &'a ShaftQuery<'a>, boxes: &'a [(DVec3, DVec3, usize)]) -> ShaftTest<'a> {
        let (shooter, rim) = (query.shooter, query.rim);
        let mut test = ShaftTest {
            query,
            boxes,
            offset: query.visibility.surface_offset(),
            source: Box3::new(DVec3::ZERO, DVec3::ZERO),
            centre: shooter.cell.centre(),
        };
        let (min, max) = bounds(shooter.cell.polygon().iter().copied());
        let wide = (max - min).cmpgt(DVec3::splat(2.0 * rim));
        let inset = DVec3::select(wide, DVec3::splat(rim), DVec3::ZERO);
        test.source = test.lift(min + inset, max - inset, shooter.normal);
        test
    }

    /// The box from `min` to `max` lifted off a surface of `normal`.
    fn lift(&self, min: DVec3, max: DVec3, normal: DVec3) -> Box3 {
        Box3::new(min + normal * self.offset, max + normal * self.offset)
    }

    /// Appends to `list` the triangles in the shaft to the box from `min`
    /// to `max` of receiving points on `surface`, of `normal`, if there
    /// are at most `most` of them: false when it holds more.
    fn occluders(
        &self,
        min: DVec3,
        max: DVec3,
        surface: SurfaceId,
        normal: DVec3,
        most: usize,
        list: &mut Vec<u32>,
    ) -> bool {
        self.query.visibility.shaft_occluders(
            self.source,
            self.lift(min, max, normal),
            [surface, self.query.shooter.surface],
            most,
            list,
        )
    }

    /// About how many rays `vertices` receiving points round `at` cast.
    fn rays(&self, vertices: usize, at: DVec3) -> usize {
        let side = self
            .query
            .shooter
            .side_at((at - self.centre).length(), self.query.density);
        vertices * side * side
    }

    /// What patch p's shafts hold: its own, and where its elements will be
    /// tested too (an emitter's shot), its elements'.
    fn patch(&self, p: usize) -> PatchShafts {
        let (scene, mesh, shooter) = (self.query.scene, self.query.mesh, self.query.shooter);
        let mut found = PatchShafts::default();
        let patch = &mesh.patches[p];
        let (min, max, vertices) = self.boxes[p];
        let middle = 0.5 * (min + max);
        if patch.surface == shooter.surface
            || !min.cmple(max).all()
            || self.rays(vertices, middle) < MIN_RAYS
        {
            return found;
        }
        let normal = scene.surface(patch.surface).normal();
        // Patches wholly behind the shooter, or with all of it behind
        // them, receive nothing and cast no rays anyway.
        if corners(min, max).all(|q| shooter.normal.dot(q - self.centre) <= 0.0)
            || shooter
                .cell
                .polygon()
                .iter()
                .all(|&q| normal.dot(q - patch.cell.centre()) <= 0.0)
        {
            return found;
        }
        found.tested += 1;
        // Where the elements will be tested too (an emitter's shot), the
        // patch's shaft lists its triangles, up to [`PATCH_OCCLUDERS`],
        // and each element's shaft picks its own among them; otherwise
        // it need only be clear. (Listing the patch's shaft for a
        // reflected shot's rays saved nothing, and its rays aimed into
        // the rim would test a list that left out what reaches only
        // there.)
        let by_elements = self.rays(1, middle) >= ELEMENT_RAYS;
        let mut candidates = Vec::new();
        let listed = self.occluders(
            min,
            max,
            patch.surface,
            normal,
            if by_elements { PATCH_OCCLUDERS } else { 0 },
            &mut candidates,
        );
        if listed && candidates.is_empty() {
            let corners = |&e: &u32| mesh.elements[e as usize].corners().iter().copied();
            found.clear.extend(patch.elements.iter().flat_map(corners));
            found.cleared += 1;
            return found;
        }
        if by_elements {
            let candidates = listed.then_some(&candidates[..]);
            self.elements(p, normal, candidates, &mut found);
        }
        found
    }

    /// The shafts of patch p's elements (its surface's `normal`), each
    /// picking its triangles among the patch's `candidates` when the
    /// patch's shaft listed them, into `found`.
    fn elements(
        &self,
        p: usize,
        normal: DVec3,
        candidates: Option<&[u32]>,
        found: &mut PatchShafts,
    ) {
        let (mesh, rim) = (self.query.mesh, self.query.rim);
        let patch = &mesh.patches[p];
        let patch_box = (self.boxes[p].0, self.boxes[p].1);
        // Lists only where the shafts keep the whole shooter: a ray
        // aimed into the rim could meet what reaches only there.
        let most = if rim == 0.0 { MOST_OCCLUDERS } else { 0 };
        for &e in &patch.elements {
            let element = &mesh.elements[e as usize];
            let points = element
                .corners()
                .iter()
                .map(|&v| mesh.vertices[v as usize].receiver_position());
            let (min, max) = bounds(points);
            // The patch's list holds the element's triangles only if
            // its shaft lies within the patch's.
            debug_assert!(min.cmpge(patch_box.0).all() && max.cmple(patch_box.1).all());
            found.tested += 1;
            let start = found.occluders.len();
            let few = match candidates {
                Some(candidates) => self.query.visibility.shaft_occluders_among(
                    self.source,
                    self.lift(min, max, normal),
                    candidates,
                    most,
                    &mut found.occluders,
                ),
                None => self.occluders(min, max, patch.surface, normal, most, &mut found.occluders),
            };
            if few {
                found.record(element.corners(), start);
            }
        }
    }
}

/// The box round `points`.
fn bounds(points: impl IntoIterator<Item = DVec3>) -> (DVec3, DVec3) {
    points
        .into_iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(min, max), p| {
            (min.min(p), max.max(p))
        })
}

/// The eight corners of a box.
fn corners(min: DVec3, max: DVec3) -> impl Iterator<Item = DVec3> {
    (0..8).map(move |k| {
        DVec3::new(
            if k & 1 == 0 { min.x } else { max.x },
            if k & 2 == 0 { min.y } else { max.y },
            if k & 4 == 0 { min.z } else { max.z },
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertex takes the shortest verdict its shafts give: clear beats
    /// any list, a shorter list a longer one whichever came first; a reset
    /// forgets them all, and a vertex beyond the mesh is ignored.
    #[test]
    fn a_vertex_keeps_the_shortest_verdict_of_its_shafts() {
        let mut shafts = ReceiverShafts::default();
        shafts.reset(4);
        shafts.occluders.extend([10, 11, 12, 20]);
        shafts.lists.extend([(0, 3), (3, 1)]);
        shafts.offer(0, 0);
        shafts.offer(0, 1);
        shafts.offer(1, 1);
        shafts.offer(1, 0);
        shafts.offer(2, 0);
        shafts.mark(2);
        shafts.offer(2, 1);
        shafts.offer(9, 0);
        shafts.mark(9);
        assert_eq!(shafts.occluders_of(0), Some(&[20][..]));
        assert_eq!(shafts.occluders_of(1), Some(&[20][..]));
        assert!(shafts.is_clear(2) && shafts.occluders_of(2) == Some(&[][..]));
        assert_eq!(shafts.occluders_of(3), None);
        assert!(!shafts.is_clear(3) && !shafts.is_clear(9));
        shafts.reset(4);
        assert!((0..4).all(|v| shafts.occluders_of(v).is_none()));
        assert!(shafts.lists.is_empty() && shafts.occluders.is_empty() && shafts.set.is_empty());
    }
}
