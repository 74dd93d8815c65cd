//! Repair steps for meshes as found in the wild. Each step is optional ([`RepairOptions`]),
//! and [`repair`] reports what every step changed, with ids in the input order and maps from
//! the output back to the input.

use crate::fasthash::{FaceKey, FastMap, FastSet};
use crate::geometry::{
    Aabb, exact_scale_exponent, newell_normal, power_of_two, scale_by_power_of_two, signed_volume,
};
use crate::topology::Topology;
use crate::triangulate::triangulate_polygon;
use crate::validate::DEFAULT_DEGENERATE_AREA;
use crate::{MeshError, PolygonMesh, Property, PropertyValues};
use glam::DVec3;
use rayon::prelude::*;
use std::fmt;

/// Default weld tolerance relative to the bounding-box diagonal.
///
/// Why `1e-9`: duplicated vertices in files (one copy per patch, per face or per corner) are
/// written from the same value and are bit-equal or differ by f64 arithmetic noise
/// (`~1e-16` relative, amplified a little by transforms). `1e-9 * diagonal` merges those
/// while staying far below any real feature: distinct vertices that close would need a mesh
/// with ~10^18 triangles. For float32 files whose duplicates were rounded independently,
/// raise it to about `1e-6` (float32 resolution is `6e-8` of the coordinate).
pub const DEFAULT_WELD_TOLERANCE: f64 = 1e-9;

/// Which repair steps [`repair`] performs. `Default` enables all of them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RepairOptions {
    /// Weld vertices closer than `tolerance * bounding-box diagonal` (`None`: no welding;
    /// `Some(0.0)`: merge bit-identical positions only). Default
    /// `Some(`[`DEFAULT_WELD_TOLERANCE`]`)`.
    pub weld_tolerance: Option<f64>,
    /// Split polygons with more than three corners by ear clipping. Default `true`.
    pub triangulate: bool,
    /// Drop faces whose area is at most `degenerate_area * diagonal²`. Default `true`.
    pub drop_degenerate_faces: bool,
    /// Relative area threshold for degenerate faces (see [`DEFAULT_DEGENERATE_AREA`]).
    pub degenerate_area: f64,
    /// Drop faces with the same vertex set as an earlier face. Default `true`.
    pub drop_duplicate_faces: bool,
    /// Drop vertices that no face uses. Default `true`.
    pub drop_unused_vertices: bool,
    /// Make the mesh manifold without dropping faces: every vertex with more than one fan
    /// of faces (faces are joined into a fan across edges with exactly two faces) keeps its
    /// first fan and gets a new copy, with the same position, normal and properties, for
    /// each further fan. Because fans never cross an edge with more than two faces, this
    /// also detaches the faces of every non-manifold edge from each other: afterwards each
    /// edge has at most two faces, and two faces stay joined along a former non-manifold
    /// edge only when they are in the same fan at both of its endpoints. Runs after
    /// duplicate-face removal (so doubled faces are dropped rather than detached) and before
    /// orientation. Default `true`.
    pub split_non_manifold_vertices: bool,
    /// Orient faces consistently per component, outward (positive signed volume) for closed
    /// manifold components; open components keep the orientation of the majority of their
    /// faces. Default `true`.
    pub orient: bool,
    /// After orientation, flip the longest edge of every *folded cap*: a triangle with an
    /// angle above 150° whose normal points against its neighbour across that edge (a corner
    /// pushed through the opposite edge, common in scans). Vertices stay; only the two faces'
    /// connectivity changes, and only when both new triangles face the neighbour's side.
    /// Default `true`.
    pub flip_folded_caps: bool,
    /// Then move every *folded* vertex — one whose triangles' normals fit in no cone of
    /// half-angle `acos(DEFAULT_MIN_NORMAL_COSINE)` = 84°, so no vertex normal is well on the
    /// positive side of all its faces (the rim of a thin flap whose sides cross, a crease
    /// turned back on itself) — the least distance towards its neighbours' centroid that
    /// opens its and its neighbours' faces to that cone. Smooth surfaces through the mesh
    /// (A-patches, §3 of Xu–Huang–Bajaj 2001) need this; it changes the data, so each move is
    /// reported with its distance. Default `true`.
    pub unfold_vertices: bool,
}

