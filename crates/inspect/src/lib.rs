//! See and measure algesurf surfaces.
//!
//! - [`render`]: a deterministic CPU renderer writing PNG (shaded, isophotes, zebra, patch
//!   colours, wireframe overlay, mean curvature).
//! - [`check`]: the measurement battery (interpolation, C1 across hull facets, normal agreement
//!   across patch boundaries, simple roots, watertightness, parameter margins), generic over
//!   the [`check::PatchSurface`] trait that every patch-based surface implements.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod check;
pub mod render;

/// Errors of the inspection layer.
#[derive(Debug, thiserror::Error)]
pub enum InspectError {
    /// An option is out of range (size zero, empty mesh, …).
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// The surface cannot be measured (it cannot be tessellated, a piece is degenerate).
    #[error("cannot measure the surface: {0}")]
    Measurement(String),
    /// Writing a PNG failed.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// The [`algesurf_mesh::progress::Progress`] given to
    /// [`check::check_with_progress`] asked to stop.
    #[error("cancelled")]
    Cancelled,
}

impl From<algesurf_mesh::progress::Cancelled> for InspectError {
    fn from(_: algesurf_mesh::progress::Cancelled) -> Self {
        InspectError::Cancelled
    }
}
