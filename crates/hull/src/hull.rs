//! Face tetrahedra (§3.1) and edge tetrahedra (§3.2) of one mesh, without refinement.

use crate::apex::{nearest_apex, nearest_apex_pair};
use crate::classify::{
    ApexParameters, Convexity, Side, apex_parameters, classify_edge, classify_face, edge_slopes,
};
use crate::{ApexPlacement, HullError, HullOptions};
use algesurf_bb::Tetrahedron;
use algesurf_mesh::parallel::{collect_first_error, collect_first_error_into};
use algesurf_mesh::{Topology, TriMesh};
use glam::DVec3;
use rayon::prelude::*;

/// A face tetrahedron `[p_i p_j p_k w]` of §3.1, `w` the apex `u_ijk` (positive side) or
/// `v_ijk` (negative side).
///
/// Vertex order: the face's three corners in the mesh's (oriented) order, then the apex
/// **last**. The paper writes the same tetrahedron `[p_k p_i p_j u_ijk]` with `α4` the apex
/// coordinate: a cyclic rotation of the first three, so the orientation is the same.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceTetrahedron {
    /// Positive (`u`) or negative (`v`).
    pub side: Side,
    /// The apex's signed height over the face, `t = (apex − c)ᵀn_ijk`. With
    /// [`ApexPlacement::FaceNormal`] the apex is `c + t n_ijk` and `t` the paper's `t_max` or
    /// `t_min`, pushed away from the face to at least [`HullOptions::min_apex_height`] times
    /// the longest edge when smaller (a floor the paper does not have; it only acts where the
    /// paper's value would make the tetrahedron (nearly) flat and keeps every property
    /// `t_max`/`t_min` exist for). With [`ApexPlacement::Nearest`] (the default) `|t|` is at
    /// most that.
    pub t: f64,
    /// The apex.
    pub apex: DVec3,
    /// `[p_i, p_j, p_k, apex]`.
    pub tetrahedron: Tetrahedron,
}

/// An edge tetrahedron of §3.2 for the edge `[p_i p_j]` between faces `[p_i p_j p_k]` and
/// `[p_i p_j p_l]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeTetrahedron {
    /// Positive (`[u_ijl p_i p_j u_ijk]`) or negative (`[v_ijl p_i p_j v_ijk]`).
    pub side: Side,
    /// `[w_ijl, p_i, p_j, w_ijk]` (w = u or v), the order of (4.3)/(4.4).
    pub tetrahedron: Tetrahedron,
    /// `μ` of (4.15): `w_ijl = μ1 p_k + μ2 p_i + μ3 p_j + μ4 w_ijk`, the barycentric coordinates
    /// of `w_ijl` with respect to `[p_k p_i p_j w_ijk]`.
    pub mu: [f64; 4],
    /// `ν` of (4.15): `w_ijk = ν1 w_ijl + ν2 p_i + ν3 p_j + ν4 p_l`, with respect to
    /// `[w_ijl p_i p_j p_l]`.
    pub nu: [f64; 4],
}

/// One face of the (possibly refined) mesh with its hull data.
#[derive(Clone, Debug, PartialEq)]
pub struct HullFace {
    /// Corner vertex ids `[i, j, k]` (mesh order; counter-clockwise seen from the positive side).
    pub vertices: [u32; 3],
    /// The input face this face lies in (the face map).
    pub source_face: u32,
    /// Convexity class (§3).
    pub convexity: Convexity,
    /// Ids (into [`crate::SimplicialHull::edges`]) of the edges `[i j]`, `[j k]`, `[k i]`.
    pub edges: [u32; 3],
    /// `c = (p_i + p_j + p_k) / 3`.
    pub centroid: DVec3,
    /// Unit normal `n_ijk` (right-hand rule on the corner order: the positive side).
    pub normal: DVec3,
    /// `t_l`, `t_lm`, `ε`, `t_max`, `t_min` of §3.1 (computed for every face, also for those
    /// that get no apex; `None` only for zero convex faces).
    pub parameters: Option<ApexParameters>,
    /// The positive face tetrahedron (positive convex or nonconvex faces).
    pub positive: Option<FaceTetrahedron>,
    /// The negative face tetrahedron (negative convex or nonconvex faces).
    pub negative: Option<FaceTetrahedron>,
}

