//! **algesurf**: smooth piecewise-polynomial surfaces in Bernstein–Bézier form.
//!
//! This facade re-exports the layered crates as modules (depend on a single crate such as
//! `algesurf-bb` if that is all you need):
//!
//! | module | crate | what |
//! | --- | --- | --- |
//! | [`bb`] | `algesurf-bb` | BB polynomials on simplices, continuity, roots, bases |
//! | [`polar`] | `algesurf-polar` | polar forms of Bézier curves and triangular patches |
//! | [`mesh`] | `algesurf-mesh` | meshes with adjacency, validation, repair, normals, subdivision, BVH |
//! | [`io`] | `algesurf-io` | OBJ, PLY, STL, OFF, glTF/GLB readers and writers |
//! | [`hull`] | `algesurf-hull` | the outer simplicial hull of a mesh with normals (A-patches §3) |
//! | [`apatch`] | `algesurf-apatch` | C1 rational A-patch surfaces over the hull, and their tessellation |
//! | [`inspect`] | `algesurf-inspect` | PNG rendering and the continuity/interpolation check battery |
//!
//! ```
//! use algesurf::bb::{BbPoly, Tetrahedron};
//! use glam::DVec3;
//!
//! // A cubic on a tetrahedron, built from its 20 BB coefficients, and evaluated.
//! let tet = Tetrahedron::new([DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z])?;
//! let f = BbPoly::<f64, 4>::from_fn(3, |l| (l[0] as f64) - (l[3] as f64));
//! let value = f.value_at(&tet, DVec3::new(0.1, 0.2, 0.3));
//! assert!((value - (3.0 * 0.4 - 3.0 * 0.3)).abs() < 1e-14);
//! # Ok::<(), algesurf::bb::BbError>(())
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub use algesurf_apatch as apatch;
pub use algesurf_bb as bb;
pub use algesurf_hull as hull;
pub use algesurf_inspect as inspect;
pub use algesurf_io as io;
pub use algesurf_mesh as mesh;
pub use algesurf_polar as polar;