impl RepairOptions {
    /// Checks the ranges: `weld_tolerance` (when welding) and `degenerate_area` finite and
    /// `≥ 0`. A NaN or negative value would silently switch its step off, and an infinite
    /// weld tolerance would merge every vertex into one. [`repair`] calls it first.
    ///
    /// ```
    /// use algesurf_mesh::RepairOptions;
    /// assert!(RepairOptions::default().validate().is_ok());
    /// let bad = RepairOptions { weld_tolerance: Some(f64::NAN), ..RepairOptions::default() };
    /// assert!(bad.validate().unwrap_err().to_string().contains("weld_tolerance"));
    /// ```
    ///
    /// # Errors
    /// [`MeshError::InvalidOption`] naming the option.
    pub fn validate(&self) -> Result<(), MeshError> {
        let weld = self.weld_tolerance.unwrap_or(0.0);
        for (name, x) in [
            ("weld_tolerance", weld),
            ("degenerate_area", self.degenerate_area),
        ] {
            if !(x >= 0.0 && x.is_finite()) {
                return Err(MeshError::InvalidOption(format!(
                    "{name} = {x} must be finite and ≥ 0"
                )));
            }
        }
        Ok(())
    }
}

impl Default for RepairOptions {
    fn default() -> Self {
        RepairOptions {
            weld_tolerance: Some(DEFAULT_WELD_TOLERANCE),
            triangulate: true,
            drop_degenerate_faces: true,
            degenerate_area: DEFAULT_DEGENERATE_AREA,
            drop_duplicate_faces: true,
            drop_unused_vertices: true,
            split_non_manifold_vertices: true,
            orient: true,
            flip_folded_caps: true,
            unfold_vertices: true,
        }
    }
}

/// What [`repair`] changed. All ids are input ids unless said otherwise.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RepairReport {
    /// Faces dropped because they could not be kept at all: an index out of range, fewer than
    /// three corners, or a corner at a vertex with non-finite coordinates.
    pub dropped_invalid_faces: Vec<u32>,
    /// Welded vertices: `(vertex, the vertex it was merged into)`.
    pub welded: Vec<(u32, u32)>,
    /// Faces dropped because, after welding, they had fewer than three distinct corners or
    /// used a vertex twice.
    pub collapsed_faces: Vec<u32>,
    /// Polygons split into triangles.
    pub triangulated_faces: Vec<u32>,
    /// Faces (or triangles of a split polygon) dropped as degenerate.
    pub dropped_degenerate_faces: Vec<u32>,
    /// Faces dropped as duplicates of an earlier face.
    pub dropped_duplicate_faces: Vec<u32>,
    /// Edges with more than two faces (as pairs of input vertex ids, after welding) whose
    /// faces were detached from each other by [`RepairOptions::split_non_manifold_vertices`].
    pub detached_non_manifold_edges: Vec<[u32; 2]>,
    /// Vertices split by [`RepairOptions::split_non_manifold_vertices`]:
    /// `(input vertex, number of fans)`; the vertex keeps its first fan and each further fan
    /// gets a new output vertex (appended after the others, and mapped back to the input
    /// vertex by [`RepairReport::vertex_map`]).
    pub split_vertices: Vec<(u32, u32)>,
    /// Faces whose orientation was reversed.
    pub flipped_faces: Vec<u32>,
    /// Longest edges of folded caps flipped by [`RepairOptions::flip_folded_caps`] (input
    /// vertex ids, after welding).
    pub flipped_cap_edges: Vec<[u32; 2]>,
    /// Folded vertices moved by [`RepairOptions::unfold_vertices`]: `(output vertex, distance
    /// moved)`.
    pub moved_vertices: Vec<(u32, f64)>,
    /// Number of components that cannot be oriented consistently (Möbius-like); their faces
    /// are consistent along a spanning tree only.
    pub non_orientable_components: usize,
    /// Vertices dropped because no face used them (welded-away vertices are not listed here).
    pub dropped_unused_vertices: Vec<u32>,
    /// For each output vertex, the input vertex it comes from.
    pub vertex_map: Vec<u32>,
    /// For each output face, the input face it comes from.
    pub face_map: Vec<u32>,
}