impl HullFace {
    /// The apex `u_ijk`, if the face has a positive tetrahedron.
    pub fn u(&self) -> Option<DVec3> {
        self.positive.map(|t| t.apex)
    }
    /// The apex `v_ijk`, if the face has a negative tetrahedron.
    pub fn v(&self) -> Option<DVec3> {
        self.negative.map(|t| t.apex)
    }
    /// The tetrahedron on `side`.
    pub fn tetrahedron(&self, side: Side) -> Option<&FaceTetrahedron> {
        match side {
            Side::Positive => self.positive.as_ref(),
            Side::Negative => self.negative.as_ref(),
        }
    }
}

/// One edge of the (possibly refined) mesh with its hull data.
///
/// `[i, j]` is oriented as in `face_k = [p_i p_j p_k]` (the face that runs `i → j`); the other
/// face `face_l = [p_i p_j p_l]` runs `j → i`.
#[derive(Clone, Debug, PartialEq)]
pub struct HullEdge {
    /// `[i, j]`.
    pub vertices: [u32; 2],
    /// Convexity class (§3).
    pub convexity: Convexity,
    /// `[a, b] = [(p_j − p_i)ᵀn_j, (p_i − p_j)ᵀn_i]` ([`crate::edge_slopes`]).
    pub slopes: [f64; 2],
    /// The face `[p_i p_j p_k]`.
    pub face_k: u32,
    /// Its vertex `k` opposite the edge.
    pub k: u32,
    /// The face `[p_i p_j p_l]`; `None` on the boundary.
    pub face_l: Option<u32>,
    /// Its vertex `l`; `None` on the boundary.
    pub l: Option<u32>,
    /// The positive edge tetrahedron (interior positive convex or nonconvex edges).
    pub positive: Option<EdgeTetrahedron>,
    /// The negative edge tetrahedron (interior negative convex or nonconvex edges).
    pub negative: Option<EdgeTetrahedron>,
}

impl HullEdge {
    /// True on the boundary of an open mesh (one face). Boundary edges are classified like the
    /// others but carry no edge tetrahedra.
    pub fn is_boundary(&self) -> bool {
        self.face_l.is_none()
    }
    /// The tetrahedron on `side`.
    pub fn tetrahedron(&self, side: Side) -> Option<&EdgeTetrahedron> {
        match side {
            Side::Positive => self.positive.as_ref(),
            Side::Negative => self.negative.as_ref(),
        }
    }
}

fn face_name(face_map: &[u32], f: usize) -> String {
    format!("face {} (input face {})", f, face_map[f])
}

/// The length of a triangle's longest edge: the size all of §3.1's per-face lengths (`ε`,
/// the apex floor) are taken relative to.
pub(crate) use algesurf_mesh::primitives::longest_edge_length as longest_edge;

/// Checks vertex data.
pub(crate) fn check_input(mesh: &TriMesh, normals: &[DVec3]) -> Result<(), HullError> {
    if normals.len() != mesh.vertex_count() {
        return Err(HullError::NormalCount {
            vertices: mesh.vertex_count(),
            normals: normals.len(),
        });
    }
    for (v, (p, n)) in mesh.positions().iter().zip(normals).enumerate() {
        if !p.is_finite() {
            return Err(HullError::BadVertexData {
                vertex: v as u32,
                what: "position",
            });
        }
        if !n.is_finite() || *n == DVec3::ZERO {
            return Err(HullError::BadVertexData {
                vertex: v as u32,
                what: "normal",
            });
        }
    }
    Ok(())
}

