//! The normal of the modified Butterfly limit surface at a vertex.
//!
//! Butterfly subdivision is interpolating: a vertex stays where it is, and the faces around it
//! turn, level by level, into the tangent plane of the limit surface there (Zorin, Schröder and
//! Sweldens 1996 prove that limit C1 for every valence). The simplicial hull refines by
//! Butterfly splits (§3.1 of Xu–Huang–Bajaj 2001), so with these normals the faces that
//! refinement makes around a vertex approach the plane orthogonal to its normal, and §3.1's
//! apex heights `t_l = (p_l − c)ᵀn_l / n_ijkᵀn_l` shrink with the faces. Loop limit normals
//! have no such link to Butterfly refinement: at a sharp rim the two limit tangent planes
//! differ by tens of degrees, and there refinement never separated the hull's tetrahedra.

use crate::fasthash::{FastMap, FastSet};
use crate::subdivision::{butterfly_edge_points, split_triangles};
use crate::{MeshError, TriMesh};
use glam::DVec3;
use rayon::prelude::*;

/// How many rings around the vertex each level keeps. A Butterfly edge point reads at most two
/// rings around its edge (the eight-point stencil, or one end's one-ring), so points of the
/// cut-out are those of the whole mesh's subdivision within `RINGS − 2` rings of the vertex;
/// after the step that is `2 (RINGS − 2)` rings of the finer mesh, which with `RINGS = 4` is
/// again at least `RINGS`: every level's cut-out is exact, the cut's own boundary rules never
/// reach the vertex's faces.
const RINGS: usize = 4;

/// Levels of subdivision. The faces at the vertex approach the tangent plane geometrically
/// (by the ratio of the subdivision matrix's subdominant eigenvalues, ½ for the regular
/// stencil); `butterfly_normal_converges` measures the change from level 7 to 8 below
/// 2e-3 rad on the corpus-like shapes of the tests.
pub const BUTTERFLY_NORMAL_LEVELS: usize = 8;

/// The faces within `rings` rings of the vertices `seeds` (distinct) of the triangles
/// `triangles` over `positions`, as a mesh of their own in which the seeds are vertices
/// `0, 1, …` in their order. `vertex_faces(u, out)` appends the faces at vertex `u` in
/// increasing id order (`Topology::vertex_faces`' order), which fixes the numbering of the
/// cut-out.
fn neighbourhood(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    vertex_faces: impl Fn(u32, &mut Vec<u32>),
    seeds: &[u32],
    rings: usize,
) -> Result<TriMesh, MeshError> {
    // Fast hashes: only looked up, never iterated, so the cut-out is the same as with any.
    let mut local = FastMap::default();
    for (i, &v) in seeds.iter().enumerate() {
        local.insert(v, i as u32);
    }
    let mut order = seeds.to_vec();
    let mut frontier = seeds.to_vec();
    let mut faces = Vec::new();
    let mut seen_face = FastSet::default();
    let mut around = Vec::new();
    for _ in 0..rings {
        let mut next = Vec::new();
        for &u in &frontier {
            around.clear();
            vertex_faces(u, &mut around);
            for &f in &around {
                if !seen_face.insert(f) {
                    continue;
                }
                faces.push(f);
                for w in triangles[f as usize] {
                    if let std::collections::hash_map::Entry::Vacant(e) = local.entry(w) {
                        e.insert(order.len() as u32);
                        order.push(w);
                        next.push(w);
                    }
                }
            }
        }
        frontier = next;
    }
    let positions = order.iter().map(|&w| positions[w as usize]).collect();
    let triangles = faces
        .iter()
        .map(|&f| triangles[f as usize].map(|w| local[&w]))
        .collect();
    TriMesh::new(positions, triangles)
}

/// The faces at each vertex of a triangle list, in increasing face id order (compressed rows).
struct VertexFaces {
    offsets: Vec<u32>,
    faces: Vec<u32>,
}

