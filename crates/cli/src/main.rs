//! The `algesurf` command-line tool.
#![forbid(unsafe_code)]

mod check;
mod convert;
mod info;
mod render;
mod smooth;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// mimalloc instead of the system allocator. Construction allocates and frees millions of small
/// buffers on two threads (coefficient vectors, root sets, per-face systems) and large ones per
/// refinement round; with glibc's malloc 15 % of `algesurf smooth` on the bunny was in
/// `malloc`/`free` and page faults (`perf record`, 2026-12-01). Safe code: the crate's
/// `GlobalAlloc` impl carries the `unsafe`.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Smooth piecewise-polynomial surfaces in Bernstein–Bézier form.
#[derive(Parser, Debug)]
#[command(name = "algesurf", version, about, long_about = None, arg_required_else_help = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Describe a mesh: counts, components, genus, validation findings and the repairs
    /// `convert --repair` would make.
    Info(info::InfoArgs),
    /// Convert a mesh between OBJ, PLY, STL, OFF, glTF and GLB, optionally repairing it.
    Convert(convert::ConvertArgs),
    /// Build a C1-smooth A-patch surface through a triangle mesh and its normals, tessellate
    /// it and write it (with no INPUT: a built-in icosahedron, which becomes the unit sphere,
    /// to smooth.glb).
    Smooth(smooth::SmoothArgs),
    /// Render a mesh (or with --smooth its A-patch surface) to PNG: shaded, isophotes, zebra,
    /// patches or curvature, from preset views or an explicit camera.
    Render(render::RenderArgs),
    /// Build the surface as `smooth` does and measure every property it must have
    /// (interpolation, C1, normal agreement, simple roots, watertightness, parameter margins);
    /// exit status 2 when one fails.
    Check(check::CheckArgs),
}

/// Reads a mesh for a command; a file with neither vertices nor faces is an error (the
/// lenient OBJ reader skips lines it does not know, so any text file reads as an empty OBJ).
pub(crate) fn read_mesh(
    path: &std::path::Path,
) -> Result<algesurf_mesh::PolygonMesh, Box<dyn std::error::Error>> {
    let mesh = algesurf_io::read(path)?;
    if mesh.vertex_count() == 0 && mesh.face_count() == 0 {
        return Err(format!(
            "{}: no vertices or faces found (not a mesh file?)",
            path.display()
        )
        .into());
    }
    Ok(mesh)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Info(a) => info::run(a).map(|()| ExitCode::SUCCESS),
        Command::Convert(a) => convert::run(a).map(|()| ExitCode::SUCCESS),
        Command::Smooth(a) => smooth::run(a),
        Command::Render(a) => render::run(a).map(|()| ExitCode::SUCCESS),
        Command::Check(a) => check::run(a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("algesurf: error: {e}");
            ExitCode::FAILURE
        }
    }
}
