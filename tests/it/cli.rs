//! The `isorad` binary, run for real on files in a temporary directory.

use std::path::Path;
use std::process::{Command, Output};

pub fn isorad(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_isorad"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the isorad binary runs")
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn render_with_no_scene_writes_the_cornell_box() {
    let dir = tempfile::tempdir().unwrap();
    let out = isorad(
        dir.path(),
        &[
            "render",
            "--width",
            "48",
            "--height",
            "48",
            "--tolerance",
            "0.05",
            "-q",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let image = isorad::render::read_exr(&dir.path().join("isorad.exr")).unwrap();
    assert_eq!((image.width(), image.height()), (48, 48));
    let mean = image.mean();
    assert!(mean.r > mean.b && mean.b > 0.0, "a warm, lit box: {mean}");
    assert!(dir.path().join("isorad.png").is_file());
    let summary = stderr(&out);
    for word in [
        "surfaces",
        "elements",
        "vertices",
        "shots",
        "shadow rays",
        "rays/s",
    ] {
        assert!(summary.contains(word), "summary lacks `{word}`: {summary}");
    }
    // Each phase's time, in the order the phases ran.
    let times = summary
        .lines()
        .find_map(|line| line.strip_prefix("time: "))
        .unwrap_or_else(|| panic!("no `time:` line: {summary}"));
    // "closed rooms 0.0 s" names "closed rooms".
    let phases: Vec<&str> = times
        .split(", ")
        .filter_map(|part| Some(part.strip_suffix(" s")?.rsplit_once(' ')?.0))
        .collect();
    let expected = [
        "closed rooms",
        "shadow boundaries",
        "meshing",
        "solve",
        "ambient term",
    ];
    assert_eq!(phases, expected, "{times}");
}

#[test]
fn an_unknown_scene_fails_with_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let out = isorad(dir.path(), &["render", "no-such-scene", "-q"]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("no-such-scene"), "{}", stderr(&out));
}

#[test]
fn swapped_image_names_fail_before_solving_and_say_which_flag_takes_which() {
    let dir = tempfile::tempdir().unwrap();
    for args in [["-o", "out.png"], ["--png", "out.EXR"]] {
        let out = isorad(dir.path(), &["render", "cornell", args[0], args[1]]);
        assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
        let message = stderr(&out);
        assert!(
            message.contains(args[1]) && message.contains("--png out.png"),
            "{message}"
        );
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}

#[test]
fn a_nan_vertex_fails_naming_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.mtl"),
        "newmtl m\nKd 0.5 0.5 0.5\nKe 1 1 1\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("bad.obj"),
        "mtllib bad.mtl\no quad\nusemtl m\nv 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 1 0\nf 1 2 3 4\n",
    )
    .unwrap();
    let out = isorad(dir.path(), &["render", "bad.obj", "-q"]);
    assert!(!out.status.success());
    let message = stderr(&out);
    assert!(
        message.contains("bad.obj") && message.contains(":6"),
        "{message}"
    );
}

#[test]
fn an_unwritable_output_fails_before_solving_and_keeps_existing_files() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("isorad.png"), b"precious").unwrap();
    let out = isorad(dir.path(), &["render", "-o", "missing/dir/out.exr", "-q"]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("missing/dir"), "{}", stderr(&out));
    assert_eq!(
        std::fs::read(dir.path().join("isorad.png")).unwrap(),
        b"precious"
    );
}

