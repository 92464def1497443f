//! Wavefront OBJ + MTL scenes, read with tobj.
//!
//! Every face (`f`) becomes one [`Surface`](crate::scene::Surface) — quads and n-gons stay whole —
//! named after its object or group (`o`/`g`), with the material of the last
//! `usemtl`. MTL `Kd` is the diffuse reflectance ρ (0 ≤ ρ < 1 per channel),
//! `Ke` the emitted radiance L_e (≥ 0), as in pbrt and Mitsuba.
//!
//! Faces that are slightly off plane are projected onto their best-fit
//! plane; clearly non-planar faces are split into triangles and degenerate
//! ones skipped, with a warning in [`Scene::warnings`] (see
//! [`clean_polygon`]). Polylines (`l`) are ignored with a warning.
//!
//! Errors name the file and the line or object: malformed statements,
//! non-finite coordinates, out-of-range `Kd`/`Ke`, an unreadable MTL file, a
//! face without a known material, and a scene without surfaces or without
//! an emitter.

use std::borrow::Cow;
use std::cell::RefCell;
use std::path::Path;

use glam::DVec3;

use crate::error::{Error, Result};

use super::build::check_not_empty;
use super::coplanar_merge::merge_scene_faces;
use super::mtl::{parse_mtl, to_material};
use super::obj_scan::{ObjScan, scan_obj};
use super::repair_report::RepairReport;
use super::source::{Disk, SourceFiles};
use super::statement::{canonical_line, canonical_text, split_statement};
use crate::scene::geometry::polygon::clean_polygon;
use crate::scene::material::Material;
use crate::scene::{Scene, Warning};

/// Loads an OBJ file and the MTL libraries it names (relative to the OBJ's
/// directory), merging adjacent coplanar faces (see
/// [`super::merge_coplanar_faces`]). The scene has no camera; see
/// [`Scene::camera_or_default`].
pub fn load_obj(path: &Path) -> Result<Scene> {
    load_obj_from(path, &Disk, true, false)
}

/// [`load_obj`] reading the OBJ and its MTL files from `files`; adjacent
/// coplanar faces are merged when `merge_coplanar` holds. With
/// `lit_elsewhere` (a scene file's luminaires light it) the scene need not
/// have an emitting face.
pub(crate) fn load_obj_from(
    path: &Path,
    files: &dyn SourceFiles,
    merge_coplanar: bool,
    lit_elsewhere: bool,
) -> Result<Scene> {
    // Read and check the text, with line numbers.
    let text = files.read_to_string(path)?;
    let scan = scan_obj(path, &text)?;
    // Parse with tobj, loading each MTL through our checks.
    let parsed = parse_with_tobj(path, &text, files)?;
    let mut scene = Scene {
        materials: parsed.materials,
        warnings: parsed.warnings,
        ..Scene::default()
    };
    if !scan.polyline_lines.is_empty() {
        scene.warnings.push(Warning {
            message: format!(
                "{}:{}: {} polyline (`l`) statement(s) ignored",
                path.display(),
                scan.polyline_lines[0],
                scan.polyline_lines.len()
            ),
        });
    }
    // One face, one or more surfaces.
    add_surfaces(path, &scan, &parsed.models, &mut scene)?;
    if merge_coplanar {
        merge_scene_faces(path, &mut scene);
    }
    // A lamp modelled as faces on many planes is one luminaire.
    scene.join_emitting_bodies();
    // With luminaires to come, the scene file checks once they are there.
    if !lit_elsewhere {
        check_not_empty(path, &scene)?;
    }
    Ok(scene)
}

/// tobj's output, with materials converted.
struct Parsed {
    models: Vec<tobj::Model>,
    materials: Vec<Material>,
    warnings: Vec<Warning>,
}

