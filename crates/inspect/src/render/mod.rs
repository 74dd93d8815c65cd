//! A deterministic CPU renderer writing PNG: a tiled z-buffer rasteriser with supersampling,
//! rayon over tiles.
//!
//! Modes ([`Mode`]): `shaded` (per-vertex normals, Phong), `isophotes` (stripes of n·L, the
//! papers' figure style), `zebra` (reflection lines), `patches` (a colour per patch: face
//! patches warm, edge patches cool, planar grey, lightness varying by id, like Fig. 14 of
//! Xu–Huang–Bajaj 2001) and `curvature` (cotangent mean curvature as a colour map, with a
//! labelled legend). A wire overlay ([`RenderOptions::wire`]) draws edge sets as antialiased
//! lines with a depth test, on top of any mode. Several views make a grid.
//!
//! ```
//! use algesurf_inspect::render::{render, Mode, RenderMesh, RenderOptions, View};
//! use algesurf_mesh::shapes;
//!
//! let mesh = RenderMesh::from(&shapes::icosphere(3));
//! let options = RenderOptions {
//!     mode: Mode::Isophotes,
//!     views: vec![View::Front, View::Iso],
//!     size: (96, 64),
//!     ..RenderOptions::default()
//! };
//! let image = render(&mesh, &options)?;
//! assert_eq!((image.width, image.height), (192, 64)); // two views side by side
//! let png = image.encode_png()?;
//! assert_eq!(&png[1..4], b"PNG");
//! # Ok::<(), algesurf_inspect::InspectError>(())
//! ```
//!
//! Compose scenes with [`render_scene`]: several meshes (each with its own colour and a
//! highlighted subset of triangles) and extra line sets in one frame.
//!
//! Output is the same bytes for the same input and options, whatever the number of threads:
//! each tile is rasterised by one task, in triangle order, with a strict depth test (the first
//! triangle in scene order wins ties), and tiles write disjoint pixels.

mod camera;
mod colour;
mod curvature;
mod font;
mod image;
mod raster;
mod scene;

pub use camera::{Camera, Projection, View};
pub use colour::{Rgb, kind_hue_range, patch_colour, sequential};
pub use curvature::mean_curvature;
pub use font::format_value;
pub use image::Image;
pub use scene::{LineSet, RenderMesh};

use crate::InspectError;
use glam::DVec3;

/// What colours the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Mode {
    /// Phong shading with per-vertex normals.
    #[default]
    Shaded,
    /// Alternating bands of `n·L` (isophotes: `n·L = j / stripes` are the band boundaries).
    Isophotes,
    /// Reflection lines: bands of the reflected view ray's elevation angle (a zebra
    /// environment of horizontal light strips in camera space).
    Zebra,
    /// A colour per patch ([`patch_colour`]); needs per-triangle patch ids.
    Patches,
    /// Mean curvature ([`mean_curvature`]) through [`sequential`], with a legend strip.
    Curvature,
}

impl Mode {
    /// Parses `shaded`, `isophotes`, `zebra`, `patches` or `curvature`.
    ///
    /// # Errors
    /// [`InspectError::InvalidOption`] naming the unknown mode.
    pub fn parse(name: &str) -> Result<Mode, InspectError> {
        match name.trim().to_ascii_lowercase().as_str() {
            "shaded" => Ok(Mode::Shaded),
            "isophotes" => Ok(Mode::Isophotes),
            "zebra" => Ok(Mode::Zebra),
            "patches" => Ok(Mode::Patches),
            "curvature" => Ok(Mode::Curvature),
            other => Err(InspectError::InvalidOption(format!(
                "unknown mode `{other}` (expected shaded, isophotes, zebra, patches or curvature)"
            ))),
        }
    }
}

/// The image background.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Background {
    /// Alpha 0 where nothing is drawn (partial alpha on antialiased silhouettes).
    #[default]
    Transparent,
    /// An opaque colour.
    Solid(Rgb),
}