impl RepairReport {
    /// True when the output differs from the input in anything but numbering.
    pub fn changed(&self) -> bool {
        !(self.dropped_invalid_faces.is_empty()
            && self.welded.is_empty()
            && self.collapsed_faces.is_empty()
            && self.triangulated_faces.is_empty()
            && self.dropped_degenerate_faces.is_empty()
            && self.dropped_duplicate_faces.is_empty()
            && self.detached_non_manifold_edges.is_empty()
            && self.split_vertices.is_empty()
            && self.flipped_faces.is_empty()
            && self.flipped_cap_edges.is_empty()
            && self.moved_vertices.is_empty()
            && self.dropped_unused_vertices.is_empty())
    }

    /// For each input vertex, its output vertex (`None` when dropped). Welded vertices map to
    /// the output vertex of the vertex they were merged into; a split vertex maps to the copy
    /// that kept its first fan (the lowest output id).
    pub fn input_to_output_vertices(&self, input_vertex_count: usize) -> Vec<Option<u32>> {
        let mut out = vec![None; input_vertex_count];
        for (o, &i) in self.vertex_map.iter().enumerate() {
            if let Some(x) = out.get_mut(i as usize)
                && x.is_none()
            {
                *x = Some(o as u32);
            }
        }
        for &(v, r) in &self.welded {
            let target = out.get(r as usize).copied().flatten();
            if let Some(x) = out.get_mut(v as usize) {
                *x = target;
            }
        }
        out
    }
}

fn ids(f: &mut fmt::Formatter<'_>, what: &str, v: &[u32]) -> fmt::Result {
    list(f, what, v.iter().map(|x| x.to_string()))
}

fn list(
    f: &mut fmt::Formatter<'_>,
    what: &str,
    items: impl ExactSizeIterator<Item = String>,
) -> fmt::Result {
    let n = items.len();
    if n == 0 {
        return Ok(());
    }
    const SHOW: usize = 20;
    let shown: Vec<String> = items.take(SHOW).collect();
    write!(f, "{what}: {n} [{}", shown.join(", "))?;
    if n > SHOW {
        write!(f, ", ...")?;
    }
    writeln!(f, "]")
}

impl fmt::Display for RepairReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.changed() {
            return writeln!(f, "no repairs needed");
        }
        ids(f, "dropped invalid faces", &self.dropped_invalid_faces)?;
        let welded: Vec<u32> = self.welded.iter().map(|w| w.0).collect();
        ids(f, "welded vertices", &welded)?;
        ids(f, "collapsed faces", &self.collapsed_faces)?;
        ids(f, "triangulated polygons", &self.triangulated_faces)?;
        ids(
            f,
            "dropped degenerate faces",
            &self.dropped_degenerate_faces,
        )?;
        ids(f, "dropped duplicate faces", &self.dropped_duplicate_faces)?;
        list(
            f,
            "detached faces along non-manifold edges",
            self.detached_non_manifold_edges
                .iter()
                .map(|[a, b]| format!("({a}, {b})")),
        )?;
        list(
            f,
            "split non-manifold vertices",
            self.split_vertices
                .iter()
                .map(|(v, n)| format!("{v} into {n}")),
        )?;
        ids(f, "flipped faces", &self.flipped_faces)?;
        list(
            f,
            "flipped edges of folded caps",
            self.flipped_cap_edges
                .iter()
                .map(|[a, b]| format!("({a}, {b})")),
        )?;
        list(
            f,
            "moved folded vertices (output id by distance)",
            self.moved_vertices
                .iter()
                .map(|(v, d)| format!("{v} by {d:.3e}")),
        )?;
        ids(f, "dropped unused vertices", &self.dropped_unused_vertices)?;
        if self.non_orientable_components > 0 {
            writeln!(
                f,
                "non-orientable components: {}",
                self.non_orientable_components
            )?;
        }
        Ok(())
    }
}

