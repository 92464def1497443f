//! Every input a fuzz target has crashed on, run through the target's own
//! code (`fuzz/src/lib.rs`, shared with `cargo fuzz`), so that a fixed crash
//! stays fixed. A new crash file from `fuzz/artifacts/<target>/` goes into
//! `tests/fuzz_regressions/<target>/`.

#[path = "../../fuzz/src/lib.rs"]
#[allow(dead_code)]
mod fuzz_support;

use std::path::Path;

/// The files of `tests/fuzz_regressions/<target>`, by name.
fn crash_inputs(target: &str) -> Vec<(String, Vec<u8>)> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz_regressions")
        .join(target);
    let mut inputs: Vec<(String, Vec<u8>)> = std::fs::read_dir(&folder)
        .unwrap_or_else(|e| panic!("{}: {e}", folder.display()))
        .map(|entry| {
            let path = entry.expect("folder entry").path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&path).expect("crash input"))
        })
        .collect();
    inputs.sort();
    inputs
}

#[test]
fn meshers_crash_inputs_mesh_cleanly() {
    let inputs = crash_inputs("meshers");
    assert!(!inputs.is_empty());
    for (name, data) in inputs {
        let outcome = std::panic::catch_unwind(|| fuzz_support::mesh_random_floor(&data));
        assert!(outcome.is_ok(), "{name} crashes the meshers again");
    }
}
