//! The runs a shot's receivers are gathered in, in parallel: each run of a
//! fixed length with its own fresh [`ShadowCache`], so that the cache's
//! answers, and so the solve, are the same on any number of threads.

use rayon::prelude::*;

use crate::scene::ShadowCache;

/// Receivers in one run of a shot's shadow rays through one [`ShadowCache`].
/// Runs of a fixed length make the cache's answers, and so the solve, the
/// same however rayon spreads the runs over its threads; each run's first
/// blocked ray pays a traversal to fill its cache.
const SHADOW_CACHE_RUN: usize = 256;

/// `f` of each item, in parallel over runs of [`SHADOW_CACHE_RUN`] items,
/// each run with a fresh [`ShadowCache`]; in the items' order.
pub(crate) fn in_shadow_cache_runs<T: Sync, R: Send + Default>(
    items: &[T],
    f: impl Fn(&T, &mut ShadowCache) -> R + Sync,
) -> Vec<R> {
    indices_in_shadow_cache_runs(items.len(), |k, cache| f(&items[k], cache))
}

/// `f` of each index below `count`, as [`in_shadow_cache_runs`] does it.
pub(crate) fn indices_in_shadow_cache_runs<R: Send + Default>(
    count: usize,
    f: impl Fn(usize, &mut ShadowCache) -> R + Sync,
) -> Vec<R> {
    let mut results: Vec<R> = std::iter::repeat_with(R::default).take(count).collect();
    results
        .par_chunks_mut(SHADOW_CACHE_RUN)
        .enumerate()
        .for_each(|(run, results)| {
            let mut cache = ShadowCache::default();
            for (k, result) in results.iter_mut().enumerate() {
                *result = f(run * SHADOW_CACHE_RUN + k, &mut cache);
            }
        });
    results
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each run of receivers starts with a fresh shadow cache at the same
    /// receivers, however many threads share the runs: the cache's answers,
    /// and so a solve, cannot depend on rayon's scheduling.
    #[test]
    fn shadow_cache_runs_start_fresh_at_fixed_receivers_on_any_pool() {
        let items: Vec<usize> = (0..1000).collect();
        let expected: Vec<bool> = items.iter().map(|i| i % SHADOW_CACHE_RUN == 0).collect();
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let fresh: Vec<bool> = pool.install(|| {
                in_shadow_cache_runs(&items, |_, cache| {
                    let fresh = cache.is_fresh();
                    cache.fill_for_test();
                    fresh
                })
            });
            assert_eq!(fresh, expected, "{threads} threads");
        }
    }
}