#[test]
fn a_bad_flag_value_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["render", "--tolerance", "2", "-q"][..],
        &["render", "--max-edge", "-1", "-q"],
        &["render", "--width", "0", "-q"],
        &["render", "--closed-zone-weight", "0", "-q"],
        &["render", "--closed-zone-weight", "1.5", "-q"],
        &["render", "--ambient-sweeps", "100", "-q"],
        &["render", "--ambient-sweeps", "-1", "-q"],
        &["render", "--patch-tolerance", "0", "-q"],
        &["render", "--patch-tolerance", "1.5", "-q"],
    ] {
        let out = isorad(dir.path(), args);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(!stderr(&out).contains("panicked"), "{}", stderr(&out));
    }
    // Named by its flag.
    let out = isorad(dir.path(), &["render", "--closed-zone-weight", "1.5", "-q"]);
    assert!(
        stderr(&out).contains("--closed-zone-weight"),
        "{}",
        stderr(&out)
    );
    let out = isorad(dir.path(), &["render", "--ambient-sweeps", "100", "-q"]);
    assert!(
        stderr(&out).contains("--ambient-sweeps"),
        "{}",
        stderr(&out)
    );
    let out = isorad(dir.path(), &["render", "--patch-tolerance", "0", "-q"]);
    assert!(
        stderr(&out).contains("--patch-tolerance"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn probe_prints_a_csv_row_per_point() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("points.csv"),
        "x,y,z\n278,0,279.5\n278,0,279.5,0,1,0\n",
    )
    .unwrap();
    let out = isorad(
        dir.path(),
        &[
            "probe",
            "--points",
            "points.csv",
            "--gradient",
            "--tolerance",
            "0.05",
            "-q",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let csv = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    assert!(lines[0].starts_with(
        "x,y,z,irradiance_r,irradiance_g,irradiance_b,radiosity_r,radiosity_g,radiosity_b,grad_r_x"
    ));
    let row: Vec<f64> = lines[1].split(',').map(|v| v.parse().unwrap()).collect();
    assert!(lines[0].ends_with(
        ",grad_b_z,irradiance_se_r,irradiance_se_g,irradiance_se_b,illuminance_lux,luminance_cd_m2"
    ));
    assert_eq!(row.len(), 23);
    assert!(
        row[18..21]
            .iter()
            .all(|&se| (0.0..=0.005 * row[3]).contains(&se)),
        "the standard error is small and not negative: {csv}"
    );
    assert!(
        row[3] > 0.0 && row[6] > 0.0,
        "the floor under the light is lit: {csv}"
    );

    std::fs::write(dir.path().join("off.csv"), "278,0,279.5\n278,100,279.5\n").unwrap();
    let out = isorad(
        dir.path(),
        &["probe", "--points", "off.csv", "--tolerance", "0.05", "-q"],
    );
    assert!(!out.status.success());
    assert!(stderr(&out).contains("off.csv:2"), "{}", stderr(&out));
}

#[test]
fn info_lists_the_cornell_light_and_which_receivers_get_the_contour_mesher() {
    let dir = tempfile::tempdir().unwrap();
    let out = isorad(dir.path(), &["info", "cornell"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let row = |name: &str| -> Vec<String> {
        let line = text
            .lines()
            .find(|l| l.split_whitespace().nth(1) == Some(name))
            .unwrap_or_else(|| panic!("no row for {name}: {text}"));
        line.split_whitespace().map(str::to_owned).collect()
    };
    // One luminaire, surface 15: 130 × 105 mm, radius ½√(130² + 105²) ≈ 83.6 mm.
    let light = text
        .lines()
        .find(|l| l.trim_start().starts_with("0 "))
        .unwrap();
    let fields: Vec<&str> = light.split_whitespace().collect();
    assert_eq!(fields[1], "15", "{text}");
    let (area, radius): (f64, f64) = (fields[2].parse().unwrap(), fields[3].parse().unwrap());
    assert!(
        (area - 13650.0).abs() < 1.0 && (radius - 83.55).abs() < 0.1,
        "{text}"
    );
    // The floor: lit only by the light, 549 mm below it, so 83.6/548.8 ≈ 0.152.
    let floor = row("floor");
    assert_eq!(
        (floor[3].as_str(), floor[4].as_str()),
        ("0", "100.0"),
        "{text}"
    );
    let ratio: f64 = floor[5].parse().unwrap();
    assert!((ratio - 83.55 / 548.7).abs() < 0.002, "{text}");
    assert_eq!(floor[6], "radial");
    // The ceiling is behind the light: no direct light, no dominant.
    let ceiling = row("ceiling");
    assert_eq!(
        (ceiling[3].as_str(), ceiling[6].as_str()),
        ("-", "square"),
        "{text}"
    );
    // The walls are nearer than four radii (ratio ≈ 0.26): not the radial
    // mesher, but the light's level lines.
    assert_eq!(row("back_wall")[6], "level-lines", "{text}");
    // A stricter size bound takes the floor off the radial mesher.
    let out = isorad(dir.path(), &["info", "--max-size-ratio", "0.1"]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(!text.contains("radial"), "{text}");
    // Out-of-range flags fail with their name.
    let out = isorad(dir.path(), &["info", "--min-share", "1.5"]);
    assert!(
        !out.status.success() && stderr(&out).contains("min-share"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn compare_writes_records_pictures_and_a_plot() {
    let dir = tempfile::tempdir().unwrap();
    let scene =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/seed/seed_disc_tilted.toml");
    let out = isorad(
        dir.path(),
        &[
            "compare",
            scene.to_str().unwrap(),
            "--json",
            "c.json",
            "--image",
            "c.png",
            "--plot",
            "c.svg",
            "--grid",
            "200",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(dir.path().join("c.json")).unwrap();
    let records: serde_json::Value = serde_json::from_str(&text).unwrap();
    let records = records.as_array().unwrap();
    let find = |mesher: &str, key: &str, value: u64| {
        records
            .iter()
            .find(|r| r["mesher"] == mesher && r["params"][key] == value)
            .unwrap_or_else(|| panic!("{mesher} {key}={value}"))
    };
    for record in records {
        for field in [
            "receiver",
            "mesher",
            "params",
            "vertices",
            "triangles",
            "rms_rel_error",
            "max_rel_error",
            "mean_rel_error",
            "seconds",
        ] {
            assert!(!record[field].is_null(), "{field} missing in {record}");
        }
    }
    let (square10, square30) = (find("square", "n", 10), find("square", "n", 30));
    let contour = find("contour", "directions", 20);
    let rms = |r: &serde_json::Value| r["rms_rel_error"].as_f64().unwrap();
    assert!(
        rms(contour) < rms(square10),
        "contour 20×5 beats square 10×10"
    );
    assert!(contour["vertices"].as_u64() < square30["vertices"].as_u64());
    assert!(dir.path().join("c.png").is_file() && dir.path().join("c.svg").is_file());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("the contour and greedy meshes' vertices for the same RMS error"));
    assert!(stdout.contains("for the same mean relative error"));
    // Each mesher's own vertices for square 30 × 30's errors.
    assert!(stdout.contains("\n    greedy: "), "{stdout}");
    assert!(stdout.contains("\n    contour: "), "{stdout}");
}

#[test]
fn render_with_the_contour_mesher() {
    let dir = tempfile::tempdir().unwrap();
    let out = isorad(
        dir.path(),
        &[
            "render",
            "--mesh",
            "contour",
            "--levels",
            "6",
            "--directions",
            "12",
            "--width",
            "48",
            "--height",
            "48",
            "-q",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("contour mesher on"),
        "{}",
        stderr(&out)
    );
    let out = isorad(dir.path(), &["render", "--mesh", "hexagonal", "-q"]);
    assert!(!out.status.success() && stderr(&out).contains("hexagonal"));
}

/// Waits for a child for at most `seconds`, killing it after.
fn wait_at_most(child: &mut std::process::Child, seconds: u64) -> std::process::ExitStatus {
    let start = std::time::Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if start.elapsed().as_secs() > seconds {
            child.kill().unwrap();
            panic!("isorad did not stop within {seconds} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

#[test]
fn ctrl_c_writes_the_solution_so_far_says_so_and_fails() {
    use std::io::Read;
    let dir = tempfile::tempdir().unwrap();
    // A solve that would take minutes, with a preview after every shot.
    let mut child = Command::new(env!("CARGO_BIN_EXE_isorad"))
        .current_dir(dir.path())
        .args(["render", "--tolerance", "1e-9", "--max-edge", "10"])
        .args([
            "--width",
            "40",
            "--height",
            "40",
            "--preview-every",
            "1",
            "--export",
            "lit.ply",
            "-q",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The first preview (written by rename, so complete) says shooting began.
    let exr = dir.path().join("isorad.exr");
    let start = std::time::Instant::now();
    while !exr.is_file() {
        assert!(start.elapsed().as_secs() < 120, "no preview written");
        assert!(child.try_wait().unwrap().is_none(), "isorad ended early");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let preview = isorad::render::read_exr(&exr).unwrap();
    assert!(preview.mean().r > 0.0, "the preview is lit");
    // Previews write the images only; the export comes at the end.
    let ply = dir.path().join("lit.ply");
    assert!(!ply.exists(), "no export at a preview");
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = wait_at_most(&mut child, 60);
    let mut message = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut message)
        .unwrap();
    assert_eq!(status.code(), Some(130), "{message}");
    assert!(
        message.contains("interrupted")
            && message.contains("ambient term added")
            && message.contains("lit.ply"),
        "{message}"
    );
    // The export of the solution so far is written too.
    assert!(std::fs::read(&ply).unwrap().starts_with(b"ply\n"));
    // Both outputs are whole images of the solution so far.
    let image = isorad::render::read_exr(&exr).unwrap();
    assert_eq!((image.width(), image.height()), (40, 40));
    let mean = image.mean();
    assert!(mean.r > mean.b && mean.b > 0.0, "a warm, lit box: {mean}");
    let png = image::open(dir.path().join("isorad.png")).unwrap();
    assert_eq!((png.width(), png.height()), (40, 40));
}

#[test]
fn preview_every_zero_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = isorad(dir.path(), &["render", "--preview-every", "0", "-q"]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("preview-every"), "{}", stderr(&out));
}

/// A scene file's `[solver]` and `[mesh]` settings take effect as the flags
/// that set the same fields do, and flags override them.
#[test]
fn scene_file_settings_act_as_their_flags_and_flags_override_them() {
    let dir = tempfile::tempdir().unwrap();
    let obj = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell/cornell.obj");
    let obj = format!("obj = {:?}\n", obj.to_str().unwrap());
    let settings = "[solver]\nkernel = \"wallace\"\ntolerance = 0.05\n[mesh]\nmax_edge = 100\n";
    std::fs::write(dir.path().join("set.toml"), format!("{obj}{settings}")).unwrap();
    std::fs::write(dir.path().join("bare.toml"), &obj).unwrap();
    let render = |name: &str, args: &[&str]| {
        let exr = format!("{name}.exr");
        let png = format!("{name}.png");
        let mut all = vec!["render", "-o", &exr, "--png", &png, "-q", "--width", "32"];
        all.extend(["--height", "32", "--supersampling", "1"]);
        all.extend(args);
        let out = isorad(dir.path(), &all);
        assert!(out.status.success(), "{}", stderr(&out));
        std::fs::read(dir.path().join(&exr)).unwrap()
    };
    let flags = ["--tolerance", "0.05", "--max-edge", "100"];
    let from_file = render("file", &["set.toml"]);
    let mut with_kernel = vec!["bare.toml", "--form-factor", "wallace"];
    with_kernel.extend(flags);
    assert_eq!(from_file, render("flags", &with_kernel));
    // A flag overrides the file: back to the default kernel.
    let overridden = render("overridden", &["set.toml", "--form-factor", "mixed"]);
    let mut default_kernel = vec!["bare.toml"];
    default_kernel.extend(flags);
    assert_eq!(overridden, render("default", &default_kernel));
    assert_ne!(overridden, from_file, "the kernel made no difference");
    // An invalid flag value is named by its flag.
    let out = isorad(dir.path(), &["render", "set.toml", "--max-edge=-1", "-q"]);
    assert!(
        stderr(&out).contains("invalid value for --max-edge: -1 is not positive"),
        "{}",
        stderr(&out)
    );
}

/// `isorad info` lists a scene's photometric luminaires with their flux
/// (the shipped downlight: 1200 cos^1.5 γ (1 + 0.2 cos 2C) cd, whose flux
/// is 1200 · 0.4 · 2π = 3016 lm; linear interpolation between its 10°
/// steps adds a few tenths of a per cent), and the floor's shadow
/// boundaries under them; `isorad photometry` reads the same file.
#[test]
fn info_lists_photometric_luminaires_and_photometry_reads_their_file() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let scene = root.join("scenes/downlights/downlights.toml");
    let out = isorad(dir.path(), &["info", scene.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(text.contains("3 photometric luminaire(s)"), "{text}");
    let flux: f64 = text
        .lines()
        .find(|l| l.contains("downlight.ies"))
        .and_then(|l| l.split_whitespace().last())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no flux: {text}"));
    let expected = 1200.0 * 0.4 * std::f64::consts::TAU;
    assert!((flux / expected - 1.0).abs() < 0.01, "{flux} lm");
    let ies = root.join("scenes/downlights/downlight.ies");
    let out = isorad(dir.path(), &["photometry", ies.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        text.contains("IESNA:LM-63-2002") && text.contains("peak 1440.00 cd"),
        "{text}"
    );
}

/// `render --falsecolor` writes the view in false colour beside a legend,
/// of luminance or of illuminance.
#[test]
fn render_writes_false_colour_views_of_luminance_and_illuminance() {
    let dir = tempfile::tempdir().unwrap();
    for quantity in ["luminance", "illuminance"] {
        let out = isorad(
            dir.path(),
            &[
                "render",
                "cornell",
                "-q",
                "--width",
                "96",
                "--height",
                "96",
                "--tolerance",
                "0.05",
                "--falsecolor",
                "false.png",
                "--falsecolor-quantity",
                quantity,
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        let picture = ::image::open(dir.path().join("false.png"))
            .unwrap()
            .to_rgb8();
        // The view (96 px) and the legend beside it.
        assert!(
            picture.width() > 96 + 60 && picture.height() >= 96,
            "{:?}",
            picture.dimensions()
        );
        // Not one colour: the bands follow the light.
        let colours: std::collections::HashSet<[u8; 3]> = picture.pixels().map(|p| p.0).collect();
        assert!(colours.len() > 8, "{quantity}: {} colours", colours.len());
    }
    let out = isorad(
        dir.path(),
        &["render", "cornell", "--falsecolor", "false.jpg"],
    );
    assert!(!out.status.success());
    assert!(stderr(&out).contains("--falsecolor false.jpg: the picture is written as .png"));
}

/// Writes two closed rooms side by side (4 × 3 × 4 m, at x = 0 and 10),
/// each lit by a lamp under its ceiling, as `rooms.obj` with its MTL and a
/// scene file `rooms.toml` whose camera stands in the first; the floors
/// are objects `floor_0` and `floor_10`, and elements at most 0.5 m.
fn write_two_closed_rooms(dir: &Path) {
    use glam::DVec3;
    let mut obj = String::from("mtllib rooms.mtl\n");
    let mut count = 0;
    let mut face = |obj: &mut String, (name, material): (&str, &str), quad: &[DVec3]| {
        obj.push_str(&format!("o {name}\nusemtl {material}\n"));
        for p in quad {
            obj.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
        }
        let ids: Vec<String> = (1..=quad.len()).map(|k| (count + k).to_string()).collect();
        obj.push_str(&format!("f {}\n", ids.join(" ")));
        count += quad.len();
    };
    for x in [0.0, 10.0] {
        let offset = DVec3::new(x, 0.0, 0.0);
        for (k, quad) in crate::support::box_faces(DVec3::new(4.0, 3.0, 4.0))
            .into_iter()
            .enumerate()
        {
            let quad: Vec<DVec3> = quad.into_iter().map(|p| p + offset).collect();
            let name = if k == 2 { "floor" } else { "walls" };
            face(&mut obj, (&format!("{name}_{x}"), "wall"), &quad);
        }
        // Counter-clockwise seen from below: the lamp faces down.
        let lamp = [(1.7, 1.7), (2.3, 1.7), (2.3, 2.3), (1.7, 2.3)]
            .map(|(px, pz)| offset + DVec3::new(px, 2.99, pz));
        face(&mut obj, (&format!("lamp_{x}"), "lamp"), &lamp);
    }
    std::fs::write(dir.join("rooms.obj"), obj).unwrap();
    let mtl = "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n";
    std::fs::write(dir.join("rooms.mtl"), mtl).unwrap();
    let camera = "[camera]\nposition = [0.5, 2.0, 0.5]\nlook_at = [2.0, 0.5, 2.0]\n";
    let camera = format!("{camera}up = [0.0, 1.0, 0.0]\nvfov_deg = 60.0\n");
    let scene = format!("obj = \"rooms.obj\"\n[mesh]\nmax_edge = 0.5\n{camera}");
    std::fs::write(dir.join("rooms.toml"), scene).unwrap();
}

/// Two closed rooms ([`write_two_closed_rooms`]) seen from inside the
/// first: the image's ambient term is that room's alone, and an export,
/// which makes the whole term, leaves the image as it was.
#[test]
fn a_view_inside_a_room_renders_the_same_with_or_without_an_export() {
    let dir = tempfile::tempdir().unwrap();
    write_two_closed_rooms(dir.path());
    let render = |name: &str, export: &[&str]| {
        let exr = format!("{name}.exr");
        let png = format!("{name}.png");
        let mut args = vec!["render", "rooms.toml", "-o", &exr, "--png", &png, "-q"];
        args.extend(["--width", "40", "--height", "30"]);
        args.extend(export);
        let out = isorad(dir.path(), &args);
        assert!(out.status.success(), "{}", stderr(&out));
        isorad::render::read_exr(&dir.path().join(&exr)).unwrap()
    };
    let view = render("view", &[]);
    let exported = render("exported", &["--export", "rooms.glb"]);
    assert!(dir.path().join("rooms.glb").exists());
    let lit = view.pixels().iter().filter(|p| p[1] > 0.0).count();
    assert!(lit > view.pixels().len() / 2, "{lit} pixels lit");
    for (a, b) in view.pixels().iter().zip(exported.pixels()) {
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-5 * b[c].max(1e-6),
                "{a:?} against {b:?}"
            );
        }
    }
}

/// `isorad grid` on the work plane of one of two closed rooms, and
/// `isorad probe` on its floor ([`write_two_closed_rooms`]), read what
/// the whole solution, made by the library, gives them: the term they
/// make is the right room's (that it is that room's alone,
/// `tests/it/solver.rs` checks).
#[test]
fn a_grid_and_probes_in_one_room_read_what_the_whole_solution_gives() {
    use isorad::calculation::CalculationGrid;
    let dir = tempfile::tempdir().unwrap();
    write_two_closed_rooms(dir.path());
    let out = isorad(
        dir.path(),
        &[
            "grid",
            "rooms.toml",
            "--surface",
            "floor_0",
            "--height",
            "0.8",
            "--spacing",
            "0.5",
            "--csv",
            "grid.csv",
            "-q",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    std::fs::write(dir.path().join("points.csv"), "0.7,0,3.1\n3.2,0,0.4\n").unwrap();
    let out = isorad(
        dir.path(),
        &["probe", "rooms.toml", "--points", "points.csv", "-q"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let probed: Vec<f64> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .skip(1)
        .map(|row| row.split(',').rev().nth(1).unwrap().parse().unwrap())
        .collect();
    // The whole solution, by the library, from the same file.
    let path = dir.path().join("rooms.toml");
    let loaded = isorad::load_scene(path.to_str().unwrap()).unwrap();
    let settings = isorad::Settings::from_scene_options(&loaded.options).unwrap();
    let mut solver = isorad::Solver::new(loaded.scene, settings).unwrap();
    solver.run();
    let whole = solver.solution(isorad::Ambient::Everywhere, &isorad::phase::silent);
    let shot = solver.solution(isorad::Ambient::Omitted, &isorad::phase::silent);
    let grid = CalculationGrid::on_surface(solver.scene(), "floor_0", 0.8, Some(0.5)).unwrap();
    let (expected, lacking) = (grid.illuminance(&whole), grid.illuminance(&shot));
    let csv = std::fs::read_to_string(dir.path().join("grid.csv")).unwrap();
    let gridded: Vec<f64> = csv
        .lines()
        .filter(|row| row.ends_with(",kept"))
        .map(|row| row.split(',').nth(3).unwrap().parse().unwrap())
        .collect();
    let expected: Vec<(f64, f64)> = expected
        .into_iter()
        .zip(lacking)
        .filter(|(lux, _)| !lux.is_nan())
        .collect();
    assert_eq!(gridded.len(), expected.len());
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-5 * b.abs();
    for (&lux, &(whole, shot)) in gridded.iter().zip(&expected) {
        assert!(close(lux, whole), "{lux} lx, the whole solution {whole} lx");
        assert!(
            whole > 1.01 * shot,
            "{whole} lx with the term, {shot} lx without"
        );
    }
    let points = isorad::scene::load_probe_points(&dir.path().join("points.csv")).unwrap();
    assert_eq!(probed.len(), points.len());
    for (&lux, point) in probed.iter().zip(&points) {
        let probe = whole.probe(point, isorad::ProbeMode::Gather).unwrap();
        let expected = isorad::calculation::illuminance_lux(probe.irradiance);
        assert!(
            close(lux, expected),
            "{lux} lx, the whole solution {expected} lx"
        );
    }
}