/// The output of [`repair`].
#[derive(Clone, Debug)]
pub struct Repaired {
    /// The repaired mesh (positions, faces, and the input's normals and properties carried
    /// through the vertex and face maps).
    pub mesh: PolygonMesh,
    /// What changed.
    pub report: RepairReport,
}

/// Welds vertices of `positions` within `tolerance` (absolute distance) using a spatial hash
/// grid with cells of size `tolerance` (so only the 27 neighbouring cells are searched):
/// returns, for each vertex, the vertex it is merged into (itself for representatives).
/// Vertices are scanned in order and each joins the lowest-numbered representative within
/// reach, so the result is deterministic. Non-finite positions are never merged.
pub fn weld_map(positions: &[DVec3], tolerance: f64) -> Vec<u32> {
    let mut rep: Vec<u32> = (0..positions.len() as u32).collect();
    if tolerance > 0.0 && tolerance.is_finite() {
        let inv = 1.0 / tolerance;
        let cell = |p: DVec3| -> [i64; 3] {
            [
                (p.x * inv).floor() as i64,
                (p.y * inv).floor() as i64,
                (p.z * inv).floor() as i64,
            ]
        };
        // Each occupied cell holds a linked list of its representatives: `grid` maps the cell
        // to the last one added, `next_in_cell` links to the one added before (the scan
        // takes the lowest id within reach, so the order within a cell does not matter).
        // This avoids one heap vector per cell; the fast hasher is exact (see `fasthash`).
        let mut grid: FastMap<[i64; 3], u32> = FastMap::default();
        grid.reserve(positions.len());
        let mut next_in_cell: Vec<u32> = vec![u32::MAX; positions.len()];
        let t2 = tolerance * tolerance;
        for (v, &p) in positions.iter().enumerate() {
            if !p.is_finite() {
                continue;
            }
            let c = cell(p);
            let mut best: Option<u32> = None;
            for dx in -1..=1i64 {
                for dy in -1..=1i64 {
                    for dz in -1..=1i64 {
                        let k = [
                            c[0].saturating_add(dx),
                            c[1].saturating_add(dy),
                            c[2].saturating_add(dz),
                        ];
                        let mut r = grid.get(&k).copied().unwrap_or(u32::MAX);
                        while r != u32::MAX {
                            if positions[r as usize].distance_squared(p) <= t2
                                && best.is_none_or(|b| r < b)
                            {
                                best = Some(r);
                            }
                            r = next_in_cell[r as usize];
                        }
                    }
                }
            }
            match best {
                Some(r) => rep[v] = r,
                None => {
                    if let Some(prev) = grid.insert(c, v as u32) {
                        next_in_cell[v] = prev;
                    }
                }
            }
        }
    } else if tolerance == 0.0 {
        let mut seen: FastMap<[u64; 3], u32> = FastMap::default();
        for (v, &p) in positions.iter().enumerate() {
            if !p.is_finite() {
                continue;
            }
            // `+ 0.0` turns -0.0 into +0.0 so that the two zeros weld.
            let key = [
                (p.x + 0.0).to_bits(),
                (p.y + 0.0).to_bits(),
                (p.z + 0.0).to_bits(),
            ];
            rep[v] = *seen.entry(key).or_insert(v as u32);
        }
    }
    rep
}

fn flatten(faces: &[(u32, Vec<u32>)]) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32];
    let mut corners = Vec::new();
    for (_, face) in faces {
        corners.extend_from_slice(face);
        offsets.push(corners.len() as u32);
    }
    (offsets, corners)
}

fn dedup_sorted(mut v: Vec<u32>) -> Vec<u32> {
    v.sort_unstable();
    v.dedup();
    v
}

fn map_property(p: &Property, map: &[u32]) -> Property {
    let values = match &p.values {
        PropertyValues::Int(v) => PropertyValues::Int(
            map.iter()
                .map(|&i| v.get(i as usize).copied().unwrap_or(0))
                .collect(),
        ),
        PropertyValues::Float(v) => PropertyValues::Float(
            map.iter()
                .map(|&i| v.get(i as usize).copied().unwrap_or(f64::NAN))
                .collect(),
        ),
    };
    Property {
        name: p.name.clone(),
        values,
    }
}

