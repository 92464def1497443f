//! Luminaire files and lists as users bring them (issue 57): only regular
//! files of a sane size are read, a byte-order mark does not hide the
//! format line, EULUMDAT's counts must match its data, a `[[luminaire]]`
//! table's fault names the scene file, its line and the key, and tables
//! naming one file share one prepared distribution.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use isorad::photometry::{
    MAX_FILE_BYTES, PhotometricFile, PhotometricFormat, parse_photometric_bytes,
    read_photometric_file,
};
use isorad::{Error, load_scene};

/// A file of the bad-inputs catalogue.
fn catalogue(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/bad_inputs")
        .join(name)
}

fn bytes_of(name: &str) -> Vec<u8> {
    std::fs::read(catalogue(name)).unwrap()
}

/// `bytes` with a UTF-8 byte-order mark before them.
fn with_bom(bytes: &[u8]) -> Vec<u8> {
    [b"\xEF\xBB\xBF".as_slice(), bytes].concat()
}

#[test]
fn a_byte_order_mark_does_not_hide_the_format_line_or_the_company() {
    let dir = tempfile::tempdir().unwrap();
    let ies = dir.path().join("bom.ies");
    std::fs::write(&ies, with_bom(&bytes_of("ies_good.ies"))).unwrap();
    let Ok(PhotometricFile::Ies(file)) = read_photometric_file(&ies) else {
        panic!("the IES file with a BOM does not read");
    };
    assert_eq!(file.format, "IES:LM-63-2019");
    assert_eq!(
        file.keywords[0],
        ("TEST".to_owned(), "isorad seed".to_owned())
    );
    let ldt = dir.path().join("bom.ldt");
    std::fs::write(&ldt, with_bom(&bytes_of("ldt_good.ldt"))).unwrap();
    let Ok(PhotometricFile::Eulumdat(file)) = read_photometric_file(&ldt) else {
        panic!("the EULUMDAT file with a BOM does not read");
    };
    assert_eq!(file.company, "isorad seed");
    // The bytes read as the file reader reads them, for the fuzz targets.
    let parsed =
        parse_photometric_bytes(&with_bom(&bytes_of("ies_good.ies")), PhotometricFormat::Ies);
    assert!(matches!(parsed, Ok(PhotometricFile::Ies(f)) if f.format == "IES:LM-63-2019"));
}

#[test]
fn only_regular_files_of_at_most_16_mib_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.ies");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let huge = dir.path().join("huge.ies");
    let file = std::fs::File::create(&huge).unwrap();
    file.set_len(MAX_FILE_BYTES + 1).unwrap();
    let cases = [
        (dir.path().to_path_buf(), "cannot be read: a directory"),
        (PathBuf::from("/dev/zero"), "not a regular file"),
        (fifo, "not a regular file"),
        (huge, "larger than 16 MiB"),
        (dir.path().join("nowhere.ies"), "cannot be read"),
    ];
    for (path, message) in cases {
        let error = read_photometric_file(&path).unwrap_err();
        let Error::Photometry {
            path: named, line, ..
        } = &error
        else {
            panic!("{}: {error:?}", path.display());
        };
        assert_eq!((named, *line), (&path, None));
        assert!(error.to_string().contains(message), "{error}");
    }
}

#[test]
fn eulumdat_counts_must_match_the_data_as_lm_63_ones_do() {
    let good = bytes_of("ldt_good.ldt");
    let read = |tail: &str| {
        let bytes = [good.as_slice(), tail.as_bytes()].concat();
        parse_photometric_bytes(&bytes, PhotometricFormat::Eulumdat)
    };
    // The good file has 92 lines, the table's last value on line 92.
    let cases = [
        (
            "0.0\r\n",
            93,
            "`0.0` after the intensity table, which ends at line 92",
        ),
        ("12.5\r\n7\r\n", 93, "`12.5` after"),
        ("\r\n\r\nEND\r\n", 95, "`END` after"),
        ("\r\n 0 0 0\r\n", 94, "the counts do not match the data"),
    ];
    for (tail, line, message) in cases {
        let problem = read(tail).unwrap_err();
        assert_eq!(problem.line, Some(line), "{tail:?}: {problem:?}");
        assert!(problem.message.contains(message), "{}", problem.message);
    }
    // Blank lines after the table are no data.
    assert!(read("\r\n   \r\n\t\r\n").is_ok());
    // The same defect in LM-63, for comparison.
    let ies = [bytes_of("ies_good.ies").as_slice(), b"5\n"].concat();
    let problem = parse_photometric_bytes(&ies, PhotometricFormat::Ies).unwrap_err();
    assert!(
        problem.message.contains("counts do not match"),
        "{problem:?}"
    );
}

