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

/// The photometry target's seeds (`fuzz/corpus/photometry`), cut after
/// every line and after every token, and with each numeric token replaced
/// by values a broken exporter writes (negative, zero, huge, NaN, text):
/// every variant parses to a valid distribution or an error naming a line.
#[test]
fn photometric_files_survive_every_truncation_and_corruption_of_the_seeds() {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/photometry");
    let mut seeds: Vec<_> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    seeds.sort();
    assert!(seeds.len() >= 2);
    let mut variants = 0;
    for seed in seeds {
        let text = std::fs::read_to_string(&seed).unwrap();
        // Every prefix ending at a token boundary.
        let cuts = text
            .char_indices()
            .filter(|&(_, c)| c.is_whitespace())
            .map(|(i, _)| i);
        for cut in cuts {
            fuzz_support::parse_photometry(&text.as_bytes()[..cut]);
            variants += 1;
        }
        // Each token replaced.
        let tokens: Vec<(usize, usize)> = text
            .char_indices()
            .filter(|&(i, c)| {
                !c.is_whitespace() && (i == 0 || text[..i].ends_with(char::is_whitespace))
            })
            .map(|(i, _)| {
                let end = text[i..]
                    .find(char::is_whitespace)
                    .map_or(text.len(), |e| i + e);
                (i, end)
            })
            .collect();
        for &(start, end) in &tokens {
            for replacement in ["-1", "0", "1e308", "NaN", "x", "360", "100000"] {
                let corrupted = format!("{}{replacement}{}", &text[..start], &text[end..]);
                fuzz_support::parse_photometry(corrupted.as_bytes());
                variants += 1;
            }
        }
    }
    assert!(variants > 1000, "{variants} variants");
}

/// The minimised corpora of the `photometry_ies` and `photometry_eulumdat`
/// targets (`fuzz/corpus/`), what 1 M executions each kept as new
/// behaviour: every input reads as its target reads it, to a valid
/// distribution or an error naming a line.
#[test]
fn the_lm_63_and_eulumdat_fuzz_corpora_read_cleanly() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus");
    for target in ["photometry_ies", "photometry_eulumdat"] {
        let read = match target {
            "photometry_ies" => fuzz_support::parse_ies_bytes,
            _ => fuzz_support::parse_eulumdat_bytes,
        };
        let entries: Vec<_> = std::fs::read_dir(root.join(target))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        assert!(entries.len() > 100, "{target}: {} inputs", entries.len());
        for path in entries {
            let data = std::fs::read(&path).unwrap();
            let outcome = std::panic::catch_unwind(|| read(&data));
            assert!(outcome.is_ok(), "{target}: {} fails", path.display());
        }
    }
}
