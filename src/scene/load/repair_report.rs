//! One short report of what loading an OBJ repaired or skipped: a few
//! examples of each kind of repair with their lines, then one line per
//! kind with its count, instead of a line per face (a modelling program's
//! export can hold thousands of degenerate faces).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use super::coplanar_merge::thousands;
use crate::scene::Warning;
use crate::scene::geometry::repair::RepairKind;

/// Faces of each kind reported with their own line.
pub(crate) const EXAMPLES_PER_KIND: usize = 3;

/// The repairs of one kind.
#[derive(Debug, Default)]
struct Tally {
    faces: usize,
    objects: BTreeSet<String>,
    first_line: Option<usize>,
    first_object: String,
}

/// The repairs seen so far, by kind.
#[derive(Debug, Default)]
pub(crate) struct RepairReport {
    kinds: BTreeMap<RepairKind, Tally>,
}

impl RepairReport {
    /// Counts a face of `object` at `line` repaired or skipped as `kind`;
    /// the first [`EXAMPLES_PER_KIND`] of each kind are reported with
    /// `message`, prefixed with the file and line.
    pub(crate) fn note(
        &mut self,
        path: &Path,
        line: Option<usize>,
        object: &str,
        kind: RepairKind,
        message: &str,
        warnings: &mut Vec<Warning>,
    ) {
        let tally = self.kinds.entry(kind).or_default();
        if tally.faces == 0 {
            tally.first_line = line;
            tally.first_object = object.to_owned();
        }
        tally.faces += 1;
        if !tally.objects.contains(object) {
            tally.objects.insert(object.to_owned());
        }
        if tally.faces <= EXAMPLES_PER_KIND {
            warnings.push(located(path, line, message));
        }
    }

    /// One line per kind with more faces than its examples: how many, in
    /// how many objects, and where the first is.
    pub(crate) fn finish(self, path: &Path, warnings: &mut Vec<Warning>) {
        for (kind, tally) in self.kinds {
            if tally.faces <= EXAMPLES_PER_KIND {
                continue;
            }
            let objects = tally.objects.len();
            let first = match tally.first_line {
                Some(line) => format!("first at line {line}, object `{}`", tally.first_object),
                None => format!("first in object `{}`", tally.first_object),
            };
            warnings.push(Warning {
                message: format!(
                    "{}: {} faces {} (in {objects} object{}; {first}; {} shown above)",
                    path.display(),
                    thousands(tally.faces),
                    kind.summary(),
                    if objects == 1 { "" } else { "s" },
                    EXAMPLES_PER_KIND,
                ),
            });
        }
    }
}

/// A warning prefixed with the file and line.
pub(crate) fn located(path: &Path, line: Option<usize>, message: &str) -> Warning {
    let place = match line {
        Some(l) => format!("{}:{l}", path.display()),
        None => path.display().to_string(),
    };
    Warning {
        message: format!("{place}: {message}"),
    }
}
