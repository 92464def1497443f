//! Closed zones: groups of surfaces that exchange light only among
//! themselves, such as the rooms of a building whose doors are shut.
//!
//! A shot from a patch in one closed zone cannot reach a vertex in another:
//! every shadow ray between them is blocked. Casting those rays is all the
//! work a building of separate rooms wastes, since each shot would otherwise
//! gather at every vertex of every room that faces it. The zones are found
//! once, before solving: every surface casts `RAYS_PER_SURFACE` (64)
//! cosine-weighted rays from stratified points of its front, and two
//! surfaces are joined (union–find) when one of their rays lands on the
//! other's front. A ray that lands on a back joins nothing: backs are
//! black, so no light passes that way, and a ray that slipped through the
//! seam where two faces of a room meet lands on the back of the next room's
//! wall, or leaves the scene through the gap between two rooms. A group
//! at least `MIN_ESCAPES` of whose rays, and at least the share
//! `MIN_ESCAPE_SHARE` of them, leave the scene is open (seams leak a
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

mod labels;
mod members;

use glam::DVec3;
use rayon::prelude::*;

use crate::scene::{Scene, SurfaceBoxes, SurfaceId, Visibility};

pub use labels::ZoneLabels;
pub(crate) use members::{ShotPlaces, ZoneMembers};

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
    /// Finds the zones of `scene` by casting `RAYS_PER_SURFACE` rays from
    /// every surface, in parallel.
    #[must_use]
    pub fn new(scene: &Scene, visibility: &Visibility) -> Zones {
        let labels = ZoneLabels::new(scene, visibility);
        let visibility = if labels.count() > 1 {
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
                    (within.len() < scene.surfaces.len())
                        .then(|| Visibility::of_listed_surfaces(scene, &within, bounds))
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
        self.labels.count()
    }

    /// The zone of `surface`.
    #[must_use]
    pub fn of(&self, surface: SurfaceId) -> usize {
        self.labels.of(surface)
    }
}
