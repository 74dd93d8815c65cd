//! Face tetrahedra (§3.1) and edge tetrahedra (§3.2) of one mesh, without refinement.

use crate::apex::{nearest_apex, nearest_apex_pair};
use crate::classify::{
    ApexParameters, Convexity, Side, apex_parameters, classify_edge, classify_face, edge_slopes,
};
use crate::{ApexPlacement, HullError, HullOptions};
use algesurf_bb::Tetrahedron;
use algesurf_mesh::TriMesh;
use algesurf_mesh::geometry::power_of_two;
use algesurf_mesh::parallel::{
    collect_first_error_into_with_progress, collect_first_error_with_progress,
};
use algesurf_mesh::progress::{Progress, UnitTally};
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
    let mut largest: f64 = 0.0;
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
        largest = largest.max(p.abs().max_element());
    }
    // A fourfold product of lengths up to 2·2^252 (and a sum of three) stays below 2^1023,
    // and one of 2^-252 above 2^-1022, f64's normal range (the finite checks above make
    // `largest` a number).
    let range = power_of_two(-COORDINATE_EXPONENT_RANGE)..=power_of_two(COORDINATE_EXPONENT_RANGE);
    if largest != 0.0 && !range.contains(&largest) {
        return Err(HullError::CoordinatesOutOfRange { largest });
    }
    Ok(())
}

/// The hull is built for meshes whose largest absolute coordinate lies in
/// `[2^-252, 2^252]` ([`HullError::CoordinatesOutOfRange`]).
pub const COORDINATE_EXPONENT_RANGE: i32 = 252;

/// What the per-element builders read: the mesh's positions and normals, the face map (for
/// the input face ids that errors name) and the options. [`build`] uses them on every element
/// of a mesh; a refinement round (`crate::simplicial::rounds`) on the elements it changed.
#[derive(Clone, Copy)]
pub(crate) struct Inputs<'a> {
    pub(crate) positions: &'a [DVec3],
    pub(crate) normals: &'a [DVec3],
    pub(crate) face_map: &'a [u32],
    pub(crate) opts: &'a HullOptions,
}

