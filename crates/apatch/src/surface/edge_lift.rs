//! Step 6 of §4.2 for the edge A-patches: the least common increment of the two faces' apex
//! values that makes every ray of an edge A-patch single-sheeted (Lemma 2.3), and the
//! increments the face sides take from their edges.

use super::{BuildFailure, FaceFunction, SurfaceOptions};
use crate::sheet::{CERTIFIED_GAP, CERTIFIED_MAX_CELLS, lifted_b_min};
use crate::{ApatchError, EdgeCubic};
use algesurf_bb::sheet::square::certified_square_lift_bound;
use algesurf_hull::{Side, SimplicialHull};
use algesurf_mesh::progress::{Progress, UnitTally};
use rayon::prelude::*;
use std::collections::HashMap;

/// Increments of apex values an edge asks for: `((face, side), δ)`.
type Needs = Vec<((usize, Side), f64)>;

/// Step 6 for one edge tetrahedron (`slot` 0 positive, 1 negative) of the interior edge `e`:
/// a guaranteed upper bound, over every ray (4.9) of the edge A-patch, of the least common
/// increment `b` of the two faces' apex values for which Lemma 2.3 certifies the ray's
/// smallest root simple ([`certified_square_lift_bound`], within [`CERTIFIED_GAP`] of the
/// largest exact need sampled). Negative when the current coefficients suffice on every ray;
/// `−∞` when no ray starts where F has this side's sign.
///
/// The search stops once the bound is certified `≤ floor` (the callers compare with a
/// threshold, `−margin` or 0, and pass it or just below it), so only results above `floor`
/// are within the gap of the true maximum.
///
/// # Errors
/// [`ApatchError::UnliftableEdgeRay`] where raising the apex values cannot make some ray
/// single-sheeted (the lift is not `≥ 0` there).
pub(crate) fn edge_need(
    hull: &SimplicialHull,
    faces: &[FaceFunction],
    edges: &[[Option<EdgeCubic>; 2]],
    e: usize,
    slot: usize,
    floor: f64,
) -> Result<f64, ApatchError> {
    let pos = hull.mesh().positions();
    let he = &hull.edges()[e];
    let (Some(fl), Some(cubic)) = (he.face_l, &edges[e][slot]) else {
        return Ok(f64::NEG_INFINITY);
    };
    let (side, sign) = if slot == 0 {
        (Side::Positive, 1.0)
    } else {
        (Side::Negative, -1.0)
    };
    let (pi, pj) = (pos[he.vertices[0] as usize], pos[he.vertices[1] as usize]);
    // The lift: how the edge cubic moves per unit of a common increment of both apex values.
    let lift = EdgeCubic::apex_square_lift(
        cubic,
        faces[he.face_k as usize].edge_piece(side, pi, pj)?.tet,
        faces[fl as usize].edge_piece(side, pi, pj)?.tet,
    );
    let two_sided = edges[e][0].is_some() && edges[e][1].is_some();
    // The exact need of one ray: −∞ where it needs nothing (it starts on this side's far
    // side, or on a two-sided edge the other side serves it), +∞ where raising the apex values
    // cannot help (the lift has a negative layer 2 or 3 there and the ray does not already
    // satisfy Lemma 2.3 on its own).
    let ray_need = |x: f64, y: f64| -> f64 {
        let c = cubic.shooting_polynomial(x, y);
        if two_sided && sign * c[0] > 0.0 {
            return f64::NEG_INFINITY;
        }
        let base = c.map(|v| sign * v);
        match lifted_b_min(base, lift.shooting_polynomial(x, y)) {
            Some(b) => b,
            None if base[0] < 0.0 => {
                let own = lifted_b_min(base, [0.0, 0.0, 1.0, 1.0]);
                if own.is_some_and(|b| b <= 0.0) {
                    f64::NEG_INFINITY
                } else {
                    f64::INFINITY
                }
            }
            None => f64::NEG_INFINITY,
        }
    };
    // The base and lift coefficients are polynomials of bidegree ≤ (3, 3) in (x, y)
    // (`algesurf_bb::sheet::square`), read off the cubics' BB coefficients.
    let base = cubic
        .shooting_tensor()
        .map(|t| t.map(|row| row.map(|v| sign * v)));
    let lifted = lift.shooting_tensor();
    let scale = cubic.polynomial().max_coeff_norm();
    let bound = certified_square_lift_bound(
        &base,
        &[lifted[2], lifted[3]],
        ray_need,
        CERTIFIED_GAP * scale,
        CERTIFIED_MAX_CELLS,
        floor,
    );
    if bound.upper == f64::INFINITY {
        let [x, y] = bound.worst;
        return Err(ApatchError::UnliftableEdgeRay {
            vertices: he.vertices,
            faces: [he.face_k, fl].map(|f| hull.faces()[f as usize].source_face),
            side: side.name(),
            x,
            y,
        });
    }
    Ok(bound.upper)
}

