//! The error type of algesurf-hull.

use algesurf_bb::BbError;
use algesurf_mesh::MeshError;
use thiserror::Error;

/// Everything that can go wrong while building a [`crate::SimplicialHull`].
///
/// Faces are named by their id in the *input* triangle list, vertices and edges by vertex ids
/// of the input mesh. Refinement appends vertices, so a vertex id at or above the input vertex
/// count names a vertex inserted by the local Butterfly refinement of §3.1.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum HullError {
    /// The input mesh is malformed (index out of range, repeated vertex, ...), or a local
    /// refinement step failed.
    #[error("mesh error: {0}")]
    Mesh(#[from] MeshError),
    /// The number of normals differs from the number of vertices.
    #[error("{vertices} vertices but {normals} normals")]
    NormalCount {
        /// Number of vertices.
        vertices: usize,
        /// Number of normals.
        normals: usize,
    },
    /// A position or normal is NaN or infinite, or a normal is zero.
    #[error("vertex {vertex}: {what} is not a finite non-zero vector")]
    BadVertexData {
        /// The vertex.
        vertex: u32,
        /// "position" or "normal".
        what: &'static str,
    },
    /// The largest absolute coordinate is outside `[2^-252, 2^252]`
    /// ([`crate::COORDINATE_EXPONENT_RANGE`]): the hull's areas and normals, products of up to
    /// four lengths and their sums, would overflow or underflow `f64` (an icosahedron at `2^260`
    /// failed with a zero face normal, one at `2^-270` with zero areas). The construction is
    /// exact under scaling by a power of two, so scaling the mesh by `2^-e` (`e` the exponent
    /// of its largest coordinate) and the results back by `2^e` builds it.
    #[error(
        "the largest coordinate, {largest:e} in absolute value, is outside [2^-252, 2^252] \
         (1.4e-76 to 7.2e75), where the hull's areas and normals (products of four lengths) \
         stay within f64: scale the mesh by a power of two (exact) and the results back"
    )]
    CoordinatesOutOfRange {
        /// The largest absolute coordinate.
        largest: f64,
    },
    /// A triangle has (numerically) zero area, so it has no normal `n_ijk`.
    #[error("face {face} {vertices:?} is degenerate (zero area)")]
    DegenerateFace {
        /// The input face.
        face: u32,
        /// Its vertices.
        vertices: [u32; 3],
    },
    /// An edge has more than two faces; the hull of §3 needs a manifold surface.
    #[error("edge ({0}, {1}) has more than two faces")]
    NonManifoldEdge(u32, u32),
    /// Two faces traverse their common edge in the same direction, so "the positive side" is
    /// not defined consistently (§3 assumes normals pointing to one side of the surface).
    #[error("faces {faces:?} traverse their common edge ({}, {}) in the same direction", edge[0], edge[1])]
    InconsistentOrientation {
        /// The edge.
        edge: [u32; 2],
        /// The two input faces.
        faces: [u32; 2],
    },
    /// `n_ijkᵀ n_l ≤ 0`: the vertex normal does not point to the positive side of the face, so
    /// `t_l = (p_l − c)ᵀn_l / n_ijkᵀn_l` of §3.1 does not exist (or has the wrong sign).
    #[error(
        "face {face}: the normal of vertex {vertex} is not on the positive side of the face \
         (n_ijk·n_l = {cosine:.3e} ≤ 0)"
    )]
    NormalNotOnPositiveSide {
        /// The input face.
        face: u32,
        /// The vertex.
        vertex: u32,
        /// `n_ijkᵀ n_l / |n_l|`.
        cosine: f64,
    },
    /// The faces around a vertex fold over: their normals fit in no open hemisphere, so no
    /// normal at the vertex is on the positive side of all of them, as §3 needs (the vertex
    /// normal is not at fault, and no choice of it helps). Reported instead of
    /// [`HullError::NormalNotOnPositiveSide`] where that is the cause.
    #[error(
        "vertex {vertex}: its faces fold over, their normals fit in no open hemisphere (the \
         best direction's least cosine with them is {least_cosine:.3}), so no normal at the \
         vertex is on the positive side of all of them as §3 needs (face {face} is one it \
         fails); unfold the mesh there first (`algesurf_mesh::repair` moves such vertices, \
         `RepairOptions::unfold_vertices`)"
    )]
    FoldedVertex {
        /// The vertex.
        vertex: u32,
        /// The input face whose check failed.
        face: u32,
        /// `max_m min_f m·n_f` over the vertex's faces (≤ 0).
        least_cosine: f64,
    },
    /// A face or edge tetrahedron came out degenerate.
    #[error("the {what} tetrahedron of {element} is degenerate: {source}")]
    DegenerateTetrahedron {
        /// "positive face", "negative edge", ...
        what: &'static str,
        /// The face or edge, described in input ids.
        element: String,
        /// The underlying check.
        source: BbError,
    },
    /// An edge needs an apex that its face does not have (cannot happen for a consistent
    /// classification; see [`crate::Convexity`]).
    #[error("edge ({}, {}) needs the {side} apex of face {face}, which that face does not have", edge[0], edge[1])]
    MissingApex {
        /// The edge (input ids).
        edge: [u32; 2],
        /// The input face.
        face: u32,
        /// "positive" or "negative".
        side: &'static str,
    },
    /// Hull tetrahedra still intersect after the allowed number of local refinement rounds
    /// (§3.1). `edge` is the input edge the intersecting pair's shared edge lies on or was
    /// made by refining (for tetrahedra that share no edge, the longest edge of the first
    /// one's element); `faces` are the input faces the two tetrahedra belong to.
    #[error(
        "hull tetrahedra still intersect at edge ({}, {}) (input faces {} and {}) after {rounds} \
         rounds of local Butterfly refinement: {reason}",
        edge[0], edge[1], faces[0], faces[1]
    )]
    UnresolvedIntersection {
        /// The input edge (vertex ids of the input mesh).
        edge: [u32; 2],
        /// Input faces of the two intersecting tetrahedra.
        faces: [u32; 2],
        /// Rounds of refinement done.
        rounds: usize,
        /// Why refinement stopped: the round limit, or a refined mesh on which the hull
        /// cannot be built (for example a face the normal of one of its input vertices no
        /// longer points to the positive side of).
        reason: String,
    },
    /// An option is out of its documented range.
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// The [`algesurf_mesh::progress::Progress`] given to a `_with_progress` form asked to
    /// stop; no hull was made.
    #[error("cancelled")]
    Cancelled,
}

impl From<algesurf_mesh::progress::Cancelled> for HullError {
    fn from(_: algesurf_mesh::progress::Cancelled) -> Self {
        HullError::Cancelled
    }
}
