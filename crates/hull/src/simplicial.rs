//! The simplicial hull Σ with intersection checks and local Butterfly refinement (§3.1).

use crate::classify::Side;
use crate::crossing::CrossingZone;
use crate::hull::{
    Built, HullEdge, HullFace, PreviousRound, build as build_faces_edges, check_input, longest_edge,
};
use crate::refine::RefineState;
use crate::{HullError, HullOptions};
use algesurf_mesh::TriMesh;
use glam::DVec3;
use std::collections::HashMap;

mod intersect;
/// The mesh element a hull tetrahedron belongs to (ids of the possibly refined mesh).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Element {
    /// A face tetrahedron of this face.
    Face(u32),
    /// An edge tetrahedron of this edge (index into [`SimplicialHull::edges`]).
    Edge(u32),
}

/// One tetrahedron of Σ, as listed by [`SimplicialHull::tetrahedra`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullTetrahedron {
    /// The face or edge it belongs to.
    pub element: Element,
    /// Its side.
    pub side: Side,
    /// Its vertices in the order of [`crate::FaceTetrahedron`] / [`crate::EdgeTetrahedron`].
    pub vertices: [glam::DVec3; 4],
}

/// Two hull tetrahedra whose interiors overlap ([`SimplicialHull::intersections`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intersection {
    /// The first tetrahedron.
    pub first: HullTetrahedron,
    /// The second tetrahedron.
    pub second: HullTetrahedron,
    /// [`crate::overlap_depth`] of the pair (> the tolerance).
    pub depth: f64,
}

/// One local refinement step done while building the hull.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Refinement {
    /// The round (0-based) it was done in.
    pub round: usize,
    /// The split edge (vertex ids at the time of the split).
    pub edge: [u32; 2],
    /// The input edge whose neighbourhood it refines (input vertex ids).
    pub input_edge: [u32; 2],
    /// The inserted vertex.
    pub new_vertex: u32,
}

/// The simplicial hull Σ of §3: classification of every edge and face, the face tetrahedra
/// (§3.1) and edge tetrahedra (§3.2), built on the input mesh or — where adjacent tetrahedra
/// intersected — on a locally refined copy of it.
#[derive(Clone, Debug)]
pub struct SimplicialHull {
    mesh: TriMesh,
    normals: Vec<DVec3>,
    faces: Vec<HullFace>,
    edges: Vec<HullEdge>,
    face_map: Vec<u32>,
    input_vertex_count: usize,
    refinements: Vec<Refinement>,
    options: HullOptions,
    /// Where the input passes through itself (see [`crate::crossing`]).
    zone: CrossingZone,
    /// For edges at inserted vertices: the input edge whose refinement made them.
    ancestor: HashMap<[u32; 2], [u32; 2]>,
}

impl SimplicialHull {
    /// Builds the hull of the triangle mesh `(positions, triangles)` with per-vertex normals.
    ///
    /// `normals[v]` is used as the gradient `∇F(p_v)` (pass unit normals, as the paper does;
    /// classification tolerances are applied to their directions). Triangles must be oriented
    /// consistently, counter-clockwise seen from the positive side (the side the normals point
    /// to). Open meshes are accepted: boundary edges are classified but carry no edge
    /// tetrahedra, so the hull — and the surface built in it — ends at the boundary.
    ///
    /// Procedure (§3.1): build all tetrahedra; find every pair whose interiors overlap
    /// (candidates from a bounding-volume hierarchy over all face and edge tetrahedra, adjacent
    /// or not; each decided by [`crate::overlap_depth`]). Pairs from different connected
    /// components of the mesh (separate surfaces that meet, like the Utah teapot's spout and
    /// body) cannot be separated by refinement: they are left and reported by
    /// [`SimplicialHull::distant_intersections`]. If any same-component pair remains, bisect every face
    /// of every such pair (for an edge tetrahedron: both faces of its edge) by Rivara's
    /// longest-edge propagation, each split putting the new vertex at the modified Butterfly
    /// edge point and giving it the unit Loop limit normal of the refined mesh; rebuild and
    /// repeat, at most [`HullOptions::max_refinement_rounds`] times. The paper splits only the
    /// common edge; that makes slivers whose tetrahedra stay as tall as before and did not
    /// resolve intersections in our tests, hence the bisection of the faces. A split whose
    /// Butterfly point would tilt a new face against one of its corners' normals takes a point
    /// between it and the edge's midpoint instead (at worst the midpoint, which never tilts a
    /// face), so refinement never changes a normal it was given. Input vertices keep their
    /// positions, normals and ids.
    ///
    /// # Errors
    /// See [`HullError`]; [`HullError::UnresolvedIntersection`] names the input edge when
    /// refinement does not separate the tetrahedra.
    pub fn new(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        normals: &[DVec3],
        options: &HullOptions,
    ) -> Result<SimplicialHull, HullError> {
        let mesh = TriMesh::new(positions.to_vec(), triangles.to_vec())?;
        Self::build(mesh, normals.to_vec(), options)
    }

