//! A 3×5 bitmap font for numbers (digits, sign, point, `e`) and the curvature legend.

use super::colour::{Rgb, sequential};

/// Rows of each glyph, 3 bits per row (bit 2 = left column).
fn glyph(c: char) -> Option<[u8; 5]> {
    Some(match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        '.' => [0, 0, 0, 0, 2],
        'e' => [0, 7, 7, 4, 7],
        'H' => [5, 5, 7, 5, 5],
        ' ' => [0; 5],
        _ => return None,
    })
}

/// An RGBA canvas the legend is drawn on.
pub(crate) struct Canvas<'a> {
    pub rgba: &'a mut [u8],
    pub width: usize,
    pub height: usize,
}

impl Canvas<'_> {
    fn put(&mut self, x: usize, y: usize, c: Rgb) {
        if x < self.width && y < self.height {
            let i = 4 * (y * self.width + x);
            for (dst, v) in self.rgba[i..i + 3].iter_mut().zip(c) {
                *dst = to_u8(v);
            }
            self.rgba[i + 3] = 255;
        }
    }

    fn fill(&mut self, x0: usize, y0: usize, w: usize, h: usize, c: Rgb) {
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                self.put(x, y, c);
            }
        }
    }

    /// Draws `text` with its top-left corner at (x, y), each font pixel `scale` pixels wide.
    pub fn text(&mut self, x: usize, y: usize, scale: usize, text: &str, c: Rgb) {
        for (i, ch) in text.chars().enumerate() {
            let Some(rows) = glyph(ch) else { continue };
            for (r, bits) in rows.iter().enumerate() {
                for col in 0..3 {
                    if bits & (4 >> col) != 0 {
                        self.fill(x + (4 * i + col) * scale, y + r * scale, scale, scale, c);
                    }
                }
            }
        }
    }
}

/// Channel value in `[0, 1]` to a byte, rounding to nearest.
pub(crate) fn to_u8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// `v` in at most 9 characters of the font (`-1.23e-4`, `0.500`).
pub fn format_value(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-2..1e4).contains(&a) {
        let s = format!("{v:.3}");
        if s.len() <= 9 { s } else { format!("{v:.0}") }
    } else {
        format!("{v:.2e}")
    }
}

/// Width in pixels of the legend strip for an image of this height.
pub(crate) fn legend_width(height: usize) -> usize {
    let scale = legend_scale(height);
    (6 + 9 * 4) * scale + 12
}

fn legend_scale(height: usize) -> usize {
    (height / 160).clamp(1, 4)
}

/// Draws the colour bar of [`sequential`] over `[lo, hi]` with `lo`, the midpoint and `hi`
/// labelled, in the strip of `canvas` starting at column `x0` (background `bg`).
pub(crate) fn draw_legend(canvas: &mut Canvas<'_>, x0: usize, lo: f64, hi: f64, bg: Rgb) {
    let h = canvas.height;
    let scale = legend_scale(h);
    canvas.fill(x0, 0, canvas.width - x0, h, bg);
    let ink = if bg.iter().sum::<f32>() > 1.5 {
        [0.0; 3]
    } else {
        [1.0; 3]
    };
    let bar_w = 4 * scale;
    let top = 10 * scale;
    let bottom = h.saturating_sub(10 * scale).max(top + 1);
    let bx = x0 + 4;
    for y in top..bottom {
        let t = (bottom - 1 - y) as f64 / (bottom - 1 - top).max(1) as f64;
        canvas.fill(bx, y, bar_w, 1, sequential(t));
    }
    let tx = bx + bar_w + 2 * scale;
    let half = 5 * scale / 2;
    canvas.text(tx, top.saturating_sub(half), scale, &format_value(hi), ink);
    canvas.text(tx, bottom - half, scale, &format_value(lo), ink);
    canvas.text(
        tx,
        (top + bottom) / 2 - half,
        scale,
        &format_value((lo + hi) / 2.0),
        ink,
    );
    canvas.text(bx, top.saturating_sub(8 * scale), scale, "H", ink);
}