/// Runs tobj on the text (see [`for_tobj`]), with a material loader that
/// reads MTL files through `files` and checks them.
fn parse_with_tobj(path: &Path, text: &str, files: &dyn SourceFiles) -> Result<Parsed> {
    let dir = path.parent().unwrap_or(Path::new(""));
    let failure: RefCell<Option<Error>> = RefCell::new(None);
    let warnings: RefCell<Vec<Warning>> = RefCell::new(Vec::new());
    let loader = |mtl: &Path| -> tobj::MTLLoadResult {
        let mtl_path = dir.join(mtl);
        match load_mtl(path, mtl, &mtl_path, files) {
            Ok((parsed, mut w)) => {
                warnings.borrow_mut().append(&mut w);
                parsed
            }
            Err(e) => {
                failure.borrow_mut().get_or_insert(e);
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    };
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: false,
        ..Default::default()
    };
    let source = for_tobj(text);
    let result = tobj::load_obj_buf(&mut source.as_bytes(), &options, loader);
    // A failed MTL is the first thing to report.
    if let Some(e) = failure.into_inner() {
        return Err(e);
    }
    let tobj_error = |e: tobj::LoadError| Error::ObjParse {
        path: path.to_path_buf(),
        line: None,
        message: e.to_string(),
    };
    let (models, materials) = result.map_err(tobj_error)?;
    let materials = materials.map_err(tobj_error)?;
    Ok(Parsed {
        models,
        materials: materials.iter().map(|m| to_material(m).0).collect(),
        warnings: warnings.into_inner(),
    })
}

/// The OBJ text as tobj should read it, line numbers kept: every statement
/// in canonical form (tobj reads `o`, `g`, `usemtl` and `mtllib` names
/// after the line's first character or first space, so leading blanks or a
/// tab after the keyword would end up in the name), polyline statements
/// commented out (tobj would read an `l` of three or more points as a face)
/// and vertex colours dropped (tobj fails on a file where only some vertices
/// have one; isorad does not use them).
fn for_tobj(text: &str) -> Cow<'_, str> {
    canonical_text(text, |line| match split_statement(line) {
        Some(("l", _)) => "# polyline ignored".into(),
        Some(("v", rest)) if rest.split_whitespace().count() == 6 => {
            let xyz: Vec<&str> = rest.split_whitespace().take(3).collect();
            format!("v {}", xyz.join(" ")).into()
        }
        _ => canonical_line(line),
    })
}

/// Reads, checks and parses one MTL library named `mtl` by the OBJ at `obj`.
fn load_mtl(
    obj: &Path,
    mtl: &Path,
    mtl_path: &Path,
    files: &dyn SourceFiles,
) -> Result<(tobj::MTLLoadResult, Vec<Warning>)> {
    let text = files
        .read_to_string(mtl_path)
        .map_err(|e| Error::MissingMtl {
            path: obj.to_path_buf(),
            mtl: mtl.display().to_string(),
            message: match e {
                Error::Io { path, source } => format!("{}: {source}", path.display()),
                other => other.to_string(),
            },
        })?;
    let parsed = parse_mtl(mtl_path, &text)?;
    let materials = parsed.as_ref().map(|p| p.0.as_slice()).unwrap_or_default();
    let warnings = materials
        .iter()
        .filter_map(|m| to_material(m).1)
        .map(|message| Warning {
            message: format!("{}: {message}", mtl_path.display()),
        })
        .collect();
    Ok((parsed, warnings))
}

/// Turns every face of every model into surfaces, in file order.
fn add_surfaces(
    path: &Path,
    scan: &ObjScan,
    models: &[tobj::Model],
    scene: &mut Scene,
) -> Result<()> {
    let mut face = 0; // index into scan.face_lines
    let mut report = RepairReport::default();
    for model in models {
        let mesh = &model.mesh;
        let arities = face_arities(mesh);
        let first_line = scan.face_lines.get(face).copied();
        if arities.is_empty() {
            continue;
        }
        // Every face needs a material that a library defines.
        let material = mesh
            .material_id
            .filter(|&m| m < scene.materials.len())
            .ok_or_else(|| missing_material(path, scan, &model.name, first_line))?;
        let mut start = 0;
        for arity in arities {
            let line = scan.face_lines.get(face).copied();
            let vertices = face_vertices(mesh, start, arity).ok_or_else(|| Error::ObjParse {
                path: path.to_path_buf(),
                line,
                message: format!("object `{}`: face refers to a missing vertex", model.name),
            })?;
            if vertices.iter().any(|v| !v.is_finite()) {
                return Err(Error::NonFiniteCoordinate {
                    path: path.to_path_buf(),
                    line,
                    object: model.name.clone(),
                });
            }
            let cleaned = clean_polygon(&model.name, material, &vertices);
            if let (Some(message), Some(kind)) = (&cleaned.warning, cleaned.repair) {
                report.note(path, line, &model.name, kind, message, &mut scene.warnings);
            }
            scene.surfaces.extend(cleaned.surfaces);
            start += arity;
            face += 1;
        }
    }
    report.finish(path, &mut scene.warnings);
    Ok(())
}

