//! Narrow flat regions: the long boundary edges of a strip split where it meets another flat
//! region, so that the strip can be triangulated into well-shaped faces.
//!
//! Why: [`super::remesh_flat_regions`] keeps a region's boundary, so a strip narrower than its
//! boundary edges are long (the side wall of a thin plate: 1 × 0.02, two triangles of 1.1°)
//! has no better triangulation, and the simplicial hull's refinement fails there: a
//! 2 × 2 × 0.02 plate does not build with any normals. Its long edges lie between two flat
//! regions (the wall and the plate's large side), so points can be put on them without
//! changing the surface: each new point lies on the straight edge, in both regions' planes,
//! and both regions are retriangulated with it on their boundaries. A plate whose walls are
//! cut into squares builds without refinement (`docs/ARCHITECTURE.md`, "Thin plates").
//! Off by default ([`super::FlatRemeshOptions::split_narrow_strips`]): on meshes that build
//! as they are (a coin's rim, a box of one quad a side) it only multiplies the faces.

use super::FlatRegion;
use crate::TriMesh;
use crate::fasthash::FastMap;
use glam::DVec3;

/// A boundary edge of a face that stays skinny after remeshing is split when it is longer than
/// this many times the face's height over it (the strip's width there), into
/// `ceil(length / height)` pieces ([`splits`]).
///
/// Why 2: an edge of at most twice the width makes faces across the strip with angles of
/// `atan(1/2)` = 26.6° or more, above the remesher's 25°
/// ([`super::DEFAULT_REMESH_MIN_ANGLE_DEGREES`]); pieces no longer than the width make them 45°
/// or more.
pub const NARROW_RATIO: f64 = 2.0;

/// The most pieces one edge is split into. It bounds the vertices added for a strip far
/// narrower than long: at this bound a strip 1000 times narrower than long gets pieces four
/// widths long, whose faces have angles of 14° or more, still above the 10° skinny limit
/// ([`super::DEFAULT_SKINNY_ANGLE_DEGREES`]).
pub const MAX_PIECES: u32 = 256;

/// The points put on split edges, numbered after the mesh's vertices.
#[derive(Clone, Debug, Default)]
pub(super) struct EdgeSplits {
    /// The id of the first split point (the mesh's vertex count).
    pub base: u32,
    /// Positions of the points `base..`.
    pub positions: Vec<DVec3>,
    /// For each split edge (its vertex ids, lower first): the id of its first point and its
    /// number of pieces; its points run from the lower id's end to the higher's.
    edges: FastMap<[u32; 2], (u32, u32)>,
    /// For each flat region, whether one of its boundary edges is split.
    pub touched: Vec<bool>,
}

impl EdgeSplits {
    /// No splits (for a mesh of `base` vertices and `regions` regions).
    pub fn none(base: u32, regions: usize) -> EdgeSplits {
        EdgeSplits {
            base,
            positions: Vec::new(),
            edges: FastMap::default(),
            touched: vec![false; regions],
        }
    }

    /// True when no edge is split.
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty()
    }

    /// How many edges are split.
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// The vertices of the directed edge `a → b` in order, `a` and `b` included (just the two
    /// when it is not split).
    pub fn chain(&self, a: u32, b: u32) -> Vec<u32> {
        let key = [a.min(b), a.max(b)];
        let Some(&(first, pieces)) = self.edges.get(&key) else {
            return vec![a, b];
        };
        let mut out = Vec::with_capacity(pieces as usize + 1);
        out.push(key[0]);
        out.extend(first..first + pieces - 1);
        out.push(key[1]);
        if a > b {
            out.reverse();
        }
        out
    }

    /// The position of vertex `v`: the mesh's, or a split point's.
    pub fn position(&self, p: &[DVec3], v: u32) -> DVec3 {
        match v.checked_sub(self.base) {
            Some(i) => self.positions[i as usize],
            None => p[v as usize],
        }
    }

    /// Every split edge with the id of its first point and its number of pieces, in the
    /// order of the points.
    pub fn edges(&self) -> Vec<([u32; 2], u32, u32)> {
        let mut out: Vec<([u32; 2], u32, u32)> =
            self.edges.iter().map(|(&k, &(f, n))| (k, f, n)).collect();
        out.sort_unstable_by_key(|e| e.1);
        out
    }

    /// The split points on the boundary `edges` (directed, of one region).
    pub fn points_on(&self, edges: &[[u32; 2]]) -> u32 {
        edges
            .iter()
            .filter_map(|&[a, b]| self.edges.get(&[a.min(b), a.max(b)]))
            .map(|&(_, pieces)| pieces - 1)
            .sum()
    }
}

/// The interior angle of each region's boundary corners, `(region, vertex) → angle` (the
/// least where a vertex is a corner twice): the angle between a corner's incoming and outgoing
/// boundary edges on the region's side, seen along the region's normal.
fn corner_angles(
    p: &[DVec3],
    regions: &[FlatRegion],
    boundaries: &[Vec<[u32; 2]>],
) -> FastMap<(usize, u32), f64> {
    let mut out: FastMap<(usize, u32), f64> = FastMap::default();
    for (r, boundary) in boundaries.iter().enumerate() {
        let next: FastMap<u32, u32> = boundary.iter().map(|&[a, b]| (a, b)).collect();
        let n = regions[r].normal;
        for &[u, v] in boundary {
            let Some(&w) = next.get(&v) else { continue };
            let (a, b) = (p[w as usize] - p[v as usize], p[u as usize] - p[v as usize]);
            // Counter-clockwise about `n` from the outgoing edge to the incoming one: the
            // region lies on the left of its directed boundary.
            let angle = n
                .dot(a.cross(b))
                .atan2(a.dot(b))
                .rem_euclid(std::f64::consts::TAU);
            let slot = out.entry((r, v)).or_insert(f64::INFINITY);
            *slot = slot.min(angle);
        }
    }
    out
}

