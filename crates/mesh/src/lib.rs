//! Polygon and triangle meshes for algesurf: adjacency, validation and repair, vertex normals,
//! Loop and modified Butterfly subdivision steps (whole mesh and local), and f64 spatial
//! queries on a BVH ([`BoxBvh`], [`TriangleBvh`]) and overlapping pairs of boxes
//! ([`morton::MortonBvh`]).
//!
//! ```
//! use algesurf_mesh::{PolygonMesh, RepairOptions, TriMesh, NormalMethod, repair, validate, vertex_normals};
//! use glam::DVec3;
//!
//! // A unit cube made of quads, with one face flipped and one duplicated corner.
//! let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
//! let positions = vec![
//!     p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.),
//!     p(0., 0., 1.), p(1., 0., 1.), p(1., 1., 1.), p(0., 1., 1.),
//!     p(1., 1., 1.), // a duplicate of vertex 6
//! ];
//! let mut mesh = PolygonMesh::new();
//! mesh.positions = positions;
//! for q in [[0, 3, 2, 1], [4, 5, 8, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 5, 6, 2], [0, 4, 7, 3]] {
//!     mesh.push_face(&q);
//! }
//! let report = validate(&mesh);
//! assert!(!report.is_valid()); // face 4 is reversed against its neighbours
//! println!("{report}");
//!
//! let repaired = repair(&mesh, &RepairOptions::default())?;
//! println!("{}", repaired.report);
//! assert_eq!(repaired.report.welded, vec![(8, 6)]);
//! assert_eq!(repaired.report.flipped_faces, vec![4]);
//! let tri = TriMesh::from_polygon_mesh(&repaired.mesh)?;
//! assert_eq!(tri.face_count(), 12);
//! assert_eq!(tri.euler_characteristic(), 2);
//! assert!(tri.signed_volume() > 0.0);
//! let normals = vertex_normals(&tri, NormalMethod::Loop)?;
//! assert!((normals[0].length() - 1.0).abs() < 1e-12);
//! # Ok::<(), algesurf_mesh::MeshError>(())
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod error;
pub mod fasthash;
pub mod flat;
pub mod geometry;
pub mod polygon;
pub mod topology;
pub mod triangulate;
pub mod trimesh;
mod union_find;

pub use error::MeshError;
pub use flat::{FlatRemeshOptions, remesh_flat_regions};
pub use geometry::Aabb;
pub use polygon::{PolygonMesh, Property, PropertyValues};
pub use topology::{Component, Fan, Topology};
pub use triangulate::triangulate_polygon;
pub use trimesh::TriMesh;
pub mod repair;
pub mod validate;
pub use repair::{RepairOptions, RepairReport, Repaired, repair};
pub use validate::{Finding, ValidationOptions, ValidationReport, validate, validate_with};
mod butterfly_normal;
mod butterfly_ring;
mod cone;
pub use butterfly_normal::{
    BUTTERFLY_NORMAL_LEVELS, HUB_VALENCE, butterfly_limit_normal, butterfly_limit_normals,
};
mod folds;
pub mod normals;
pub mod parallel;
pub mod progress;
pub use normals::{
    DEFAULT_MIN_NORMAL_COSINE, NormalMethod, STEEP_NORMAL_DEGREES, condition_normals,
    condition_vertex_normals, cone_axis, face_cone_axis, file_normal_changes, loop_limit_normal,
    unit_face_normals, vertex_normals,
};
pub mod shapes;
pub mod subdivision;
pub use subdivision::{
    LocalRefinement, LoopWeights, Subdivided, VertexOrigin, butterfly_refine_edge,
    butterfly_subdivide, loop_refine_edge, loop_subdivide, split_edge,
};
pub mod bvh;
pub mod morton;
pub mod primitives;
pub mod radix;
mod self_intersection;
pub mod self_join;
pub mod spatial_order;
#[cfg(any(test, feature = "test-util"))]
#[doc(hidden)]
pub mod test_corpus;
#[cfg(any(test, feature = "test-util"))]
#[doc(hidden)]
pub mod test_rng;
pub use bvh::{BoxBvh, ClosestPoint, RayHit, TriangleBvh};
pub use self_intersection::{SELF_INTERSECTION_TOLERANCE, self_intersections};