/// The number of vertices of each face; tobj leaves `face_arities` empty
/// when every face is a triangle.
fn face_arities(mesh: &tobj::Mesh) -> Vec<usize> {
    if mesh.face_arities.is_empty() {
        vec![3; mesh.indices.len() / 3]
    } else {
        mesh.face_arities.iter().map(|&a| a as usize).collect()
    }
}

/// The positions of the face whose indices start at `start`.
fn face_vertices(mesh: &tobj::Mesh, start: usize, arity: usize) -> Option<Vec<DVec3>> {
    let indices = mesh.indices.get(start..start + arity)?;
    indices
        .iter()
        .map(|&i| {
            let i = i as usize * 3;
            let p = mesh.positions.get(i..i + 3)?;
            Some(DVec3::new(
                f64::from(p[0]),
                f64::from(p[1]),
                f64::from(p[2]),
            ))
        })
        .collect()
}

/// The error for a model without a known material: names the `usemtl` in
/// force at its first face, or that face when there is none.
fn missing_material(path: &Path, scan: &ObjScan, object: &str, face_line: Option<usize>) -> Error {
    let usemtl = face_line.and_then(|l| scan.material_at(l));
    Error::MissingMaterial {
        path: path.to_path_buf(),
        line: usemtl.map(|(l, _)| *l).or(face_line),
        object: object.to_owned(),
        material: usemtl.map(|(_, m)| m.clone()).unwrap_or_default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MTL: &str = "newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 1 1 1\n";

    /// Files held in memory: (path, text).
    struct Memory(Vec<(&'static str, String)>);

    impl SourceFiles for Memory {
        fn read_to_string(&self, path: &Path) -> Result<String> {
            let file = self.0.iter().find(|(p, _)| Path::new(p) == path);
            Ok(file.map(|(_, text)| text.clone()).unwrap_or_default())
        }
    }

    /// Loads `s.obj` with text `obj` and the library `mtl` holding [`MTL`].
    fn load(obj: String, mtl: &'static str) -> Scene {
        let files = Memory(vec![("s.obj", obj), (mtl, MTL.to_owned())]);
        load_obj_from(Path::new("s.obj"), &files, false, false).unwrap()
    }

    /// A lamp over a floor, its MTL library named `mtl`.
    fn lamp_and_floor(mtl: &str) -> String {
        format!(
            "mtllib {mtl}\no lamp\nv 0 1 0\nv 0 1 1\nv 1 1 1\nv 1 1 0\nusemtl lamp\nf 1 2 3 4\n\
             o floor\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nusemtl white\nf 5 6 7 8\n"
        )
    }

    /// Every line indented, blanks after it and tabs between its tokens.
    fn indented(text: &str) -> String {
        text.lines()
            .enumerate()
            .map(|(i, line)| {
                let (keyword, rest) = line.split_once(' ').unwrap();
                let lead = [" \t", "\t", "   "][i % 3];
                format!("{lead}{keyword}\t \t{} \t\n", rest.replace(' ', "\t "))
            })
            .collect()
    }

    /// Regression: tobj read an indented `mtllib base.mtl` as the file name
    /// `mtllib base.mtl` (and `o`, `usemtl` likewise).
    #[test]
    fn tobj_reads_indented_statements() {
        let canonical = for_tobj("  mtllib base.mtl\n\to\tlamp \n\n usemtl\t lamp\r\nl 1 2\n");
        assert_eq!(
            canonical,
            "mtllib base.mtl\no lamp\n\nusemtl lamp\n# polyline ignored"
        );
        let plain = load(lamp_and_floor("m.mtl"), "m.mtl");
        let indented = load(indented(&lamp_and_floor("m.mtl")), "m.mtl");
        assert_eq!(indented.surfaces, plain.surfaces);
        assert_eq!(indented.materials, plain.materials);
        assert!(indented.warnings.is_empty());
    }

    /// A library name with spaces inside stays one name, whatever stands
    /// around it.
    #[test]
    fn mtllib_names_keep_their_spaces() {
        let scene = load(
            format!("\t{}", lamp_and_floor("\t my  room.mtl ")),
            "my  room.mtl",
        );
        assert_eq!(scene.materials.len(), 2);
    }
}
