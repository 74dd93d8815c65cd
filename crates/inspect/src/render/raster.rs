//! The tiled z-buffer rasteriser: project (f64 → f32 screen coordinates), bin triangles and
//! line segments into 32×32-pixel tiles, then per tile (one rayon task each): rasterise at
//! `samples²` samples per pixel with a strict depth test, draw the lines with a depth test
//! against that buffer, shade every sample and average the samples of each pixel.
//!
//! Per-sample work is in f32: screen coordinates are bounded by the image size, where f32
//! resolves 1/1000 of a pixel, and colours end as 8-bit values; the geometry and the camera
//! transform stay f64 until the projected point is rounded once.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::camera::{Frame, ScreenPoint};
use super::colour::Rgb;
use super::font::{Canvas, draw_legend, legend_width, to_u8};
use super::image::Image;
use super::scene::{LineSet, Prepared, RenderMesh, prepare};
use super::{Background, Mode, RenderOptions};
use crate::InspectError;

const TILE: usize = 32;
const NONE: u32 = u32::MAX;

/// Renders the scene: one cell per view in a grid, plus the legend strip in the curvature
/// mode.
pub(crate) fn render_frame(
    meshes: &[&RenderMesh],
    lines: &[&LineSet],
    o: &RenderOptions,
) -> Result<Image, InspectError> {
    let bad = |m: String| Err(InspectError::InvalidOption(m));
    let (w, h) = o.size;
    if !(1..=16384).contains(&w) || !(1..=16384).contains(&h) {
        return bad(format!("size {w}x{h}: each side must be 1 to 16384"));
    }
    if !(1..=4).contains(&o.samples) {
        return bad(format!("samples {}: must be 1 to 4", o.samples));
    }
    if o.views.is_empty() || o.views.len() > 64 {
        return bad(format!("{} views: give 1 to 64", o.views.len()));
    }
    if o.stripes == 0 {
        return bad("stripes must be at least 1".into());
    }
    if !(o.wire_width > 0.0 && o.wire_width <= 64.0) {
        return bad(format!("wire width {}: must be in (0, 64]", o.wire_width));
    }
    if !(o.wire_depth_tolerance >= 0.0 && o.wire_depth_tolerance.is_finite()) {
        return bad("the wire depth tolerance must be finite and ≥ 0".into());
    }
    if !o.light.is_finite() || o.light.length() == 0.0 {
        return bad("the light direction must be finite and nonzero".into());
    }
    // Checked here, not only by `Frame::new`: the preset views place their eye at a distance
    // computed from the field of view, and a NaN one made a NaN eye, reported as "eye and
    // target must be distinct finite points".
    if !(o.fov_y_degrees > 0.0 && o.fov_y_degrees < 180.0) {
        return bad(format!(
            "field of view {}: must be in (0, 180) degrees",
            o.fov_y_degrees
        ));
    }
    let p = prepare(meshes, lines, o)?;

    // Bounding box of everything drawn.
    let mut lo = DVec3::INFINITY;
    let mut hi = DVec3::NEG_INFINITY;
    for q in p.positions.iter().chain(p.segments.iter().flatten()) {
        lo = lo.min(*q);
        hi = hi.max(*q);
    }
    let centre = (lo + hi) / 2.0;
    let diagonal = (hi - lo).length();
    // The farthest point from the box centre: a tighter sphere than the half diagonal (a
    // round object fills the frame instead of 1/√3 of it).
    let radius = p
        .positions
        .iter()
        .chain(p.segments.iter().flatten())
        .map(|q| q.distance(centre))
        .fold(0.0, f64::max);

    let n = o.views.len();
    let cols = (n as f64).sqrt().ceil() as usize;
    let rows = n.div_ceil(cols);
    let (cw, ch) = (w as usize, h as usize);
    let legend = if p.legend_range.is_some() {
        legend_width(rows * ch)
    } else {
        0
    };
    let (iw, ih) = (cols * cw + legend, rows * ch);
    if iw > 32768 || ih > 32768 {
        return bad(format!(
            "the image would be {iw}x{ih} pixels (at most 32768 a side)"
        ));
    }
    let mut rgba = vec![0u8; 4 * iw * ih];
    if let Background::Solid(c) = o.background {
        for px in rgba.chunks_exact_mut(4) {
            px.copy_from_slice(&[to_u8(c[0]), to_u8(c[1]), to_u8(c[2]), 255]);
        }
    }
    for (k, view) in o.views.iter().enumerate() {
        let camera = view.camera(centre, radius, w as f64 / h as f64, o.fov_y_degrees);
        // Near plane 1e-3 of the scene radius in front of the eye: preset cameras are 1.05
        // radii away or more; an explicit camera inside the scene loses the triangles that
        // cross it (they are not clipped).
        let frame = Frame::new(&camera, w, h, 1e-3 * radius.max(f64::MIN_POSITIVE))?;
        let cell = render_view(&p, &frame, o, diagonal);
        let (x0, y0) = ((k % cols) * cw, (k / cols) * ch);
        for y in 0..ch {
            let dst = 4 * ((y0 + y) * iw + x0);
            rgba[dst..dst + 4 * cw].copy_from_slice(&cell[4 * y * cw..4 * (y + 1) * cw]);
        }
    }
    if let Some([lo, hi]) = p.legend_range {
        let bg = match o.background {
            Background::Solid(c) => c,
            Background::Transparent => [1.0; 3],
        };
        let mut canvas = Canvas {
            rgba: &mut rgba,
            width: iw,
            height: ih,
        };
        draw_legend(&mut canvas, cols * cw, lo, hi, bg);
    }
    Ok(Image {
        width: iw as u32,
        height: ih as u32,
        rgba,
        legend_range: p.legend_range,
    })
}