    /// As [`SimplicialHull::new`], for a [`TriMesh`] (its positions and triangles; the face map
    /// refers to its triangle ids).
    ///
    /// # Errors
    /// See [`SimplicialHull::new`].
    pub fn from_mesh(
        mesh: &TriMesh,
        normals: &[DVec3],
        options: &HullOptions,
    ) -> Result<SimplicialHull, HullError> {
        Self::new(mesh.positions(), mesh.triangles(), normals, options)
    }

    fn build(
        mesh: TriMesh,
        normals: Vec<DVec3>,
        options: &HullOptions,
    ) -> Result<SimplicialHull, HullError> {
        options.validate()?;
        check_input(&mesh, &normals)?;
        // Crossings of the input mesh: overlaps around them are the input's, not refined.
        let zone = if options.check_intersections {
            CrossingZone::new(&mesh)
        } else {
            CrossingZone::default()
        };
        Self::refine(RefineState::new(mesh, normals), zone, options, 0)
    }

    /// Bisects the faces `faces` (ids of this hull's mesh) by longest-edge propagation, as a
    /// refinement round does for the faces of intersecting tetrahedra, then builds and checks
    /// the hull again and refines its intersections as [`SimplicialHull::new`] does, with up
    /// to [`HullOptions::max_refinement_rounds`] further rounds. Input vertices keep their
    /// positions, normals and ids; the face map still leads to the input faces.
    ///
    /// For a hull that is valid but on which a later stage fails locally: the A-patch
    /// construction refines the two faces of an edge whose A-patch cannot be made
    /// single-sheeted (`algesurf_apatch::ApatchSurface::new`).
    ///
    /// # Errors
    /// As [`SimplicialHull::new`]; [`HullError::Mesh`] if a face id is out of range.
    pub fn refine_faces(&self, faces: &[u32]) -> Result<SimplicialHull, HullError> {
        let round = self.refinements.last().map_or(0, |r| r.round + 1);
        let mut state = RefineState::from_parts(
            self.mesh.clone(),
            self.normals.clone(),
            self.face_map.clone(),
            self.refinements.clone(),
            self.input_vertex_count,
            self.ancestor.clone(),
        );
        let corners: Vec<[u32; 3]> = faces
            .iter()
            .map(|&f| {
                state
                    .mesh
                    .triangles()
                    .get(f as usize)
                    .copied()
                    .ok_or_else(|| {
                        HullError::Mesh(algesurf_mesh::MeshError::NoSuchElement {
                            kind: "face",
                            id: f as usize,
                            count: state.mesh.face_count(),
                        })
                    })
            })
            .collect::<Result<_, _>>()?;
        for (&f, &c) in faces.iter().zip(&corners) {
            state.bisect_face(f, c, round)?;
        }
        state.finish_round()?;
        Self::refine(state, self.zone.clone(), &self.options, round + 1)
    }