/// Rendering options; `RenderOptions::default()` gives a shaded 800×800 front view.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Colouring.
    pub mode: Mode,
    /// One or more views; several are laid out in a grid of `ceil(√n)` columns.
    pub views: Vec<View>,
    /// Width and height of each view's cell, pixels.
    pub size: (u32, u32),
    /// Background.
    pub background: Background,
    /// Light direction in camera coordinates (x right, y up, z towards the viewer); need not
    /// be unit. The isophote mode uses it as `L`.
    pub light: DVec3,
    /// Vertical field of view of the preset views, degrees.
    pub fov_y_degrees: f64,
    /// Supersampling factor per axis (1 to 4): `samples²` samples per pixel.
    pub samples: u32,
    /// No lighting in `shaded` and `patches`: every triangle gets its flat base colour.
    pub flat: bool,
    /// Number of bands over `n·L ∈ [0, 1]` (isophotes) or over a quarter turn (zebra).
    pub stripes: u32,
    /// Draw each mesh's [`RenderMesh::wire`] edges.
    pub wire: bool,
    /// Line width of wires, pixels.
    pub wire_width: f64,
    /// Line colour.
    pub wire_colour: Rgb,
    /// A line sample is drawn when it is at most this far behind the surface, as a fraction
    /// of the scene's bounding-box diagonal: lines on the surface need a tolerance (depth
    /// rounding; a control mesh lies off the smooth surface by its chord sag), lines on the
    /// far side must stay hidden (they are a diameter away).
    pub wire_depth_tolerance: f64,
    /// Colour of highlighted triangles ([`RenderMesh::highlighted`]).
    pub highlight_colour: Rgb,
    /// Range of the curvature colour map; `None`: the 2nd to 98th percentile of the vertex
    /// values (robust against a few extreme vertices).
    pub curvature_range: Option<[f64; 2]>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            mode: Mode::Shaded,
            views: vec![View::Front],
            size: (800, 800),
            background: Background::Transparent,
            light: DVec3::new(-0.4, 0.5, 1.0),
            fov_y_degrees: 30.0,
            samples: 2,
            flat: false,
            stripes: 8,
            wire: false,
            wire_width: 1.2,
            wire_colour: [0.05, 0.05, 0.08],
            wire_depth_tolerance: 0.01,
            highlight_colour: [0.95, 0.25, 0.2],
            curvature_range: None,
        }
    }
}

/// Parses `WxH` (e.g. `1024x768`), each between 1 and 16384.
///
/// # Errors
/// [`InspectError::InvalidOption`] naming the bad string.
pub fn parse_size(s: &str) -> Result<(u32, u32), InspectError> {
    let bad = || {
        InspectError::InvalidOption(format!(
            "bad size `{s}` (expected WIDTHxHEIGHT, e.g. 800x600, each 1 to 16384)"
        ))
    };
    let (w, h) = s.trim().split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if !(1..=16384).contains(&w) || !(1..=16384).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

/// Renders one mesh (and its wire, with [`RenderOptions::wire`]).
///
/// # Errors
/// [`InspectError::InvalidOption`] for inconsistent meshes or options (see [`render_scene`]).
pub fn render(mesh: &RenderMesh, options: &RenderOptions) -> Result<Image, InspectError> {
    render_scene(&[mesh], &[], options)
}

/// Renders several meshes and extra line sets into one frame (framing from all of them).
///
/// # Errors
/// [`InspectError::InvalidOption`]: an empty scene, indices out of range, non-finite
/// positions, a size or supersampling factor out of range, no views, a degenerate camera, or
/// the patches mode on a mesh without patch ids.
pub fn render_scene(
    meshes: &[&RenderMesh],
    lines: &[&LineSet],
    options: &RenderOptions,
) -> Result<Image, InspectError> {
    raster::render_frame(meshes, lines, options)
}

#[cfg(test)]
mod tests;
