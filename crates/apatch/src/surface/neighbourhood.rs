//! The neighbourhood of a face that its quadric is fitted to (the default free parameters,
//! Theorem 4.2 and Corollary 4.3 of Xu–Huang–Bajaj 2001).

use algesurf_mesh::TriMesh;
use glam::DVec3;

/// The vertex ids met so far by [`neighbourhood`], which keeps them in the order met (the
/// quadric fit sums over them in that order). Open addressing in 128 slots: a face's
/// neighbourhood has about 15 vertices, met ~55 times, and scanning the list for each was
/// 5 % of the bunny's function stage. Past 64 ids (a vertex of valence 40 or so) the ids go
/// to a hash set instead, so it is right, and linear, for any size: scanning the list there
/// made a face at a vertex of valence `k` cost O(k²), and a capped cylinder of 4096
/// segments (two fans of valence 4096) spent 4.4 s in its function stage.
pub(super) struct SmallVertexSet {
    slots: [u32; 128],
    len: usize,
    overflow: Option<algesurf_mesh::fasthash::FastSet<u32>>,
}

impl SmallVertexSet {
    const EMPTY: u32 = u32::MAX;

    fn new() -> Self {
        SmallVertexSet {
            slots: [Self::EMPTY; 128],
            len: 0,
            overflow: None,
        }
    }

    /// Whether `w` is new (not in `listed`, the ids inserted so far in order); records it.
    fn insert(&mut self, w: u32, listed: &[u32]) -> bool {
        if w == Self::EMPTY {
            return !listed.contains(&w);
        }
        if self.len >= 64 {
            // Every id listed so far, then the new ones as they come.
            return self
                .overflow
                .get_or_insert_with(|| listed.iter().copied().collect())
                .insert(w);
        }
        // Fibonacci hashing: the top 7 bits of w·φ⁻¹·2³².
        let mut i = (w.wrapping_mul(0x9E37_79B9) >> 25) as usize;
        loop {
            match self.slots[i] {
                x if x == w => return false,
                Self::EMPTY => {
                    self.slots[i] = w;
                    self.len += 1;
                    return true;
                }
                _ => i = (i + 1) & 127,
            }
        }
    }
}

/// Vertices of the face and of every face touching its vertices, with their gradients.
pub(super) fn neighbourhood(mesh: &TriMesh, grads: &[DVec3], f: usize) -> Vec<(DVec3, DVec3)> {
    let topo = mesh.topology();
    let mut verts: Vec<u32> = Vec::with_capacity(16);
    let mut seen = SmallVertexSet::new();
    for &v in &mesh.triangles()[f] {
        for g in topo.vertex_faces(v) {
            for &w in &mesh.triangles()[g as usize] {
                if seen.insert(w, &verts) {
                    verts.push(w);
                }
            }
        }
    }
    verts
        .iter()
        .map(|&v| (mesh.positions()[v as usize], grads[v as usize]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::SmallVertexSet;
    use algesurf_mesh::test_rng::Lcg;

    /// The set answers as a scan of the list would, below and past its 64 hashed ids (where
    /// a hash set takes over), with ids that collide in the table (multiples of 2²⁵ share
    /// their top bits' hash) and the table's empty marker.
    #[test]
    fn small_vertex_set_answers_as_a_scan_of_the_list() {
        let mut rng = Lcg(11);
        for (case, range) in [(0, 20.0), (1, 200.0), (2, 5000.0)] {
            let mut set = SmallVertexSet::new();
            let mut listed: Vec<u32> = Vec::new();
            for k in 0..400 {
                let w = if k % 50 == 3 {
                    // The table's empty marker, before and past the hashed part.
                    u32::MAX
                } else if k % 7 == 0 {
                    (k as u32 % 5) << 25
                } else {
                    (rng.next() * range) as u32
                };
                let new = !listed.contains(&w);
                assert_eq!(set.insert(w, &listed), new, "case {case}, step {k}, id {w}");
                if new {
                    listed.push(w);
                }
            }
            if case > 0 {
                assert!(listed.len() > 64, "case {case} passes the hashed part");
            }
        }
    }
}
