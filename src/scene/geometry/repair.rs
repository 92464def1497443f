//! What cleaning a raw face may do to it, by kind, so that a loader can
//! count repairs instead of listing each.

/// A repair or skip of one face ([`super::polygon::clean_polygon`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RepairKind {
    /// Skipped: a coordinate is not finite.
    NonFinite,
    /// Skipped: fewer than three distinct vertices.
    TooFewVertices,
    /// Skipped: its area is zero against its size.
    ZeroArea,
    /// Skipped: its edges cross (a bow-tie).
    EdgesCross,
    /// Skipped: its outline touches itself and covers some area twice.
    CoversTwice,
    /// Split into triangles: its outline touches itself.
    TouchesItself,
    /// Split into triangles: it is not planar.
    NotPlanar,
}

impl RepairKind {
    /// What happened to faces of this kind, as a report's line says it.
    #[must_use]
    pub fn summary(self) -> &'static str {
        match self {
            RepairKind::NonFinite => "skipped: a coordinate is not finite",
            RepairKind::TooFewVertices => "skipped: fewer than 3 distinct vertices",
            RepairKind::ZeroArea => "skipped: zero area",
            RepairKind::EdgesCross => "skipped: edges crossing each other",
            RepairKind::CoversTwice => "skipped: outline touching itself, covering area twice",
            RepairKind::TouchesItself => "split into triangles: outline touching itself",
            RepairKind::NotPlanar => "split into triangles: not planar",
        }
    }
}