/// Tile rectangle `[x0, x1] × [y0, y1]` (inclusive tile indices) of a screen box, or `None`
/// when it misses the image.
fn tile_rect(
    min: [f32; 2],
    max: [f32; 2],
    w: f32,
    h: f32,
    tx: usize,
    ty: usize,
) -> Option<[u16; 4]> {
    if !(max[0] >= 0.0 && max[1] >= 0.0 && min[0] < w && min[1] < h) {
        return None; // also rejects NaN
    }
    let t = TILE as f32;
    let x0 = (min[0].max(0.0) / t) as usize;
    let y0 = (min[1].max(0.0) / t) as usize;
    let x1 = ((max[0] / t) as usize).min(tx - 1);
    let y1 = ((max[1] / t) as usize).min(ty - 1);
    Some([x0 as u16, y0 as u16, x1 as u16, y1 as u16])
}

/// Items binned per tile, in item order (a counting sort over the rectangles).
fn bin(rects: &[Option<[u16; 4]>], tx: usize, ty: usize) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; tx * ty + 1];
    for r in rects.iter().flatten() {
        for y in r[1]..=r[3] {
            for x in r[0]..=r[2] {
                start[y as usize * tx + x as usize + 1] += 1;
            }
        }
    }
    for i in 0..tx * ty {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut items = vec![0u32; start[tx * ty] as usize];
    for (i, r) in rects.iter().enumerate() {
        let Some(r) = r else { continue };
        for y in r[1]..=r[3] {
            for x in r[0]..=r[2] {
                let slot = &mut fill[y as usize * tx + x as usize];
                items[*slot as usize] = i as u32;
                *slot += 1;
            }
        }
    }
    (start, items)
}

/// Edge function of the directed edge (a, b) at p, evaluated with the endpoints in vertex
/// index order and negated when swapped, so two triangles sharing an edge get exactly
/// opposite values: with the inclusive test below no sample on a shared edge is missed.
#[inline]
fn edge(s: &[ScreenPoint], a: u32, b: u32, px: f32, py: f32) -> f32 {
    let (u, v, sign) = if a < b { (a, b, 1.0) } else { (b, a, -1.0) };
    let (u, v) = (s[u as usize], s[v as usize]);
    sign * ((v.x - u.x) * (py - u.y) - (v.y - u.y) * (px - u.x))
}

/// Barycentric coordinates of (px, py) in triangle t (any orientation), or `None` when the
/// triangle is degenerate on screen.
#[inline]
fn barycentric(s: &[ScreenPoint], t: [u32; 3], px: f32, py: f32) -> Option<[f32; 3]> {
    let l0 = edge(s, t[1], t[2], px, py);
    let l1 = edge(s, t[2], t[0], px, py);
    let l2 = edge(s, t[0], t[1], px, py);
    let sum = l0 + l1 + l2; // twice the signed area
    if sum == 0.0 || !sum.is_finite() {
        return None;
    }
    Some([l0 / sum, l1 / sum, l2 / sum])
}

