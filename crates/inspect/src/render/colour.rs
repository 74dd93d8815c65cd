//! Colour maps: the patch palette (Fig. 14 of Xu–Huang–Bajaj 2001 shows face and edge patches
//! in different shades) and the sequential map of the curvature mode.

use algesurf_apatch::PatchKind;

/// An RGB colour with components in `[0, 1]` (sRGB-encoded values, written to PNG as they are).
pub type Rgb = [f32; 3];

/// From hue (degrees), saturation and lightness.
fn hsl(h: f32, s: f32, l: f32) -> Rgb {
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let hp = (h.rem_euclid(360.0)) / 60.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - c / 2.0;
    [r + m, g + m, b + m]
}

/// A well-mixed hash of a patch id (so that neighbouring ids get unrelated variations).
fn mix(id: u32) -> u32 {
    let mut x = id.wrapping_mul(0x9E37_79B9) ^ 0x85EB_CA6B;
    x ^= x >> 15;
    x = x.wrapping_mul(0x2C1B_3C6D);
    x ^= x >> 12;
    x
}

/// The hue range of each patch kind's family: face patches warm (orange–yellow), edge patches
/// cool (cyan–blue), planar faces grey (no hue).
pub fn kind_hue_range(kind: PatchKind) -> Option<(f32, f32)> {
    match kind {
        PatchKind::Face => Some((20.0, 55.0)),
        PatchKind::Edge => Some((185.0, 230.0)),
        PatchKind::Planar => None,
    }
}

/// The colour of patch `id` of `kind`: a hue in the kind's family and a lightness that varies
/// with the id (eight levels) so that neighbouring patches are distinguishable.
pub fn patch_colour(kind: PatchKind, id: u32) -> Rgb {
    let h = mix(id);
    let level = (h % 8) as f32 / 7.0; // 0..=1
    match kind_hue_range(kind) {
        Some((lo, hi)) => {
            let hue = lo + (hi - lo) * ((h >> 8) % 16) as f32 / 15.0;
            hsl(hue, 0.75, 0.42 + 0.3 * level)
        }
        None => {
            let g = 0.5 + 0.3 * level;
            [g, g, g]
        }
    }
}

/// Sequential colour map for `t ∈ [0, 1]` (blue → cyan → green → yellow → red, piecewise
/// linear between five stops; values outside are clamped).
pub fn sequential(t: f64) -> Rgb {
    const STOPS: [Rgb; 5] = [
        [0.15, 0.25, 0.85],
        [0.1, 0.75, 0.9],
        [0.3, 0.8, 0.3],
        [0.95, 0.85, 0.2],
        [0.85, 0.15, 0.1],
    ];
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) } as f32 * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f32;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    [
        a[0] + (b[0] - a[0]) * f,
        a[1] + (b[1] - a[1]) * f,
        a[2] + (b[2] - a[2]) * f,
    ]
}
