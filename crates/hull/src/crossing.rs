//! Where the input mesh passes through itself: overlaps no refinement can remove.
//!
//! Refinement separates two tetrahedra by shrinking them towards their faces (§3.1): their
//! heights scale with the faces' widths, so faces a positive distance apart end up with
//! disjoint tetrahedra. Faces that pass through each other ([`algesurf_mesh::self_intersections`])
//! are at distance zero, and so are the faces around them: every refinement of the
//! neighbourhood still has tetrahedra on both sheets that overlap along the crossing curve.
//! Those overlaps are the input's, exactly like those between two separate surfaces that meet
//! (the Utah teapot's spout through its body): they are left and reported
//! ([`crate::SimplicialHull::distant_intersections`]), and each patch is still evaluated in its
//! own tetrahedra, so the surface follows the input there, through itself where the input
//! is. The cow's ears pass through its head: 72 crossing face pairs.
//!
//! The zone is taken two rings wide around each crossing face: the faces next to a crossing
//! face reach the other sheet within a face width too, so their tetrahedra meet the other
//! sheet's as well.

use algesurf_mesh::{TriMesh, self_intersections};
use std::collections::HashSet;

/// The crossings of the input mesh and the face pairs around them.
#[derive(Clone, Debug, Default)]
pub(crate) struct CrossingZone {
    crossings: Vec<[u32; 2]>,
    /// Unordered input face pairs `(f′, g′)`, `f′` within two rings of `f` and `g′` of `g`,
    /// for every crossing `(f, g)`.
    pairs: HashSet<[u32; 2]>,
}

fn key(a: u32, b: u32) -> [u32; 2] {
    if a < b { [a, b] } else { [b, a] }
}

impl CrossingZone {
    /// The crossing zone of `mesh` (the input mesh, before refinement).
    pub(crate) fn new(mesh: &TriMesh) -> CrossingZone {
        let topo = mesh.topology();
        // The faces within two rings of a face: the faces of its corners, then the faces
        // sharing a vertex with any of them.
        let rings = |f: u32| -> Vec<u32> {
            let mut r: Vec<u32> = mesh.triangles()[f as usize]
                .iter()
                .flat_map(|&v| topo.vertex_faces(v))
                .flat_map(|g| mesh.triangles()[g as usize])
                .flat_map(|v| topo.vertex_faces(v))
                .collect();
            r.sort_unstable();
            r.dedup();
            r
        };
        let crossings = self_intersections(mesh);
        let mut pairs = HashSet::new();
        for &[f, g] in &crossings {
            let rg = rings(g);
            for a in rings(f) {
                for &b in &rg {
                    if a != b {
                        pairs.insert(key(a, b));
                    }
                }
            }
        }
        CrossingZone { crossings, pairs }
    }

    /// The crossing input face pairs, ascending.
    pub(crate) fn crossings(&self) -> &[[u32; 2]] {
        &self.crossings
    }

    /// Whether input faces `a` and `b` lie around the two sheets of one crossing.
    pub(crate) fn contains(&self, a: u32, b: u32) -> bool {
        self.pairs.contains(&key(a, b))
    }
}