/// Shading constants of one view.
struct Shader<'a> {
    p: &'a Prepared,
    screen: &'a [ScreenPoint],
    frame: &'a Frame,
    o: &'a RenderOptions,
    light: Vec3,
    up: Vec3,
}

impl Shader<'_> {
    fn shade(&self, t: u32, x: f32, y: f32) -> Rgb {
        let tri = self.p.triangles[t as usize];
        let Some(mut w) = barycentric(self.screen, tri, x, y) else {
            return self.p.colours[t as usize];
        };
        if self.frame.perspective {
            // Perspective-correct interpolation: weights λ_i / d_i, normalised (q = 1/d).
            for k in 0..3 {
                w[k] *= self.screen[tri[k] as usize].q;
            }
            let s = w[0] + w[1] + w[2];
            if s != 0.0 {
                w = w.map(|v| v / s);
            }
        }
        if let Some(vc) = &self.p.vertex_colours {
            let c = tri.map(|v| vc[v as usize]);
            return [0, 1, 2].map(|i| w[0] * c[0][i] + w[1] * c[1][i] + w[2] * c[2][i]);
        }
        let d = self
            .frame
            .ray_direction(f64::from(x), f64::from(y))
            .as_vec3();
        let n = tri.iter().zip(w).fold(Vec3::ZERO, |a, (&v, wk)| {
            a + wk * self.p.normals[v as usize]
        });
        let mut n = n.try_normalize().unwrap_or(-d);
        if n.dot(d) > 0.0 {
            n = -n; // two-sided: shade the side facing the viewer
        }
        let base = self.p.colours[t as usize];
        let stripe = |band: f32| {
            let f = if band.rem_euclid(2.0) < 1.0 {
                0.95
            } else {
                0.12
            };
            base.map(|c| c * f)
        };
        let k = self.o.stripes as f32;
        match self.o.mode {
            Mode::Isophotes => stripe((n.dot(self.light) * k).floor()),
            Mode::Zebra => {
                let r = d - 2.0 * d.dot(n) * n;
                let elevation = r.dot(self.up).clamp(-1.0, 1.0).asin();
                stripe((elevation / std::f32::consts::FRAC_PI_2 * k).floor())
            }
            _ if self.o.flat => base,
            _ => {
                let nl = n.dot(self.light);
                let diffuse = nl.max(0.0);
                let spec = if nl > 0.0 {
                    let r = 2.0 * nl * n - self.light;
                    r.dot(-d).max(0.0).powi(32)
                } else {
                    0.0
                };
                base.map(|c| c * (0.2 + 0.8 * diffuse) + 0.25 * spec)
            }
        }
    }
}

/// Renders one view into a `w × h` RGBA buffer.
fn render_view(p: &Prepared, frame: &Frame, o: &RenderOptions, diagonal: f64) -> Vec<u8> {
    let (w, h) = (frame.width as usize, frame.height as usize);
    let (tx, ty) = (w.div_ceil(TILE), h.div_ceil(TILE));
    let (wf, hf) = (w as f32, h as f32);
    let screen: Vec<ScreenPoint> = p.positions.par_iter().map(|&q| frame.project(q)).collect();
    let tri_rects: Vec<Option<[u16; 4]>> = p
        .triangles
        .par_iter()
        .map(|t| {
            let s = t.map(|v| screen[v as usize]);
            if !s.iter().all(|v| v.visible) {
                return None;
            }
            let min = [
                s[0].x.min(s[1].x).min(s[2].x),
                s[0].y.min(s[1].y).min(s[2].y),
            ];
            let max = [
                s[0].x.max(s[1].x).max(s[2].x),
                s[0].y.max(s[1].y).max(s[2].y),
            ];
            tile_rect(min, max, wf, hf, tx, ty)
        })
        .collect();
    let (tri_start, tri_items) = bin(&tri_rects, tx, ty);
    let hw = (o.wire_width / 2.0) as f32;
    let segs: Vec<[ScreenPoint; 2]> = p
        .segments
        .iter()
        .map(|s| [frame.project(s[0]), frame.project(s[1])])
        .collect();
    let seg_rects: Vec<Option<[u16; 4]>> = segs
        .iter()
        .map(|[a, b]| {
            if !(a.visible && b.visible) {
                return None;
            }
            let min = [a.x.min(b.x) - hw - 1.0, a.y.min(b.y) - hw - 1.0];
            let max = [a.x.max(b.x) + hw + 1.0, a.y.max(b.y) + hw + 1.0];
            tile_rect(min, max, wf, hf, tx, ty)
        })
        .collect();
    let (seg_start, seg_items) = bin(&seg_rects, tx, ty);
    let light = frame.camera_to_world(o.light.normalize()).as_vec3();
    let shader = Shader {
        p,
        screen: &screen,
        frame,
        o,
        light,
        up: frame.up.as_vec3(),
    };
    let tol = (o.wire_depth_tolerance * diagonal) as f32;
    let bg = match o.background {
        Background::Solid(c) => Some(c),
        Background::Transparent => None,
    };
    let tiles: Vec<Vec<u8>> = (0..tx * ty)
        .into_par_iter()
        .map(|ti| {
            let r = |s: &[u32], i: &[u32]| -> Vec<u32> {
                i[s[ti] as usize..s[ti + 1] as usize].to_vec()
            };
            let tris = r(&tri_start, &tri_items);
            let lines = r(&seg_start, &seg_items);
            Tile::new(ti % tx * TILE, ti / tx * TILE, w, h, o.samples as usize).draw(
                &shader,
                &tris,
                &segs,
                &lines,
                tol,
                o.wire_colour,
                bg,
            )
        })
        .collect();
    let mut out = vec![0u8; 4 * w * h];
    for (ti, tile) in tiles.iter().enumerate() {
        let (x0, y0) = (ti % tx * TILE, ti / tx * TILE);
        let tw = TILE.min(w - x0);
        for (row, chunk) in tile.chunks_exact(4 * tw).enumerate() {
            let dst = 4 * ((y0 + row) * w + x0);
            out[dst..dst + 4 * tw].copy_from_slice(chunk);
        }
    }
    out
}