/// Per face side, the increment of its apex value that its edges need (Step 6 with
/// [`lifted_b_min`]), only where positive.
pub(super) fn edge_increments(
    hull: &SimplicialHull,
    faces: &[FaceFunction],
    edges: &[[Option<EdgeCubic>; 2]],
    options: &SurfaceOptions,
    progress: &dyn Progress,
) -> Result<HashMap<(usize, Side), f64>, BuildFailure> {
    let tally = UnitTally::start(
        progress,
        "surface: edge single-sheet bounds",
        hull.edges().len(),
    );
    let needs: Vec<Result<Needs, ApatchError>> = hull
        .edges()
        .par_iter()
        .enumerate()
        .map(|(e, he)| -> Result<Needs, ApatchError> {
            if tally.stopped() {
                return Ok(Vec::new());
            }
            // Counted as it starts: the early returns need no count of their own.
            tally.unit_done(e);
            let Some(fl) = he.face_l else {
                return Ok(Vec::new());
            };
            let mut out = Vec::new();
            for (slot, side) in [(0usize, Side::Positive), (1usize, Side::Negative)] {
                let Some(cubic) = &edges[e][slot] else {
                    continue;
                };
                let margin = options.sheet_margin * cubic.polynomial().max_coeff_norm();
                // Needs up to −margin ask for nothing: exact only above that.
                let need = edge_need(hull, faces, edges, e, slot, -margin)?;
                if need > -margin {
                    let delta = need + margin;
                    out.push(((he.face_k as usize, side), delta));
                    out.push(((fl as usize, side), delta));
                }
            }
            Ok(out)
        })
        .collect();
    tally.finish().map_err(ApatchError::from)?;
    // The first error in edge order, whatever the thread count; with it, every unliftable
    // edge, so that one refinement pass can take them all.
    if let Some(first) = needs.iter().position(Result::is_err) {
        let unliftable: Vec<[u32; 2]> = needs
            .iter()
            .filter_map(|n| match n {
                Err(ApatchError::UnliftableEdgeRay { vertices, .. }) => Some(*vertices),
                _ => None,
            })
            .collect();
        let error = needs.into_iter().nth(first).and_then(Result::err);
        return Err(match error {
            Some(e @ ApatchError::UnliftableEdgeRay { .. }) => BuildFailure::Unliftable {
                first: e,
                edges: unliftable,
            },
            Some(e) => BuildFailure::Other(e),
            None => unreachable!("position found an error"),
        });
    }
    let needs: Vec<Needs> = needs.into_iter().map(|n| n.unwrap_or_default()).collect();
    let mut raise: HashMap<(usize, Side), f64> = HashMap::new();
    for (key, d) in needs.into_iter().flatten() {
        let e = raise.entry(key).or_insert(0.0);
        *e = e.max(d);
    }
    Ok(raise)
}
