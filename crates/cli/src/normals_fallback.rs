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
//!
//! The second try is also made where the auto normals' hull has a degenerate tetrahedron: a
//! tetrahedron's apex comes from its corners' normals (§3.1's `t_l`), and on a puck of 1024
//! segments with remeshed fan caps, the faces that the single-sheet refinement splits at its
//! rim get a negative face tetrahedron of relative volume 6e-11 (below the hull's `1e-10`)
//! with the auto normals, while the angle-weighted normals build it.

use crate::numbering::{Numbering, build_surface};
use algesurf_apatch::{ApatchError, ApatchSurface, SurfaceOptions};
use algesurf_hull::HullError;
use algesurf_mesh::progress::Progress;
use algesurf_mesh::{NormalMethod, TriMesh, vertex_normals};
use glam::DVec3;
use std::time::Instant;

/// How the build with the auto normals failed, where a build with angle-weighted normals is
/// tried next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FallbackCause {
    /// Hull refinement could not separate the tetrahedra
    /// ([`HullError::UnresolvedIntersection`]).
    Unseparated,
    /// A hull tetrahedron came out degenerate ([`HullError::DegenerateTetrahedron`]).
    Degenerate,
}

impl FallbackCause {
    /// The cause of `error`, where it is one that other normals can remove.
    fn of(error: &ApatchError) -> Option<FallbackCause> {
        match error {
            ApatchError::Hull(HullError::UnresolvedIntersection { .. }) => {
                Some(FallbackCause::Unseparated)
            }
            ApatchError::Hull(HullError::DegenerateTetrahedron { .. }) => {
                Some(FallbackCause::Degenerate)
            }
            _ => None,
        }
    }

    /// What went wrong with the auto normals, as a clause: "the hull's tetrahedra still
    /// overlapped after refinement".
    pub fn failure(self) -> &'static str {
        match self {
            FallbackCause::Unseparated => "the hull's tetrahedra still overlapped after refinement",
            FallbackCause::Degenerate => "a hull tetrahedron came out degenerate",
        }
    }

    /// What the angle-weighted normals did instead: "which separate".
    pub fn success(self) -> &'static str {
        match self {
            FallbackCause::Unseparated => "which separate",
            FallbackCause::Degenerate => "whose hull tetrahedra are not degenerate",
        }
    }

    /// The report's name of the cause.
    pub fn name(self) -> &'static str {
        match self {
            FallbackCause::Unseparated => "unseparated",
            FallbackCause::Degenerate => "degenerate_tetrahedron",
        }
    }
}

/// A build with the auto normals whose hull refinement could not separate, or whose hull had
/// a degenerate tetrahedron, after which the surface was built with angle-weighted normals.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct NormalsFallback {
    /// The failed build's error (ids of the repaired mesh).
    pub error: String,
    /// How it failed.
    pub cause: FallbackCause,
    /// Wall-clock seconds the failed build took: part of construction's time.
    pub seconds: f64,
}

impl NormalsFallback {
    /// The reports' `normals_fallback` object (`algesurf smooth --report`, `algesurf check
    /// --json`).
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "normals": "angle",
            "cause": self.cause.name(),
            "auto_error": self.error,
            "seconds": self.seconds,
        })
    }
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
/// tetrahedra stay overlapping after refinement ([`HullError::UnresolvedIntersection`]) or one
/// of them is degenerate ([`HullError::DegenerateTetrahedron`]), built again with
/// angle-weighted normals. Returns that build when it succeeds, else the first.
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
    let cause = first.as_ref().err().and_then(FallbackCause::of);
    let Some(cause) = cause.filter(|_| auto) else {
        return (first, tri, numbering, Attempts::default());
    };
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
                cause,
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
