//! `algesurf render IN -o OUT.png`: a PNG of a mesh (or, with `--smooth`, of its A-patch
//! surface) in one of the renderer's modes, from preset views or an explicit camera.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use algesurf_inspect::render::{
    Background, Camera, LineSet, Mode, Projection, RenderMesh, RenderOptions, View, format_value,
    parse_size, render,
};
use algesurf_mesh::{RepairOptions, TriMesh, repair};
use glam::DVec3;

use crate::grid::GridArgs;
use crate::smooth::{SurfaceArgs, build};

/// Colouring (see the renderer's documentation).
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeArg {
    /// Phong shading with per-vertex normals.
    Shaded,
    /// Stripes of n·L (isophotes).
    Isophotes,
    /// Reflection lines.
    Zebra,
    /// A colour per patch: face patches warm, edge patches cool, planar grey (without
    /// --smooth: one colour per input face).
    Patches,
    /// Mean curvature (cotangent Laplacian) with a labelled legend.
    Curvature,
}

impl ModeArg {
    fn mode(self) -> Mode {
        match self {
            ModeArg::Shaded => Mode::Shaded,
            ModeArg::Isophotes => Mode::Isophotes,
            ModeArg::Zebra => Mode::Zebra,
            ModeArg::Patches => Mode::Patches,
            ModeArg::Curvature => Mode::Curvature,
        }
    }
}

/// Arguments of `algesurf render`.
#[derive(clap::Args, Debug, Clone)]
#[command(after_help = "\
Without --smooth, renders the input mesh (repaired as `smooth` does: welded, polygons \
triangulated, …) with the file's normals or area-weighted ones; `--mode patches` then colours \
each input face (the triangles of a triangulated polygon share one colour). With --smooth, \
renders the A-patch surface (with no INPUT: of the built-in icosahedron); `--mode patches` \
colours its face and edge patches and --wire overlays the input mesh.

Several comma-separated views make a grid (2×2 for four); --size is each view's size. \
--eye gives an explicit camera instead (with --target, default the bounding-box centre, --up \
and --fov).")]
pub struct RenderArgs {
    /// Input mesh (OBJ, PLY, STL, OFF, glTF or GLB); with --smooth it may be omitted.
    pub input: Option<PathBuf>,
    /// Output PNG (written atomically; never the input).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Colouring.
    #[arg(long, value_enum, default_value_t = ModeArg::Shaded)]
    pub mode: ModeArg,
    /// Comma-separated views: front, side, top, iso.
    #[arg(long, default_value = "iso")]
    pub view: String,
    /// Size of each view, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x800")]
    pub size: String,
    /// `transparent`, `white`, `black` or `#rrggbb`.
    #[arg(long, default_value = "transparent")]
    pub background: String,
    /// Overlay the input mesh's edges.
    #[arg(long)]
    pub wire: bool,
    /// Render the smooth A-patch surface through the input (the `smooth` pipeline).
    #[arg(long)]
    pub smooth: bool,
    /// Explicit camera position `X,Y,Z` (replaces --view).
    #[arg(long)]
    pub eye: Option<String>,
    /// Point looked at with --eye, `X,Y,Z` (default the bounding-box centre).
    #[arg(long)]
    pub target: Option<String>,
    /// Up direction with --eye, `X,Y,Z`.
    #[arg(long, default_value = "0,1,0")]
    pub up: String,
    /// Vertical field of view, degrees.
    #[arg(long, default_value_t = 30.0)]
    pub fov: f64,
    /// Supersampling per axis (1–4).
    #[arg(long, default_value_t = 2)]
    pub samples: u32,
    /// Number of stripes (isophotes, zebra).
    #[arg(long, default_value_t = 8)]
    pub stripes: u32,
    /// Flat colours, no lighting (shaded and patches modes).
    #[arg(long)]
    pub flat: bool,
    /// Tessellation resolution (with --smooth).
    #[command(flatten)]
    pub grid: GridArgs,
    /// Surface options (used with --smooth).
    #[command(flatten)]
    pub surface: SurfaceArgs,
}

type BoxError = Box<dyn std::error::Error>;

fn parse_point(what: &str, s: &str) -> Result<DVec3, BoxError> {
    let v: Vec<f64> = s
        .split(',')
        .map(|c| c.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("--{what} `{s}`: expected X,Y,Z"))?;
    match v[..] {
        [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(DVec3::new(x, y, z)),
        _ => Err(format!("--{what} `{s}`: expected three finite numbers X,Y,Z").into()),
    }
}

fn parse_background(s: &str) -> Result<Background, BoxError> {
    let t = s.trim().to_ascii_lowercase();
    let rgb = match t.as_str() {
        "transparent" | "none" => return Ok(Background::Transparent),
        "white" => [1.0; 3],
        "black" => [0.0; 3],
        hex if hex.len() == 7 && hex.starts_with('#') => {
            let c = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16);
            match (c(1), c(3), c(5)) {
                (Ok(r), Ok(g), Ok(b)) => [r, g, b].map(|v| f32::from(v) / 255.0),
                _ => return Err(format!("bad background `{s}`").into()),
            }
        }
        _ => {
            return Err(format!(
                "bad background `{s}` (expected transparent, white, black or #rrggbb)"
            )
            .into());
        }
    };
    Ok(Background::Solid(rgb))
}

