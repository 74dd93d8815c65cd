//! facade
pub use algesurf_bb as bb;
pub use algesurf_polar as polar;