/// Repairs `mesh` with the chosen steps, in this order: drop invalid faces, weld, drop
/// collapsed faces, triangulate, drop degenerate faces, drop duplicate faces, split
/// non-manifold vertices (detaching non-manifold edges), orient, drop unused vertices. Vertex
/// normals and per-vertex/per-face properties follow the maps.
///
/// With every step enabled (the default) the output is a valid, consistently oriented
/// triangle mesh ([`crate::validate()`] finds nothing) unless a component is non-orientable
/// (counted in [`RepairReport::non_orientable_components`]).
///
/// Every tolerance is relative to the mesh's size, and a mesh whose coordinates are beyond
/// `2^±64` is repaired as a copy scaled by a power of two, with the result scaled back
/// ([`crate::geometry::exact_scale_exponent`]; exact): a tiny mesh's areas no longer underflow
/// to "degenerate".
///
/// # Errors
/// [`MeshError::TooLarge`] when the mesh exceeds 32-bit indices;
/// [`MeshError::InvalidOption`] when [`RepairOptions::validate`] refuses the options.
pub fn repair(mesh: &PolygonMesh, options: &RepairOptions) -> Result<Repaired, MeshError> {
    options.validate()?;
    let e = exact_scale_exponent(&mesh.positions);
    if e == 0 {
        return repair_at_scale(mesh, options);
    }
    let mut scaled = mesh.clone();
    scale_by_power_of_two(&mut scaled.positions, -e);
    let mut repaired = repair_at_scale(&scaled, options)?;
    scale_by_power_of_two(&mut repaired.mesh.positions, e);
    let s = power_of_two(e);
    for (_, d) in &mut repaired.report.moved_vertices {
        *d *= s;
    }
    Ok(repaired)
}