impl VertexFaces {
    fn of(vertex_count: usize, triangles: &[[u32; 3]]) -> VertexFaces {
        // Items in face order, so each vertex's faces come in increasing id order.
        let corners = triangles
            .iter()
            .enumerate()
            .flat_map(|(f, t)| t.iter().map(move |&w| (w, f as u32)));
        let (offsets, faces) = crate::topology::csr(vertex_count, corners);
        VertexFaces { offsets, faces }
    }

    fn at(&self, u: u32) -> &[u32] {
        &self.faces[self.offsets[u as usize] as usize..self.offsets[u as usize + 1] as usize]
    }
}

/// The unit normal of the modified Butterfly limit surface at vertex `v`, oriented with the
/// faces, after `levels` subdivision steps of a cut-out around `v` (see
/// [`BUTTERFLY_NORMAL_LEVELS`]): the area-weighted normal of `v`'s faces there.
///
/// `None` where the neighbourhood cannot be subdivided (a non-manifold vertex or edge within
/// four rings, or a cut-out that wraps around a tube only a few faces round and pinches), has
/// no faces, or the normal vanishes; [`crate::NormalMethod::Butterfly`] then falls back to the
/// Loop normal.
///
/// ```
/// use algesurf_mesh::{butterfly_limit_normal, shapes, BUTTERFLY_NORMAL_LEVELS};
///
/// // The icosahedron is symmetric about each vertex: the limit normal is radial.
/// let ico = shapes::icosphere(0);
/// let n = butterfly_limit_normal(&ico, 0, BUTTERFLY_NORMAL_LEVELS).unwrap();
/// assert!((n - ico.positions()[0].normalize()).length() < 1e-12);
/// ```
pub fn butterfly_limit_normal(mesh: &TriMesh, v: u32, levels: usize) -> Option<DVec3> {
    if v as usize >= mesh.vertex_count() {
        return None;
    }
    // The cut-outs number `v` first: it is vertex 0 of each.
    let mut local = cut_out(mesh, &[v]).ok()?;
    for _ in 0..levels {
        local = step_around(&local, &[0])?;
    }
    area_weighted_normal(&local, 0)
}

/// One Butterfly step of the cut-out `local` (`butterfly_subdivide`) without the topology of
/// the whole finer mesh, of which only the faces around the seeds are needed (that topology
/// was a third of a normal's work), then the [`neighbourhood`] of the seeds (local ids) in the
/// finer mesh, which numbers them `0, 1, …`. The finer mesh cannot fail the step (three
/// distinct ids per face, from a mesh that passed). Old vertices keep their ids through a
/// subdivision, so the seeds' ids stay valid.
fn step_around(local: &TriMesh, seeds: &[u32]) -> Option<TriMesh> {
    let points = butterfly_edge_points(local).ok()?;
    let (positions, triangles, _) = split_triangles(local, local.positions().to_vec(), &points);
    let incidence = VertexFaces::of(positions.len(), &triangles);
    let around = |u: u32, out: &mut Vec<u32>| out.extend_from_slice(incidence.at(u));
    neighbourhood(&positions, &triangles, around, seeds, RINGS).ok()
}

/// [`neighbourhood`] of vertices `seeds` of a mesh, through its topology.
fn cut_out(mesh: &TriMesh, seeds: &[u32]) -> Result<TriMesh, MeshError> {
    let topo = mesh.topology();
    let around = |u: u32, out: &mut Vec<u32>| out.extend(topo.vertex_faces(u));
    neighbourhood(mesh.positions(), mesh.triangles(), around, seeds, RINGS)
}

/// Valence (faces at a vertex) from which a vertex is a *hub* whose neighbours share their
/// first two subdivision levels ([`butterfly_limit_normals`]).
///
/// Why this size: a vertex within three rings of a hub of valence `k` has the hub's whole fan
/// in its cut-out for the first levels, so the `~k` vertices around a hub cost `O(k²)` one by
/// one (98 s at valence 4096). At 64 the fan roughly doubles a regular vertex's cut-out (~60
/// faces), where one by one costs about as much as the shared step. The corpus's largest
/// valence is 40 (the teapot), so its normals are the one-by-one ones, bit for bit.
pub const HUB_VALENCE: usize = 64;

