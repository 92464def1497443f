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
use common::{RawBvh, random_segments, shot_segments};

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

    let mut group = c.benchmark_group("shadow_rays_cornell_100k");
    group.sample_size(20);
    group.throughput(Throughput::Elements(SEGMENTS as u64));
    group.bench_function("isorad_visibility", |b| {
        b.iter(|| {
            segments
                .iter()
                .filter(|s| visibility.is_unblocked(s.from, s.to, s.end_surfaces))
                .count()
        })
    });
    group.bench_function("obvhs_direct", |b| {
        b.iter(|| {
            segments
                .iter()
                .filter(|s| raw.is_unblocked(black_box(s)))
                .count()
        })
    });
    group.finish();

    let mesh = mesh_square(&scene, &SquareMeshSettings::for_scene(&scene));
    let shots = shot_segments(&scene, &mesh, 40, 2);
    let mut group = c.benchmark_group("shot_rays_cornell_40_shots");
    group.sample_size(20);
    group.throughput(Throughput::Elements(shots.len() as u64));
    group.bench_function("isorad_visibility", |b| {
        b.iter(|| {
            shots
                .iter()
                .filter(|s| visibility.is_unblocked(s.from, s.to, s.end_surfaces))
                .count()
        })
    });
    group.bench_function("isorad_visibility_shadow_cache", |b| {
        b.iter(|| {
            let mut cache = ShadowCache::default();
            shots
                .iter()
                .filter(|s| {
                    visibility.is_unblocked_cached(s.from, s.to, s.end_surfaces, &mut cache)
                })
                .count()
        })
    });
    group.bench_function("obvhs_direct", |b| {
        b.iter(|| {
            shots
                .iter()
                .filter(|s| raw.is_unblocked(black_box(s)))
                .count()
        })
    });
    group.finish();
}

criterion_group!(benches, visibility);
criterion_main!(benches);