/// [`repair`] of a mesh at its own scale.
fn repair_at_scale(mesh: &PolygonMesh, options: &RepairOptions) -> Result<Repaired, MeshError> {
    let nv = mesh.vertex_count();
    if nv >= u32::MAX as usize || mesh.face_count() >= u32::MAX as usize {
        return Err(MeshError::TooLarge(nv.max(mesh.face_count())));
    }
    let mut report = RepairReport::default();
    let bbox = Aabb::from_points(&mesh.positions);
    let diag = bbox.diagonal();
    // 1. Invalid faces.
    let mut faces: Vec<(u32, Vec<u32>)> = Vec::with_capacity(mesh.face_count());
    for (f, face) in mesh.faces().enumerate() {
        let bad = face.len() < 3
            || face
                .iter()
                .any(|&v| v as usize >= nv || !mesh.positions[v as usize].is_finite());
        if bad {
            report.dropped_invalid_faces.push(f as u32);
        } else {
            faces.push((f as u32, face.to_vec()));
        }
    }
    // 2. Weld.
    let rep = match options.weld_tolerance {
        Some(t) => weld_map(&mesh.positions, t * diag),
        None => (0..nv as u32).collect(),
    };
    for (v, &r) in rep.iter().enumerate() {
        if r != v as u32 {
            report.welded.push((v as u32, r));
        }
    }
    // 3. Collapse repeated corners; drop faces that are not simple polygons any more.
    faces.retain_mut(|(f, face)| {
        for c in face.iter_mut() {
            *c = rep[*c as usize];
        }
        face.dedup();
        while face.len() > 1 && face.first() == face.last() {
            face.pop();
        }
        // No vertex twice: quadratic scan for the usual small faces (no allocation), sort a
        // copy for large ones; both answer "all ids distinct".
        let simple = face.len() >= 3
            && if face.len() <= 8 {
                (1..face.len()).all(|i| !face[..i].contains(&face[i]))
            } else {
                let mut s = face.clone();
                s.sort_unstable();
                s.windows(2).all(|w| w[0] != w[1])
            };
        if !simple {
            report.collapsed_faces.push(*f);
        }
        simple
    });
    // 4. Triangulate.
    if options.triangulate {
        let mut out = Vec::with_capacity(faces.len());
        let mut pts = Vec::new();
        for (f, face) in faces {
            if face.len() == 3 {
                out.push((f, face));
                continue;
            }
            report.triangulated_faces.push(f);
            pts.clear();
            pts.extend(face.iter().map(|&v| mesh.positions[v as usize]));
            for t in triangulate_polygon(&pts) {
                out.push((f, vec![face[t[0]], face[t[1]], face[t[2]]]));
            }
        }
        faces = out;
    }
    // 5. Degenerate faces.
    if options.drop_degenerate_faces {
        let threshold = options.degenerate_area * diag * diag;
        let mut pts = Vec::new();
        let mut dropped = Vec::new();
        faces.retain(|(f, face)| {
            pts.clear();
            pts.extend(face.iter().map(|&v| mesh.positions[v as usize]));
            let keep = 0.5 * newell_normal(&pts).length() > threshold;
            if !keep {
                dropped.push(*f);
            }
            keep
        });
        report.dropped_degenerate_faces = dedup_sorted(dropped);
    }
    // 6. Duplicate faces.
    if options.drop_duplicate_faces {
        let mut seen: FastSet<FaceKey> = FastSet::default();
        seen.reserve(faces.len());
        let mut dropped = Vec::new();
        faces.retain(|(f, face)| {
            let fresh = seen.insert(FaceKey::new(face));
            if !fresh {
                dropped.push(*f);
            }
            fresh
        });
        report.dropped_duplicate_faces = dedup_sorted(dropped);
    }
    // 7. Non-manifold vertices and edges: one vertex copy per extra fan. `src[v]` is the
    // input vertex that (possibly new) vertex `v` stands for.
    let mut src: Vec<u32> = (0..nv as u32).collect();
    // The adjacency built here is reused by the orientation step when nothing was split
    // (then the faces and the vertex count are unchanged, so it would be built identically).
    let mut split_topo: Option<Topology> = None;
    if options.split_non_manifold_vertices && !faces.is_empty() {
        let (offsets, corners) = flatten(&faces);
        let topo = Topology::new(nv, &offsets, &corners)?;
        for e in 0..topo.edge_count() as u32 {
            if topo.edge_face_count(e) > 2 {
                report.detached_non_manifold_edges.push(topo.edge(e));
            }
        }
        // The vertices with more than one fan, found in parallel (counting is cheaper than
        // building the fans, which only split vertices need; still ~1.3 k instructions a
        // vertex, 46 M on the bunny), then split in order of their ids as before.
        let pinched: Vec<u32> = (0..nv as u32)
            .into_par_iter()
            .with_min_len(crate::parallel::SERIAL_BELOW)
            .filter(|&v| topo.vertex_corners(v).len() >= 2 && topo.fan_count(v) >= 2)
            .collect();
        for v in pinched {
            let fans = topo.fans(v);
            report.split_vertices.push((v, fans.len() as u32));
            for fan in &fans[1..] {
                let copy = src.len() as u32;
                src.push(v);
                for &f in &fan.faces {
                    for c in faces[f as usize].1.iter_mut().filter(|c| **c == v) {
                        *c = copy;
                    }
                }
            }
        }
        if report.split_vertices.is_empty() {
            split_topo = Some(topo);
        }
    }
    let nv_split = src.len();
    let pos = |v: u32| mesh.positions[src[v as usize] as usize];
    // 8. Orientation.
    if options.orient && !faces.is_empty() {
        let topo = match split_topo {
            Some(t) => t,
            None => {
                let (offsets, corners) = flatten(&faces);
                Topology::new(nv_split, &offsets, &corners)?
            }
        };
        let (mut flips, comp, orientable) = topo.orientation_flips();
        report.non_orientable_components = orientable.iter().filter(|o| !**o).count();
        let ncomp = orientable.len();
        let mut comp_faces: Vec<Vec<u32>> = vec![Vec::new(); ncomp];
        for (f, &c) in comp.iter().enumerate() {
            comp_faces[c as usize].push(f as u32);
        }
        for cf in &comp_faces {
            let closed = cf.iter().all(|&f| {
                topo.face_corners(f as usize)
                    .all(|c| topo.edge_face_count(topo.corner_edge(c)) == 2)
            });
            let invert = if closed {
                // Signed volume of the component as it will be after the flips.
                let mut o = DVec3::ZERO;
                let mut n = 0.0;
                for &f in cf {
                    for &v in topo.face(f as usize) {
                        o += pos(v);
                        n += 1.0;
                    }
                }
                o /= n;
                let tris = cf.iter().flat_map(|&f| {
                    let face = topo.face(f as usize);
                    let flip = flips[f as usize];
                    (1..face.len() - 1).map(move |i| {
                        let (a, b, c) = (face[0], face[i], face[i + 1]);
                        let (b, c) = if flip { (c, b) } else { (b, c) };
                        [pos(a), pos(b), pos(c)]
                    })
                });
                signed_volume(o, tris) < 0.0
            } else {
                2 * cf.iter().filter(|&&f| flips[f as usize]).count() > cf.len()
            };
            if invert {
                for &f in cf {
                    flips[f as usize] = !flips[f as usize];
                }
            }
        }
        let mut flipped = Vec::new();
        for (k, (f, face)) in faces.iter_mut().enumerate() {
            if flips[k] {
                face.reverse();
                flipped.push(*f);
            }
        }
        report.flipped_faces = dedup_sorted(flipped);
    }
    // Faces the fold repairs make must stay above the degenerate-face threshold (the one step
    // 5 drops faces at, and validation flags): a face made degenerate would drop its normal
    // out of the cone tests instead of satisfying them.
    let min_area = options.degenerate_area * diag * diag;
    // 8b. Folded caps (after orientation: "folded" compares orientations).
    if options.flip_folded_caps {
        report.flipped_cap_edges = crate::folds::flip_folded_caps(&mut faces, pos, min_area)
            .into_iter()
            .map(|e| e.map(|v| src[v as usize]))
            .collect();
    }
    // 8c. Folded vertices.
    let mut pts: Vec<DVec3> = (0..nv_split as u32).map(pos).collect();
    let moved = if options.unfold_vertices {
        crate::folds::unfold_vertices(&faces, &mut pts, crate::DEFAULT_MIN_NORMAL_COSINE, min_area)
    } else {
        Vec::new()
    };
    // 9. Vertices: drop welded-away ones always, unused ones on request; split copies (all
    // used) come after the input's vertices.
    let mut used = vec![false; nv_split];
    for (_, face) in &faces {
        for &v in face {
            used[v as usize] = true;
        }
    }
    let mut new_id = vec![u32::MAX; nv_split];
    for v in 0..nv_split {
        let own = v >= nv || rep[v] == v as u32;
        let keep = own && (used[v] || !options.drop_unused_vertices);
        if keep {
            new_id[v] = report.vertex_map.len() as u32;
            report.vertex_map.push(src[v]);
        } else if own {
            report.dropped_unused_vertices.push(v as u32);
        }
    }
    let mut out = PolygonMesh::new();
    out.positions = (0..nv_split)
        .filter(|&v| new_id[v] != u32::MAX)
        .map(|v| pts[v])
        .collect();
    report.moved_vertices = moved
        .into_iter()
        .map(|(v, d)| (new_id[v as usize], d))
        .collect();
    for (f, face) in &faces {
        let mapped: Vec<u32> = face.iter().map(|&v| new_id[v as usize]).collect();
        out.push_face(&mapped);
        report.face_map.push(*f);
    }
    if let Some(n) = &mesh.normals
        && n.len() == nv
    {
        out.normals = Some(report.vertex_map.iter().map(|&v| n[v as usize]).collect());
    }
    out.vertex_properties = mesh
        .vertex_properties
        .iter()
        .map(|p| map_property(p, &report.vertex_map))
        .collect();
    out.face_properties = mesh
        .face_properties
        .iter()
        .map(|p| map_property(p, &report.face_map))
        .collect();
    Ok(Repaired { mesh: out, report })
}
