//! Mesh files in and out for algesurf: OBJ, PLY (ascii and binary), STL (ascii and binary), OFF,
//! glTF 2.0 and GLB, all read into and written from one [`PolygonMesh`].
//!
//! ```
//! use algesurf_io::{read, write, WriteOptions};
//! use algesurf_mesh::PolygonMesh;
//! use glam::DVec3;
//!
//! let dir = std::env::temp_dir().join(format!("algesurf-io-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! let mesh = PolygonMesh::from_triangles(
//!     vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.1, 0.2, 1.0 / 3.0)],
//!     &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
//! );
//! let path = dir.join("tetrahedron.ply");
//! write(&path, &mesh, &WriteOptions::default())?; // format from the extension
//! let back = read(&path)?;
//! assert_eq!(back, mesh); // PLY keeps full f64 precision by default
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! * The format is chosen by the file extension, with a content sniff ([`Format::sniff`]) when
//!   the extension is missing or unknown.
//! * Loaded meshes keep the file's vertex and face order, so element ids reported by later
//!   stages can be found in the user's file. (STL has no shared vertices: bit-identical corner
//!   positions are merged, in order of first appearance; glTF primitives are concatenated in
//!   scene order with their node transforms applied.)
//! * Normals are per vertex. OBJ names them per corner: a vertex takes the normal its corners
//!   name, and where they name different values (a hard edge, where exporters write one
//!   normal per side) the mean of those directions, each value counted once, whatever the
//!   order of the faces.
//! * Readers never panic, on any input; errors ([`IoError`]) name the file, the line, byte or
//!   element, and what was expected.
//! * OBJ, OFF and PLY writers keep full `f64` precision unless [`WriteOptions::f32`] is set; STL
//!   and glTF store `f32` by definition of the format.
//! * Writers write a temporary file in the target directory and rename it over the target, so a
//!   failed write never clobbers an existing file. A symbolic link is followed (its target is
//!   replaced, the link kept); a device or named pipe (`/dev/null`, a FIFO) is written in
//!   place instead of being replaced by a plain file.
//! * PLY and GLB files are streamed to disk: encoded in blocks of elements in parallel and
//!   written in order, without a copy of the whole file in memory (a tessellation's file is
//!   tens of megabytes, and the fresh pages of such a copy cost more than the encoding).
//!
//! Hand-written parts (no maintained crate does them, or not in the way we need): the OBJ
//! reader (tobj renumbers vertices per group and drops unused ones; it is used as a test oracle
//! instead), the OBJ, OFF and ascii-STL writers, and GLB buffer packing.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod atomic;
mod blocks;
mod error;
mod format;
mod gltf_io;
mod gltf_write;
mod number;
mod obj;
mod off;
mod ply;
mod stl;

use std::io::Write;
use std::path::Path;

pub use algesurf_mesh::PolygonMesh;
use algesurf_mesh::progress::{NoProgress, Progress, check_cancelled};
pub use atomic::{probe_writable, write_atomic};
pub use error::{IoError, Location};
pub use format::Format;

use error::Ctx;

/// Name of the per-vertex property written to glTF as the custom attribute `_PATCH_ID`, and
/// the name given to that attribute when read back.
pub const PATCH_ID: &str = "patch_id";

/// Name of the per-face property holding the OBJ group (`g`/`o`) index of each face, set by the
/// OBJ reader when a file has more than one group, and written back as `g` lines.
pub const OBJ_GROUP: &str = "obj_group";

/// Options for the writers. The default writes full precision, binary PLY (little endian),
/// binary STL, and normals when the mesh has them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WriteOptions {
    /// Store coordinates, normals and float properties as `f32` (OBJ, OFF, PLY) instead of
    /// full `f64` precision. STL and glTF are always `f32`.
    pub f32: bool,
    /// Write ascii instead of binary (PLY and STL).
    pub ascii: bool,
    /// Write binary PLY big endian instead of little endian.
    pub big_endian: bool,
    /// Write the mesh's vertex normals when it has them (OBJ, OFF, PLY, glTF).
    pub normals: bool,
}

impl Default for WriteOptions {
    fn default() -> Self {
        WriteOptions {
            f32: false,
            ascii: false,
            big_endian: false,
            normals: true,
        }
    }
}

/// Reads a mesh, choosing the format by extension and falling back to a content sniff.
pub fn read(path: impl AsRef<Path>) -> Result<PolygonMesh, IoError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| IoError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let format = Format::from_path(path)
        .or_else(|| Format::sniff(&bytes))
        .ok_or_else(|| IoError::UnknownFormat {
            path: path.to_path_buf(),
        })?;
    read_impl(&bytes, format, path, path.parent())
}

