//! Shadow boundaries merged where the mesh cannot tell them apart, the
//! longest kept first.

use glam::DVec2;

use super::BoundaryLimits;
use crate::scene::distance_to_segment;

/// Keeps the longest boundaries first, leaving out any that lies within
/// `min_feature` of one already kept along its whole length (its ends and
/// middle), up to `max_per_receiver`. A kept boundary stands for the
/// cluster of those it covers; where that cluster is at least `min_feature`
/// wide across (the offsets of its members' middles from the kept line, on
/// both sides), its two outermost members are kept instead: the edge of the
/// umbra and the outer edge of the penumbra, which one line in between
/// left without vertices. The two count against `max_per_receiver` like
/// any others.
pub(super) fn merge_boundaries(
    mut found: Vec<[DVec2; 2]>,
    limits: BoundaryLimits,
) -> Vec<[DVec2; 2]> {
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
