//! The crate's error type.

use thiserror::Error;

/// Everything that can go wrong in `algesurf-mesh`. Bad input never panics; it is reported
/// through one of these variants, naming the offending element by its id in the input order.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum MeshError {
    /// A face refers to a vertex that does not exist.
    #[error(
        "face {face}: corner {corner} refers to vertex {index}, but there are only {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Face id.
        face: usize,
        /// Corner within the face.
        corner: usize,
        /// The offending vertex index.
        index: u32,
        /// Number of vertices in the mesh.
        vertex_count: usize,
    },
    /// A triangle uses the same vertex twice (a [`crate::TriMesh`] requires three distinct corners).
    #[error("triangle {face} repeats a vertex: {corners:?}")]
    RepeatedVertex {
        /// Triangle id.
        face: usize,
        /// Its corners.
        corners: [u32; 3],
    },
    /// A face has fewer than three corners.
    #[error("face {face} has only {corners} corners")]
    TooFewCorners {
        /// Face id.
        face: usize,
        /// Its number of corners.
        corners: usize,
    },
    /// An edge is shared by more than two faces, so the operation (which needs a manifold mesh)
    /// is undefined there.
    #[error("edge ({0}, {1}) is shared by more than two faces")]
    NonManifoldEdge(u32, u32),
    /// A vertex has more than one fan of faces around it.
    #[error("vertex {0} is non-manifold (more than one fan of faces)")]
    NonManifoldVertex(u32),
    /// An element id passed to a query does not exist.
    #[error("{kind} {id} does not exist (there are {count})")]
    NoSuchElement {
        /// "vertex", "edge" or "face".
        kind: &'static str,
        /// The requested id.
        id: usize,
        /// How many elements of that kind there are.
        count: usize,
    },
    /// There is no edge between the two vertices.
    #[error("there is no edge between vertices {0} and {1}")]
    NoSuchEdge(u32, u32),
    /// Normals were requested from the file, but the mesh carries none (or the wrong number).
    #[error(
        "the mesh has no per-vertex normals from the file (expected {expected}, found {found})"
    )]
    MissingNormals {
        /// Number of vertices.
        expected: usize,
        /// Number of normals present.
        found: usize,
    },
    /// A coordinate or parameter is NaN or infinite.
    #[error("non-finite value: {0}")]
    NonFinite(String),
    /// A per-element array has the wrong length.
    #[error("{what}: expected {expected} values, found {found}")]
    LengthMismatch {
        /// What array.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        found: usize,
    },
    /// An option is out of its range (named, with its value).
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// The mesh has more elements than 32-bit indices can address.
    #[error("too many elements for 32-bit indices: {0}")]
    TooLarge(usize),
}
