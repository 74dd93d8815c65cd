//! The one error type of this crate.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::Format;

/// Where in a file a problem was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// A 1-based line number (text formats).
    Line(usize),
    /// A 0-based byte offset (binary formats).
    Byte(u64),
    /// An element of the file: `kind` (`"vertex"`, `"face"`, `"accessor"`, ...) and its 0-based id.
    Element(&'static str, usize),
    /// The file as a whole.
    File,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(l) => write!(f, "line {l}"),
            Location::Byte(b) => write!(f, "byte {b}"),
            Location::Element(kind, id) => write!(f, "{kind} {id}"),
            Location::File => f.write_str("file"),
        }
    }
}

/// Everything that can go wrong reading or writing a mesh file.
///
/// Every variant names the file; parse errors also say where in it and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The operating system refused to read, create, write or rename a file.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// Neither the extension nor the content identify a supported format.
    #[error("{}: unknown mesh format (expected extension .obj, .ply, .stl, .off, .gltf or .glb, or recognisable content)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The content does not follow the format.
    #[error("{}: {location}: {format} parse error: expected {expected}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The format being read.
        format: Format,
        /// Where the problem is.
        location: Location,
        /// What the reader expected to find there.
        expected: String,
    },
    /// The file is well formed but uses a feature this crate does not read.
    #[error("{}: {location}: {format}: unsupported: {what}", path.display())]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// The format being read.
        format: Format,
        /// Where the feature is used.
        location: Location,
        /// The feature.
        what: String,
    },
    /// The mesh handed to a writer cannot be written (for example a face index out of range).
    #[error("{}: cannot write mesh as {format}: {what}", path.display())]
    InvalidMesh {
        /// The target file.
        path: PathBuf,
        /// The target format.
        format: Format,
        /// What is wrong with the mesh.
        what: String,
    },
    /// A write was stopped by its [`Progress`](algesurf_mesh::progress::Progress) sink
    /// ([`write_with_progress`](crate::write_with_progress)); the temporary file is removed
    /// and the target left as it was.
    #[error("{}: writing cancelled (the file was left as it was)", path.display())]
    Cancelled {
        /// The target file.
        path: PathBuf,
    },
}

impl IoError {
    /// The file this error is about.
    pub fn path(&self) -> &Path {
        match self {
            IoError::Io { path, .. }
            | IoError::UnknownFormat { path }
            | IoError::Parse { path, .. }
            | IoError::Unsupported { path, .. }
            | IoError::InvalidMesh { path, .. }
            | IoError::Cancelled { path } => path,
        }
    }
}

/// Reading context: the file and format, to build errors tersely.
#[derive(Clone, Copy)]
pub(crate) struct Ctx<'a> {
    pub path: &'a Path,
    pub format: Format,
}

impl Ctx<'_> {
    pub fn parse(&self, location: Location, expected: impl Into<String>) -> IoError {
        IoError::Parse {
            path: self.path.to_path_buf(),
            format: self.format,
            location,
            expected: expected.into(),
        }
    }
    pub fn line(&self, line: usize, expected: impl Into<String>) -> IoError {
        self.parse(Location::Line(line), expected)
    }
    pub fn unsupported(&self, location: Location, what: impl Into<String>) -> IoError {
        IoError::Unsupported {
            path: self.path.to_path_buf(),
            format: self.format,
            location,
            what: what.into(),
        }
    }
    /// An I/O failure on this file (a streamed writer's sink).
    pub fn io(&self, source: std::io::Error) -> IoError {
        IoError::Io {
            path: self.path.to_path_buf(),
            source,
        }
    }
    pub fn invalid(&self, what: impl Into<String>) -> IoError {
        IoError::InvalidMesh {
            path: self.path.to_path_buf(),
            format: self.format,
            what: what.into(),
        }
    }
}
