//! The simplicial hull Σ with intersection checks and local Butterfly refinement (§3.1).

use crate::classify::Side;
use crate::crossing::CrossingZone;
use crate::hull::{HullEdge, HullFace, build as build_faces_edges, check_input};
use crate::refine::RefineState;
use crate::{HullError, HullOptions};
use algesurf_mesh::TriMesh;
use algesurf_mesh::progress::{NoProgress, Progress, check_cancelled};
use glam::DVec3;
use std::collections::HashMap;

mod intersect;
mod rounds;
use rounds::{Overlap, Rounds};
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
        Self::build(mesh, normals.to_vec(), options, &NoProgress)
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
        Self::from_mesh_with_progress(mesh, normals, options, &NoProgress)
    }

    /// [`SimplicialHull::from_mesh`], reporting its steps to `progress`: the edges, the faces
    /// and the edge tetrahedra (each with its count of elements), the overlap check (counted in
    /// tetrahedra), and every refinement round (named with its number and the overlapping pairs it separates; no
    /// count, as a round's work is not known before it runs). The hull is the same with any
    /// `progress`. It stops with [`HullError::Cancelled`] when `progress` asks
    /// ([`Progress::cancelled`]: polled per batch of elements, per leaf of the overlap
    /// check's tree and at every round).
    ///
    /// ```
    /// use algesurf_hull::{HullOptions, SimplicialHull};
    /// use algesurf_mesh::progress::{Progress, ProgressCounter};
    /// use algesurf_mesh::{NormalMethod, shapes, vertex_normals};
    ///
    /// let mesh = shapes::icosphere(2);
    /// let normals = vertex_normals(&mesh, NormalMethod::Loop)?;
    /// let counter = ProgressCounter::new();
    /// let hull =
    ///     SimplicialHull::from_mesh_with_progress(&mesh, &normals, &HullOptions::default(), &counter)?;
    /// assert_eq!(hull.faces().len(), mesh.face_count());
    /// assert_eq!(counter.snapshot().step, "hull: overlap check");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// See [`SimplicialHull::new`]; [`HullError::Cancelled`] when `progress` asked to stop.
    pub fn from_mesh_with_progress(
        mesh: &TriMesh,
        normals: &[DVec3],
        options: &HullOptions,
        progress: &dyn Progress,
    ) -> Result<SimplicialHull, HullError> {
        // The mesh's own topology, copied rather than built again (`TriMesh::plain_copy`).
        Self::build(mesh.plain_copy(), normals.to_vec(), options, progress)
    }

    fn build(
        mesh: TriMesh,
        normals: Vec<DVec3>,
        options: &HullOptions,
        progress: &dyn Progress,
    ) -> Result<SimplicialHull, HullError> {
        options.validate()?;
        check_input(&mesh, &normals)?;
        // Crossings of the input mesh: overlaps around them are the input's, not refined.
        let zone = if options.check_intersections {
            CrossingZone::new(&mesh)
        } else {
            CrossingZone::default()
        };
        Self::refine(RefineState::new(mesh, normals), zone, options, 0, progress)
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
        self.refine_faces_with_progress(faces, &NoProgress)
    }

    /// [`SimplicialHull::refine_faces`], reporting its steps to `progress` as
    /// [`SimplicialHull::from_mesh_with_progress`] does.
    ///
    /// # Errors
    /// As [`SimplicialHull::refine_faces`]; [`HullError::Cancelled`] when `progress` asked to
    /// stop.
    pub fn refine_faces_with_progress(
        &self,
        faces: &[u32],
        progress: &dyn Progress,
    ) -> Result<SimplicialHull, HullError> {
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
        Self::refine(state, self.zone.clone(), &self.options, round + 1, progress)
    }

    /// The build-check-refine loop of [`SimplicialHull::new`] from `state`, numbering its
    /// rounds from `first_round`: the first round builds and checks everything, later ones
    /// what their splits changed ([`rounds`]).
    fn refine(
        mut state: RefineState,
        zone: CrossingZone,
        options: &HullOptions,
        first_round: usize,
        progress: &dyn Progress,
    ) -> Result<SimplicialHull, HullError> {
        // Splits made before (`refine_faces`) are in the mesh this round builds in full.
        state.take_changes();
        let (faces, edges) = build_faces_edges(
            &state.mesh,
            &state.normals,
            &state.face_map,
            options,
            progress,
        )?;
        // The mesh moves into the hull (and back out for the splits; a clone was 10 MB of
        // copying on the bunny), which takes the state's bookkeeping when done.
        let take_mesh = |state: &mut RefineState| {
            TriMesh::new(Vec::new(), Vec::new())
                .map(|empty| std::mem::replace(&mut state.mesh, empty))
        };
        let shell = |mesh, faces, edges| SimplicialHull {
            mesh,
            normals: Vec::new(),
            faces,
            edges,
            face_map: Vec::new(),
            input_vertex_count: 0,
            refinements: Vec::new(),
            options: options.clone(),
            zone: CrossingZone::default(),
            ancestor: HashMap::new(),
        };
        let done = |hull: SimplicialHull, state: RefineState, zone: CrossingZone| SimplicialHull {
            zone,
            ancestor: state.ancestor,
            normals: state.normals,
            face_map: state.face_map,
            refinements: state.refinements,
            input_vertex_count: state.input_vertex_count,
            ..hull
        };
        let hull = shell(take_mesh(&mut state)?, faces, edges);
        if !options.check_intersections {
            return Ok(done(hull, state, zone));
        }
        // The connected component of every input face: bisection keeps a face's children in
        // its component and joins no two, so a face's component in any round is its input
        // face's (`face_map`), and the mesh's components are found once, not every round.
        let input_component: Vec<u32> = {
            let comp = hull.mesh.topology().face_components();
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
        // Overlaps between tetrahedra of different connected components are between
        // different surfaces (the Utah teapot's spout passes through its body), and those
        // around two input faces that cross are the input's (the cow's ears through its
        // head): no refinement separates them, so only the other overlaps are refined;
        // these are reported by `distant_intersections()`.
        let removable = |state: &RefineState, found: Vec<Overlap>| -> Vec<Overlap> {
            let component = |f: u32| input_component[state.face_map[f as usize] as usize];
            found
                .into_iter()
                .filter(|h| !rounds::unremovable(component, &zone, &state.face_map, h))
                .collect()
        };
        let (found, index) = hull.indexed_intersections(progress)?;
        let found = found.iter().map(|h| hull.overlap(h)).collect();
        let mut hits = removable(&state, found);
        if hits.is_empty() {
            return Ok(done(hull, state, zone));
        }
        let first_keys = hull.mesh.topology().edges().to_vec();
        state.mesh = hull.mesh;
        let mut rounds = Rounds::new(hull.faces, hull.edges, first_keys, index);
        let mut round = first_round;
        // Every input face is in the face map (splits keep their halves' input face).
        let input_faces = state.face_map.iter().max().map_or(0, |&f| f as usize + 1);
        let face_bound = (options.max_refinement_growth * input_faces as f64)
            .max(crate::REFINEMENT_FACE_FLOOR as f64);
        let first_overlaps = hits.len();
        let overlap_bound = (options.max_overlap_growth * first_overlaps as f64)
            .max(crate::REFINEMENT_OVERLAP_FLOOR as f64);
        loop {
            let (positions, triangles) = state.current();
            let hit = &hits[0];
            let [a, b] = rounds::conflict_edge(hit, positions, triangles);
            // The overlap is named by an input edge and the input faces of its two parts.
            let edge = state.input_edge(a, b);
            let faces =
                [hit.first, hit.second].map(|t| state.face_map[t.part.first_face() as usize]);
            let unresolved = |rounds: usize, reason: String| HullError::UnresolvedIntersection {
                edge,
                faces,
                rounds,
                reason,
            };
            // Same-component overlaps that survive every round, or that have multiplied the
            // faces or themselves beyond the growth bounds, are an error.
            let grown = triangles.len() as f64 > face_bound;
            let multiplied = hits.len() as f64 > overlap_bound;
            if round - first_round == options.max_refinement_rounds || grown || multiplied {
                let why = if multiplied && !grown {
                    format!(
                        "the overlapping pairs have grown from {first_overlaps} to {} in {} \
                         rounds, more than {} times the first round's (`max_overlap_growth`), \
                         while the mesh grew from {input_faces} to {} faces: refinement \
                         multiplies them here instead of separating them",
                        hits.len(),
                        round - first_round,
                        options.max_overlap_growth,
                        triangles.len()
                    )
                } else if grown {
                    format!(
                        "the mesh has grown to {} faces, more than {} times the input's {} \
                         (`max_refinement_growth`), and {} pairs still overlap: refinement \
                         multiplies them here instead of separating them",
                        triangles.len(),
                        options.max_refinement_growth,
                        input_faces,
                        hits.len()
                    )
                } else {
                    format!("the limit of {round} rounds is reached")
                };
                return Err(unresolved(
                    round,
                    format!(
                        "{why}; {}",
                        rounds::tallest_explained(
                            &hits,
                            rounds.faces(),
                            positions,
                            &state.normals,
                            &state.face_map,
                            state.input_vertex_count,
                        )
                    ),
                ));
            }
            // Faces to bisect, with their corners now (ids of split faces get reused).
            let mut targets: Vec<(u32, [u32; 3])> = Vec::new();
            let mut seen = vec![false; triangles.len()];
            for hit in &hits {
                for part in [hit.first.part, hit.second.part] {
                    for f in part.faces() {
                        if !std::mem::replace(&mut seen[f as usize], true) {
                            targets.push((f, triangles[f as usize]));
                        }
                    }
                }
            }
            for (f, corners) in targets {
                state.bisect_face(f, corners, round)?;
            }
            round += 1;
            progress.start(
                &format!(
                    "hull: refinement round {} ({} overlapping pairs)",
                    round - first_round,
                    hits.len()
                ),
                0,
            );
            check_cancelled(progress)?;
            let found = rounds
                .round(&mut state, options)
                .map_err(|e| unresolved(round, format!("refining made the hull invalid: {e}")))?;
            hits = removable(&state, found);
            if hits.is_empty() {
                let (faces, edges) = rounds.finish(&mut state)?;
                let hull = shell(take_mesh(&mut state)?, faces, edges);
                return Ok(done(hull, state, zone));
            }
        }
    }

    /// The overlap `h` of this hull's tetrahedra with its elements named by [`rounds::Part`].
    fn overlap(&self, h: &Intersection) -> Overlap {
        let tet = |t: &HullTetrahedron| rounds::RoundTet {
            part: match t.element {
                Element::Face(f) => rounds::Part::Face(f),
                Element::Edge(e) => {
                    let edge = &self.edges[e as usize];
                    rounds::Part::Edge {
                        vertices: edge.vertices,
                        face_k: edge.face_k,
                        face_l: edge.face_l,
                    }
                }
            },
            side: t.side,
            vertices: t.vertices,
        };
        Overlap {
            first: tet(&h.first),
            second: tet(&h.second),
            depth: h.depth,
        }
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
            .filter(|h| {
                let of = |f: u32| component[f as usize];
                rounds::unremovable(of, &self.zone, &self.face_map, &self.overlap(h))
            })
            .collect()
    }

    /// The pairs of input faces `[f, g]` (`f < g`, ascending) that share no vertex and pass
    /// through each other ([`algesurf_mesh::self_intersections`]). Empty unless
    /// [`HullOptions::check_intersections`] is set (it is by default).
    pub fn input_crossings(&self) -> &[[u32; 2]] {
        self.zone.crossings()
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
