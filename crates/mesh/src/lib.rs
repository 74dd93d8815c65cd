//! Polygon and triangle meshes for algesurf (work in progress).
#![forbid(unsafe_code)]

pub mod polygon;
pub use polygon::{PolygonMesh, Property, PropertyValues};
