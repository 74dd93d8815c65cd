//! The refinement rounds after the first (§3.1), each rebuilding and checking only what its
//! splits changed.
//!
//! The first round builds every face and edge of the mesh and checks every pair of tetrahedra
//! (`intersect`). A later round bisects a few hundred faces of the bunny's 70 k; rebuilding
//! the mesh's topology, every face and edge record and the tetrahedra's numbering for them
//! cost 55–70 ms a round on the bunny (four rounds: about 250 ms, an eighth of its
//! construction), almost all of it copying what did not change. Here a round rebuilds the
//! faces its splits changed or appended, and the edges of those faces, from the edited mesh
//! alone, and checks their tetrahedra against the first round's tree and a tree over the
//! tetrahedra later rounds made ([`TetIndex::overlaps_of`]); the topology and the edge
//! numbering are made once, by [`Rounds::finish`], when no round is left.
//!
//! A round names its tetrahedra without edge ids ([`Part`]): an edge by its vertices. Pairs
//! are ordered as the whole hull's numbering orders them (faces by id, then edges by their
//! vertex ids, the topology's order; positive before negative), so the refinement, which
//! bisects the faces of the overlaps in that order, is the one a rebuild of everything gives
//! (`local_rounds_find_the_overlaps_of_a_rebuild_of_everything` below).

use super::intersect::{TetIndex, TetKey};
use crate::classify::Side;
use crate::crossing::CrossingZone;
use crate::hull::{HullEdge, HullFace, Inputs, filler_edge, filler_face, longest_edge};
use crate::refine::{RefineState, key};
use crate::{HullError, HullOptions};
use algesurf_mesh::fasthash::FastMap;
use algesurf_mesh::parallel::collect_first_error;
use glam::DVec3;
use rayon::prelude::*;

/// The face or edge a tetrahedron of a round belongs to, named without the topology's edge
/// ids (which a round does not have).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Part {
    /// A face, by id (a face keeps its id while refinement splits it).
    Face(u32),
    /// An edge `[i, j]` (oriented as in `face_k`) with its faces.
    Edge {
        vertices: [u32; 2],
        face_k: u32,
        face_l: Option<u32>,
    },
}

/// The keys of a triangle's edges `[i j]`, `[j k]`, `[k i]` (the order of `HullFace::edges`).
fn triangle_edge_keys(t: [u32; 3]) -> [[u32; 2]; 3] {
    std::array::from_fn(|c| key(t[c], t[(c + 1) % 3]))
}

impl Part {
    /// The faces of the part: one for a face, one or two for an edge.
    pub(crate) fn faces(&self) -> impl Iterator<Item = u32> {
        let (first, second) = match *self {
            Part::Face(f) => (f, None),
            Part::Edge { face_k, face_l, .. } => (face_k, face_l),
        };
        std::iter::once(first).chain(second)
    }

    /// The part's first face (the face, or an edge's `face_k`): the face an overlap is named
    /// by and whose component it is in.
    pub(crate) fn first_face(&self) -> u32 {
        match *self {
            Part::Face(f) => f,
            Part::Edge { face_k, .. } => face_k,
        }
    }

    /// The part's edges as keys: three for a face (`[i j]`, `[j k]`, `[k i]`), one for an edge.
    fn edge_keys(&self, triangles: &[[u32; 3]]) -> Vec<[u32; 2]> {
        match *self {
            Part::Face(f) => triangle_edge_keys(triangles[f as usize]).to_vec(),
            Part::Edge {
                vertices: [a, b], ..
            } => vec![key(a, b)],
        }
    }
}

/// A tetrahedron of the hull named by its [`Part`] and side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RoundTet {
    pub(crate) part: Part,
    pub(crate) side: Side,
    pub(crate) vertices: [DVec3; 4],
}

impl RoundTet {
    /// Its name in the index of the tetrahedra (`TetIndex`).
    pub(crate) fn key(&self) -> TetKey {
        match self.part {
            Part::Face(f) => TetKey::Face(f, self.side),
            Part::Edge { vertices, .. } => TetKey::Edge(vertices, self.side),
        }
    }

    /// Its place in the whole hull's numbering ([`TetKey::order`]).
    pub(crate) fn order(&self) -> (u8, u64, u8) {
        self.key().order()
    }
}

/// Two tetrahedra of a round whose interiors overlap, `first` before `second` in
/// [`RoundTet::order`], with their [`crate::overlap_depth`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Overlap {
    pub(crate) first: RoundTet,
    pub(crate) second: RoundTet,
    pub(crate) depth: f64,
}