impl Inputs<'_> {
    fn p(&self, v: u32) -> DVec3 {
        self.positions[v as usize]
    }

    fn n(&self, v: u32) -> DVec3 {
        self.normals[v as usize]
    }

    /// The edge `[i, j]` of `face_k = [p_i p_j p_k]` (which runs `i → j`) and, inside the
    /// mesh, of `face_l = [p_j p_i p_l]` (`other = (face_l, l)`), classified, without its
    /// tetrahedra ([`Inputs::edge_tetrahedra`]).
    pub(crate) fn edge(
        &self,
        [i, j]: [u32; 2],
        face_k: u32,
        k: u32,
        other: Option<(u32, u32)>,
    ) -> HullEdge {
        let (p, n) = (|v| self.p(v), |v| self.n(v));
        HullEdge {
            vertices: [i, j],
            convexity: classify_edge(p(i), p(j), n(i), n(j), self.opts.zero_tolerance),
            slopes: edge_slopes(p(i), p(j), n(i), n(j)),
            face_k,
            k,
            face_l: other.map(|(g, _)| g),
            l: other.map(|(_, l)| l),
            positive: None,
            negative: None,
        }
    }

    /// Face `f` with corners `t`: its classification from its edges' (`edge_convexity`, in
    /// the order `[i j]`, `[j k]`, `[k i]`, whose ids are `edges`) and its face tetrahedra
    /// (§3.1).
    pub(crate) fn face(
        &self,
        f: usize,
        t: [u32; 3],
        edges: [u32; 3],
        edge_convexity: [Convexity; 3],
    ) -> Result<HullFace, HullError> {
        let (opts, face_map) = (self.opts, self.face_map);
        let n = |v: u32| self.n(v);
        let corners = t.map(|v| self.p(v));
        let convexity = classify_face(edge_convexity);
        let longest = longest_edge(corners);
        let cross = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let area_ok = cross.length() > 1e-14 * longest * longest; // false for NaN too
        if !area_ok {
            return Err(HullError::DegenerateFace {
                face: face_map[f],
                vertices: t,
            });
        }
        let normal = cross.normalize();
        let centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
        let mut face = HullFace {
            vertices: t,
            source_face: face_map[f],
            convexity,
            edges,
            centroid,
            normal,
            parameters: None,
            positive: None,
            negative: None,
        };
        if convexity == Convexity::ZeroConvex {
            return Ok(face);
        }
        let params =
            apex_parameters(corners, t.map(n), normal, opts.epsilon * longest).map_err(|l| {
                HullError::NormalNotOnPositiveSide {
                    face: face_map[f],
                    vertex: t[l],
                    cosine: normal.dot(n(t[l]).normalize()),
                }
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
        Ok(face)
    }

    /// The edge tetrahedra (§3.2) of an interior edge, on the sides its class asks for, from
    /// its faces' apexes (`faces` holds its two faces, built); none on the boundary.
    pub(crate) fn edge_tetrahedra(
        &self,
        edge: &mut HullEdge,
        faces: &[HullFace],
    ) -> Result<(), HullError> {
        let (Some(face_l), Some(l)) = (edge.face_l, edge.l) else {
            return Ok(()); // boundary: no edge tetrahedra
        };
        let p = |v: u32| self.p(v);
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
                faces[g as usize]
                    .tetrahedron(side)
                    .map(|t| t.apex)
                    .ok_or(HullError::MissingApex {
                        edge: [i, j],
                        face: self.face_map[g as usize],
                        side: side.name(),
                    })
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
        Ok(())
    }
}

/// A record to fill a failed slot of [`collect_first_error_with_progress`] with (never returned).
pub(crate) fn filler_edge() -> HullEdge {
    HullEdge {
        vertices: [0, 0],
        convexity: Convexity::ZeroConvex,
        slopes: [0.0; 2],
        face_k: 0,
        k: 0,
        face_l: None,
        l: None,
        positive: None,
        negative: None,
    }
}

/// A record to fill a failed slot of [`collect_first_error_into_with_progress`] with (never returned).
pub(crate) fn filler_face() -> HullFace {
    HullFace {
        vertices: [0; 3],
        source_face: 0,
        convexity: Convexity::ZeroConvex,
        edges: [0; 3],
        centroid: DVec3::ZERO,
        normal: DVec3::ZERO,
        parameters: None,
        positive: None,
        negative: None,
    }
}

/// Every face and edge of `mesh` with its classification and tetrahedra (§3.1, §3.2), in
/// parallel; the error reported is the first in edge order (the edges' structure), then in
/// face order, then in edge order again (the edge tetrahedra), whatever the thread count.
pub(crate) fn build(
    mesh: &TriMesh,
    normals: &[DVec3],
    face_map: &[u32],
    opts: &HullOptions,
    progress: &dyn Progress,
) -> Result<(Vec<HullFace>, Vec<HullEdge>), HullError> {
    let topo = mesh.topology();
    let tris = mesh.triangles();
    let inputs = Inputs {
        positions: mesh.positions(),
        normals,
        face_map,
        opts,
    };
    // Edges: orientation, faces, classification.
    progress.start("hull: edges", topo.edge_count() as u64);
    let mut edges: Vec<HullEdge> = collect_first_error_with_progress(
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
            let other = if hs.len() == 2 {
                let (a, b) = dir(hs[1]);
                let g = topo.corner_face(hs[1]);
                if (a, b) != (j, i) {
                    return Err(HullError::InconsistentOrientation {
                        edge: [i, j],
                        faces: [face_map[face_k as usize], face_map[g as usize]],
                    });
                }
                Some((g, topo.corner_vertex(topo.prev(hs[1]))))
            } else {
                None
            };
            Ok(inputs.edge([i, j], face_k, k, other))
        },
        filler_edge,
        progress,
    )?;

    // Faces: classification and face tetrahedra (§3.1). Room for the halves that refinement
    // rounds append (a few hundred faces on the bunny), so that they do not move the 43 MB
    // vector to fresh memory.
    let mut faces = Vec::with_capacity(tris.len() + tris.len() / 64 + 16);
    progress.start("hull: faces", tris.len() as u64);
    collect_first_error_into_with_progress(
        &mut faces,
        tris.len(),
        |f| {
            let first = topo.face_corners(f).start;
            let fe: [u32; 3] = std::array::from_fn(|c| topo.corner_edge(first + c as u32));
            inputs.face(f, tris[f], fe, fe.map(|e| edges[e as usize].convexity))
        },
        filler_face,
        progress,
    )
    .map_err(|e| folded_vertex_or(e, mesh))?;

    // Edge tetrahedra (§3.2).
    let tally = UnitTally::start(progress, "hull: edge tetrahedra", edges.len());
    let done: Vec<Result<(), HullError>> = edges
        .par_iter_mut()
        .enumerate()
        .map(|(i, edge)| {
            if tally.stopped() {
                return Ok(());
            }
            let r = inputs.edge_tetrahedra(edge, &faces);
            tally.unit_done(i);
            r
        })
        .collect();
    tally.finish()?;
    done.into_iter().collect::<Result<(), _>>()?;
    Ok((faces, edges))
}

/// `e`, or [`HullError::FoldedVertex`] when `e` is a vertex normal on the wrong side of a face
/// and the vertex's faces fit in no open hemisphere (then no normal would do). Only on the
/// error path: it computes the mesh's face normals.
fn folded_vertex_or(e: HullError, mesh: &TriMesh) -> HullError {
    if let HullError::NormalNotOnPositiveSide { face, vertex, .. } = e
        && (vertex as usize) < mesh.vertex_count()
    {
        let face_normals = algesurf_mesh::unit_face_normals(mesh);
        if let Some((_, least)) = algesurf_mesh::face_cone_axis(mesh, &face_normals, vertex)
            && least <= 0.0
        {
            return HullError::FoldedVertex {
                vertex,
                face,
                least_cosine: least,
            };
        }
    }
    e
}
