//! `--normals auto`'s second try: angle-weighted normals where the auto normals leave hull
//! tetrahedra that refinement cannot separate.
//!
//! The auto normals (Loop, and the Butterfly limit normal at sharp rims) are made for
//! refinement: Butterfly splits turn the faces around a vertex into the plane its normal
//! says. Both are averages over a vertex's ring that weigh each neighbour alike, whatever
//! the shape of the faces between them; on meshes of long thin faces they lean far from
//! the faces (68° on every vertex of a washer whose flat rings are single strips of
//! slivers, as CAD exporters triangulate them), every face's tetrahedron leans over its
//! neighbours, and refinement multiplies the overlaps. Angle-weighted normals (each face
//! weighted by its angle at the vertex: Thürmer and Wüthrich 1998) do not depend on how the
//! faces are cut, and there they lean 46°: the washer's hull, and that of the spot mesh
//! tessellated into strips, need no refinement at all. Where the auto normals build, nothing
//! changes; every corpus mesh builds with them.

use crate::numbering::{Numbering, build_surface};
use algesurf_apatch::{ApatchError, ApatchSurface, SurfaceOptions};
use algesurf_hull::HullError;
use algesurf_mesh::progress::Progress;
use algesurf_mesh::{NormalMethod, TriMesh, vertex_normals};
use glam::DVec3;
use std::time::Instant;

/// A build with the auto normals whose hull refinement could not separate, after which the
/// surface was built with angle-weighted normals.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct NormalsFallback {
    /// The failed build's error (ids of the repaired mesh).
    pub error: String,
    /// Wall-clock seconds the failed build took: part of construction's time.
    pub seconds: f64,
}

/// What [`build_surface_or_fall_back`] did besides the build it returns.
#[derive(Debug, Default)]
pub(crate) struct Attempts {
    /// The surface was built with angle-weighted normals after the auto normals failed.
    pub fallback: Option<NormalsFallback>,
    /// The angle-weighted normals were tried after the auto normals failed, and failed too
    /// (the error returned is the auto normals').
    pub fallback_failed: bool,
}

/// [`build_surface`] with `normals`; when they are the auto normals (`auto`) and the hull's
/// tetrahedra stay overlapping after refinement ([`HullError::UnresolvedIntersection`]), built
/// again with angle-weighted normals. Returns that build when it succeeds, else the first.
pub(crate) fn build_surface_or_fall_back(
    tri: TriMesh,
    normals: &[DVec3],
    auto: bool,
    options: &SurfaceOptions,
    progress: &dyn Progress,
) -> (
    Result<ApatchSurface, ApatchError>,
    TriMesh,
    Numbering,
    Attempts,
) {
    let start = Instant::now();
    let (first, tri, numbering) = build_surface(tri, normals, options, progress);
    let unseparated = matches!(
        &first,
        Err(ApatchError::Hull(HullError::UnresolvedIntersection { .. }))
    );
    if !(auto && unseparated) {
        return (first, tri, numbering, Attempts::default());
    }
    let seconds = start.elapsed().as_secs_f64();
    // `tri` is numbered as the failed build left it: the normals follow that numbering.
    let Ok(angle) = vertex_normals(&tri, NormalMethod::Angle) else {
        return (first, tri, numbering, Attempts::default());
    };
    let (second, tri, second_numbering) = build_surface(tri, &angle, options, progress);
    match (first, second) {
        (Err(e), Ok(surface)) => {
            let fallback = NormalsFallback {
                error: e.to_string(),
                seconds,
            };
            let attempts = Attempts {
                fallback: Some(fallback),
                fallback_failed: false,
            };
            (Ok(surface), tri, second_numbering, attempts)
        }
        (_, Err(ApatchError::Cancelled)) => (
            Err(ApatchError::Cancelled),
            tri,
            second_numbering,
            Attempts::default(),
        ),
        (first, _) => {
            let attempts = Attempts {
                fallback: None,
                fallback_failed: true,
            };
            (first, tri, numbering, attempts)
        }
    }
}