/// One tile's sample buffers.
struct Tile {
    x0: usize,
    y0: usize,
    /// Pixels.
    w: usize,
    h: usize,
    ss: usize,
    depth: Vec<f32>,
    id: Vec<u32>,
    line: Vec<bool>,
}

impl Tile {
    fn new(x0: usize, y0: usize, img_w: usize, img_h: usize, ss: usize) -> Tile {
        let (w, h) = (TILE.min(img_w - x0), TILE.min(img_h - y0));
        let n = w * h * ss * ss;
        Tile {
            x0,
            y0,
            w,
            h,
            ss,
            depth: vec![f32::NEG_INFINITY; n],
            id: vec![NONE; n],
            line: vec![false; n],
        }
    }

    /// Pixel-space position of sample column/row `i`.
    #[inline]
    fn at(&self, origin: usize, i: usize) -> f32 {
        origin as f32 + (i as f32 + 0.5) / self.ss as f32
    }

    /// Inclusive sample index range covering pixel coordinates `[lo, hi]` along one axis.
    fn range(&self, origin: usize, n: usize, lo: f32, hi: f32) -> Option<(usize, usize)> {
        let ss = self.ss as f32;
        let a = ((lo - origin as f32) * ss - 0.5).ceil().max(0.0);
        let b = ((hi - origin as f32) * ss - 0.5)
            .floor()
            .min((n * self.ss) as f32 - 1.0);
        (a <= b).then_some((a as usize, b as usize))
    }

