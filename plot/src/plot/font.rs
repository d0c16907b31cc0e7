//! The embedded font: DejaVu Sans (Bitstream Vera licence, see `plot/assets/`).
//!
//! plotters' `ab_glyph` backend loads no system fonts; registering the embedded file under the
//! usual family names makes PNG text render the same on every machine.

use std::sync::Once;

use plotters::style::{FontStyle, register_font};

/// The TrueType file, compiled into the binary.
pub static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Family names that resolve to the embedded font.
pub const FAMILIES: [&str; 4] = ["sans-serif", "serif", "monospace", "DejaVu Sans"];

static REGISTER: Once = Once::new();

/// Registers the embedded font for every family in [`FAMILIES`]; cheap after the first call.
pub fn ensure_registered() {
    REGISTER.call_once(|| {
        for family in FAMILIES {
            for style in [
                FontStyle::Normal,
                FontStyle::Bold,
                FontStyle::Italic,
                FontStyle::Oblique,
            ] {
                if register_font(family, style, DEJAVU_SANS).is_err() {
                    panic!("the embedded DejaVuSans.ttf is not a valid font");
                }
            }
        }
    });
}