/// The splits that make the narrow strips among `regions` of `mesh` triangulable into
/// well-shaped faces, read off `plain`, the mesh remeshed without splits (`face_map`: its
/// faces' faces in `mesh`); `boundaries[r]` is region `r`'s directed boundary edges.
///
/// A face of `plain` in a region that is still skinny (an angle below `skinny`, radians) after
/// the remeshing without splits owes it to the region's boundary, which that remeshing keeps.
/// Where its smallest angle is not the region's own corner (a wedge that no split widens),
/// each of its edges on the region's boundary that is more than [`NARROW_RATIO`] times longer
/// than the face's height over it asks to be split into `ceil(length / height)` pieces (at most
/// [`MAX_PIECES`]). An edge is split, into the most pieces asked for, when it lies between two
/// flat regions (two faces) whose normals differ by more than `crease` degrees (at 0 every
/// edge between two flat regions: [`super::FlatRemeshOptions::split_narrow_strips`]); the
/// mesh's own boundary is never split (an open mesh keeps its boundary, edge for edge). Points
/// are numbered in the order of the edges' sorted vertex ids, so the result depends on the
/// mesh alone.
pub(super) fn splits(
    mesh: &TriMesh,
    plain: &TriMesh,
    face_map: &[u32],
    regions: &[FlatRegion],
    boundaries: &[Vec<[u32; 2]>],
    skinny: f64,
    crease: f64,
) -> EdgeSplits {
    let p = mesh.positions();
    let base = mesh.vertex_count() as u32;
    let mut out = EdgeSplits::none(base, regions.len());
    let mut region_of = vec![usize::MAX; mesh.face_count()];
    for (r, region) in regions.iter().enumerate() {
        for &f in &region.faces {
            region_of[f as usize] = r;
        }
    }
    // Which regions have each boundary edge (undirected) on their boundary.
    let mut sides: FastMap<[u32; 2], Vec<usize>> = FastMap::default();
    for (r, boundary) in boundaries.iter().enumerate() {
        for &[a, b] in boundary {
            sides.entry([a.min(b), a.max(b)]).or_default().push(r);
        }
    }
    let corners = corner_angles(p, regions, boundaries);
    let q = plain.positions();
    let mut wanted: FastMap<[u32; 2], u32> = FastMap::default();
    for (f, t) in plain.triangles().iter().enumerate() {
        let r = region_of[face_map[f] as usize];
        if r == usize::MAX {
            continue;
        }
        let x = t.map(|v| q[v as usize]);
        let angles: [f64; 3] = std::array::from_fn(|k| {
            let (u, w) = (x[(k + 1) % 3] - x[k], x[(k + 2) % 3] - x[k]);
            u.angle_between(w)
        });
        let least = (0..3)
            .min_by(|&i, &j| angles[i].total_cmp(&angles[j]))
            .expect("three");
        // A NaN angle (a degenerate face) is not skinny here: nothing to split for it.
        let is_skinny = angles[least] < skinny;
        if !is_skinny
            || corners
                .get(&(r, t[least]))
                .is_some_and(|&corner| corner < skinny)
        {
            continue;
        }
        let area2 = (x[1] - x[0]).cross(x[2] - x[0]).length();
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = [a.min(b), a.max(b)];
            if key[1] >= base || !sides.get(&key).is_some_and(|on| on.contains(&r)) {
                continue;
            }
            let l = x[k].distance(x[(k + 1) % 3]);
            let height = area2 / l;
            if l > NARROW_RATIO * height {
                let pieces = (l / height).ceil().min(f64::from(MAX_PIECES)) as u32;
                let slot = wanted.entry(key).or_insert(0);
                *slot = (*slot).max(pieces);
            }
        }
    }
    if wanted.is_empty() {
        return out;
    }
    let mut faces: FastMap<[u32; 2], u32> = FastMap::default();
    for t in mesh.triangles() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = [a.min(b), a.max(b)];
            if wanted.contains_key(&key) {
                *faces.entry(key).or_insert(0) += 1;
            }
        }
    }
    // At 0° the normals' cosine is at most 1: every pair of distinct regions qualifies.
    let crease = if crease > 0.0 {
        crease.to_radians().cos()
    } else {
        f64::INFINITY
    };
    let mut keys: Vec<([u32; 2], u32)> = wanted
        .into_iter()
        .filter(|(key, _)| {
            let on = sides.get(key).map_or(&[][..], Vec::as_slice);
            match (faces.get(key).copied().unwrap_or(0), on) {
                (2, &[r, s]) => r != s && regions[r].normal.dot(regions[s].normal) < crease,
                _ => false,
            }
        })
        .collect();
    keys.sort_unstable();
    for (key, pieces) in keys {
        let (a, b) = (p[key[0] as usize], p[key[1] as usize]);
        let first = base + out.positions.len() as u32;
        out.positions
            .extend((1..pieces).map(|i| a + (b - a) * (f64::from(i) / f64::from(pieces))));
        out.edges.insert(key, (first, pieces));
        for &r in &sides[&key] {
            out.touched[r] = true;
        }
    }
    out
}