/// Reads and repairs a mesh as `smooth` does, as a triangle mesh.
fn read_triangles(path: &Path) -> Result<TriMesh, BoxError> {
    let mesh = crate::read_mesh(path)?;
    let repaired = repair(&mesh, &RepairOptions::default())
        .map_err(|e| format!("{}: repair failed: {e}", path.display()))?;
    let tri = TriMesh::from_polygon_mesh(&repaired.mesh)
        .map_err(|e| format!("{}: not a triangle mesh after repair: {e}", path.display()))?;
    if tri.face_count() == 0 {
        return Err(format!("{}: the mesh has no faces", path.display()).into());
    }
    Ok(tri)
}

/// `Err` when `path` has an extension other than `.png` (any case): the image is always
/// PNG, and `x.jpg` holding PNG bytes would mislead whatever opens it. A name without one
/// (`/dev/stdout`, `preview`) is taken as it is.
fn png_name(path: &std::path::Path) -> Result<(), BoxError> {
    match path.extension() {
        Some(ext) if !ext.eq_ignore_ascii_case("png") => Err(format!(
            "{}: render writes PNG images: name the output .png (or give no extension)",
            path.display()
        )
        .into()),
        _ => Ok(()),
    }
}

/// Renders and writes the PNG.
///
/// # Errors
/// Bad options (size, view, background, camera), a missing or unreadable input, a surface
/// that cannot be built, the output equal to the input, or a write failure.
pub fn run(args: &RenderArgs) -> Result<(), BoxError> {
    let size = parse_size(&args.size)?;
    let background = parse_background(&args.background)?;
    let mode = args.mode.mode();
    if let Some(input) = &args.input
        && crate::smooth::resolved(input) == crate::smooth::resolved(&args.output)
    {
        return Err(format!(
            "{}: refusing to overwrite the input with the output",
            input.display()
        )
        .into());
    }
    // Before the work: rendering a smoothed bunny takes seconds, and the write came last.
    png_name(&args.output)?;
    crate::smooth::folder_exists(&args.output, "image")?;
    let views: Vec<View> = if args.eye.is_none() {
        args.view
            .split(',')
            .map(View::parse)
            .collect::<Result<_, _>>()?
    } else {
        Vec::new()
    };
    let (mesh, source, wire_tolerance) = if args.smooth {
        // Progress on a terminal, as `smooth` shows it (construction takes seconds on
        // large meshes).
        let progress = std::io::stderr().is_terminal();
        let mut s = build(args.input.as_deref(), &args.surface, progress)?;
        let name = args
            .input
            .as_ref()
            .map_or("built-in icosahedron".into(), |p| p.display().to_string());
        let (n, m) = args
            .grid
            .fitting_steps(&s.surface)
            .map_err(|e| format!("{name}: {e}"))?;
        let (tess, _) = crate::stage::stage("tessellating", progress, |p| {
            s.surface.tessellate_with_progress(n, m, p)
        });
        crate::interrupt::check()?;
        let mut tess =
            tess.map_err(|e| format!("{name}: cannot tessellate at resolution {n} × {m}: {e}"))?;
        // In the input's coordinates, which an explicit camera (--eye, --target) is given in.
        s.frame.move_to_input(&mut s.tri, &mut tess.positions);
        let mut mesh = RenderMesh::from(&tess);
        // The input (control) mesh's edges are chords of the surface: on convex parts they
        // lie inside it by the chord sag (0.15 of the radius for the icosahedron, 4 % of the
        // bbox diagonal), so they need a depth tolerance above that; the far side is a
        // diameter (over 50 % of the diagonal) away and stays hidden.
        mesh.wire = Some(LineSet::edges_of(&s.tri));
        (mesh, format!("{name} (smoothed)"), 0.1)
    } else {
        let Some(input) = &args.input else {
            return Err(
                "render: an INPUT mesh is required (or --smooth for the built-in icosahedron)"
                    .into(),
            );
        };
        let tri = read_triangles(input)?;
        (RenderMesh::from(&tri), input.display().to_string(), 0.01)
    };
    let views = match &args.eye {
        None => views,
        Some(eye) => {
            let eye = parse_point("eye", eye)?;
            let target = match &args.target {
                Some(t) => parse_point("target", t)?,
                None => {
                    let (lo, hi) = mesh
                        .positions
                        .iter()
                        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                            (lo.min(*p), hi.max(*p))
                        });
                    (lo + hi) / 2.0
                }
            };
            vec![View::Camera(Camera {
                eye,
                target,
                up: parse_point("up", &args.up)?,
                projection: Projection::Perspective {
                    fov_y_degrees: args.fov,
                },
            })]
        }
    };
    let options = RenderOptions {
        mode,
        views,
        size,
        background,
        fov_y_degrees: args.fov,
        samples: args.samples,
        flat: args.flat,
        stripes: args.stripes,
        wire: args.wire,
        wire_depth_tolerance: wire_tolerance,
        ..RenderOptions::default()
    };
    let image = render(&mesh, &options)?;
    // The renderer does not poll for Ctrl-C (a second or two at the largest sizes): the
    // image is not written when one came while it ran.
    crate::interrupt::check()?;
    image.write_png(&args.output)?;
    let mut line = format!(
        "{source} → {} ({}x{}, {} triangles, mode {:?})",
        args.output.display(),
        image.width,
        image.height,
        mesh.triangles.len(),
        args.mode
    );
    if let Some([lo, hi]) = image.legend_range {
        line += &format!(
            "; mean curvature colour range [{}, {}]",
            format_value(lo),
            format_value(hi)
        );
    }
    crate::print_stdout(&(line + "\n"))?;
    Ok(())
}
