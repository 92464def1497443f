//! The page's files, built into the binary (no network and no file system
//! at run time): the only paths the server answers with a file.

/// One embedded file.
pub struct Asset {
    /// The request path that names it.
    pub path: &'static str,
    pub content_type: &'static str,
    pub bytes: &'static [u8],
}

macro_rules! asset {
    ($path:literal, $file:literal, $type:expr) => {
        Asset {
            path: $path,
            content_type: $type,
            bytes: include_bytes!(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/assets/viewer/",
                $file
            )),
        }
    };
}

const JS: &str = "text/javascript; charset=utf-8";

/// Every file the page is made of.
pub const ASSETS: &[Asset] = &[
    asset!("/", "index.html", "text/html; charset=utf-8"),
    asset!("/index.html", "index.html", "text/html; charset=utf-8"),
    asset!("/viewer.css", "viewer.css", "text/css; charset=utf-8"),
    asset!("/js/main.js", "js/main.js", JS),
    asset!("/js/renderer.js", "js/renderer.js", JS),
    asset!("/js/navigation.js", "js/navigation.js", JS),
    asset!("/js/falsecolor.js", "js/falsecolor.js", JS),
    asset!("/js/connection.js", "js/connection.js", JS),
    asset!("/js/picking.js", "js/picking.js", JS),
    asset!("/js/linear.js", "js/linear.js", JS),
    asset!("/js/ui.js", "js/ui.js", JS),
];

/// The embedded file a request path names, if any: an exact match, so no
/// path reaches anything else.
pub fn asset(path: &str) -> Option<&'static Asset> {
    ASSETS.iter().find(|asset| asset.path == path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_listed_paths_are_served() {
        assert!(asset("/").is_some_and(|a| a.bytes.starts_with(b"<!")));
        assert!(asset("/js/main.js").is_some());
        for path in [
            "/../Cargo.toml",
            "/js/../index.html",
            "//etc/passwd",
            "/js/",
            "",
        ] {
            assert!(asset(path).is_none(), "{path}");
        }
    }
}