/// The faces and edges of the previous refinement round, for [`build`] to reuse (and, for
/// the faces, to update in place).
///
/// Refinement splits faces in place and appends the new halves (`EditMesh::split_edge`), so a
/// face id that survives a round with the same corners is the same triangle: same positions,
/// same normals (refinement only appends vertices and never changes a normal), hence the same
/// classification, apexes and tetrahedra. Only its edge ids may change (the topology numbers
/// the edges afresh). An edge whose two faces both survive has the same vertices, faces and
/// apexes, hence the same edge tetrahedra.
pub(crate) struct PreviousRound {
    pub(crate) faces: Vec<HullFace>,
    pub(crate) edges: Vec<HullEdge>,
}

impl PreviousRound {
    /// Whether face `f` survived with corners `t`.
    fn survived(&self, f: usize, t: &[u32; 3]) -> bool {
        self.faces.get(f).is_some_and(|pf| pf.vertices == *t)
    }

    /// For each edge of `topo`, the id in the previous round of the same edge when both its
    /// faces survived (`fresh_faces` false): same vertices in the same orientation, same two
    /// faces. `None` for the others and for boundary and non-manifold edges.
    ///
    /// The previous round's edges are in its topology's order, sorted by their (smaller,
    /// larger) vertex ids, as this round's are ([`Topology::edges`]), and refinement never
    /// renumbers a vertex. So an edge is found by a binary search over a compact copy of the
    /// previous keys (0.8 MB on the bunny), not through a surviving face's previous edge ids,
    /// which read the 44 MB of faces and 62 MB of edges at random: that lookup was 130 ms of
    /// CPU time over the bunny's four rounds, and the hull stage is about 45 ms faster
    /// without it.
    fn surviving_edges(&self, topo: &Topology, fresh_faces: &[bool]) -> Vec<Option<u32>> {
        let keys: Vec<[u32; 2]> = self
            .edges
            .par_iter()
            .map(|e| {
                let [a, b] = e.vertices;
                [a.min(b), a.max(b)]
            })
            .collect();
        debug_assert!(keys.is_sorted(), "a round's edges are in topology order");
        (0..topo.edge_count() as u32)
            .into_par_iter()
            .map(|e| {
                let &[h, g] = topo.edge_half_edges(e) else {
                    return None;
                };
                let (face_k, face_l) = (topo.corner_face(h), topo.corner_face(g));
                if fresh_faces[face_k as usize] || fresh_faces[face_l as usize] {
                    return None;
                }
                let id = keys.binary_search(&topo.edge(e)).ok()?;
                let pe = &self.edges[id];
                let ij = [topo.corner_vertex(h), topo.corner_vertex(topo.next(h))];
                (pe.vertices == ij && pe.face_k == face_k && pe.face_l == Some(face_l))
                    .then_some(id as u32)
            })
            .collect()
    }
}

/// What [`build`] gives: the faces and edges, and which of them are new since the previous
/// round (all of them without one).
pub(crate) struct Built {
    pub(crate) faces: Vec<HullFace>,
    pub(crate) edges: Vec<HullEdge>,
    pub(crate) fresh_faces: Vec<bool>,
    pub(crate) fresh_edges: Vec<bool>,
}

