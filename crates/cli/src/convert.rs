//! `algesurf convert IN OUT [--repair] [--normals area|angle|loop] [--f32] [--ascii]`.

use std::path::PathBuf;

use algesurf_io::WriteOptions;
use algesurf_mesh::{NormalMethod, RepairOptions, TriMesh, repair, vertex_normals};

/// How `--normals` computes vertex normals.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalsArg {
    /// Area-weighted face normals.
    Area,
    /// Angle-weighted face normals.
    Angle,
    /// Loop subdivision limit normals.
    Loop,
}

/// Arguments of `algesurf convert`.
#[derive(clap::Args, Debug, Clone)]
pub struct ConvertArgs {
    /// Input mesh (OBJ, PLY, STL, OFF, glTF or GLB; format by extension, else by content).
    pub input: PathBuf,
    /// Output mesh; the format follows the extension (.obj .ply .stl .off .gltf .glb).
    pub output: PathBuf,
    /// Weld, drop degenerate/duplicate faces and unused vertices, triangulate, and orient
    /// (the default repair steps); prints what changed to stderr.
    #[arg(long)]
    pub repair: bool,
    /// Compute vertex normals and write them (replacing any read from the input).
    #[arg(long, value_enum)]
    pub normals: Option<NormalsArg>,
    /// Store coordinates as f32 in OBJ, OFF and PLY (default: full f64 precision).
    #[arg(long)]
    pub f32: bool,
    /// Write ascii PLY or STL instead of binary.
    #[arg(long)]
    pub ascii: bool,
}

/// Converts `args.input` to `args.output`.
///
/// # Errors
/// Unreadable or malformed input (the message names the file and the place), a mesh the
/// normals cannot be computed on (non-manifold or invalid faces: try `--repair`), or a write
/// failure (the output file is then left untouched).
pub fn run(args: &ConvertArgs) -> Result<(), Box<dyn std::error::Error>> {
    crate::known_format(&args.output)?;
    let mut mesh = crate::read_mesh(&args.input)?;
    if args.repair {
        let repaired = repair(&mesh, &RepairOptions::default())?;
        // Not `eprint!`, which panics when stderr is a closed pipe (see `print_stderr`).
        use std::io::Write;
        let _ = write!(
            std::io::stderr().lock(),
            "{}: {}",
            args.input.display(),
            repaired.report
        );
        mesh = repaired.mesh;
    }
    if let Some(method) = args.normals {
        let tri = TriMesh::from_polygon_mesh(&mesh).map_err(|e| {
            format!(
                "{}: cannot compute normals: {e} (try --repair)",
                args.input.display()
            )
        })?;
        let method = match method {
            NormalsArg::Area => NormalMethod::Area,
            NormalsArg::Angle => NormalMethod::Angle,
            NormalsArg::Loop => NormalMethod::Loop,
        };
        let normals = vertex_normals(&tri, method).map_err(|e| {
            format!(
                "{}: cannot compute normals: {e} (try --repair)",
                args.input.display()
            )
        })?;
        mesh.normals = Some(normals);
    }
    let options = WriteOptions {
        f32: args.f32,
        ascii: args.ascii,
        ..WriteOptions::default()
    };
    // Reading, repair and normals do not poll for Ctrl-C (each well under a second on the
    // corpus); the write does (first thing, so a signal that came before writes nothing),
    // and removes its temporary file when stopped.
    let sink = crate::interrupt::Interruptible(&algesurf_mesh::progress::NoProgress);
    if let Err(e) = algesurf_io::write_with_progress(&args.output, &mesh, &options, &sink) {
        crate::interrupt::check()?;
        return Err(e.into());
    }
    Ok(())
}