/// Levels subdivided once for all the vertices near hubs: after two levels a hub is at least
/// four rings of the finer mesh from every vertex that was within three rings of it (each
/// level doubles ring distances), so a vertex's cut-out no longer holds the hub's whole fan.
const SHARED_LEVELS: usize = 2;

/// Ring distance within which a cut-out of [`RINGS`] rings holds a vertex's whole fan: the
/// cut adds the faces of the vertices at distance `0 .. RINGS − 1`.
const FAN_REACH: u8 = (RINGS - 1) as u8;

/// [`butterfly_limit_normal`] at each of `vertices` (`None` where it gives `None`, and for
/// ids out of range), computed together.
///
/// The vertices within three rings of a *hub* (a vertex of valence ≥ [`HUB_VALENCE`], such as
/// the centre of a fan a CAD exporter makes of a circular face) share their first two
/// subdivision levels: one cut-out holding all their neighbourhoods is subdivided twice, and
/// each continues from its own cut-out of that. One by one, each would subdivide the hub's
/// whole fan twice, and the normals at a fan's rim would cost time quadratic in its valence.
/// Every value a vertex's later levels read is the whole mesh's subdivision there either way
/// (each cut-out keeps four rings around its vertices, twice the reach of a Butterfly
/// stencil), so the normals agree with [`butterfly_limit_normal`]'s up to rounding (the
/// cut-outs number their points differently, and stencils sum in that order: 7e-13 on a tube
/// with fans of 80, the size of the differences renumbering the mesh makes). Elsewhere each
/// normal is [`butterfly_limit_normal`]'s, bit for bit. If the shared cut-out cannot be
/// subdivided (a non-manifold spot anywhere in it), its vertices are done one by one.
///
/// ```
/// use algesurf_mesh::{butterfly_limit_normal, butterfly_limit_normals, shapes, BUTTERFLY_NORMAL_LEVELS};
///
/// let ico = shapes::icosphere(1);
/// let all: Vec<u32> = (0..ico.vertex_count() as u32).collect();
/// let together = butterfly_limit_normals(&ico, &all, BUTTERFLY_NORMAL_LEVELS);
/// for &v in &all {
///     assert_eq!(together[v as usize], butterfly_limit_normal(&ico, v, BUTTERFLY_NORMAL_LEVELS));
/// }
/// assert_eq!(butterfly_limit_normals(&ico, &[1000], 3), vec![None]);
/// ```
pub fn butterfly_limit_normals(
    mesh: &TriMesh,
    vertices: &[u32],
    levels: usize,
) -> Vec<Option<DVec3>> {
    let near_hub = if levels >= SHARED_LEVELS {
        near_hubs(mesh)
    } else {
        Vec::new()
    };
    let mut crowded: Vec<u32> = vertices
        .iter()
        .copied()
        .filter(|&v| near_hub.get(v as usize) == Some(&true))
        .collect();
    crowded.sort_unstable();
    crowded.dedup();
    let shared = if crowded.is_empty() {
        Vec::new()
    } else {
        shared_levels(mesh, &crowded, levels).unwrap_or_else(|| one_by_one(mesh, &crowded, levels))
    };
    vertices
        .par_iter()
        .map(|&v| match crowded.binary_search(&v) {
            Ok(i) => shared[i],
            Err(_) => butterfly_limit_normal(mesh, v, levels),
        })
        .collect()
}

fn one_by_one(mesh: &TriMesh, vertices: &[u32], levels: usize) -> Vec<Option<DVec3>> {
    vertices
        .par_iter()
        .map(|&v| butterfly_limit_normal(mesh, v, levels))
        .collect()
}