    /// The build-check-refine loop of [`SimplicialHull::new`] from `state`, numbering its
    /// rounds from `first_round`.
    fn refine(
        mut state: RefineState,
        zone: CrossingZone,
        options: &HullOptions,
        first_round: usize,
    ) -> Result<SimplicialHull, HullError> {
        let mut round = first_round;
        // The error to report if a refinement round makes the hull invalid.
        let mut pending: Option<HullError> = None;
        // The previous round's faces and edges, reused where they survived.
        let mut previous: Option<PreviousRound> = None;
        // The first round's tetrahedra, for later rounds to check their new ones against.
        let mut index: Option<intersect::TetIndex> = None;
        // The connected component of every input face: bisection keeps a face's children in
        // its component and joins no two, so a face's component in any round is its input
        // face's (`face_map`), and the mesh's components are found once, not every round.
        let input_component: Vec<u32> = {
            let comp = state.mesh.topology().face_components();
            let size = state
                .face_map
                .iter()
                .map(|&g| g as usize + 1)
                .max()
                .unwrap_or(0);
            let mut ic = vec![u32::MAX; size];
            for (f, &g) in state.face_map.iter().enumerate() {
                ic[g as usize] = comp[f];
            }
            ic
        };
        loop {
            let reusing = previous.is_some();
            let built = build_faces_edges(
                &state.mesh,
                &state.normals,
                &state.face_map,
                options,
                previous.take(),
            );
            let Built {
                faces,
                edges,
                fresh_faces,
                fresh_edges,
            } = match (built, pending.take()) {
                (Ok(x), _) => x,
                (Err(e), None) => return Err(e),
                (
                    Err(e),
                    Some(HullError::UnresolvedIntersection {
                        edge,
                        faces,
                        rounds,
                        ..
                    }),
                ) => {
                    return Err(HullError::UnresolvedIntersection {
                        edge,
                        faces,
                        rounds: rounds + 1,
                        reason: format!("refining made the hull invalid: {e}"),
                    });
                }
                (Err(_), Some(other)) => return Err(other),
            };
            // The mesh moves into the round's hull and back out before the splits (a clone
            // per round was 10 MB of copying on the bunny).
            let hull = SimplicialHull {
                mesh: std::mem::replace(&mut state.mesh, TriMesh::new(Vec::new(), Vec::new())?),
                normals: Vec::new(),
                faces,
                edges,
                face_map: Vec::new(),
                input_vertex_count: state.input_vertex_count,
                refinements: Vec::new(),
                options: options.clone(),
                zone: CrossingZone::default(),
                ancestor: HashMap::new(),
            };
            // Overlaps between tetrahedra of different connected components are between
            // different surfaces (the Utah teapot's spout passes through its body), and those
            // around two input faces that cross are the input's (the cow's ears through its
            // head): no refinement separates them, so only the other overlaps are refined;
            // these are reported by `distant_intersections()`.
            let hits: Vec<Intersection> = if options.check_intersections {
                let component: Vec<u32> = state
                    .face_map
                    .iter()
                    .map(|&g| input_component[g as usize])
                    .collect();
                // Survivors were checked against each other in the previous round.
                let found = match (reusing, index.as_mut()) {
                    (true, Some(index)) => {
                        hull.fresh_intersections(index, &fresh_faces, &fresh_edges)
                    }
                    _ => {
                        let (found, built) = hull.indexed_intersections();
                        index = Some(built);
                        found
                    }
                };
                found
                    .into_iter()
                    .filter(|h| !hull.unremovable(&component, &zone, &state.face_map, h))
                    .collect()
            } else {
                Vec::new()
            };
            if hits.is_empty() {
                return Ok(SimplicialHull {
                    zone,
                    ancestor: state.ancestor,
                    normals: state.normals,
                    face_map: state.face_map,
                    refinements: state.refinements,
                    ..hull
                });
            }
            let hit = &hits[0];
            let [a, b] = hull.edges[hull.conflict_edge(hit) as usize].vertices;
            let unresolved = |reason: String| HullError::UnresolvedIntersection {
                edge: state.input_edge(a, b),
                faces: [
                    state.face_map[hull.element_faces(hit.first.element)[0] as usize],
                    state.face_map[hull.element_faces(hit.second.element)[0] as usize],
                ],
                rounds: round,
                reason,
            };
            if round - first_round == options.max_refinement_rounds {
                // Same-component overlaps that survive every round are an error.
                return Err(unresolved(format!(
                    "the limit of {round} rounds is reached; {}",
                    hull.tallest_explained(&hits, &state.normals, &state.face_map)
                )));
            }
            pending = Some(unresolved(String::new()));
            // Faces to bisect, with their corners now (ids of split faces get reused).
            let mut targets: Vec<u32> = Vec::new();
            let mut seen = vec![false; hull.faces.len()];
            for hit in &hits {
                for el in [hit.first.element, hit.second.element] {
                    for f in hull.element_faces(el) {
                        if !std::mem::replace(&mut seen[f as usize], true) {
                            targets.push(f);
                        }
                    }
                }
            }
            let corners: Vec<[u32; 3]> = targets
                .iter()
                .map(|&f| hull.mesh.triangles()[f as usize])
                .collect();
            state.mesh = hull.mesh;
            for (&f, &c) in targets.iter().zip(&corners) {
                state.bisect_face(f, c, round)?;
            }
            state.finish_round()?;
            previous = Some(PreviousRound {
                faces: hull.faces,
                edges: hull.edges,
            });
            round += 1;
        }
    }

