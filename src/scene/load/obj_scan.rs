//! A line-by-line pass over an OBJ text before tobj reads it.
//!
//! tobj reports errors without line numbers and accepts `nan` and `inf` as
//! coordinates. This pass checks what isorad relies on, with line numbers,
//! and records where faces and `usemtl` statements are so that later
//! messages can point at them. Statements are read as tobj reads their
//! canonical form (see [`super::statement`]): blanks and tabs may stand
//! anywhere between tokens.

use std::path::Path;

use crate::error::{Error, Result};

use super::statement::split_statement;

/// What the scan learned about an OBJ text.
#[derive(Debug, Default)]
pub(crate) struct ObjScan {
    /// 1-based line of every face (`f`), in file order: tobj's faces, model
    /// after model, come in this order.
    pub face_lines: Vec<usize>,
    /// Every `usemtl` statement: (1-based line, material name).
    pub usemtl: Vec<(usize, String)>,
    /// Lines holding polylines (`l`), which isorad ignores.
    pub polyline_lines: Vec<usize>,
}

impl ObjScan {
    /// The `usemtl` in force at a line: the last one before it.
    pub fn material_at(&self, line: usize) -> Option<&(usize, String)> {
        self.usemtl.iter().rev().find(|(l, _)| *l < line)
    }
}

/// Counts of vertex data seen so far, to check face indices.
#[derive(Default)]
struct Counts {
    positions: usize,
    texcoords: usize,
    normals: usize,
}

/// Scans an OBJ text; the first malformed statement is an error naming the
/// file and line.
pub(crate) fn scan_obj(path: &Path, text: &str) -> Result<ObjScan> {
    let mut scan = ObjScan::default();
    let mut counts = Counts::default();
    let mut object = String::from("unnamed_object");
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let Some((keyword, rest)) = split_statement(line) else {
            continue;
        };
        let words = rest.split_whitespace();
        let bad = |message: String| Error::ObjParse {
            path: path.to_path_buf(),
            line: Some(number),
            message,
        };
        match keyword {
            "v" => {
                let p = check_position(words).map_err(bad)?;
                if p.iter().any(|c| !c.is_finite()) {
                    return Err(Error::NonFiniteCoordinate {
                        path: path.to_path_buf(),
                        line: Some(number),
                        object: object.clone(),
                    });
                }
                counts.positions += 1;
            }
            "vt" => {
                check_numbers(words, 2, "`vt` needs two numbers").map_err(bad)?;
                counts.texcoords += 1;
            }
            "vn" => {
                check_numbers(words, 3, "`vn` needs three numbers").map_err(bad)?;
                counts.normals += 1;
            }
            "f" => {
                check_face(words, &counts).map_err(bad)?;
                scan.face_lines.push(number);
            }
            "l" => scan.polyline_lines.push(number),
            "o" | "g" => object = object_name(rest),
            "usemtl" => {
                // The name is the rest of the line, spaces inside it kept.
                if rest.is_empty() {
                    return Err(bad("`usemtl` without a material name".into()));
                }
                scan.usemtl.push((number, rest.to_owned()));
            }
            _ => {}
        }
    }
    Ok(scan)
}

/// An object or group name (the rest of an `o` or `g` line), as tobj reads
/// it.
fn object_name(rest: &str) -> String {
    if rest.is_empty() {
        "unnamed_object".to_owned()
    } else {
        rest.to_owned()
    }
}

/// A `v` statement: x y z, then nothing, a weight w (≠ 0) or a colour r g b.
/// Returns the position (x, y, z)/w as tobj computes it, in f32.
fn check_position(mut words: std::str::SplitWhitespace) -> Result<[f32; 3], String> {
    let mut p = [0.0f32; 3];
    for c in &mut p {
        *c = words
            .next()
            .and_then(|w| w.parse().ok())
            .ok_or("`v` needs three numbers (x y z)")?;
    }
    let rest: Vec<&str> = words.collect();
    match rest.len() {
        0 => Ok(p),
        1 => {
            let w: f32 = rest[0].parse().map_err(|_| "`v` weight is not a number")?;
            if w == 0.0 {
                return Err("`v` weight is zero".into());
            }
            Ok(p.map(|c| c / w))
        }
        3 => Ok(p),
        n => Err(format!("`v` takes 3, 4 or 6 numbers, not {}", n + p.len())),
    }
}

