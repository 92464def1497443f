//! The scene's polygon edges and the surfaces that share each one: which
//! edges are an occluder's silhouette from a light's corner.

use std::hash::{Hash, Hasher};

use glam::DVec3;

use crate::fixed_hash::FixedMap;
use crate::scene::{Scene, SurfaceId};

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
/// every receiver, and SipHash over the 48 bytes is slower.
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
        EdgeNeighbours::of_surfaces(scene, |_| true)
    }

    /// [`EdgeNeighbours::new`] over the surfaces `keep` keeps alone (the
    /// sun's occluders leave glazing out: a window's frame is a silhouette
    /// to it though the pane shares its edges).
    #[must_use]
    pub fn of_surfaces(scene: &Scene, keep: impl Fn(SurfaceId) -> bool) -> EdgeNeighbours {
        let quantum = (1e-6 * scene.diagonal()).max(f64::MIN_POSITIVE);
        let mut neighbours = EdgeNeighbours {
            quantum,
            edges: FixedMap::default(),
        };
        for (id, surface) in scene.surfaces_with_ids().filter(|(id, _)| keep(*id)) {
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
    pub(super) fn across(
        &self,
        surface: SurfaceId,
        a: DVec3,
        b: DVec3,
    ) -> impl Iterator<Item = SurfaceId> {
        self.edges
            .get(&self.key(a, b))
            .into_iter()
            .flatten()
            .copied()
            .filter(move |&other| other != surface)
    }
}