/// For each vertex, whether it is within [`FAN_REACH`] rings of a hub; empty when the mesh
/// has no hub. A breadth-first search from all hubs at once, each vertex expanded once.
fn near_hubs(mesh: &TriMesh) -> Vec<bool> {
    let topo = mesh.topology();
    let nv = mesh.vertex_count();
    let mut frontier: Vec<u32> = (0..nv as u32)
        .filter(|&u| topo.vertex_faces(u).len() >= HUB_VALENCE)
        .collect();
    if frontier.is_empty() {
        return Vec::new();
    }
    let mut near = vec![false; nv];
    for &u in &frontier {
        near[u as usize] = true;
    }
    for _ in 0..FAN_REACH {
        let mut next = Vec::new();
        for &u in &frontier {
            for f in topo.vertex_faces(u) {
                for w in mesh.triangles()[f as usize] {
                    if !near[w as usize] {
                        near[w as usize] = true;
                        next.push(w);
                    }
                }
            }
        }
        frontier = next;
    }
    near
}

/// The normals at `seeds` (distinct) through one cut-out holding all their neighbourhoods,
/// subdivided [`SHARED_LEVELS`] times; `None` when that cut-out cannot be subdivided.
fn shared_levels(mesh: &TriMesh, seeds: &[u32], levels: usize) -> Option<Vec<Option<DVec3>>> {
    let mut shared = cut_out(mesh, seeds).ok()?;
    let local: Vec<u32> = (0..seeds.len() as u32).collect();
    for _ in 0..SHARED_LEVELS {
        shared = step_around(&shared, &local)?;
    }
    let incidence = VertexFaces::of(shared.vertex_count(), shared.triangles());
    let around = |u: u32, out: &mut Vec<u32>| out.extend_from_slice(incidence.at(u));
    Some(
        local
            .par_iter()
            .map(|&at| {
                let mut own =
                    neighbourhood(shared.positions(), shared.triangles(), around, &[at], RINGS)
                        .ok()?;
                for _ in SHARED_LEVELS..levels {
                    own = step_around(&own, &[0])?;
                }
                area_weighted_normal(&own, 0)
            })
            .collect(),
    )
}

