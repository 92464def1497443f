//! The solve's counters: shots, shadow rays, and what shaft culling, the
//! visibility memory and coarse reception saved.

/// What a solve has done so far ([`crate::Solver::stats`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct SolveStats {
    /// Shots made so far (patches and photometric luminaires).
    pub shots: usize,
    /// Shadow rays cast so far.
    pub rays: u64,
    /// Vertex receptions of a reflected shot interpolated from their
    /// patch's samples rather than gathered
    /// ([`crate::SolverSettings::coarse_reception`]).
    pub interpolated_receptions: u64,
    /// Vertex receptions of a reflected shot, interpolated or gathered.
    pub receptions: u64,
    /// Shafts between a shooter and a receiving patch tested
    /// ([`crate::SolverSettings::cull_shafts`]).
    pub shafts_tested: u64,
    /// Shafts found clear: their receivers see all of the shooter.
    pub shafts_clear: u64,
    /// Visibility samples taken without shadow rays (each a ray saved) by
    /// receivers known to see all of their shooter, from a clear shaft or
    /// from the shooter's last shot.
    pub known_visible: u64,
    /// Shadow rays answered by the few triangles that reach into their
    /// shaft, tested one by one, rather than by a traversal of the BVH.
    pub listed_rays: u64,
    /// Vertex views of a reflected shot taken from what the vertex saw of
    /// the same patch's last shot, all or none of it, without rays
    /// ([`crate::SolverSettings::remember_visibility`]).
    pub recalled_views: u64,
}
