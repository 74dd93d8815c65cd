//! Implicit A-patch surfaces (Xu–Huang–Bajaj 2001): a C1 piecewise rational cubic F over a
//! simplicial hull whose zero set interpolates a triangle mesh and its normals.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Index loops over barycentric components (τ_k, ∇τ_k, λ_k with one k) read like the
// formulas they implement; iterator chains over zipped arrays would hide that.
#![allow(clippy::needless_range_loop)]

mod constrained;
mod cubic;
pub mod edge;
pub mod error;
pub mod examples;
pub mod face;
mod geometry;
pub mod gradient_scale;
pub mod parameter;
pub mod quadric;
pub mod rational;
pub mod retessellate;
mod rowspace;
pub mod sheet;
pub mod split;
pub mod surface;
pub mod tessellate;
pub mod verify;

pub use edge::{EdgeCubic, EdgeNeighbour};
pub use error::ApatchError;
pub use face::{FaceCubic, VertexData};
pub use parameter::UpdatedPatches;
pub use quadric::Quadric;
pub use retessellate::Retessellation;
pub use split::{SplitFace, SplitSide};
pub use surface::{
    ApatchSurface, ConstructionTimings, FaceFunction, FreeParameter, FreeParameterRule,
    GradientMagnitudes, MAX_UNLIFTABLE_EDGE_REFINEMENTS, SurfaceOptions,
};
pub use tessellate::{PatchKind, Tessellation, TessellationLayout};
pub use verify::{Owner, Piece, PieceFunction};
