//! Shadow rays through isorad's `Visibility::is_unblocked` against obvhs
//! called directly (`ray_traverse_miss` over the same CWBVH preset), on the
//! same 100k random segments between points on the Cornell box's surfaces,
//! single-threaded: the difference is the cost of isorad's layer. Then the
//! rays of shots as the solver casts them (vertex after vertex to one
//! patch), through obvhs, `Visibility` and `Visibility` with its shadow
//! cache.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use isorad::{
    load_scene,
    mesh::{SquareMeshSettings, mesh_square},
    scene::{ShadowCache, Visibility},
};

mod common;
use common::{RawBvh, Segment, random_segments, shot_segments};

const SEGMENTS: usize = 100_000;

fn visibility(c: &mut Criterion) {
    let scene = load_scene("cornell").expect("built-in Cornell box").scene;
    let segments = random_segments(&scene, SEGMENTS, 1);
    let visibility = Visibility::new(&scene);
    let raw = RawBvh::new(&scene);
    // Both must answer the same on the same rays, or the comparison is moot.
    let disagree = segments
        .iter()
        .filter(|s| visibility.is_unblocked(s.from, s.to, s.end_surfaces) != raw.is_unblocked(s))
        .count();
    assert!(
        disagree * 1000 < SEGMENTS,
        "{disagree} of {SEGMENTS} segments disagree"
    );

    let plain =
        |s: &Segment, _: &mut ShadowCache| visibility.is_unblocked(s.from, s.to, s.end_surfaces);
    let cached = |s: &Segment, cache: &mut ShadowCache| {
        visibility.is_unblocked_cached(s.from, s.to, s.end_surfaces, cache)
    };
    let direct = |s: &Segment, _: &mut ShadowCache| raw.is_unblocked(black_box(s));
    count_unblocked(
        c,
        "shadow_rays_cornell_100k",
        &segments,
        &[("isorad_visibility", &plain), ("obvhs_direct", &direct)],
    );

    let mesh = mesh_square(&scene, &SquareMeshSettings::for_scene(&scene));
    let shots = shot_segments(&scene, &mesh, 40, 2);
    count_unblocked(
        c,
        "shot_rays_cornell_40_shots",
        &shots,
        &[
            ("isorad_visibility", &plain),
            ("isorad_visibility_shadow_cache", &cached),
            ("obvhs_direct", &direct),
        ],
    );
}

/// A shadow-ray query: whether a segment is unblocked, through a cache
/// that a query may use.
type Query<'a> = &'a dyn Fn(&Segment, &mut ShadowCache) -> bool;

/// One benchmark group: each named query counting the unblocked
/// `segments` in order, one cache for the whole sequence.
fn count_unblocked(
    c: &mut Criterion,
    group: &str,
    segments: &[Segment],
    queries: &[(&str, Query)],
) {
    let mut group = c.benchmark_group(group);
    group.sample_size(20);
    group.throughput(Throughput::Elements(segments.len() as u64));
    for &(name, query) in queries {
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut cache = ShadowCache::default();
                segments.iter().filter(|s| query(s, &mut cache)).count()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, visibility);
criterion_main!(benches);
