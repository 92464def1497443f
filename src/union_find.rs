//! The representative of a group in a union–find forest, for the loaders
//! and lights that join touching faces into groups.
//!
//! # References
//! R. E. Tarjan, "Efficiency of a Good But Not Linear Set Union
//! Algorithm", JACM 22 (1975).

/// The representative of `k`'s group in `parent` (each entry its parent,
/// a root its own), halving the path on the way.
pub(crate) fn root(parent: &mut [usize], mut k: usize) -> usize {
    while parent[k] != k {
        parent[k] = parent[parent[k]];
        k = parent[k];
    }
    k
}