/// `count` numbers in a row.
fn check_numbers(
    mut words: std::str::SplitWhitespace,
    count: usize,
    message: &str,
) -> Result<(), String> {
    for _ in 0..count {
        if words.next().and_then(|w| w.parse::<f32>().ok()).is_none() {
            return Err(message.to_owned());
        }
    }
    Ok(())
}

/// An `f` statement: at least one vertex `v`, `v/vt`, `v//vn` or `v/vt/vn`,
/// with 1-based (or negative, relative) indices to data defined above.
fn check_face(words: std::str::SplitWhitespace, counts: &Counts) -> Result<(), String> {
    let mut vertices = 0;
    for word in words {
        let parts: Vec<&str> = word.split('/').collect();
        if parts.len() > 3 || parts[0].is_empty() {
            return Err(format!(
                "`{word}` is not a face vertex (v, v/vt, v//vn or v/vt/vn)"
            ));
        }
        let limits = [
            ("vertex", counts.positions),
            ("texture coordinate", counts.texcoords),
            ("normal", counts.normals),
        ];
        for (part, (what, count)) in parts.iter().zip(limits) {
            if !part.is_empty() {
                check_index(part, count, what)?;
            }
        }
        vertices += 1;
    }
    if vertices == 0 {
        return Err("face without vertices".into());
    }
    Ok(())
}

/// A 1-based index i ∈ 1..=count, or a relative one −count..=−1.
fn check_index(word: &str, count: usize, what: &str) -> Result<(), String> {
    let index: isize = word
        .parse()
        .map_err(|_| format!("`{word}` is not a {what} index"))?;
    if index != 0 && index.unsigned_abs() <= count {
        Ok(())
    } else {
        Err(format!(
            "{what} index {index} is out of range: {count} defined so far"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scan(text: &str) -> Result<ObjScan> {
        scan_obj(Path::new("t.obj"), text)
    }

    #[test]
    fn records_faces_and_materials() {
        let s =
            scan("v 0 0 0\nv 1 0 0\nv 0 1 0 1\nusemtl a\nf 1 2 3\nf -3 -2 -1\nl 1 2\n").unwrap();
        assert_eq!(s.face_lines, vec![5, 6]);
        assert_eq!(s.usemtl, vec![(4, "a".to_owned())]);
        assert_eq!(s.polyline_lines, vec![7]);
        assert_eq!(s.material_at(5).map(|m| m.0), Some(4));
        assert!(s.material_at(3).is_none());
    }

    /// Regression: an indented `usemtl` or `o` (or a tab after the keyword)
    /// gave the name with the keyword in it, `usemtl white`.
    #[test]
    fn indented_statements_read_as_plain_ones() {
        let plain = scan("o box\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl white\nf 1 2 3\n").unwrap();
        let indented = scan(
            "\t o\tbox \n  v 0 0 0\t\n\tv\t1 0 0\n v 0\t 1 0 \n \tusemtl\t white \t\n\t\tf 1\t2 3  \n",
        )
        .unwrap();
        assert_eq!(indented.usemtl, vec![(5, "white".to_owned())]);
        assert_eq!(indented.usemtl, plain.usemtl);
        assert_eq!(indented.face_lines, plain.face_lines);
        let message = scan("  o\tbox\n\tv 0 nan 0\n").unwrap_err().to_string();
        assert!(message.starts_with("t.obj:2: object `box`"), "{message}");
        // A name with spaces inside keeps them.
        let spaced = scan(" usemtl\tcold  white \n").unwrap();
        assert_eq!(spaced.usemtl, vec![(1, "cold  white".to_owned())]);
    }

    #[test]
    fn errors_name_the_line() {
        let cases = [
            ("v 1 2\n", "t.obj:1"),
            ("v 0 0 0\nf 1 2 x\n", "t.obj:2"),
            ("v 0 0 0\n\nf 1 2 4\n", "t.obj:3"),
            ("v 0 0 0\nf 0 1 1\n", "t.obj:2"),
            ("v 0 0 0\nf 1/1 1 1\n", "t.obj:2"),
            ("v 0 0 0 0\n", "t.obj:1"),
            ("f\n", "t.obj:1"),
            ("usemtl\n", "t.obj:1"),
            ("o box\nv 0 nan 0\n", "t.obj:2: object `box`"),
            ("v 1e39 0 0\n", "t.obj:1"),
            ("v 1 1 1 1e-39\n", "t.obj:1"),
        ];
        for (text, expected) in cases {
            let message = scan(text).unwrap_err().to_string();
            assert!(message.starts_with(expected), "{text:?}: {message}");
        }
    }
}
