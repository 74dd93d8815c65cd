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

/// The faces within `rings` rings of vertex `v` of the triangles `triangles` over
/// `positions`, as a mesh of their own, and `v`'s id in it. `vertex_faces(u, out)` appends the
/// faces at vertex `u` in increasing id order (`Topology::vertex_faces`' order), which
/// fixes the numbering of the cut-out.
fn neighbourhood(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    vertex_faces: impl Fn(u32, &mut Vec<u32>),
    v: u32,
    rings: usize,
) -> Result<(TriMesh, u32), MeshError> {
    // Fast hashes: only looked up, never iterated, so the cut-out is the same as with any.
    let mut local = FastMap::default();
    local.insert(v, 0u32);
    let mut order = vec![v];
    let mut frontier = vec![v];
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
    Ok((TriMesh::new(positions, triangles)?, 0))
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
    let (mut local, mut at) = cut_out(mesh, v).ok()?;
    for _ in 0..levels {
        // One Butterfly step of the cut-out (`butterfly_subdivide`) without the topology of
        // the whole finer mesh, of which only the faces around `at` are needed: that
        // topology was a third of the normal's work. The finer mesh cannot fail it (three
        // distinct ids per face, from a mesh that passed). Old vertices keep their ids
        // through a step, so `at` stays valid.
        let points = butterfly_edge_points(&local).ok()?;
        let (positions, triangles, _) =
            split_triangles(&local, local.positions().to_vec(), &points);
        let incidence = VertexFaces::of(positions.len(), &triangles);
        let around = |u: u32, out: &mut Vec<u32>| out.extend_from_slice(incidence.at(u));
        (local, at) = neighbourhood(&positions, &triangles, around, at, RINGS).ok()?;
    }
    area_weighted_normal(&local, at)
}

/// [`neighbourhood`] of vertex `v` of a mesh, through its topology.
fn cut_out(mesh: &TriMesh, v: u32) -> Result<(TriMesh, u32), MeshError> {
    let topo = mesh.topology();
    let around = |u: u32, out: &mut Vec<u32>| out.extend(topo.vertex_faces(u));
    neighbourhood(mesh.positions(), mesh.triangles(), around, v, RINGS)
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
        let (mut local, mut at) = cut_out(mesh, v).ok()?;
        for _ in 0..levels {
            let fine = crate::subdivision::butterfly_subdivide(&local).ok()?.mesh;
            (local, at) = cut_out(&fine, at).ok()?;
        }
        area_weighted_normal(&local, at)
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
