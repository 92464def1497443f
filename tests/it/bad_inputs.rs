//! The catalogue of bad inputs (`tests/bad_inputs/cases.toml`): the real
//! binary on every file a user might feed it, checked for the promised
//! outcome — a clear error (non-zero exit, not a panic, nothing written), or
//! a warning or nothing with a finite image — and never a hang.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use serde::Deserialize;

/// Longest a case may run before it counts as a hang (the machine may be
/// busy: a case normally takes well under a second).
const TIMEOUT: Duration = Duration::from_secs(120);

#[derive(Deserialize)]
struct Catalogue {
    case: Vec<Case>,
}

#[derive(Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    file: String,
    expect: Expect,
    #[serde(default)]
    message: String,
    #[serde(default)]
    args: Vec<String>,
    #[serde(default)]
    command: Option<String>,
    #[serde(default)]
    generate: Option<String>,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "lowercase")]
enum Expect {
    Fine,
    Warning,
    Error,
}

fn catalogue_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs")
}

fn load_catalogue() -> Vec<Case> {
    let text = std::fs::read_to_string(catalogue_dir().join("cases.toml")).unwrap();
    toml::from_str::<Catalogue>(&text).unwrap().case
}

/// Copies the catalogue into `dir` (subfolders included, for the MTL that is
/// a directory) and writes the generated files.
fn stage(dir: &Path, cases: &[Case]) {
    copy_dir(&catalogue_dir(), dir);
    for case in cases {
        if let Some(kind) = &case.generate {
            std::fs::write(dir.join(&case.file), generated(kind)).unwrap();
        }
    }
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

/// The lamp over a floor of `fine_basic.obj`, the floor replaced by `floor`
/// (an OBJ fragment with vertices numbered from 5).
fn lamp_over(floor: &str) -> String {
    format!(
        "mtllib common.mtl\no lamp\nv -0.25 1 -0.25\nv 0.25 1 -0.25\nv 0.25 1 0.25\n\
         v -0.25 1 0.25\nusemtl lamp\nf 1 2 3 4\n{floor}"
    )
}

/// Files too large to commit.
fn generated(kind: &str) -> String {
    match kind {
        // A 300 kB comment and a 20 000-number vertex colour line (the first
        // six numbers count; tobj ignores the rest, isorad refuses them), so
        // only the comment stays.
        "long_line" => {
            let comment = format!("# {}\n", "exported ".repeat(33_000));
            comment
                + &lamp_over(
                    "o floor\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nusemtl white\nf 5 6 7 8\n",
                )
        }
        // A floor that is a 10 000-gon (a disc of radius 1).
        "polygon_10000" => {
            let n = 10_000;
            let mut floor = String::from("o floor\n");
            for k in 0..n {
                let angle = -std::f64::consts::TAU * k as f64 / n as f64;
                floor += &format!("v {} 0 {}\n", angle.cos(), angle.sin());
            }
            floor += "usemtl white\nf";
            for k in 0..n {
                floor += &format!(" {}", k + 5);
            }
            lamp_over(&(floor + "\n"))
        }
        other => panic!("unknown generator `{other}`"),
    }
}

/// What a run printed and how it ended.
struct Run {
    code: Option<i32>,
    stderr: String,
    seconds: f64,
}

/// Runs the binary with a deadline; a run past it is killed.
fn run(dir: &Path, args: &[String]) -> Result<Run, String> {
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_isorad"))
        .current_dir(dir)
        .args(args)
        .env("RAYON_NUM_THREADS", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start isorad: {e}"))?;
    let mut pipe = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = pipe.read_to_string(&mut text);
        text
    });
    loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            return Ok(Run {
                code: status.code(),
                stderr: reader.join().unwrap(),
                seconds: start.elapsed().as_secs_f64(),
            });
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("no answer within {} s", TIMEOUT.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The command line of a case; outputs go to `out/<index>.exr|png`.
fn command_line(case: &Case, index: usize) -> Vec<String> {
    let exr = format!("out/{index}.exr");
    let png = format!("out/{index}.png");
    if case.command.as_deref() == Some("photometry") {
        let mut args = vec!["photometry".to_owned(), case.file.clone()];
        args.extend(case.args.iter().cloned());
        return args;
    }
    let mut args: Vec<String> = match case.command.as_deref() {
        Some("probe") => ["probe", "fine_basic.obj", "--points", &case.file]
            .map(String::from)
            .to_vec(),
        Some("grid") => ["grid", &case.file, "--csv", &format!("out/{index}.csv")]
            .map(String::from)
            .to_vec(),
        _ => {
            let mut a: Vec<String> = ["render", &case.file, "--output", &exr, "--png", &png]
                .map(String::from)
                .to_vec();
            if !case.file.ends_with(".toml") {
                a.extend(["--width", "24", "--height", "24"].map(String::from));
            }
            a
        }
    };
    args.extend(["--tolerance", "0.2", "-q"].map(String::from));
    if args[0] == "render" {
        args.extend(["--supersampling", "1"].map(String::from));
    }
    // The case's own flags replace the defaults of the same name.
    for flag in case.args.iter().filter(|a| a.starts_with("--")) {
        if let Some(at) = args.iter().position(|a| a == flag) {
            args.drain(at..at + 2);
        }
    }
    args.extend(case.args.iter().cloned());
    args
}

/// Runs one case and returns what is wrong with its outcome, if anything.
fn check(dir: &Path, case: &Case, index: usize) -> Result<f64, String> {
    let args = command_line(case, index);
    let run = run(dir, &args)?;
    let stderr = &run.stderr;
    let say = |what: String| format!("{what}\n    stderr: {}", stderr.trim_end());
    if stderr.contains("panicked") || run.code == Some(101) {
        return Err(say("panicked".into()));
    }
    let Some(code) = run.code else {
        return Err(say("killed by a signal".into()));
    };
    if !stderr.contains(&case.message) {
        return Err(say(format!("stderr lacks {:?}", case.message)));
    }
    let warned = stderr.contains("warning:");
    let (exr, png) = (
        dir.join(format!("out/{index}.exr")),
        dir.join(format!("out/{index}.png")),
    );
    match case.expect {
        Expect::Error => {
            if code == 0 {
                return Err(say("succeeded, expected an error".into()));
            }
            if !stderr.contains("error:") {
                return Err(say("no `error:` message".into()));
            }
            let csv = dir.join(format!("out/{index}.csv"));
            if exr.exists() || png.exists() || csv.exists() {
                return Err(say("an output was written despite the error".into()));
            }
        }
        Expect::Fine | Expect::Warning => {
            if code != 0 {
                return Err(say(format!("exit code {code}, expected success")));
            }
            if warned != (case.expect == Expect::Warning) {
                return Err(say(format!(
                    "expected {:?}, warning: {warned}",
                    case.expect
                )));
            }
            if args[0] == "render" {
                let image = isorad::render::read_exr(&exr).map_err(|e| say(e.to_string()))?;
                if image.pixels().iter().flatten().any(|c| !c.is_finite()) {
                    return Err(say("the image holds a non-finite value".into()));
                }
                if !png.is_file() {
                    return Err(say("no PNG".into()));
                }
            }
        }
    }
    Ok(run.seconds)
}

#[test]
fn every_bad_input_gets_its_promised_answer() {
    let cases = load_catalogue();
    assert!(
        cases.len() >= 40,
        "the catalogue holds {} cases",
        cases.len()
    );
    let dir = tempfile::tempdir().unwrap();
    stage(dir.path(), &cases);
    std::fs::create_dir(dir.path().join("out")).unwrap();
    // A few cases at a time, each isorad on one thread.
    let next = Mutex::new(0_usize);
    let failures = Mutex::new(Vec::new());
    let slowest = Mutex::new((0.0, String::new()));
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get().clamp(2, 4));
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| {
                loop {
                    let index = {
                        let mut next = next.lock().unwrap();
                        *next += 1;
                        *next - 1
                    };
                    let Some(case) = cases.get(index) else { break };
                    match check(dir.path(), case, index) {
                        Ok(seconds) => {
                            let mut slowest = slowest.lock().unwrap();
                            if seconds > slowest.0 {
                                *slowest = (seconds, case.file.clone());
                            }
                        }
                        Err(why) => failures.lock().unwrap().push(format!(
                            "case {index} `{}` {:?} ({:?}): {why}",
                            case.file, case.args, case.expect
                        )),
                    }
                }
            });
        }
    });
    let (seconds, file) = slowest.into_inner().unwrap();
    println!("{} cases; slowest {file}: {seconds:.2} s", cases.len());
    let failures = failures.into_inner().unwrap();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

