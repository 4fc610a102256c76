//! How wide a label will be drawn, without a font engine.
//!
//! An SVG names its fonts but the viewer picks them, so a box sized for one font may be too
//! small in another. The widths here are DejaVu Sans' (the common Linux sans-serif, and
//! among the widest): Helvetica, Arial and Liberation Sans are narrower for every letter,
//! so a label measured here fits its box in all of them.

/// Advance widths of the printable ASCII characters (space to `~`), in thousandths of the
/// font size, of DejaVu Sans Book.
pub(crate) const REGULAR: [u16; 95] = [
    318, 401, 460, 838, 636, 950, 780, 275, 390, 390, 500, 838, 318, 361, 318, 337, 636, 636, 636,
    636, 636, 636, 636, 636, 636, 636, 337, 337, 838, 838, 838, 531, 1000, 684, 686, 698, 770, 632,
    575, 775, 752, 295, 295, 656, 557, 863, 748, 787, 603, 787, 695, 635, 611, 732, 684, 989, 685,
    611, 685, 390, 337, 390, 838, 500, 500, 613, 635, 550, 635, 615, 352, 635, 634, 278, 278, 579,
    278, 974, 634, 612, 635, 635, 411, 521, 392, 634, 592, 818, 592, 592, 525, 636, 337, 636, 838,
];

/// The same for DejaVu Sans Bold.
pub(crate) const BOLD: [u16; 95] = [
    348, 456, 521, 838, 696, 1002, 872, 306, 457, 457, 523, 838, 380, 415, 380, 365, 696, 696, 696,
    696, 696, 696, 696, 696, 696, 696, 400, 400, 838, 838, 838, 580, 1000, 774, 762, 734, 830, 683,
    683, 821, 837, 372, 372, 775, 637, 995, 837, 850, 733, 850, 770, 720, 682, 812, 774, 1103, 771,
    724, 725, 457, 365, 457, 838, 500, 500, 675, 716, 593, 716, 678, 435, 716, 712, 343, 343, 665,
    343, 1042, 712, 687, 716, 716, 493, 595, 478, 712, 652, 924, 645, 652, 582, 712, 365, 712, 838,
];

/// The width of `text` drawn at `font_size`, in the same unit as `font_size`.
pub(crate) fn text_width(text: &str, font_size: f64, bold: bool) -> f64 {
    scaled(text.chars().map(|c| thousandths(c, bold)).sum(), font_size)
}

/// One character's width in thousandths of the font size: summed along a label, so that
/// a long one is measured once rather than once per place it could be cut.
pub(crate) fn thousandths(c: char, bold: bool) -> u64 {
    u64::from(char_width(c, if bold { &BOLD } else { &REGULAR }))
}

/// A width of `thousandths` of the font size, at `font_size`.
pub(crate) fn scaled(thousandths: u64, font_size: f64) -> f64 {
    // Exact below 2^53 thousandths, far past any label a page can send.
    thousandths as f64 * font_size / 1000.0
}

/// Code points of wide scripts (CJK, Hangul, full-width forms, pictographs), inclusive:
/// they take a full em.
pub(crate) const WIDE_RANGES: [[u32; 2]; 6] = [
    [0x1100, 0x115F],
    [0x2E80, 0xA4CF],
    [0xAC00, 0xD7A3],
    [0xF900, 0xFAFF],
    [0xFF00, 0xFF60],
    [0x1F300, 0x1FAFF],
];
/// The width of those, in thousandths.
pub(crate) const WIDE: u16 = 1000;
/// Most other letters are about as wide as an upper-case Latin one.
pub(crate) const OTHER: u16 = 760;

fn char_width(c: char, table: &[u16; 95]) -> u32 {
    if (' '..='~').contains(&c) {
        return u32::from(table[c as usize - ' ' as usize]);
    }
    let code = u32::from(c);
    if WIDE_RANGES
        .iter()
        .any(|[from, to]| (*from..=*to).contains(&code))
    {
        u32::from(WIDE)
    } else {
        u32::from(OTHER)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widths_add_up_per_character() {
        assert_eq!(text_width("", 12.0, false), 0.0);
        // 'i' is 278, 'm' is 974 thousandths.
        assert!((text_width("im", 10.0, false) - 12.52).abs() < 1e-9);
        assert!(text_width("Sequence", 12.0, true) > text_width("Sequence", 12.0, false));
        assert_eq!(text_width("界", 10.0, false), 10.0);
        assert_eq!(text_width("é", 10.0, false), 7.6);
    }
}
