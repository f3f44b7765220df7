//! How the recording looks: one fixed colour per filter (by its place in the experiment file, so a
//! filter has the same colour in every view, scenario and variant), and the names its series carry
//! in the viewer's legend.

/// An sRGBA colour.
pub(crate) type Rgba = [u8; 4];

/// Ten colours that stay apart from each other and from the neutral truth on the viewer's dark
/// background (a brightened Tableau 10 without its grey, which is kept for the truth).
const PALETTE: [[u8; 3]; 9] = [
    [0x4c, 0x9b, 0xe8], // blue
    [0xf2, 0x8e, 0x2b], // orange
    [0x6b, 0xcb, 0x5e], // green
    [0xe1, 0x57, 0x59], // red
    [0xb0, 0x7a, 0xd1], // purple
    [0xed, 0xc9, 0x48], // yellow
    [0x76, 0xd7, 0xd2], // teal
    [0xff, 0x9d, 0xa7], // pink
    [0xa6, 0x7c, 0x52], // brown
];

/// The true signal: neutral, so every coloured line is an estimate.
pub(crate) const TRUTH: Rgba = [0xe8, 0xe8, 0xe8, 0xff];
/// The Markov mode of a sample trial: grey, below the truth's white.
pub(crate) const MODE: Rgba = [0x8c, 0x8c, 0x8c, 0xff];
/// The noise-free z the truth scatters around (seed 003 Figs. 3–4): a grey between the mode's
/// and the truth's; its curve is smooth where the truth is jagged, which tells the two apart.
pub(crate) const NOISE_FREE: Rgba = [0xb4, 0xb4, 0xb4, 0xff];
/// Lost measurements: a saturated magenta no filter has, drawn as crosses.
pub const DROPOUT: Rgba = [0xff, 0x1f, 0xd2, 0xff];

/// The colour of the filter at `index` in the file: the palette first, then hues spread by the
/// golden angle, so even galerkin_string's 32 filters get 32 different colours.
pub(crate) fn filter_colour(index: usize) -> Rgba {
    if let Some([r, g, b]) = PALETTE.get(index) {
        return [*r, *g, *b, 0xff];
    }
    let hue = ((index - PALETTE.len()) as f64 * 137.507_764 + 15.0) % 360.0;
    let [r, g, b] = hsv(hue, 0.6, 0.95);
    [r, g, b, 0xff]
}

/// The same colour, faded: the 95 % band around an empirical curve.
pub(crate) fn faded(c: Rgba) -> Rgba {
    [c[0], c[1], c[2], 0x70]
}

fn hsv(h: f64, s: f64, v: f64) -> [u8; 3] {
    let c = v * s;
    let x = c * (1.0 - ((h / 60.0) % 2.0 - 1.0).abs());
    let (r, g, b) = match (h / 60.0) as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    let byte = |u: f64| ((u + m) * 255.0).round() as u8;
    [byte(r), byte(g), byte(b)]
}

/// Line widths in UI points: the empirical curve is what a reader follows; the band and the exact
/// curve sit around it.
pub(crate) const EMPIRICAL_WIDTH: f32 = 2.5;
pub(crate) const BAND_WIDTH: f32 = 0.75;
pub(crate) const EXACT_WIDTH: f32 = 1.0;
pub(crate) const ESTIMATE_WIDTH: f32 = 1.5;
pub(crate) const TRUTH_WIDTH: f32 = 2.5;
pub(crate) const NOISE_FREE_WIDTH: f32 = 2.0;
