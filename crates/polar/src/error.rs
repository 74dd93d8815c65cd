//! The error type of algesurf-polar.

use algesurf_bb::BbError;
use thiserror::Error;

/// Everything that can go wrong in algesurf-polar. Functions that take untrusted input return
/// this rather than panicking.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum PolarError {
    /// The three points of an affine frame Δrst are (nearly) collinear (thesis §2.7.3: a frame
    /// needs three affinely independent points).
    #[error(
        "degenerate affine frame: relative area {relative_area:.3e} is below the tolerance {tolerance:.1e} \
         (|det(s − r, t − r)| / longest-edge²)"
    )]
    DegenerateFrame {
        /// `|det(s − r, t − r)| / L²` with L the longest edge.
        relative_area: f64,
        /// The threshold that was applied.
        tolerance: f64,
    },
    /// The two points r, s of an interval frame (nearly) coincide.
    #[error("degenerate interval frame: r = {r}, s = {s}")]
    DegenerateInterval {
        /// First point of the frame.
        r: f64,
        /// Second point of the frame.
        s: f64,
    },
    /// An input had a NaN or infinite coordinate.
    #[error("non-finite coordinate in {what}")]
    NonFinite {
        /// Which input was not finite.
        what: &'static str,
    },
    /// A blossom of a degree-n form takes exactly n arguments.
    #[error(
        "the polar form of a degree-{degree} patch or curve takes {degree} arguments, got {found}"
    )]
    ArgumentCount {
        /// The degree n (= the required number of arguments).
        degree: usize,
        /// The number of arguments supplied.
        found: usize,
    },
    /// Two patches (or curves) that must have the same degree do not.
    #[error("degree mismatch: {left} and {right}")]
    DegreeMismatch {
        /// Degree of the first operand.
        left: usize,
        /// Degree of the second operand.
        right: usize,
    },
    /// Two domain triangles are not adjacent along a common edge (Lemma 3.1.4 needs two frames
    /// that share exactly two vertices, with the third vertices on opposite sides of the edge).
    #[error("frames are not adjacent along a common edge: {0}")]
    NotAdjacent(String),
    /// A domain point that must be a vertex of a frame is not.
    #[error("the point ({x}, {y}) is not a vertex of the patch's frame")]
    NotAVertex {
        /// x coordinate of the point.
        x: f64,
        /// y coordinate of the point.
        y: f64,
    },
    /// The patch is singular at the point (∂F/∂x × ∂F/∂y vanishes relative to the scale of the
    /// first derivatives), so the unit normal is undefined.
    #[error(
        "singular patch: |F_x × F_y| is {relative:.3e} of the derivative scale² (tolerance {tolerance:.1e})"
    )]
    SingularNormal {
        /// `|F_x × F_y| / scale²`, scale = n · (net size) / (frame size).
        relative: f64,
        /// The threshold that was applied.
        tolerance: f64,
    },
    /// An argument violated a documented precondition.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// An error of the underlying Bernstein–Bézier layer.
    #[error(transparent)]
    Bb(#[from] BbError),
}