    /// Names the tallest face tetrahedron among `hits` and the corner normal that makes it
    /// tall: §3.1's apex height `t_l = (p_l − c)ᵀn_l / n_ijkᵀn_l` grows without bound as `n_l`
    /// turns into the face's plane, and refinement only helps when the faces around `p_l`
    /// turn towards the plane orthogonal to `n_l`, which they do not at a sharp rim.
    fn tallest_explained(
        &self,
        hits: &[Intersection],
        normals: &[DVec3],
        face_map: &[u32],
    ) -> String {
        let pos = self.mesh.positions();
        let mut best: Option<(f64, u32, Side)> = None;
        for h in hits {
            for (el, side) in [
                (h.first.element, h.first.side),
                (h.second.element, h.second.side),
            ] {
                for f in self.element_faces(el) {
                    let face = &self.faces[f as usize];
                    let Some(t) = face.tetrahedron(side) else {
                        continue;
                    };
                    let ratio = t.t.abs() / longest_edge(face.vertices.map(|v| pos[v as usize]));
                    if best.is_none_or(|(r, _, _)| ratio > r) {
                        best = Some((ratio, f, side));
                    }
                }
            }
        }
        let Some((ratio, f, side)) = best else {
            return "the intersecting tetrahedra are edge tetrahedra only".to_string();
        };
        let face = &self.faces[f as usize];
        let (v, cos) = face
            .vertices
            .iter()
            .map(|&v| (v, face.normal.dot(normals[v as usize].normalize())))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .expect("a face has three corners");
        let which = if (v as usize) < self.input_vertex_count {
            format!("input vertex {v}")
        } else {
            format!("vertex {v} inserted by refinement")
        };
        format!(
            "the tallest of them, the {} tetrahedron of face {f} (in input face {}), stands \
             {ratio:.2} times its longest edge off the face; the normal of its corner {which} is \
             {:.1}° from the face's normal (a sharp rim or fold: smoothing or re-meshing it \
             there, or other normals, helps)",
            side.name(),
            face_map[f as usize],
            cos.clamp(-1.0, 1.0).acos().to_degrees(),
        )
    }

    /// The mesh vertices of an element's tetrahedron (three for a face, two for an edge).
    fn element_vertices(&self, e: Element) -> Vec<u32> {
        match e {
            Element::Face(f) => self.mesh.triangles()[f as usize].to_vec(),
            Element::Edge(e) => self.edges[e as usize].vertices.to_vec(),
        }
    }

    /// Whether two elements share a mesh vertex (their tetrahedra are adjacent in Σ).
    pub fn elements_adjacent(&self, a: Element, b: Element) -> bool {
        let va = self.element_vertices(a);
        self.element_vertices(b).iter().any(|v| va.contains(v))
    }

    /// The connected component of every face.
    fn face_components(&self) -> Vec<u32> {
        self.mesh.topology().face_components()
    }

    fn same_component(&self, component: &[u32], a: Element, b: Element) -> bool {
        let ca = component[self.element_faces(a)[0] as usize];
        let cb = component[self.element_faces(b)[0] as usize];
        ca == cb
    }

    /// Overlapping tetrahedra that refinement cannot separate, left in the hull and reported
    /// here:
    /// * those of different connected components of the mesh: places where separate surfaces
    ///   of the input come within the hull's thickness of each other or pass through each
    ///   other (the Utah teapot's spout and handle pass through its body);
    /// * two tetrahedra, one around each of two input faces that cross
    ///   ([`SimplicialHull::input_crossings`]; "around": of an input face within two rings
    ///   of it, see `crate::crossing`):
    ///   the input passes through itself there (the cow's ears and head).
    ///
    /// Each patch is still evaluated in its own tetrahedra, so the surface follows the input
    /// there, through itself where the input is.
    pub fn distant_intersections(&self) -> Vec<Intersection> {
        let component = self.face_components();
        self.intersections()
            .into_iter()
            .filter(|h| self.unremovable(&component, &self.zone, &self.face_map, h))
            .collect()
    }