pub(crate) fn build(
    mesh: &TriMesh,
    normals: &[DVec3],
    face_map: &[u32],
    opts: &HullOptions,
    prev: Option<PreviousRound>,
) -> Result<Built, HullError> {
    let topo = mesh.topology();
    let pos = mesh.positions();
    let tris = mesh.triangles();
    let p = |v: u32| pos[v as usize];
    let n = |v: u32| normals[v as usize];

    // The faces that did not survive the previous round (all of them without one).
    let fresh_faces: Vec<bool> = match &prev {
        None => vec![true; tris.len()],
        Some(pr) => tris
            .par_iter()
            .enumerate()
            .map(|(f, t)| !pr.survived(f, t))
            .collect(),
    };
    // The previous round's id of each edge that survived it.
    let reused: Vec<Option<u32>> = match &prev {
        None => vec![None; topo.edge_count()],
        Some(pr) => pr.surviving_edges(topo, &fresh_faces),
    };
    // Edges: orientation, faces, classification; in parallel, the first error in edge order.
    // An edge whose two faces survived the previous round is that round's edge, tetrahedra
    // and all (one copy instead of a classification and a second pass for the tetrahedra).
    let mut edges: Vec<HullEdge> = collect_first_error(
        topo.edge_count(),
        |e| {
            let e = e as u32;
            let hs = topo.edge_half_edges(e);
            if hs.len() > 2 {
                let [a, b] = topo.edge(e);
                return Err(HullError::NonManifoldEdge(a, b));
            }
            // Half-edge c runs from corner_vertex(c) to corner_vertex(next(c)).
            let dir = |c: u32| (topo.corner_vertex(c), topo.corner_vertex(topo.next(c)));
            let (i, j) = dir(hs[0]);
            let face_k = topo.corner_face(hs[0]);
            let k = topo.corner_vertex(topo.prev(hs[0]));
            let (face_l, l) = if hs.len() == 2 {
                let (a, b) = dir(hs[1]);
                let g = topo.corner_face(hs[1]);
                if (a, b) != (j, i) {
                    return Err(HullError::InconsistentOrientation {
                        edge: [i, j],
                        faces: [face_map[face_k as usize], face_map[g as usize]],
                    });
                }
                (Some(g), Some(topo.corner_vertex(topo.prev(hs[1]))))
            } else {
                (None, None)
            };
            if let (Some(pr), Some(id)) = (&prev, reused[e as usize]) {
                return Ok(pr.edges[id as usize].clone());
            }
            Ok(HullEdge {
                vertices: [i, j],
                convexity: classify_edge(p(i), p(j), n(i), n(j), opts.zero_tolerance),
                slopes: edge_slopes(p(i), p(j), n(i), n(j)),
                face_k,
                k,
                face_l,
                l,
                positive: None,
                negative: None,
            })
        },
        || HullEdge {
            vertices: [0, 0],
            convexity: Convexity::ZeroConvex,
            slopes: [0.0; 2],
            face_k: 0,
            k: 0,
            face_l: None,
            l: None,
            positive: None,
            negative: None,
        },
    )?;

    // Faces: classification and face tetrahedra (§3.1).
    // Faces are independent of each other: built in parallel, the first error (in face
    // order) reported, so the result does not depend on the thread count.
    let face_edges = |f: usize| -> [u32; 3] {
        let first = topo.face_corners(f).start;
        std::array::from_fn(|c| topo.corner_edge(first + c as u32))
    };
    let make_face = |f: usize| -> Result<HullFace, HullError> {
        let t = &tris[f];
        let fe = face_edges(f);
        let corners = [p(t[0]), p(t[1]), p(t[2])];
        let convexity = classify_face(fe.map(|e| edges[e as usize].convexity));
        let longest = longest_edge(corners);
        let cross = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let area_ok = cross.length() > 1e-14 * longest * longest; // false for NaN too
        if !area_ok {
            return Err(HullError::DegenerateFace {
                face: face_map[f],
                vertices: *t,
            });
        }
        let normal = cross.normalize();
        let centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
        let mut face = HullFace {
            vertices: *t,
            source_face: face_map[f],
            convexity,
            edges: fe,
            centroid,
            normal,
            parameters: None,
            positive: None,
            negative: None,
        };
        if convexity != Convexity::ZeroConvex {
            let params = apex_parameters(corners, t.map(n), normal, opts.epsilon * longest)
                .map_err(|l| HullError::NormalNotOnPositiveSide {
                    face: face_map[f],
                    vertex: t[l],
                    cosine: normal.dot(n(t[l]).normalize()),
                })?;
            let floor = opts.min_apex_height * longest;
            // A nearest apex may lean far over a neighbour; standing at least ε off the face
            // keeps its tetrahedron from going flat (see `ApexPlacement::Nearest`).
            let lean_floor = opts.epsilon.max(opts.min_apex_height) * longest;
            let margin = opts.epsilon * longest;
            // The paper's t_max / t_min, pushed off the face to the floor.
            let paper_t = |side: Side| match side {
                Side::Positive => params.t_max.max(floor),
                Side::Negative => params.t_min.min(-floor),
            };
            let nearest = opts.apex == ApexPlacement::Nearest;
            // A nonconvex face's two apexes are placed together (on one line through c).
            let pair = (nearest && convexity == Convexity::Nonconvex)
                .then(|| nearest_apex_pair(corners, t.map(n), normal, margin, lean_floor))
                .flatten();
            let placed = |side: Side| -> Option<DVec3> {
                if !nearest {
                    return None;
                }
                if convexity == Convexity::Nonconvex {
                    return pair.map(|(u, v)| if side == Side::Positive { u } else { v });
                }
                nearest_apex(corners, t.map(n), normal, margin, lean_floor, side)
            };
            let make = |side: Side| -> Result<FaceTetrahedron, HullError> {
                // Where the quadratic program has no solution (only rounding on degenerate
                // data can do that), the paper's apex, which always satisfies it.
                let (apex, tt) = match placed(side) {
                    Some(apex) => (apex, (apex - centroid).dot(normal)),
                    None => (centroid + paper_t(side) * normal, paper_t(side)),
                };
                let tetrahedron = Tetrahedron::new([corners[0], corners[1], corners[2], apex])
                    .map_err(|source| HullError::DegenerateTetrahedron {
                        what: if side == Side::Positive {
                            "positive face"
                        } else {
                            "negative face"
                        },
                        element: face_name(face_map, f),
                        source,
                    })?;
                Ok(FaceTetrahedron {
                    side,
                    t: tt,
                    apex,
                    tetrahedron,
                })
            };
            if convexity.has_positive_side() {
                face.positive = Some(make(Side::Positive)?);
            }
            if convexity.has_negative_side() {
                face.negative = Some(make(Side::Negative)?);
            }
            face.parameters = Some(params);
        }
        Ok(face)
    };
    let filler = || HullFace {
        vertices: [0; 3],
        source_face: 0,
        convexity: Convexity::ZeroConvex,
        edges: [0; 3],
        centroid: DVec3::ZERO,
        normal: DVec3::ZERO,
        parameters: None,
        positive: None,
        negative: None,
    };
    let faces: Vec<HullFace> = match prev {
        None => {
            // Room for the halves that refinement rounds append (a few hundred faces on the
            // bunny), so that they do not move the 43 MB vector to fresh memory.
            let mut faces = Vec::with_capacity(tris.len() + tris.len() / 64 + 16);
            collect_first_error_into(&mut faces, tris.len(), make_face, filler)?;
            faces
        }
        // The previous round's faces, updated in place (refinement only appends faces): a
        // survivor gets its new edge ids, a split face is built again, and the new halves are
        // appended. On the bunny this saves copying 43 MB of faces per round.
        Some(PreviousRound {
            faces: mut kept,
            edges: _,
        }) => {
            kept.truncate(tris.len());
            let first_error = kept
                .par_iter_mut()
                .enumerate()
                .filter_map(|(f, face)| {
                    if !fresh_faces[f] {
                        face.edges = face_edges(f);
                        return None;
                    }
                    match make_face(f) {
                        Ok(built) => {
                            *face = built;
                            None
                        }
                        Err(e) => Some((f, e)),
                    }
                })
                .min_by_key(|(f, _)| *f);
            if let Some((_, e)) = first_error {
                return Err(e);
            }
            let start = kept.len();
            let appended =
                collect_first_error(tris.len() - start, |i| make_face(start + i), filler)?;
            kept.extend(appended);
            kept
        }
    };

    // Edge tetrahedra (§3.2).
    let done: Vec<Result<bool, HullError>> = edges
        .par_iter_mut()
        .zip(reused.par_iter())
        .map(|(edge, reused)| -> Result<bool, HullError> {
            if reused.is_some() {
                return Ok(false);
            }
            let (Some(face_l), Some(l)) = (edge.face_l, edge.l) else {
                return Ok(true); // boundary: no edge tetrahedra
            };
            let [i, j] = edge.vertices;
            for side in [Side::Positive, Side::Negative] {
                let wanted = match side {
                    Side::Positive => edge.convexity.has_positive_side(),
                    Side::Negative => edge.convexity.has_negative_side(),
                };
                if !wanted {
                    continue;
                }
                let apex = |g: u32| -> Result<DVec3, HullError> {
                    faces[g as usize].tetrahedron(side).map(|t| t.apex).ok_or(
                        HullError::MissingApex {
                            edge: [i, j],
                            face: face_map[g as usize],
                            side: side.name(),
                        },
                    )
                };
                let wk = apex(edge.face_k)?;
                let wl = apex(face_l)?;
                let what = if side == Side::Positive {
                    "positive edge"
                } else {
                    "negative edge"
                };
                let degenerate = |source| HullError::DegenerateTetrahedron {
                    what,
                    element: format!("edge ({i}, {j})"),
                    source,
                };
                let tetrahedron = Tetrahedron::new([wl, p(i), p(j), wk]).map_err(degenerate)?;
                let mu = Tetrahedron::new([p(edge.k), p(i), p(j), wk])
                    .map_err(degenerate)?
                    .barycentric(wl);
                let nu = Tetrahedron::new([wl, p(i), p(j), p(l)])
                    .map_err(degenerate)?
                    .barycentric(wk);
                let et = EdgeTetrahedron {
                    side,
                    tetrahedron,
                    mu,
                    nu,
                };
                match side {
                    Side::Positive => edge.positive = Some(et),
                    Side::Negative => edge.negative = Some(et),
                }
            }
            Ok(true)
        })
        .collect();
    let fresh_edges = done.into_iter().collect::<Result<Vec<bool>, _>>()?;
    Ok(Built {
        faces,
        edges,
        fresh_faces,
        fresh_edges,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::refine::RefineState;
    use algesurf_mesh::shapes::icosphere;

    /// A refinement round reuses the faces and edges that survived it, and the result is the
    /// hull a build from scratch gives; the fresh flags mark exactly the new elements.
    #[test]
    fn reused_round_equals_a_build_from_scratch() {
        let mesh = icosphere(2);
        let normals: Vec<DVec3> = mesh.positions().iter().map(|p| p.normalize()).collect();
        let opts = HullOptions::default();
        let face_map: Vec<u32> = (0..mesh.face_count() as u32).collect();
        let first = build(&mesh, &normals, &face_map, &opts, None).unwrap();
        assert!(first.fresh_faces.iter().all(|&f| f));
        let mut state = RefineState::new(mesh.clone(), normals);
        for f in [0u32, 17, 40, 111] {
            let corners = state.mesh.triangles()[f as usize];
            state.bisect_face(f, corners, 0).unwrap();
        }
        state.finish_round().unwrap();
        let build_now = |prev| build(&state.mesh, &state.normals, &state.face_map, &opts, prev);
        let reused = build_now(Some(PreviousRound {
            faces: first.faces.clone(),
            edges: first.edges.clone(),
        }))
        .unwrap();
        let scratch = build_now(None).unwrap();
        assert_eq!(reused.faces, scratch.faces);
        assert_eq!(reused.edges, scratch.edges);
        let mut survivors = 0;
        for (f, face) in scratch.faces.iter().enumerate() {
            let survived = first
                .faces
                .get(f)
                .is_some_and(|pf| pf.vertices == face.vertices);
            assert_eq!(reused.fresh_faces[f], !survived, "face {f}");
            survivors += survived as usize;
        }
        let nf = scratch.faces.len();
        assert!(survivors > nf / 2 && survivors < nf, "{survivors} of {nf}");
        // An edge is reused exactly when both its faces survived with the same orientation.
        let mut reused_edges = 0;
        for (e, edge) in scratch.edges.iter().enumerate() {
            let faces_fresh = reused.fresh_faces[edge.face_k as usize]
                || edge.face_l.is_none_or(|l| reused.fresh_faces[l as usize]);
            if faces_fresh {
                assert!(reused.fresh_edges[e], "edge {e} reused next to a new face");
            }
            reused_edges += !reused.fresh_edges[e] as usize;
        }
        assert!(reused_edges > scratch.edges.len() / 2, "{reused_edges}");
    }
}