/// The unit area-weighted normal of vertex `v`'s faces; `None` when it vanishes.
fn area_weighted_normal(mesh: &TriMesh, v: u32) -> Option<DVec3> {
    let sum: DVec3 = mesh
        .topology()
        .vertex_faces(v)
        .map(|f| mesh.face_normal(f as usize))
        .sum();
    let l = sum.length();
    (l > 0.0 && l.is_finite()).then(|| sum / l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    #[test]
    fn butterfly_normal_of_a_plane_is_its_normal() {
        // A fan of six triangles in z = 2 with an irregular ring: every subdivision stays in
        // the plane.
        let p: Vec<DVec3> = [
            (0.0, 0.0),
            (1.0, 0.1),
            (0.6, 0.9),
            (-0.4, 1.1),
            (-1.2, 0.0),
            (-0.5, -0.8),
            (0.7, -1.0),
        ]
        .iter()
        .map(|&(x, y)| DVec3::new(x, y, 2.0))
        .collect();
        let t = (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        let mesh = TriMesh::new(p, t).unwrap();
        let n = butterfly_limit_normal(&mesh, 0, BUTTERFLY_NORMAL_LEVELS).unwrap();
        assert!((n - DVec3::Z).length() < 1e-12, "{n}");
    }

    /// The normal as it was computed: each level a full `butterfly_subdivide` (with its
    /// topology) and a cut-out through that topology.
    fn normal_through_whole_steps(mesh: &TriMesh, v: u32, levels: usize) -> Option<DVec3> {
        let mut local = cut_out(mesh, &[v]).ok()?;
        for _ in 0..levels {
            let fine = crate::subdivision::butterfly_subdivide(&local).ok()?.mesh;
            local = cut_out(&fine, &[0]).ok()?;
        }
        area_weighted_normal(&local, 0)
    }

    /// A torus with vertex 5 moved off it.
    fn jittered_torus(n: u32, m: u32) -> TriMesh {
        let torus = shapes::torus(n, m, 1.0, 0.4);
        let mut p = torus.positions().to_vec();
        p[5] += DVec3::new(0.05, -0.03, 0.04);
        TriMesh::new(p, torus.triangles().to_vec()).unwrap()
    }

    /// Cutting the finer mesh through its own vertex–face lists instead of its topology gives
    /// the same normal, bit for bit, at every vertex of an icosphere, a jittered torus (valence
    /// 6) and the bicone (valences 4 and 16).
    #[test]
    fn cut_outs_without_the_fine_topology_give_the_same_normal() {
        for mesh in [
            shapes::icosphere(1),
            jittered_torus(12, 8),
            shapes::bicone(16, 0.1),
        ] {
            for v in 0..mesh.vertex_count() as u32 {
                let got =
                    butterfly_limit_normal(&mesh, v, 3).map(|n| n.to_array().map(f64::to_bits));
                let want =
                    normal_through_whole_steps(&mesh, v, 3).map(|n| n.to_array().map(f64::to_bits));
                assert_eq!(got, want, "vertex {v}");
            }
        }
    }

    /// A closed tube of `n` segments and `rings` rings of side faces between two fans (the
    /// caps, whose centres have valence `n`), its radius varying along it and around it so
    /// that no two vertices are alike.
    fn capped_tube(n: u32, rings: u32) -> TriMesh {
        let mut p = Vec::new();
        for r in 0..=rings {
            let z = r as f64 / rings as f64 * 2.0 - 1.0;
            for i in 0..n {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                let radius = 1.0 + 0.1 * z * z + 0.03 * (3.0 * a).sin();
                p.push(DVec3::new(radius * a.cos(), radius * a.sin(), z));
            }
        }
        let (bottom, top) = (p.len() as u32, p.len() as u32 + 1);
        p.push(DVec3::new(0.02, 0.01, -1.1));
        p.push(DVec3::new(-0.01, 0.02, 1.1));
        let mut t = Vec::new();
        for r in 0..rings {
            for i in 0..n {
                let (a, b) = (r * n + i, r * n + (i + 1) % n);
                let (c, d) = ((r + 1) * n + (i + 1) % n, (r + 1) * n + i);
                t.push([a, b, c]);
                t.push([a, c, d]);
            }
        }
        for i in 0..n {
            t.push([bottom, (i + 1) % n, i]);
            t.push([top, rings * n + i, rings * n + (i + 1) % n]);
        }
        TriMesh::new(p, t).unwrap()
    }

    /// Near a hub the normals share their first levels, and they are the one-by-one normals
    /// up to rounding: the cut-outs number their points differently, and renumbering the
    /// mesh's vertices moves the one-by-one normals by as much (measured below).
    #[test]
    fn normals_near_a_hub_share_their_first_levels_and_agree() {
        // Rounding scale of these normals: renumbering the tube moves the one-by-one normals
        // by up to 6.2e-13 (eight levels of cross products of ever shorter edges amplify the
        // stencils' last-bit differences), and sharing moves them by 7.3e-13; 2e-12 leaves a
        // factor of ~3. A shared cut-out of one ring instead of four moves them by 3.8e-4.
        const ROUNDING: f64 = 2e-12;
        let mesh = capped_tube(80, 10);
        let nv = mesh.vertex_count() as u32;
        let near = near_hubs(&mesh);
        // The caps' rims and the two rings next to them, and the centres.
        assert_eq!(near.iter().filter(|&&x| x).count(), 2 + 2 * 3 * 80);
        let one: Vec<DVec3> = (0..nv)
            .map(|v| butterfly_limit_normal(&mesh, v, BUTTERFLY_NORMAL_LEVELS).unwrap())
            .collect();
        let renumber = |v: u32| (v * 37 + 11) % nv;
        let mut p = vec![DVec3::ZERO; nv as usize];
        for v in 0..nv {
            p[renumber(v) as usize] = mesh.positions()[v as usize];
        }
        let t = mesh.triangles().iter().rev();
        let t = t.map(|t| [renumber(t[1]), renumber(t[2]), renumber(t[0])]);
        let renumbered = TriMesh::new(p, t.collect()).unwrap();
        let noise = (0..nv)
            .map(|v| {
                let n = butterfly_limit_normal(&renumbered, renumber(v), BUTTERFLY_NORMAL_LEVELS);
                (n.unwrap() - one[v as usize]).length()
            })
            .fold(0.0, f64::max);
        assert!(noise > 0.0 && noise <= ROUNDING, "renumbering: {noise:e}");
        // All the vertices, every seventh (the shared cut-out has a boundary of its own),
        // one rim vertex, and repeats with an id out of range.
        let all: Vec<u32> = (0..nv).collect();
        let every_seventh: Vec<u32> = (0..nv).step_by(7).collect();
        for list in [&all[..], &every_seventh[..], &[85], &[5, 7, 5, nv]] {
            let together = butterfly_limit_normals(&mesh, list, BUTTERFLY_NORMAL_LEVELS);
            let mut worst = 0.0f64;
            for (&v, n) in list.iter().zip(&together) {
                match one.get(v as usize) {
                    Some(want) => worst = worst.max((n.unwrap() - *want).length()),
                    None => assert_eq!(*n, None, "vertex {v} is out of range"),
                }
            }
            assert!(worst <= ROUNDING, "{} vertices: {worst:e}", list.len());
        }
        // Below the hub valence nothing is shared: the bits are the one-by-one ones.
        let small = capped_tube(40, 6);
        assert!(near_hubs(&small).is_empty());
        let all: Vec<u32> = (0..small.vertex_count() as u32).collect();
        let together = butterfly_limit_normals(&small, &all, 3);
        for &v in &all {
            assert_eq!(together[v as usize], butterfly_limit_normal(&small, v, 3));
        }
    }

    #[test]
    fn butterfly_normal_converges() {
        // The change in direction between the last two levels, on a sphere-like mesh with
        // valences 5 and 6 and on a torus with a jittered vertex.
        for (mesh, v) in [(shapes::icosphere(1), 20), (jittered_torus(24, 16), 5)] {
            let a = butterfly_limit_normal(&mesh, v, BUTTERFLY_NORMAL_LEVELS - 1).unwrap();
            let b = butterfly_limit_normal(&mesh, v, BUTTERFLY_NORMAL_LEVELS).unwrap();
            let angle = a.dot(b).clamp(-1.0, 1.0).acos();
            assert!(angle < 2e-3, "vertex {v}: {angle} rad");
        }
    }

    #[test]
    fn loop_butterfly_takes_butterfly_only_at_steep_vertices() {
        use crate::{NormalMethod, STEEP_NORMAL_DEGREES, vertex_normals};
        // No vertex of an icosphere is steep: the hybrid is the Loop normal, bit for bit.
        let sphere = shapes::icosphere(2);
        assert_eq!(
            vertex_normals(&sphere, NormalMethod::LoopButterfly).unwrap(),
            vertex_normals(&sphere, NormalMethod::Loop).unwrap()
        );
        // The bicone's rim vertices are 84° off their faces with Loop normals.
        let bicone = shapes::bicone(16, 0.1);
        let looped = vertex_normals(&bicone, NormalMethod::Loop).unwrap();
        let hybrid = vertex_normals(&bicone, NormalMethod::LoopButterfly).unwrap();
        let steep = STEEP_NORMAL_DEGREES.to_radians().cos();
        let mut changed = 0;
        for v in 0..bicone.vertex_count() as u32 {
            let n = looped[v as usize];
            let expected = if crate::normals::worst_face_cosine(&bicone, v, n) < steep {
                changed += 1;
                butterfly_limit_normal(&bicone, v, BUTTERFLY_NORMAL_LEVELS).unwrap()
            } else {
                n
            };
            assert_eq!(hybrid[v as usize], expected, "vertex {v}");
        }
        assert!(changed > 0);
    }
}
