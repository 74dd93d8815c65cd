//! The error type of algesurf-apatch.

use thiserror::Error;

/// Everything that can go wrong while building or evaluating A-patches.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ApatchError {
    /// The simplicial hull could not be built (§3).
    #[error(transparent)]
    Hull(#[from] algesurf_hull::HullError),
    /// An error of the BB algebra (degenerate tetrahedron, ...).
    #[error(transparent)]
    Bb(#[from] algesurf_bb::BbError),
    /// A coefficient equation had (numerically) no solution: the geometry it depends on is
    /// degenerate (e.g. a direction along an edge that should cross it).
    #[error("degenerate configuration: {0}")]
    Degenerate(String),
    /// A ray of an edge A-patch (4.9) that Step 6 cannot make single-sheeted: its smallest
    /// root in `[0, 1)` is not certified simple, and raising the faces' apex values does not
    /// help, because the lift it receives from them (their `τ_apex²` continued C1 into the
    /// edge tetrahedron) is negative on its layers 2 or 3 (Lemma 2.3 needs them `≥ 0`). That
    /// happens when the edge tetrahedron lies far outside its faces' tetrahedra measured in
    /// their size (a flat face tetrahedron next to a tall neighbour).
    #[error(
        "edge A-patch of edge ({}, {}) between input faces {} and {} ({side} side): the ray \
         from x = {x} along the edge to y = {y} along the apex segment cannot be made \
         single-sheeted: raising the apex values lowers it there (Step 6, Lemma 2.3)",
        vertices[0], vertices[1], faces[0], faces[1]
    )]
    UnliftableEdgeRay {
        /// The hull edge's vertex ids (of the hull's possibly refined mesh).
        vertices: [u32; 2],
        /// The input faces of the edge's two faces.
        faces: [u32; 2],
        /// `"positive"` or `"negative"`.
        side: &'static str,
        /// The ray's start `q = x p_i + (1 − x) p_j` on the edge.
        x: f64,
        /// Its end `u = y u_k + (1 − y) u_l` on the apex segment.
        y: f64,
    },
    /// An option of [`crate::SurfaceOptions`] is out of its range (named, with its value).
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// Two tetrahedra that must share a face do not.
    #[error("inconsistent hull: {0}")]
    Inconsistent(String),
    /// Building F on one face of the hull failed (a degenerate sub-tetrahedron of a sliver
    /// face, a fit, inconsistent split-face constraints), with the face named: the hull's own
    /// id (of its possibly refined mesh) and the input face it lies on.
    #[error("hull face {face} (on input face {input_face}): {source}")]
    AtFace {
        /// The hull face.
        face: u32,
        /// The input face it lies on.
        input_face: u32,
        /// What went wrong there.
        source: Box<ApatchError>,
    },
    /// Building the edge cubics of one edge of the hull failed, with the edge named.
    #[error(
        "hull edge ({}, {}) between input faces {} and {}: {source}",
        vertices[0], vertices[1], faces[0], faces[1]
    )]
    AtEdge {
        /// The hull edge's vertex ids (of the hull's possibly refined mesh).
        vertices: [u32; 2],
        /// The input faces of the edge's two faces.
        faces: [u32; 2],
        /// What went wrong there.
        source: Box<ApatchError>,
    },
    /// The [`algesurf_mesh::progress::Progress`] given to a `_with_progress` form asked to
    /// stop (in the hull's construction too: it is this variant, not
    /// `Hull(HullError::Cancelled)`); no surface or tessellation was made.
    #[error("cancelled")]
    Cancelled,
}

impl From<algesurf_mesh::progress::Cancelled> for ApatchError {
    fn from(_: algesurf_mesh::progress::Cancelled) -> Self {
        ApatchError::Cancelled
    }
}

impl ApatchError {
    /// This error with hull face `f` of `hull` named ([`ApatchError::AtFace`]).
    pub(crate) fn at_face(self, hull: &algesurf_hull::SimplicialHull, f: usize) -> ApatchError {
        ApatchError::AtFace {
            face: f as u32,
            input_face: hull.faces()[f].source_face,
            source: Box::new(self),
        }
    }

    /// This error with hull edge `e` of `hull` named ([`ApatchError::AtEdge`]); errors
    /// that name their edge already ([`ApatchError::UnliftableEdgeRay`]) stay as they are.
    pub(crate) fn at_edge(self, hull: &algesurf_hull::SimplicialHull, e: usize) -> ApatchError {
        if matches!(self, ApatchError::UnliftableEdgeRay { .. }) {
            return self;
        }
        let he = &hull.edges()[e];
        let face = |f: u32| hull.faces()[f as usize].source_face;
        ApatchError::AtEdge {
            vertices: he.vertices,
            faces: [face(he.face_k), he.face_l.map_or(u32::MAX, face)],
            source: Box::new(self),
        }
    }
}
