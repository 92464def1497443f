//! Visibility memory: what each vertex saw of a patch the last time the
//! patch shot, so that its next shot need not cast those rays again.
//!
//! A patch in a furnished room shoots several times over a solve, and many
//! of a solve's rays are cast by patches that have shot before, to vertices
//! whose view of the patch has not changed: the geometry is fixed, only the
//! light the patch sends differs. So each
//! vertex that cast at least [`MIN_EVIDENCE`] rays to a shooter remembers
//! whether all of them were unblocked, or all blocked; at the shooter's
//! next shot it takes all of the shooter as visible, or none, without
//! rays. A vertex whose rays disagreed (a penumbra of that patch) casts
//! them again, and remembers anew. This is the classic reuse of form
//! factors between iterations (Cohen & Wallace 1993, §5.3) kept to its
//! safe part: a pair is only remembered where its rays were unanimous, so
//! an occluder small enough for all of them to miss stays missed in later
//! shots too, where fresh rays would sometimes find it.
//!
//! Memory is one byte per vertex of the shooter's closed zone per
//! remembered shooter, up to [`BUDGET`] in all; shooters beyond it cast
//! their rays as before. The memory is cleared when the mesh changes.
//!
//! # References
//! M. F. Cohen, J. R. Wallace, "Radiosity and Realistic Image Synthesis"
//! (1993), §5.3 (reusing form factors).

use crate::meshing::ShotPlaces;
use crate::solver::shot::shooter::Gathered;

/// Rays a vertex must have cast to one shooter, all agreeing, for its view
/// of the shooter to be remembered.
const MIN_EVIDENCE: u32 = 4;

/// The most bytes all remembered shooters hold.
const BUDGET: usize = 64 << 20;

/// What a vertex saw of a shooter at the shooter's last shot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Recall {
    /// Not remembered: cast the rays.
    Unknown,
    /// Every ray reached the shooter.
    Visible,
    /// Every ray was blocked.
    Hidden,
}

const UNKNOWN: u8 = 0;
const VISIBLE: u8 = 1;
const HIDDEN: u8 = 2;

/// Per shooting patch, what the vertices of its zone saw at its last shot.
#[derive(Clone, Debug, Default)]
pub(crate) struct VisibilityMemory {
    /// Per patch: one state per vertex of its zone, at the vertex's place
    /// in the zone's list ([`ShotPlaces`]).
    seen: Vec<Option<Box<[u8]>>>,
    /// The mesh's vertex and patch counts the memory was made for.
    made_for: (usize, usize),
    /// Bytes held.
    bytes: usize,
}

impl VisibilityMemory {
    /// Forgets everything if the mesh has changed.
    pub(crate) fn refresh(&mut self, vertices: usize, patches: usize) {
        if self.made_for == (vertices, patches) && self.seen.len() == patches {
            return;
        }
        self.seen = vec![None; patches];
        self.bytes = 0;
        self.made_for = (vertices, patches);
    }

    /// What the vertex at `place` in its zone's list saw of patch
    /// `shooter` at its last shot.
    pub(crate) fn recall(&self, shooter: usize, place: usize) -> Recall {
        let state = self
            .seen
            .get(shooter)
            .and_then(Option::as_ref)
            .and_then(|seen| seen.get(place).copied());
        match state {
            Some(VISIBLE) => Recall::Visible,
            Some(HIDDEN) => Recall::Hidden,
            _ => Recall::Unknown,
        }
    }

    /// Remembers what each of `vertices` saw of patch `shooter` at this
    /// shot (`gathered`, in the same order), for a zone of `zone_size`
    /// vertices, each at its place in the zone's list. Vertices that cast
    /// no rays keep what they had.
    pub(crate) fn remember(
        &mut self,
        shooter: usize,
        zone_size: usize,
        places: ShotPlaces<'_>,
        vertices: &[u32],
        gathered: &[Gathered],
    ) {
        let Some(slot) = self.seen.get_mut(shooter) else {
            return;
        };
        if slot.is_none() {
            if self.bytes + zone_size > BUDGET {
                return;
            }
            *slot = Some(vec![UNKNOWN; zone_size].into_boxed_slice());
            self.bytes += zone_size;
        }
        let Some(seen) = slot.as_mut() else {
            return;
        };
        for (&v, g) in vertices.iter().zip(gathered) {
            if g.rays == 0 {
                continue;
            }
            let state = if g.rays < MIN_EVIDENCE {
                UNKNOWN
            } else if g.blocked == 0 {
                VISIBLE
            } else if g.blocked == g.rays {
                HIDDEN
            } else {
                UNKNOWN
            };
            if let Some(entry) = seen.get_mut(places.of(v)) {
                *entry = state;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rgb::Rgb;

    fn gathered(rays: u32, blocked: u32) -> Gathered {
        Gathered {
            irradiance: Rgb::ZERO,
            rays,
            known_visible: 0,
            blocked,
        }
    }

    /// Unanimous rays are remembered, split or too few are not, and a
    /// vertex that cast none keeps what it had.
    #[test]
    fn remembers_only_unanimous_views() {
        let mut memory = VisibilityMemory::default();
        // Zones [0, 2, 4] and [1, 3]: each vertex's place in its list.
        let zone = [0, 2, 4];
        let places = ShotPlaces(Some(&[0, 0, 1, 1, 2]));
        let recall =
            |memory: &VisibilityMemory, shooter, v: u32| memory.recall(shooter, places.of(v));
        memory.refresh(5, 2);
        let views = [gathered(4, 0), gathered(4, 4), gathered(4, 1)];
        memory.remember(1, 3, places, &zone, &views);
        assert_eq!(recall(&memory, 1, 0), Recall::Visible);
        assert_eq!(recall(&memory, 1, 2), Recall::Hidden);
        assert_eq!(recall(&memory, 1, 4), Recall::Unknown);
        assert_eq!(recall(&memory, 0, 0), Recall::Unknown, "another shooter");
        let again = [gathered(0, 0), gathered(2, 0), gathered(9, 0)];
        memory.remember(1, 3, places, &zone, &again);
        assert_eq!(recall(&memory, 1, 0), Recall::Visible, "no rays: kept");
        assert_eq!(recall(&memory, 1, 2), Recall::Unknown, "two rays: too few");
        assert_eq!(recall(&memory, 1, 4), Recall::Visible);
        // A new mesh forgets.
        memory.refresh(6, 2);
        assert_eq!(recall(&memory, 1, 4), Recall::Unknown);
    }
}