/// Whether refinement cannot remove `overlap` (`SimplicialHull::distant_intersections`): its
/// tetrahedra lie in different connected components (`component` of a face), or around two
/// input faces that cross (`zone`; `face_map` maps faces to input faces).
pub(crate) fn unremovable(
    component: impl Fn(u32) -> u32,
    zone: &CrossingZone,
    face_map: &[u32],
    overlap: &Overlap,
) -> bool {
    let (a, b) = (overlap.first.part, overlap.second.part);
    if component(a.first_face()) != component(b.first_face()) {
        return true;
    }
    a.faces().any(|x| {
        b.faces()
            .any(|y| zone.contains(face_map[x as usize], face_map[y as usize]))
    })
}

/// The edge an overlap is named by (as a key): the edge its two parts share, else the longest
/// edge of the first part.
pub(crate) fn conflict_edge(
    overlap: &Overlap,
    positions: &[DVec3],
    triangles: &[[u32; 3]],
) -> [u32; 2] {
    let ea = overlap.first.part.edge_keys(triangles);
    let eb = overlap.second.part.edge_keys(triangles);
    if let Some(&e) = ea.iter().find(|e| eb.contains(e)) {
        return e;
    }
    let length = |[a, b]: [u32; 2]| positions[a as usize].distance(positions[b as usize]);
    ea.iter()
        .copied()
        .max_by(|&x, &y| length(x).total_cmp(&length(y)))
        .unwrap_or([0, 0])
}

