//! The error type of algesurf-bb.

use thiserror::Error;

/// Everything that can go wrong in algesurf-bb. Functions that take untrusted input return
/// this rather than panicking.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BbError {
    /// The simplex's vertices are (nearly) affinely dependent.
    #[error(
        "degenerate simplex: relative measure {relative_measure:.3e} is below the tolerance {tolerance:.1e} \
         (volume / longest-edge^dimension)"
    )]
    DegenerateSimplex {
        /// Measured (dimension)-volume divided by the longest edge to the power of the dimension.
        relative_measure: f64,
        /// The threshold that was applied.
        tolerance: f64,
    },
    /// A simplex vertex or an argument had a NaN or infinite coordinate.
    #[error("non-finite coordinate in {what}")]
    NonFinite {
        /// Which input was not finite.
        what: &'static str,
    },
    /// The number of coefficients does not match the degree.
    #[error(
        "a degree-{degree} polynomial in {variables} barycentric variables needs {expected} coefficients, got {found}"
    )]
    CoefficientCount {
        /// Polynomial degree.
        degree: usize,
        /// Number of barycentric variables.
        variables: usize,
        /// Required count.
        expected: usize,
        /// Supplied count.
        found: usize,
    },
    /// An operation needed a different degree (too low for a derivative order, a target degree
    /// lower than the source, ...).
    #[error("degree error: {0}")]
    Degree(String),
    /// An index (vertex, layer, multi-index) was out of range.
    #[error("index out of range: {0}")]
    Index(String),
    /// A linear system that should be regular was (numerically) singular.
    #[error("singular system: {0}")]
    Singular(String),
    /// An argument violated a documented precondition.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}
