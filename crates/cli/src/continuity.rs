//! The continuity figures of `algesurf smooth`'s summary: C1 across the facets of a sample of
//! the hull's faces, measured as `algesurf check` measures every facet
//! ([`algesurf_inspect::check::continuity`] on a view of the sampled pieces).

use algesurf_apatch::{ApatchSurface, Owner};
use algesurf_inspect::check::{ApatchView, continuity};

/// Faces sampled at most: every `k`-th hull face, with the tetrahedra of its edges, so that
/// the figure costs a bounded time on any mesh (the full battery, `algesurf check`, takes
/// 13.5 s on the bunny).
pub(crate) const SAMPLED_FACES: usize = 500;

/// Level of the barycentric grid sampled on each facet: 15 points, less those on a mesh edge
/// (where the rational blends are 0/0; see `continuity`).
const FACET_LEVEL: usize = 4;

/// C1 across the facets among the sampled faces' pieces and their edges' pieces.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SampledContinuity {
    /// Hull faces sampled, and of how many.
    pub faces: usize,
    pub of: usize,
    /// Interior facets measured, and the points sampled on them.
    pub facets: usize,
    pub samples: usize,
    /// Largest `|F₁ − F₂| / (|∇F| · facet diameter)` and `|∇F₁ − ∇F₂| / max |∇F|` (NaN if a
    /// gradient vanished on a facet, which is itself a defect).
    pub value: f64,
    pub gradient: f64,
}

/// Measures C1 on every `k`-th hull face (at most [`SAMPLED_FACES`]) and its edges.
pub(crate) fn sampled_continuity(surface: &ApatchSurface) -> SampledContinuity {
    let nf = surface.hull().mesh().face_count();
    let stride = nf.div_ceil(SAMPLED_FACES).max(1);
    let sampled = |f: usize| f.is_multiple_of(stride);
    let faces = (0..nf).step_by(stride).map(Owner::Face);
    let edges = surface
        .hull()
        .edges()
        .iter()
        .enumerate()
        .filter(|(_, edge)| {
            sampled(edge.face_k as usize) || edge.face_l.is_some_and(|l| sampled(l as usize))
        })
        .map(|(e, _)| Owner::Edge(e));
    let view = ApatchView::of_owners(surface, faces.chain(edges));
    let m = continuity(&view, FACET_LEVEL);
    SampledContinuity {
        faces: nf.div_ceil(stride),
        of: nf,
        facets: m.facets.len(),
        samples: m.samples(),
        value: m.value.value,
        gradient: m.gradient.value,
    }
}