/// Names the tallest face tetrahedron among `overlaps` and the corner normal that makes it
/// tall: §3.1's apex height `t_l = (p_l − c)ᵀn_l / n_ijkᵀn_l` grows without bound as `n_l`
/// turns into the face's plane, and refinement only helps when the faces around `p_l`
/// turn towards the plane orthogonal to `n_l`, which they do not at a sharp rim.
pub(crate) fn tallest_explained(
    overlaps: &[Overlap],
    faces: &[HullFace],
    positions: &[DVec3],
    normals: &[DVec3],
    face_map: &[u32],
    input_vertex_count: usize,
) -> String {
    let mut best: Option<(f64, u32, Side)> = None;
    for h in overlaps {
        for t in [h.first, h.second] {
            for f in t.part.faces() {
                let face = &faces[f as usize];
                let Some(tet) = face.tetrahedron(t.side) else {
                    continue;
                };
                let ratio =
                    tet.t.abs() / longest_edge(face.vertices.map(|v| positions[v as usize]));
                if best.is_none_or(|(r, _, _)| ratio > r) {
                    best = Some((ratio, f, t.side));
                }
            }
        }
    }
    let Some((ratio, f, side)) = best else {
        return "the intersecting tetrahedra are edge tetrahedra only".to_string();
    };
    let face = &faces[f as usize];
    let (v, cos) = face
        .vertices
        .iter()
        .map(|&v| (v, face.normal.dot(normals[v as usize].normalize())))
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .expect("a face has three corners");
    let which = if (v as usize) < input_vertex_count {
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

/// The hull between refinement rounds: every face (current), the first round's edges and the
/// edges made or removed since.
struct Current {
    /// Every face of the current mesh, updated in place and appended as rounds split them.
    /// Their `edges` ids are the first round's (stale for faces made since) until
    /// [`Rounds::finish`] numbers the edges again.
    faces: Vec<HullFace>,
    /// The first round's edges and their keys (the topology's order, ascending).
    first_edges: Vec<HullEdge>,
    first_keys: Vec<[u32; 2]>,
    /// Edges made (`Some`: their round's list in `made` and their place there) or removed by
    /// a split (`None`) since the first round, by key. (A fast hash: the lookups of every
    /// candidate pair's edge were 9 % of Suzanne's hull. Places, not the 600-byte records:
    /// growing the map moved them all, 8 % of the main thread's samples over Suzanne's
    /// rounds.)
    changed: FastMap<[u32; 2], Option<(u32, u32)>>,
    /// The edges each round made, as it made them (a remade edge's older record stays,
    /// unnamed): one list per round, moved in whole, where one list of all grew by copying.
    made: Vec<Vec<HullEdge>>,
}

impl Current {
    /// The current edge with key `k`: made since the first round, or the first round's.
    fn edge(&self, k: [u32; 2]) -> Option<&HullEdge> {
        self.edge_with(k, |keys| keys.binary_search(&k).ok())
    }

    /// [`Current::edge`] for keys asked in ascending order: `hint` is where the first
    /// round's keys are looked at first (the place after the last one found, kept by the
    /// caller), and a binary search is made only when `k` is not among the next few.
    ///
    /// Between two edges of the refined mesh that the first round made lie only the few
    /// edges splits removed, so the walk is a step or two where a binary search over the
    /// bunny's 104 k keys is seventeen, mostly cache misses: [`Rounds::finish`]'s list of
    /// every edge took 14–19 ms that way.
    fn edge_after(&self, k: [u32; 2], hint: &mut usize) -> Option<&HullEdge> {
        self.edge_with(k, |keys| {
            let start = (*hint).min(keys.len());
            let near = keys[start..]
                .iter()
                .take(8)
                .position(|x| *x >= k)
                .map(|d| start + d);
            let id = match near {
                Some(i) if keys[i] == k => i,
                _ => keys.binary_search(&k).ok()?,
            };
            *hint = id + 1;
            Some(id)
        })
    }

    /// The current edge with key `k`: from the changes since the first round, else the first
    /// round's edge at the place `find` gives in its keys.
    fn edge_with(
        &self,
        k: [u32; 2],
        find: impl FnOnce(&[[u32; 2]]) -> Option<usize>,
    ) -> Option<&HullEdge> {
        match self.changed.get(&k) {
            Some(made) => made.map(|(r, i)| &self.made[r as usize][i as usize]),
            None => find(&self.first_keys).map(|id| &self.first_edges[id]),
        }
    }

    /// The tetrahedron on `side` of face `f`, as it is now.
    fn face_tet(&self, f: u32, side: Side) -> Option<RoundTet> {
        let t = self.faces.get(f as usize)?.tetrahedron(side)?;
        Some(RoundTet {
            part: Part::Face(f),
            side,
            vertices: *t.tetrahedron.vertices(),
        })
    }

    /// The tetrahedron on `side` of the edge with key `k`, as it is now.
    fn edge_tet(&self, k: [u32; 2], side: Side) -> Option<RoundTet> {
        let e = self.edge(k)?;
        let t = e.tetrahedron(side)?;
        Some(RoundTet {
            part: Part::Edge {
                vertices: e.vertices,
                face_k: e.face_k,
                face_l: e.face_l,
            },
            side,
            vertices: *t.tetrahedron.vertices(),
        })
    }

    /// The tetrahedron a key of the index names, as it is now.
    fn resolve(&self, name: TetKey) -> Option<RoundTet> {
        match name {
            TetKey::Face(f, side) => self.face_tet(f, side),
            TetKey::Edge([a, b], side) => self.edge_tet(key(a, b), side),
        }
    }
}

/// The refinement rounds after the first: the hull as it is now, and the first round's tree
/// over every tetrahedron with the tetrahedra made since.
pub(crate) struct Rounds {
    hull: Current,
    index: TetIndex,
}

impl Rounds {
    /// The state after the first round: its faces and edges (`first_keys` the edges' keys in
    /// topology order) and the index its check built.
    pub(crate) fn new(
        faces: Vec<HullFace>,
        first_edges: Vec<HullEdge>,
        first_keys: Vec<[u32; 2]>,
        index: TetIndex,
    ) -> Rounds {
        debug_assert!(first_keys.is_sorted(), "edges in topology order");
        Rounds {
            hull: Current {
                faces,
                first_edges,
                first_keys,
                changed: FastMap::default(),
                made: Vec::new(),
            },
            index,
        }
    }

    /// Every face of the current mesh (edge ids stale until [`Rounds::finish`]).
    pub(crate) fn faces(&self) -> &[HullFace] {
        &self.hull.faces
    }

    /// One round after the splits `state` holds: rebuilds the faces they changed or appended
    /// and the edges of those faces (as the first round built every face and edge, with the
    /// same errors in the same order: the edges' structure, the faces, the edge tetrahedra),
    /// then returns the overlaps of their tetrahedra with any tetrahedron of the hull, in
    /// [`RoundTet::order`].
    pub(crate) fn round(
        &mut self,
        state: &mut RefineState,
        opts: &HullOptions,
    ) -> Result<Vec<Overlap>, HullError> {
        let changes = state.take_changes();
        let mut fresh_faces = changes.faces;
        fresh_faces.sort_unstable();
        fresh_faces.dedup();
        let hull = &mut self.hull;
        for k in changes.removed_edges {
            hull.changed.insert(k, None);
        }
        let (positions, triangles) = state.current();
        let inputs = Inputs {
            positions,
            normals: &state.normals,
            face_map: &state.face_map,
            opts,
        };
        let third = |t: [u32; 3], [a, b]: [u32; 2]| -> (u32, u32, u32) {
            let c = (0..3)
                .find(|&c| key(t[c], t[(c + 1) % 3]) == key(a, b))
                .expect("the edge is a side of the face it was found in");
            (t[c], t[(c + 1) % 3], t[(c + 2) % 3])
        };
        // The edges of the changed faces, in topology order. Each is built as the whole
        // build builds it from the topology: `face_k` is the face with the lower id (the
        // edge's first half-edge is the lower corner id, and corners are numbered by face),
        // `[i, j]` its direction there.
        let mut keys: Vec<[u32; 2]> = fresh_faces
            .iter()
            .flat_map(|&f| triangle_edge_keys(triangles[f as usize]))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        // Edges, faces and edge tetrahedra each in parallel, with the first error in the
        // order a loop meets it (built one by one on the main thread while the other core
        // waited, with the apexes' searches they were ~12 % of its samples over Suzanne's
        // 17 rounds).
        let state: &RefineState = state;
        let mut fresh_edges = collect_first_error(
            keys.len(),
            |n| {
                let [a, b] = keys[n];
                let faces = state.edge_faces(a, b).unwrap_or_default();
                if faces.len() > 2 {
                    return Err(HullError::NonManifoldEdge(a, b));
                }
                // A changed face's side is an edge of the edited mesh: never empty.
                let Some(&face_k) = faces.first() else {
                    return Err(algesurf_mesh::MeshError::NoSuchEdge(a, b).into());
                };
                let (i, j, k) = third(triangles[face_k as usize], [a, b]);
                let other = match faces.get(1) {
                    Some(&g) => {
                        let (x, y, l) = third(triangles[g as usize], [a, b]);
                        if (x, y) != (j, i) {
                            return Err(HullError::InconsistentOrientation {
                                edge: [i, j],
                                faces: [
                                    state.face_map[face_k as usize],
                                    state.face_map[g as usize],
                                ],
                            });
                        }
                        Some((g, l))
                    }
                    None => None,
                };
                Ok(inputs.edge([i, j], face_k, k, other))
            },
            filler_edge,
        )?;
        let convexity = |k: [u32; 2]| {
            let at = keys
                .binary_search(&k)
                .expect("a changed face's edges are rebuilt with it");
            fresh_edges[at].convexity
        };
        let built = collect_first_error(
            fresh_faces.len(),
            |n| {
                let f = fresh_faces[n];
                let t = triangles[f as usize];
                // Edge ids are given when the topology is made ([`Rounds::finish`]).
                let convexities = triangle_edge_keys(t).map(convexity);
                inputs.face(f as usize, t, [u32::MAX; 3], convexities)
            },
            filler_face,
        )?;
        for (&f, face) in fresh_faces.iter().zip(built) {
            match hull.faces.get_mut(f as usize) {
                Some(slot) => *slot = face,
                None => {
                    debug_assert_eq!(f as usize, hull.faces.len(), "halves are appended");
                    hull.faces.push(face);
                }
            }
        }
        let faces = &hull.faces;
        let done: Vec<Result<(), HullError>> = fresh_edges
            .par_iter_mut()
            .map(|edge| inputs.edge_tetrahedra(edge, faces))
            .collect();
        done.into_iter().collect::<Result<(), _>>()?;
        let r = hull.made.len() as u32;
        for (i, &k) in keys.iter().enumerate() {
            hull.changed.insert(k, Some((r, i as u32)));
        }
        hull.made.push(fresh_edges);
        let hull = &self.hull;
        // The new tetrahedra, in order, and their overlaps with every tetrahedron.
        let sides = [Side::Positive, Side::Negative];
        let new: Vec<RoundTet> = fresh_faces
            .iter()
            .flat_map(|&f| sides.iter().filter_map(move |&s| hull.face_tet(f, s)))
            .chain(
                keys.iter()
                    .flat_map(|&k| sides.iter().filter_map(move |&s| hull.edge_tet(k, s))),
            )
            .collect();
        Ok(self
            .index
            .overlaps_of(&new, |name| hull.resolve(name), opts.overlap_tolerance))
    }

    /// The faces and edges of the refined mesh, numbered by its topology, which this makes
    /// (`state.mesh`, from the edits): the edges as the last round left them, in topology
    /// order, and every face's edge ids.
    pub(crate) fn finish(
        self,
        state: &mut RefineState,
    ) -> Result<(Vec<HullFace>, Vec<HullEdge>), HullError> {
        // The overlap check's index (~92 MB on the bunny) is not needed any more: dropped
        // before the final edge list is made, so that list takes the index's pages instead
        // of fresh ones (docs/PERFORMANCE.md, twenty-fifth pass).
        let Rounds { hull, index } = self;
        drop(index);
        state.finish_round()?;
        let topo = state.mesh.topology();
        // In the topology's (ascending) order, each thread walking the first round's keys
        // from where it found the last ([`Current::edge_after`]).
        let edges: Vec<HullEdge> = (0..topo.edge_count() as u32)
            .into_par_iter()
            .map_init(
                || 0,
                |hint, e| {
                    let k = topo.edge(e);
                    hull.edge_after(k, hint)
                        .expect("every edge of the refined mesh was built by some round")
                        .clone()
                },
            )
            .collect();
        let mut faces = hull.faces;
        faces.par_iter_mut().enumerate().for_each(|(f, face)| {
            let first = topo.face_corners(f).start;
            face.edges = std::array::from_fn(|c| topo.corner_edge(first + c as u32));
        });
        Ok((faces, edges))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hull::build;
    use crate::{ApexPlacement, SimplicialHull};
    use algesurf_mesh::TriMesh;
    use algesurf_mesh::progress::NoProgress;

    /// `z = a sin(ωx) sin(ωy)` on an `n × n` grid over `[−1, 1]²` with exact unit normals,
    /// counter-clockwise seen from +z: with the paper's apexes on the face normals, adjacent
    /// tetrahedra overlap, and refinement needs several rounds to separate them.
    fn wave(n: usize, a: f64, w: f64) -> (TriMesh, Vec<DVec3>) {
        let (mut p, mut normals, mut t) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (
                    -1.0 + 2.0 * i as f64 / n as f64,
                    -1.0 + 2.0 * j as f64 / n as f64,
                );
                let (sx, cx, sy, cy) = ((w * x).sin(), (w * x).cos(), (w * y).sin(), (w * y).cos());
                p.push(DVec3::new(x, y, a * sx * sy));
                normals.push(DVec3::new(-a * w * cx * sy, -a * w * sx * cy, 1.0).normalize());
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (TriMesh::new(p, t).unwrap(), normals)
    }

    fn paper() -> HullOptions {
        HullOptions {
            apex: ApexPlacement::FaceNormal,
            ..HullOptions::default()
        }
    }

    /// Each round's overlaps are those of a hull rebuilt in full on the round's mesh whose
    /// pairs have a tetrahedron of a changed face or of one of its edges, in the same order
    /// with the same depths; after the last round, the faces and edges are those of a build
    /// from scratch, edge ids included.
    #[test]
    fn local_rounds_find_the_overlaps_of_a_rebuild_of_everything() {
        let opts = paper();
        let whole = HullOptions {
            check_intersections: false,
            max_refinement_rounds: 0,
            ..paper()
        };
        let (mut rounds_run, mut overlaps_seen) = (0, 0);
        // Four, four and twelve rounds (28, 63 and 280 splits) with a whole loop.
        for (n, a, w) in [(2, 0.4, 5.0), (3, 0.2, 5.0), (5, 0.3, 5.0)] {
            let (mesh, normals) = wave(n, a, w);
            let hull = SimplicialHull::from_mesh(&mesh, &normals, &whole).unwrap();
            let (found, index) = hull.indexed_intersections(&NoProgress).unwrap();
            let mut overlaps: Vec<Overlap> = found.iter().map(|h| hull.overlap(h)).collect();
            assert!(!overlaps.is_empty(), "the test needs overlaps");
            let keys = hull.mesh.topology().edges().to_vec();
            let mut rounds = Rounds::new(hull.faces.clone(), hull.edges.clone(), keys, index);
            let mut state = RefineState::new(mesh, normals);
            for round in 0..16 {
                let before = state.current().1.to_vec();
                for o in &overlaps {
                    for f in o.first.part.faces().chain(o.second.part.faces()) {
                        state.bisect_face(f, before[f as usize], round).unwrap();
                    }
                }
                let got = rounds.round(&mut state, &opts).unwrap();
                let (positions, triangles) = state.current();
                let fresh = |f: u32| before.get(f as usize) != Some(&triangles[f as usize]);
                let fresh_tet = |t: &RoundTet| t.part.faces().any(fresh);
                let full =
                    SimplicialHull::new(positions, triangles, &state.normals, &whole).unwrap();
                let want: Vec<Overlap> = full
                    .intersections()
                    .iter()
                    .map(|h| full.overlap(h))
                    .filter(|o| fresh_tet(&o.first) || fresh_tet(&o.second))
                    .collect();
                assert_eq!(got, want, "n = {n}, round {round}");
                rounds_run += 1;
                overlaps_seen += got.len();
                overlaps = got;
                if overlaps.is_empty() {
                    break;
                }
            }
            assert!(
                overlaps.is_empty(),
                "n = {n}: sixteen rounds were not enough"
            );
            let (faces, edges) = rounds.finish(&mut state).unwrap();
            let (scratch_faces, scratch_edges) = build(
                &state.mesh,
                &state.normals,
                &state.face_map,
                &opts,
                &NoProgress,
            )
            .unwrap();
            assert_eq!(faces, scratch_faces, "n = {n}");
            assert_eq!(edges, scratch_edges, "n = {n}");
        }
        assert!(
            rounds_run >= 17 && overlaps_seen >= 50,
            "{rounds_run} rounds, {overlaps_seen} overlaps after the first"
        );
    }

    /// The whole loop (`SimplicialHull::new`) ends in the hull a build from scratch gives on
    /// the refined mesh, with no overlap left.
    #[test]
    fn refined_hull_is_the_hull_of_its_mesh() {
        let (mesh, normals) = wave(5, 0.3, 5.0);
        let hull = SimplicialHull::from_mesh(&mesh, &normals, &paper()).unwrap();
        assert!(
            hull.refinements().len() > 100,
            "{}",
            hull.refinements().len()
        );
        let (faces, edges) = build(
            hull.mesh(),
            hull.normals(),
            hull.face_map(),
            hull.options(),
            &NoProgress,
        )
        .unwrap();
        assert_eq!(hull.faces(), faces.as_slice());
        assert_eq!(hull.edges(), edges.as_slice());
        assert!(hull.intersections().is_empty());
    }

    /// Looking edges up from a hint gives what a binary search gives (and `Current::edge`,
    /// which searches at once), whatever order the keys are asked in: ascending with gaps
    /// short and long (the walk and the search after it), descending, repeated, keys the
    /// first round did not make, and keys made or removed since, which the changes answer.
    #[test]
    fn edges_found_from_a_hint_are_those_a_search_finds() {
        let mut r = algesurf_mesh::test_rng::Lcg(5);
        let mut first_keys: Vec<[u32; 2]> = (0..600)
            .map(|_| {
                let a = (r.next() * 300.0) as u32;
                [a, a + 1 + (r.next() * 40.0) as u32]
            })
            .collect();
        first_keys.sort_unstable();
        first_keys.dedup();
        let named = |k: [u32; 2]| HullEdge {
            vertices: k,
            ..filler_edge()
        };
        let mut current = Current {
            faces: Vec::new(),
            first_edges: first_keys.iter().map(|&k| named(k)).collect(),
            first_keys: first_keys.clone(),
            changed: FastMap::default(),
            made: vec![vec![named([1000, 1001])]],
        };
        current.changed.insert(first_keys[10], None);
        current.changed.insert([1000, 1001], Some((0, 0)));
        let want = |k: [u32; 2]| match current.changed.get(&k) {
            Some(made) => made.map(|(r, i)| current.made[r as usize][i as usize].vertices),
            None => first_keys.binary_search(&k).ok().map(|_| k),
        };
        let mut asked: Vec<[u32; 2]> = Vec::new();
        for (i, &k) in first_keys.iter().enumerate() {
            // Runs of neighbours, then jumps of up to 60 keys; some absent keys between.
            if i % 50 < 30 || r.next() < 0.05 {
                asked.push(k);
            }
            if r.next() < 0.1 {
                asked.push([k[0], k[1] + 1000]);
            }
        }
        asked.push([1000, 1001]);
        let descending: Vec<[u32; 2]> = asked.iter().rev().copied().collect();
        let repeated: Vec<[u32; 2]> = asked.iter().flat_map(|&k| [k, k]).collect();
        for order in [&asked, &descending, &repeated] {
            let mut hint = 0;
            for &k in order {
                let got = current.edge_after(k, &mut hint).map(|e| e.vertices);
                assert_eq!(got, want(k), "key {k:?}");
                assert_eq!(current.edge(k).map(|e| e.vertices), want(k), "key {k:?}");
            }
        }
        assert!(asked.len() > 300, "{} keys asked", asked.len());
    }
}