/// Reads a mesh in the given format, whatever the file's extension.
pub fn read_as(path: impl AsRef<Path>, format: Format) -> Result<PolygonMesh, IoError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| IoError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_impl(&bytes, format, path, path.parent())
}

/// Reads a mesh from bytes in memory. Errors name the file `<memory>`; a `.gltf` whose
/// buffers live in other files cannot be read this way (data URIs can).
pub fn read_bytes(bytes: &[u8], format: Format) -> Result<PolygonMesh, IoError> {
    read_impl(bytes, format, Path::new("<memory>"), None)
}

fn read_impl(
    bytes: &[u8],
    format: Format,
    path: &Path,
    base_dir: Option<&Path>,
) -> Result<PolygonMesh, IoError> {
    let ctx = Ctx { path, format };
    match format {
        Format::Obj => obj::read(without_bom(bytes), ctx),
        Format::Ply => ply::read(bytes, ctx),
        // The STL reader strips a byte order mark itself, from ascii files only: a binary
        // file's 80-byte header may begin with any bytes.
        Format::Stl => stl::read(bytes, ctx),
        Format::Off => off::read(without_bom(bytes), ctx),
        Format::Gltf => gltf_io::read(without_bom(bytes), ctx, base_dir),
        Format::Glb => gltf_io::read(bytes, ctx, base_dir),
    }
}

/// The UTF-8 encoding of U+FEFF, the byte order mark that Windows editors (Notepad, Excel's
/// "CSV UTF-8", some exporters) put at the start of text files.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// `bytes` without a leading UTF-8 byte order mark. For the text formats (OBJ, OFF, ascii
/// STL, glTF JSON): the mark is not whitespace, so an OBJ's first statement read as the
/// unknown keyword `\u{FEFF}v` and was skipped, and its first vertex with it (the file then
/// failed at its first face naming a vertex count one short, or read with a vertex missing).
/// Line numbers are unchanged: the mark is on the first line.
pub(crate) fn without_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(UTF8_BOM).unwrap_or(bytes)
}

/// Writes a mesh, choosing the format by the extension of `path`; writes a temporary file in
/// the same directory and renames it over `path`, so that a failure leaves `path` untouched.
pub fn write(
    path: impl AsRef<Path>,
    mesh: &PolygonMesh,
    options: &WriteOptions,
) -> Result<(), IoError> {
    write_with_progress(path, mesh, options, &NoProgress)
}

/// Writes a mesh in the given format, whatever the extension of `path` (atomically, as
/// [`write()`]).
pub fn write_as(
    path: impl AsRef<Path>,
    mesh: &PolygonMesh,
    format: Format,
    options: &WriteOptions,
) -> Result<(), IoError> {
    write_as_with_progress(path, mesh, format, options, &NoProgress)
}

