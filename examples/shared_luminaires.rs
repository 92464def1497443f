//! Times loading a scene whose luminaires share one photometric file: the
//! downlights room (`scenes/downlights`) with N `[[luminaire]]` tables
//! (default 10,000, a car park's worth) naming `downlight.ies`, on a grid
//! under its ceiling. Loading reads, parses and prepares (integrates the
//! flux of) the file once, and places it N times.
//!
//! ```sh
//! cargo run --release --example shared_luminaires -- 10000
//! ```
//!
//! Prints the scene file's size and the load's wall time; with `--keep`,
//! also the scene folder's path, left in place for `isorad info` and the
//! like.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let keep = args.iter().any(|a| a == "--keep");
    let count: usize = args
        .iter()
        .find(|a| !a.starts_with("--"))
        .map_or(10_000, |a| a.parse().expect("a number of luminaires"));
    let dir = tempfile::tempdir().expect("a temporary folder");
    let scene = write_scene(dir.path(), count);
    println!(
        "{count} luminaires sharing downlight.ies: {} ({} KiB)",
        scene.display(),
        std::fs::metadata(&scene).expect("the scene file").len() / 1024
    );
    let start = Instant::now();
    let loaded = isorad::load_scene(scene.to_str().expect("a UTF-8 path")).expect("the scene");
    let seconds = start.elapsed().as_secs_f64();
    assert_eq!(loaded.scene.luminaires.len(), count);
    let flux: f64 = loaded.scene.luminaires[0].power().luminance() * 179.0;
    println!(
        "loaded in {seconds:.3} s ({:.1} µs a luminaire); each emits {flux:.4} lm",
        seconds * 1e6 / count as f64
    );
    if keep {
        println!("kept: {}", dir.keep().display());
    }
}

/// Copies the downlights room's OBJ, MTL and IES file into `dir` and
/// writes `many.toml` with `count` luminaires on a grid 2.75 m high;
/// returns the scene file's path.
fn write_scene(dir: &Path, count: usize) -> std::path::PathBuf {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/downlights");
    for name in ["downlights.obj", "downlights.mtl", "downlight.ies"] {
        std::fs::copy(source.join(name), dir.join(name)).expect("the downlights scene");
    }
    let side = (count as f64).sqrt().ceil().max(1.0) as usize;
    let mut text = String::from("obj = \"downlights.obj\"\n");
    for k in 0..count {
        let (i, j) = (k % side, k / side);
        let x = 0.2 + 4.6 * i as f64 / side as f64;
        let z = 0.2 + 3.6 * j as f64 / side as f64;
        write!(
            text,
            "\n[[luminaire]]\nies = \"downlight.ies\"\nposition = [{x:.4}, 2.75, {z:.4}]\n\
             aim = [0.0, -1.0, 0.0]\nc0 = [1.0, 0.0, 0.0]\nmultiplier = 0.001\n"
        )
        .expect("writing to a string");
    }
    let path = dir.join("many.toml");
    std::fs::write(&path, text).expect("the scene file");
    path
}
