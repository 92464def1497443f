//! The meshers on random polygons: see `isorad_fuzz::mesh_random_floor`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| isorad_fuzz::mesh_random_floor(data));