/// A scene folder: `fine_basic.obj` and its MTL, the catalogue's IES and
/// EULUMDAT files (also as `b.ies`), and `scene.toml` holding `text`.
fn scene_folder(text: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "fine_basic.obj",
        "common.mtl",
        "ies_good.ies",
        "ldt_good.ldt",
    ] {
        std::fs::copy(catalogue(name), dir.path().join(name)).unwrap();
    }
    std::fs::copy(catalogue("ies_good.ies"), dir.path().join("b.ies")).unwrap();
    std::fs::create_dir(dir.path().join("lamps")).unwrap();
    std::fs::write(dir.path().join("scene.toml"), text).unwrap();
    dir
}

/// A `[[luminaire]]` table naming `ies`, with `extra` lines after it.
fn table(ies: &str, extra: &str) -> String {
    format!(
        "\n[[luminaire]]\nies = {ies}\nposition = [0.0, 0.9, 0.0]\naim = [0.0, -1.0, 0.0]\n\
         c0 = [1.0, 0.0, 0.0]\n{extra}"
    )
}

#[test]
fn a_luminaire_tables_fault_names_the_scene_file_its_line_and_the_key() {
    let good = table("\"ies_good.ies\"", "");
    // (second table, its key at fault, the line of its value, the message).
    let cases = [
        (table("\"\"", ""), "ies", 10, "names no file"),
        (table("\"lamps\"", ""), "ies", 10, "a directory"),
        (table("\"/dev/zero\"", ""), "ies", 10, "not a regular file"),
        (
            table("\"nowhere.ies\"", ""),
            "ies",
            10,
            "nowhere.ies: cannot be read",
        ),
        (
            table("\"fine_basic.obj\"", ""),
            "ies",
            10,
            "fine_basic.obj: no TILT= line",
        ),
        (
            table("\"ldt_good.ldt\"", "").replace("[0.0, 0.9, 0.0]", "[0.0, nan, 0.0]"),
            "position",
            11,
            "must be finite",
        ),
        (
            table("\"b.ies\"", "").replace("c0 = [1.0, 0.0, 0.0]", "c0 = [0.0, -2.0, 0.0]"),
            "c0",
            13,
            "runs along aim",
        ),
        (
            table("\"b.ies\"", "multiplier = -0.5\n"),
            "multiplier",
            14,
            "≥ 0",
        ),
        (
            table("\"b.ies\"", "\ncolor = [0, 0, 0]\n"),
            "color",
            15,
            "positive luminance",
        ),
    ];
    for (second, key_at_fault, line_at_fault, message) in cases {
        let dir = scene_folder(&format!("obj = \"fine_basic.obj\"\n{good}{second}"));
        let scene = dir.path().join("scene.toml");
        let error = load_scene(scene.to_str().unwrap()).err().unwrap();
        let Error::SceneLuminaire {
            path,
            line,
            index,
            key,
            ..
        } = &error
        else {
            panic!("{second}: {error:?}");
        };
        assert_eq!(
            (path, *line, *index, key.as_str()),
            (&scene, line_at_fault, 2, key_at_fault),
            "{error}"
        );
        let text = error.to_string();
        assert!(text.contains(message), "{message}: {text}");
        assert!(
            text.starts_with(&format!(
                "{}:{line_at_fault}: [[luminaire]] 2: {key_at_fault} = ",
                scene.display()
            )),
            "{text}"
        );
    }
}

#[test]
fn luminaires_naming_one_file_share_one_prepared_distribution() {
    let text = format!(
        "obj = \"fine_basic.obj\"\n{}{}{}{}",
        table("\"ies_good.ies\"", ""),
        table("\"./ies_good.ies\"", "multiplier = 0.5\n"),
        table("\"b.ies\"", ""),
        table("\"ies_good.ies\"", "color = [1.0, 0.5, 0.25]\n"),
    );
    let dir = scene_folder(&text);
    let loaded = load_scene(dir.path().join("scene.toml").to_str().unwrap()).unwrap();
    let l = &loaded.scene.luminaires;
    assert_eq!(l.len(), 4);
    // One file, however spelt, is one distribution; another file (even with
    // the same text) is another.
    assert!(Arc::ptr_eq(&l[0].distribution, &l[1].distribution));
    assert!(Arc::ptr_eq(&l[0].distribution, &l[3].distribution));
    assert!(!Arc::ptr_eq(&l[0].distribution, &l[2].distribution));
    // The flux is the distribution's, scaled by each placement.
    let flux = l[0].distribution.flux(isorad::photometry::FLUX_REFINEMENT);
    let lumens = |k: usize| l[k].power().luminance() * isorad::photometry::LUMENS_PER_WATT;
    assert!((lumens(0) / flux - 1.0).abs() < 1e-12);
    assert!((lumens(1) / flux - 0.5).abs() < 1e-12);
    assert!((lumens(2) / flux - 1.0).abs() < 1e-12);
    assert!((lumens(3) / flux - 1.0).abs() < 1e-9);
    assert_eq!(l[1].name, "./ies_good.ies");
}
