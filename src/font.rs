//! The one font of the plot and picture writers (`study`, `calculation`),
//! bundled with the crate.
//!
//! plotters, built without its system-font support, draws text with
//! ab_glyph from fonts registered by name; without one, drawing text on a
//! bitmap panics and text sizes cannot be estimated (which SVG charts need
//! too). DejaVu Sans ships in `assets/fonts` under its permissive licence
//! (`assets/fonts/LICENSE-DejaVu.txt`) and is registered once, as plotters'
//! `"sans-serif"` family.

use std::sync::OnceLock;

use plotters::style::{FontStyle, register_font};

/// The family name under which the bundled font is registered; use it in
/// every text style.
pub(crate) const FONT_FAMILY: &str = "sans-serif";

/// DejaVu Sans Book, 0.76 MB.
static DEJAVU_SANS: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// Whether registering succeeded, decided on the first call.
static REGISTERED: OnceLock<bool> = OnceLock::new();

/// Registers the bundled font with plotters (once per process) and tells
/// whether it is usable. Only a corrupt bundled file makes it `false`.
pub(crate) fn ensure_font_registered() -> bool {
    *REGISTERED.get_or_init(|| register_font(FONT_FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bundled_font_registers() {
        assert!(ensure_font_registered());
        assert!(ensure_font_registered());
    }
}