/// [`write()`], reporting the bytes written to `progress` (one step, `"writing"`, with no
/// total: the size is known only once the file is encoded) and stopping when it is
/// [cancelled](Progress::cancelled): before the temporary file is made, or between the
/// pieces it is written in (a megabyte or less each). A cancelled write removes its
/// temporary file and leaves `path` as it was: absent, or the old file (a device or named
/// pipe, which is written in place, has had what was written before the stop).
///
/// ```
/// use algesurf_io::{write_with_progress, IoError, WriteOptions};
/// use algesurf_mesh::progress::ProgressCounter;
/// use algesurf_mesh::PolygonMesh;
/// use glam::DVec3;
///
/// let dir = std::env::temp_dir().join(format!("algesurf-io-cancel-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let mesh = PolygonMesh::from_triangles(vec![DVec3::ZERO, DVec3::X, DVec3::Y], &[[0, 1, 2]]);
/// let path = dir.join("triangle.ply");
/// let progress = ProgressCounter::new();
/// write_with_progress(&path, &mesh, &WriteOptions::default(), &progress)?;
/// assert!(progress.snapshot().done > 0); // bytes written
/// let before = std::fs::read(&path)?;
///
/// progress.cancel(); // Ctrl-C, say
/// let e = write_with_progress(&path, &mesh, &WriteOptions::default(), &progress);
/// assert!(matches!(e, Err(IoError::Cancelled { .. })));
/// assert_eq!(std::fs::read(&path)?, before); // the old file, untouched
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`write()`], and [`IoError::Cancelled`] when `progress` stopped it.
pub fn write_with_progress(
    path: impl AsRef<Path>,
    mesh: &PolygonMesh,
    options: &WriteOptions,
    progress: &dyn Progress,
) -> Result<(), IoError> {
    let path = path.as_ref();
    let format = Format::from_path(path).ok_or_else(|| IoError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    write_as_with_progress(path, mesh, format, options, progress)
}

/// [`write_as`] with the progress reports and cancellation of [`write_with_progress`].
///
/// # Errors
/// As [`write_as`], and [`IoError::Cancelled`] when `progress` stopped it.
pub fn write_as_with_progress(
    path: impl AsRef<Path>,
    mesh: &PolygonMesh,
    format: Format,
    options: &WriteOptions,
    progress: &dyn Progress,
) -> Result<(), IoError> {
    let path = path.as_ref();
    let cancelled = || IoError::Cancelled {
        path: path.to_path_buf(),
    };
    check_cancelled(progress).map_err(|_| cancelled())?;
    progress.start("writing", 0);
    let ctx = Ctx { path, format };
    let result = match format {
        // PLY and glTF are streamed to the file: a tessellation's PLY or GLB is tens of MB.
        Format::Ply | Format::Gltf | Format::Glb => {
            let stream = if format == Format::Ply {
                ply::write_to
            } else {
                gltf_write::write_to
            };
            check_writable(mesh, ctx)?;
            atomic::write_atomic_with(path, |file| {
                stream(
                    mesh,
                    options,
                    ctx,
                    &mut atomic::Watched::new(file, progress),
                )
            })
        }
        Format::Obj | Format::Stl | Format::Off => {
            let bytes = write_impl(mesh, format, options, path)?;
            check_cancelled(progress).map_err(|_| cancelled())?;
            atomic::write_atomic_with(path, |file| {
                atomic::Watched::new(file, progress)
                    .write_all(&bytes)
                    .map_err(|e| ctx.io(e))
            })
        }
    };
    // Whatever failed once the sink said stop (the watched writer's refusal, most likely)
    // is the cancellation: that is what the caller asked for and must be told.
    match result {
        Err(_) if progress.cancelled() => Err(cancelled()),
        r => r,
    }
}

/// Encodes a mesh in memory in the given format.
pub fn write_bytes(
    mesh: &PolygonMesh,
    format: Format,
    options: &WriteOptions,
) -> Result<Vec<u8>, IoError> {
    write_impl(mesh, format, options, Path::new("<memory>"))
}

fn write_impl(
    mesh: &PolygonMesh,
    format: Format,
    options: &WriteOptions,
    path: &Path,
) -> Result<Vec<u8>, IoError> {
    let ctx = Ctx { path, format };
    check_writable(mesh, ctx)?;
    match format {
        Format::Obj => Ok(obj::write(mesh, options)),
        Format::Ply => ply::write(mesh, options, ctx),
        Format::Stl => Ok(stl::write(mesh, options)),
        Format::Off => Ok(off::write(mesh, options)),
        Format::Gltf | Format::Glb => {
            let mut bytes = Vec::new();
            gltf_write::write_to(mesh, options, ctx, &mut bytes)?;
            Ok(bytes)
        }
    }
}

/// Faces must index existing vertices and property/normal arrays must match element counts.
fn check_writable(mesh: &PolygonMesh, ctx: Ctx<'_>) -> Result<(), IoError> {
    let n = mesh.vertex_count();
    for (f, face) in mesh.faces().enumerate() {
        if let Some(&v) = face.iter().find(|&&v| v as usize >= n) {
            return Err(ctx.invalid(format!(
                "face {f} uses vertex {v}, but the mesh has {n} vertices"
            )));
        }
    }
    if let Some(normals) = &mesh.normals
        && normals.len() != n
    {
        return Err(ctx.invalid(format!("{} normals for {n} vertices", normals.len())));
    }
    for p in &mesh.vertex_properties {
        if p.values.len() != n {
            return Err(ctx.invalid(format!(
                "vertex property '{}' has {} values for {n} vertices",
                p.name,
                p.values.len()
            )));
        }
    }
    for p in &mesh.face_properties {
        if p.values.len() != mesh.face_count() {
            return Err(ctx.invalid(format!(
                "face property '{}' has {} values for {} faces",
                p.name,
                p.values.len(),
                mesh.face_count()
            )));
        }
    }
    Ok(())
}

/// Splits every face into triangles as a fan from its first corner (for STL and glTF, which
/// store triangles only). Returns the triangles and, for each, the face it came from.
/// Faces with fewer than three corners are skipped. Triangulate non-convex polygons with
/// `algesurf_mesh` first when the fan is not good enough.
pub(crate) fn fan_triangles(mesh: &PolygonMesh) -> Vec<[u32; 3]> {
    let mut out = Vec::with_capacity(mesh.face_count());
    for face in mesh.faces() {
        for i in 1..face.len().saturating_sub(1) {
            out.push([face[0], face[i], face[i + 1]]);
        }
    }
    out
}
