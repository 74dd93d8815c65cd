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
    /// Two tetrahedra that must share a face do not.
    #[error("inconsistent hull: {0}")]
    Inconsistent(String),
}