    /// The pairs of input faces `[f, g]` (`f < g`, ascending) that share no vertex and pass
    /// through each other ([`algesurf_mesh::self_intersections`]). Empty unless
    /// [`HullOptions::check_intersections`] is set (it is by default).
    pub fn input_crossings(&self) -> &[[u32; 2]] {
        self.zone.crossings()
    }

    /// Whether refinement cannot remove overlap `h` (see
    /// [`SimplicialHull::distant_intersections`]); `face_map` maps this hull's faces to
    /// input faces.
    fn unremovable(
        &self,
        component: &[u32],
        zone: &CrossingZone,
        face_map: &[u32],
        h: &Intersection,
    ) -> bool {
        let (a, b) = (h.first.element, h.second.element);
        if !self.same_component(component, a, b) {
            return true;
        }
        let fb = self.element_faces(b);
        self.element_faces(a).iter().any(|&x| {
            fb.iter()
                .any(|&y| zone.contains(face_map[x as usize], face_map[y as usize]))
        })
    }

    /// The faces of an element (one for a face, one or two for an edge).
    fn element_faces(&self, e: Element) -> Vec<u32> {
        match e {
            Element::Face(f) => vec![f],
            Element::Edge(e) => {
                let edge = &self.edges[e as usize];
                std::iter::once(edge.face_k).chain(edge.face_l).collect()
            }
        }
    }

    /// The edges of `element` (one for an edge, three for a face).
    fn element_edges(&self, e: Element) -> Vec<u32> {
        match e {
            Element::Face(f) => self.faces[f as usize].edges.to_vec(),
            Element::Edge(e) => vec![e],
        }
    }

    fn edge_length(&self, e: u32) -> f64 {
        let [a, b] = self.edges[e as usize].vertices;
        self.mesh.positions()[a as usize].distance(self.mesh.positions()[b as usize])
    }

    /// The edge an intersection is named by: the edge the two elements share, else the
    /// longest edge of the first element.
    fn conflict_edge(&self, hit: &Intersection) -> u32 {
        let ea = self.element_edges(hit.first.element);
        let eb = self.element_edges(hit.second.element);
        if let Some(&e) = ea.iter().find(|e| eb.contains(e)) {
            return e;
        }
        ea.iter()
            .copied()
            .max_by(|&x, &y| self.edge_length(x).total_cmp(&self.edge_length(y)))
            .unwrap_or(0)
    }

    /// The (possibly refined) mesh the hull is built on. Vertices `0..input_vertex_count()` are
    /// the input vertices, unchanged; later ones were inserted by refinement.
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }
    /// Per-vertex normals of [`SimplicialHull::mesh`]: the input normals unchanged, then the
    /// normals of inserted vertices (the Loop limit normal of the refined mesh, or where that
    /// would fold a face the normalised sum of the split edge's end normals; see
    /// [`SimplicialHull::new`]).
    pub fn normals(&self) -> &[DVec3] {
        &self.normals
    }
    /// Per face of [`SimplicialHull::mesh`] (same index as [`SimplicialHull::faces`]).
    pub fn faces(&self) -> &[HullFace] {
        &self.faces
    }
    /// Per edge of [`SimplicialHull::mesh`], indexed by the mesh topology's edge id.
    pub fn edges(&self) -> &[HullEdge] {
        &self.edges
    }
    /// The edge joining vertices `a` and `b`, if any.
    pub fn edge_between(&self, a: u32, b: u32) -> Option<&HullEdge> {
        self.mesh
            .topology()
            .find_edge(a, b)
            .map(|e| &self.edges[e as usize])
    }
    /// For each face of [`SimplicialHull::mesh`], the input face it lies in.
    pub fn face_map(&self) -> &[u32] {
        &self.face_map
    }
    /// Number of vertices of the input mesh.
    pub fn input_vertex_count(&self) -> usize {
        self.input_vertex_count
    }
    /// The local refinement steps done, in order (empty when the input needed none).
    pub fn refinements(&self) -> &[Refinement] {
        &self.refinements
    }
    /// The options the hull was built with.
    pub fn options(&self) -> &HullOptions {
        &self.options
    }
}