/// A concave face must be meshed inside its outline: a fan from its first
/// vertex (a tooth tip of a comb) would cover the gaps between the teeth.
#[test]
fn a_concave_face_is_meshed_inside_its_outline() {
    let path = catalogue_dir().join("face_concave_comb.obj");
    let scene = isorad::scene::load_obj(&path).unwrap();
    let floor = scene.surfaces.iter().find(|s| s.name == "floor").unwrap();
    // The comb: a 2 × 0.8 base and three teeth 0.4 wide and 1.2 long.
    assert!((floor.area() - (2.0 * 0.8 + 3.0 * 0.4 * 1.2)).abs() < 1e-6);
    let mesh =
        isorad::mesh::mesh_square(&scene, &isorad::mesh::SquareMeshSettings::for_scene(&scene));
    let areas: Vec<f64> = scene.surfaces.iter().map(|s| s.area()).collect();
    mesh.validate(&areas).unwrap();
    let index = scene.surface_named("floor").unwrap();
    let outline = floor.plane_vertices();
    let mut covered = 0.0;
    for element in mesh.elements.iter().filter(|e| e.surface == index) {
        let centroid = element.corner_mean(|v| mesh.vertices[v as usize].position);
        let p = floor.frame().to_plane(centroid);
        assert!(
            isorad::internals::polygon_contains(&outline, p),
            "element outside the comb at {centroid}"
        );
        covered += element.area;
    }
    assert!(
        (covered - floor.area()).abs() < 1e-9 * floor.area(),
        "{covered}"
    );
}

/// Blanks and tabs around and between tokens change nothing: the indented
/// and tab-separated copies of `fine_basic.obj` (and of its MTL) load as the
/// same surfaces, vertices and materials.
#[test]
fn indented_and_tabbed_files_give_the_plain_scene() {
    let load = |name: &str| isorad::scene::load_obj(&catalogue_dir().join(name)).unwrap();
    let plain = load("fine_basic.obj");
    for name in ["whitespace_indented.obj", "whitespace_tabs.obj"] {
        let scene = load(name);
        assert_eq!(scene.surfaces, plain.surfaces, "{name}");
        assert_eq!(scene.materials, plain.materials, "{name}");
        assert!(scene.warnings.is_empty(), "{name}: {:?}", scene.warnings);
    }
}
