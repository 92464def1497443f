//! One statement of an OBJ or MTL file: a keyword and the rest of its line.
//!
//! Both formats allow blanks and tabs anywhere between tokens, leading and
//! trailing included (and a CR left over from a CRLF line end). isorad's own
//! checks read statements through [`split_statement`]; tobj, which reads
//! some names as "everything after the first character" or "after the first
//! space", is handed the text in [`canonical_text`] form, one line for one
//! line so that line numbers stay those of the file.

use std::borrow::Cow;

/// A line's keyword and the rest of it, the blanks and tabs around both
/// removed; `None` for a blank line. Whitespace inside the rest (a file or
/// material name with spaces) is kept as written.
#[must_use]
pub(crate) fn split_statement(line: &str) -> Option<(&str, &str)> {
    let line = line.trim();
    if line.is_empty() {
        return None;
    }
    Some(match line.split_once(char::is_whitespace) {
        Some((keyword, rest)) => (keyword, rest.trim_start()),
        None => (line, ""),
    })
}

/// The line as `keyword rest`, one space between and nothing around; a
/// blank line becomes empty. Borrowed when the line already reads so.
#[must_use]
pub(crate) fn canonical_line(line: &str) -> Cow<'_, str> {
    let Some((keyword, rest)) = split_statement(line) else {
        return Cow::Borrowed("");
    };
    let trimmed = line.trim();
    if rest.is_empty() {
        Cow::Borrowed(keyword)
    } else if trimmed.len() == keyword.len() + 1 + rest.len()
        && trimmed.as_bytes()[keyword.len()] == b' '
    {
        Cow::Borrowed(trimmed)
    } else {
        Cow::Owned(format!("{keyword} {rest}"))
    }
}

/// The text with every line passed through `rewrite` (which may return
/// [`canonical_line`] or a replacement statement), lines joined by `\n`, so
/// that line n of the result comes from line n of `text`. Borrowed when no
/// line changed.
#[must_use]
pub(crate) fn canonical_text<'a>(
    text: &'a str,
    rewrite: impl Fn(&'a str) -> Cow<'a, str>,
) -> Cow<'a, str> {
    let lines: Vec<Cow<str>> = text.lines().map(rewrite).collect();
    if lines.iter().zip(text.lines()).all(|(new, old)| new == old) {
        return Cow::Borrowed(text);
    }
    Cow::Owned(lines.join("\n"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blanks_and_tabs_around_tokens_are_dropped() {
        assert_eq!(
            split_statement(" \tmtllib  base.mtl \t"),
            Some(("mtllib", "base.mtl"))
        );
        assert_eq!(
            split_statement("usemtl\t \twhite\r"),
            Some(("usemtl", "white"))
        );
        assert_eq!(split_statement("\to"), Some(("o", "")));
        assert_eq!(split_statement("#comment"), Some(("#comment", "")));
        assert_eq!(split_statement(" \t \r"), None);
        // A name with spaces inside keeps them.
        assert_eq!(
            split_statement("mtllib my  room.mtl "),
            Some(("mtllib", "my  room.mtl"))
        );
    }

    #[test]
    fn canonical_lines_have_one_space_after_the_keyword() {
        assert_eq!(canonical_line("\t  mtllib base.mtl  "), "mtllib base.mtl");
        assert_eq!(canonical_line("o\tlamp"), "o lamp");
        assert_eq!(canonical_line("f\t1  2\t3"), "f 1  2\t3");
        assert_eq!(canonical_line("   "), "");
        assert!(matches!(canonical_line("v 1 2 3"), Cow::Borrowed(_)));
    }

    #[test]
    fn canonical_text_keeps_line_numbers() {
        let text = "v 0 0 0\n\n\tv 1 0 0\r\n  \nf 1 2 3\n";
        let canonical = canonical_text(text, canonical_line);
        assert_eq!(canonical, "v 0 0 0\n\nv 1 0 0\n\nf 1 2 3");
        assert_eq!(canonical.lines().count(), text.lines().count());
        let plain = "v 0 0 0\nf 1 2 3\n";
        assert!(matches!(
            canonical_text(plain, canonical_line),
            Cow::Borrowed(_)
        ));
    }
}