    #[allow(clippy::too_many_arguments)]
    fn draw(
        mut self,
        sh: &Shader<'_>,
        tris: &[u32],
        segs: &[[ScreenPoint; 2]],
        lines: &[u32],
        tol: f32,
        wire: Rgb,
        bg: Option<Rgb>,
    ) -> Vec<u8> {
        let sw = self.w * self.ss;
        let s = sh.screen;
        for &t in tris {
            let tri = sh.p.triangles[t as usize];
            let v = tri.map(|i| s[i as usize]);
            let (Some((sx0, sx1)), Some((sy0, sy1))) = (
                self.range(
                    self.x0,
                    self.w,
                    v[0].x.min(v[1].x).min(v[2].x),
                    v[0].x.max(v[1].x).max(v[2].x),
                ),
                self.range(
                    self.y0,
                    self.h,
                    v[0].y.min(v[1].y).min(v[2].y),
                    v[0].y.max(v[1].y).max(v[2].y),
                ),
            ) else {
                continue;
            };
            for sy in sy0..=sy1 {
                let py = self.at(self.y0, sy);
                for sx in sx0..=sx1 {
                    let px = self.at(self.x0, sx);
                    let Some(l) = barycentric(s, tri, px, py) else {
                        break;
                    };
                    if l[0] < 0.0 || l[1] < 0.0 || l[2] < 0.0 {
                        continue;
                    }
                    let q = l[0] * v[0].q + l[1] * v[1].q + l[2] * v[2].q;
                    let k = sy * sw + sx;
                    if q > self.depth[k] {
                        self.depth[k] = q;
                        self.id[k] = t;
                    }
                }
            }
        }
        let hw = (sh.o.wire_width / 2.0) as f32;
        for &i in lines {
            let [a, b] = segs[i as usize];
            let (Some((sx0, sx1)), Some((sy0, sy1))) = (
                self.range(self.x0, self.w, a.x.min(b.x) - hw, a.x.max(b.x) + hw),
                self.range(self.y0, self.h, a.y.min(b.y) - hw, a.y.max(b.y) + hw),
            ) else {
                continue;
            };
            let (dx, dy) = (b.x - a.x, b.y - a.y);
            let len2 = dx * dx + dy * dy;
            for sy in sy0..=sy1 {
                let py = self.at(self.y0, sy);
                for sx in sx0..=sx1 {
                    let px = self.at(self.x0, sx);
                    let t = if len2 > 0.0 {
                        (((px - a.x) * dx + (py - a.y) * dy) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let (ex, ey) = (px - a.x - t * dx, py - a.y - t * dy);
                    if ex * ex + ey * ey > hw * hw {
                        continue;
                    }
                    let k = sy * sw + sx;
                    // q is affine in screen space (1/depth or −depth), so interpolating it
                    // along the projected segment gives the segment's own depth there.
                    let q = a.q + t * (b.q - a.q);
                    if self.id[k] == NONE
                        || sh.frame.depth_of_q(q) <= sh.frame.depth_of_q(self.depth[k]) + tol
                    {
                        self.line[k] = true;
                    }
                }
            }
        }
        let spp = self.ss * self.ss;
        let mut out = vec![0u8; 4 * self.w * self.h];
        for py in 0..self.h {
            for px in 0..self.w {
                // Shade each triangle once per pixel, at the centroid of its samples, weighted
                // by their count: the samples of one triangle differ by less than a pixel,
                // where the shading varies little, and this cuts the shading work by up to
                // `samples²` for triangles larger than a pixel.
                let mut acc = [0.0f32; 3];
                let mut covered = 0usize;
                let mut groups: [(u32, u32, f32, f32); 16] = [(NONE, 0, 0.0, 0.0); 16];
                let mut ng = 0;
                for j in 0..self.ss {
                    for i in 0..self.ss {
                        let (sx, sy) = (px * self.ss + i, py * self.ss + j);
                        let k = sy * sw + sx;
                        if self.line[k] {
                            covered += 1;
                            for m in 0..3 {
                                acc[m] += wire[m];
                            }
                            continue;
                        }
                        let t = self.id[k];
                        if t == NONE {
                            continue;
                        }
                        covered += 1;
                        let (x, y) = (self.at(self.x0, sx), self.at(self.y0, sy));
                        match groups[..ng].iter_mut().find(|g| g.0 == t) {
                            Some(g) => {
                                g.1 += 1;
                                g.2 += x;
                                g.3 += y;
                            }
                            None => {
                                groups[ng] = (t, 1, x, y);
                                ng += 1;
                            }
                        }
                    }
                }
                for &(t, n, x, y) in &groups[..ng] {
                    let nf = n as f32;
                    let c = sh.shade(t, x / nf, y / nf);
                    for m in 0..3 {
                        acc[m] += nf * c[m];
                    }
                }
                let o = 4 * (py * self.w + px);
                let rgba = match bg {
                    Some(b) => {
                        let free = (spp - covered) as f32;
                        let c = [0, 1, 2].map(|m| (acc[m] + free * b[m]) / spp as f32);
                        [to_u8(c[0]), to_u8(c[1]), to_u8(c[2]), 255]
                    }
                    None if covered == 0 => [0; 4],
                    None => {
                        let c = acc.map(|v| v / covered as f32);
                        let a = covered as f32 / spp as f32;
                        [to_u8(c[0]), to_u8(c[1]), to_u8(c[2]), to_u8(a)]
                    }
                };
                out[o..o + 4].copy_from_slice(&rgba);
            }
        }
        out
    }
}
