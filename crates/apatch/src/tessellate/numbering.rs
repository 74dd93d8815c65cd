//! Pass 2 of [`ApatchSurface::tessellate`]: which rays share a vertex, and every vertex's id.
//!
//! The numbering is that of one serial walk over the patches — face patches by face, each in
//! grid order, then edge patches by edge, each row by row — in which a ray gets the next id
//! unless it stays at its start on a mesh edge (t = 0) and an earlier ray of the walk already
//! made that point (its *slot*: the edge and the position along it). It is worked out in
//! parallel in four passes that give the same ids:
//!
//! 1. every slot's first ray in the walk's order (an atomic minimum of the rays' places in
//!    the walk, which does not depend on the order the threads reach them);
//! 2. per patch, how many new ids its rays take (every ray but the corners and the rays that
//!    find their slot made by an earlier ray);
//! 3. a prefix sum of those counts, each patch's first id (serial: one addition per patch);
//! 4. the ids, per block of patches, each ray's new id counted from its patch's first; a slot's
//!    first ray publishes its id for the slot's later rays, which read it after the pass.
//!
//! Serially this was 10–17 % of the stage (fandisk at 8 × 8: ~20 ms of ~200 ms; the bunny at
//! 3 × 2: ~42 ms of ~250 ms, two threads); in parallel fandisk's takes 14–17 ms, ~6 of them the
//! output buffers' first touch. The passes read one byte per ray ([`RayBlocks::at_start`]):
//! reading the rays themselves three times was as slow as the serial walk.

use super::{GridPoint, RayBlocks, block_size, filled, grid_point, patch_blocks, split_by_lengths};
use crate::ApatchSurface;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

/// The vertex ids of a tessellation's rays (see the module docs).
pub(super) struct Numbering {
    /// Vertex of every face grid point, `face × grid point`.
    pub(super) face_ids: Vec<u32>,
    /// Vertex of every edge-patch interior point, `u32::MAX` where an edge has no patch.
    pub(super) edge_ids: Vec<u32>,
    /// Ray of each vertex after the mesh vertices: `(patch, index of the ray in the patch's
    /// buffer)`, patches numbered as in [`super::Tessellation::triangle_patch`] (kept as a
    /// pair, not a flat ray index, so the gathers need no integer division).
    pub(super) source: Vec<(u32, u32)>,
    /// Rays that stay on a mesh edge (t = 0), shared by every patch: `(edge, s)` with `s`
    /// counted from the edge's first vertex. `u32::MAX`: none.
    pub(super) on_edge: Vec<u32>,
    /// Rows of face patches along mesh edges that leave the edge: `(face, local edge, s)`.
    pub(super) face_row: Vec<u32>,
}

/// A face grid point on a face edge: its index in the grid, the local edge `z` (opposite
/// vertex `z`) and the grid weight of the edge's other vertex (`g[(z + 1) % 3]`).
#[derive(Clone, Copy)]
struct EdgePoint {
    k: usize,
    z: usize,
    weight: usize,
}

/// The new ids of one block of consecutive patches (pass 4): the patches' first ids follow
/// each other ([`ApatchSurface::number_vertices`], pass 3), so the block's ids run on from its
/// first patch's, and each new id's ray goes to the block's share of `source` at the id's
/// offset from the block's first.
struct BlockIds<'s> {
    first: u32,
    next: u32,
    source: &'s mut [(u32, u32)],
}

impl BlockIds<'_> {
    /// The next id, for ray `k` of patch `patch`.
    fn take(&mut self, patch: usize, k: usize) -> u32 {
        let id = self.next;
        self.source[(id - self.first) as usize] = (patch as u32, k as u32);
        self.next += 1;
        id
    }
}

/// What the passes share: the surface, its counts and the face grid's edge points.
struct Walk<'a> {
    surface: &'a ApatchSurface,
    n: usize,
    m: usize,
    per_face: usize,
    inner: usize,
    nf: usize,
    edges_of: &'a [[usize; 3]],
    edge_points: Vec<EdgePoint>,
}

impl Walk<'_> {
    /// The slot of face `f`'s edge point `p`: `(edge, s)` flattened, `s` counted from the hull
    /// edge's first vertex.
    fn face_slot(&self, f: usize, p: &EdgePoint) -> usize {
        let tri = self.surface.hull().mesh().triangles()[f];
        let e = self.edges_of[f][p.z];
        // The face edge opposite z runs against its hull edge when its first vertex is the
        // hull edge's first.
        let reversed = tri[(p.z + 1) % 3] == self.surface.hull().edges()[e].vertices[0];
        let s = if reversed {
            self.n - p.weight
        } else {
            p.weight
        };
        e * (self.n + 1) + s
    }

    /// The slot of edge `e`'s interior ray `k` (row `k / (m − 1)`, which is `s = n − row − 1`).
    fn edge_slot(&self, e: usize, k: usize) -> usize {
        e * (self.n + 1) + self.n - (k / (self.m - 1) + 1)
    }

    /// Ray `k` of face `f` in the walk's order.
    fn face_order(&self, f: usize, k: usize) -> u32 {
        (f * self.per_face + k) as u32
    }

    /// Ray `k` of edge `e` in the walk's order (after every face ray).
    fn edge_order(&self, e: usize, k: usize) -> u32 {
        ((self.nf * self.per_face) + e * self.inner + k) as u32
    }

    /// Whether edge `e` has interior rays to number.
    fn edge_numbered(&self, e: usize) -> bool {
        self.inner > 0 && self.surface.has_edge_patch(e)
    }
}

impl ApatchSurface {
    /// Numbers the vertices (see the module docs): the same ids as the serial walk, worked
    /// out in parallel.
    pub(super) fn number_vertices(
        &self,
        n: usize,
        m: usize,
        grid: &[[usize; 3]],
        edges_of: &[[usize; 3]],
        face_rays: &RayBlocks,
        edge_rays: &RayBlocks,
    ) -> Numbering {
        let mesh = self.hull().mesh();
        let (nf, ne) = (mesh.face_count(), self.edges().len());
        let nv = mesh.vertex_count();
        let per_face = grid.len();
        let classes: Vec<GridPoint> = grid.iter().map(|g| grid_point(g, n)).collect();
        let edge_points = grid
            .iter()
            .enumerate()
            .filter_map(|(k, g)| match grid_point(g, n) {
                GridPoint::Edge(z) => Some(EdgePoint {
                    k,
                    z,
                    weight: g[(z + 1) % 3],
                }),
                _ => None,
            })
            .collect();
        let walk = Walk {
            surface: self,
            n,
            m,
            per_face,
            inner: (n - 1) * (m - 1),
            nf,
            edges_of,
            edge_points,
        };
        let slots = ne * (n + 1);

        // 1. Each slot's first ray.
        let first: Vec<AtomicU32> = (0..slots)
            .into_par_iter()
            .map(|_| AtomicU32::new(u32::MAX))
            .collect();
        let claim = |slot: usize, order: u32| {
            first[slot].fetch_min(order, Ordering::Relaxed);
        };
        (0..nf)
            .into_par_iter()
            .with_min_len(block_size(nf))
            .for_each(|f| {
                let at_start = face_rays.at_start(f);
                for p in &walk.edge_points {
                    if at_start[p.k] {
                        claim(walk.face_slot(f, p), walk.face_order(f, p.k));
                    }
                }
            });
        (0..ne)
            .into_par_iter()
            .with_min_len(block_size(ne))
            .filter(|&e| walk.edge_numbered(e))
            .for_each(|e| {
                for (k, &at_start) in edge_rays.at_start(e).iter().enumerate() {
                    if at_start {
                        claim(walk.edge_slot(e, k), walk.edge_order(e, k));
                    }
                }
            });
        // Whether a ray at its start finds its slot made by an earlier ray.
        let taken = |slot: usize, order: u32| first[slot].load(Ordering::Relaxed) != order;

        // 2. New ids per patch: faces (every grid point but the three corners, which are mesh
        // vertices), then edges.
        let counts: Vec<u32> = (0..nf)
            .into_par_iter()
            .with_min_len(block_size(nf))
            .map(|f| {
                let at_start = face_rays.at_start(f);
                let shared = walk
                    .edge_points
                    .iter()
                    .filter(|p| {
                        at_start[p.k] && taken(walk.face_slot(f, p), walk.face_order(f, p.k))
                    })
                    .count();
                (per_face - 3 - shared) as u32
            })
            .chain(
                (0..ne)
                    .into_par_iter()
                    .with_min_len(block_size(ne))
                    .map(|e| {
                        if !walk.edge_numbered(e) {
                            return 0;
                        }
                        let at_start = edge_rays.at_start(e);
                        let shared = at_start
                            .iter()
                            .enumerate()
                            .filter(|&(k, &a)| {
                                a && taken(walk.edge_slot(e, k), walk.edge_order(e, k))
                            })
                            .count();
                        (at_start.len() - shared) as u32
                    }),
            )
            .collect();

        // 3. Each patch's first id.
        let mut starts = Vec::with_capacity(counts.len());
        let mut next = nv as u32;
        for &c in &counts {
            starts.push(next);
            next += c;
        }
        let total_new = (next as usize) - nv;

        // 4. The ids, per block of consecutive patches. A ray whose slot an earlier ray made
        // is left for after the pass, when every slot's id is published.
        let on_edge: Vec<AtomicU32> = (0..slots)
            .into_par_iter()
            .map(|_| AtomicU32::new(u32::MAX))
            .collect();
        let mut face_ids = filled(nf * per_face, 0u32);
        let mut face_row = filled(nf * 3 * (n + 1), u32::MAX);
        let mut edge_ids = filled(ne * walk.inner, u32::MAX);
        let mut source = filled(total_new, (0u32, 0u32));
        // Blocks of consecutive patches, as the rays were evaluated; a block's share of every
        // per-patch buffer is one chunk of it, of its sources the sum of its patches' counts.
        let (face_blocks, edge_blocks) = (patch_blocks(nf), patch_blocks(ne));
        let block_new = |b: &std::ops::Range<usize>, offset: usize| -> usize {
            counts[offset + b.start..offset + b.end]
                .iter()
                .map(|&c| c as usize)
                .sum()
        };
        let source_lengths: Vec<usize> = face_blocks
            .iter()
            .map(|b| block_new(b, 0))
            .chain(edge_blocks.iter().map(|b| block_new(b, nf)))
            .collect();
        let mut source_parts = split_by_lengths(&mut source, &source_lengths);
        let edge_sources = source_parts.split_off(face_blocks.len());
        let face_block = block_size(nf);
        // `(index into face_ids or edge_ids, slot)` of the rays whose slot was made earlier.
        let face_later: Vec<Vec<(usize, usize)>> = face_blocks
            .par_iter()
            .zip(face_ids.par_chunks_mut(face_block * per_face))
            .zip(face_row.par_chunks_mut(face_block * 3 * (n + 1)))
            .zip(source_parts)
            .map(|(((faces, ids), rows), source)| {
                let mut later = Vec::new();
                let first = starts[faces.start];
                let mut new = BlockIds {
                    first,
                    next: first,
                    source,
                };
                for (i, f) in faces.clone().enumerate() {
                    let tri = mesh.triangles()[f];
                    let ids = &mut ids[i * per_face..(i + 1) * per_face];
                    let rows = &mut rows[i * 3 * (n + 1)..(i + 1) * 3 * (n + 1)];
                    let at_start = face_rays.at_start(f);
                    debug_assert_eq!(new.next, starts[f]);
                    // Corners are the mesh's vertices; every other point takes a new id,
                    // unless it is an edge point whose slot an earlier ray made.
                    let mut edge_points = walk.edge_points.iter();
                    for (k, class) in classes.iter().enumerate() {
                        ids[k] = match *class {
                            GridPoint::Corner(c) => tri[c],
                            GridPoint::Interior => new.take(f, k),
                            GridPoint::Edge(_) => {
                                let p =
                                    edge_points.next().expect("the grid's edge points in order");
                                debug_assert_eq!(p.k, k);
                                let slot = walk.face_slot(f, p);
                                if !at_start[k] {
                                    let v = new.take(f, k);
                                    rows[p.z * (n + 1) + slot % (n + 1)] = v;
                                    v
                                } else if taken(slot, walk.face_order(f, k)) {
                                    later.push((f * per_face + k, slot));
                                    u32::MAX
                                } else {
                                    let v = new.take(f, k);
                                    on_edge[slot].store(v, Ordering::Relaxed);
                                    v
                                }
                            }
                        };
                    }
                }
                later
            })
            .collect();
        // Without interior rays (`n` or `m` is 1) the edge patches number nothing.
        let edge_chunk = (block_size(ne) * walk.inner).max(1);
        let edge_later: Vec<Vec<(usize, usize)>> = edge_blocks
            .par_iter()
            .zip(edge_ids.par_chunks_mut(edge_chunk))
            .zip(edge_sources)
            .map(|((edges, ids), source)| {
                let mut later = Vec::new();
                let first = starts[nf + edges.start];
                let mut new = BlockIds {
                    first,
                    next: first,
                    source,
                };
                for (i, e) in edges.clone().enumerate() {
                    if !walk.edge_numbered(e) {
                        continue;
                    }
                    let ids = &mut ids[i * walk.inner..(i + 1) * walk.inner];
                    debug_assert_eq!(new.next, starts[nf + e]);
                    for (k, &at_start) in edge_rays.at_start(e).iter().enumerate() {
                        let slot = walk.edge_slot(e, k);
                        ids[k] = if at_start && taken(slot, walk.edge_order(e, k)) {
                            later.push((e * walk.inner + k, slot));
                            u32::MAX
                        } else {
                            let v = new.take(nf + e, k);
                            if at_start {
                                on_edge[slot].store(v, Ordering::Relaxed);
                            }
                            v
                        };
                    }
                }
                later
            })
            .collect();
        // The rays whose slot an earlier ray made: its id, now published. Few (rays on mesh
        // edges where F vanishes).
        let on_edge: Vec<u32> = on_edge.into_iter().map(AtomicU32::into_inner).collect();
        for (index, slot) in face_later.into_iter().flatten() {
            face_ids[index] = on_edge[slot];
        }
        for (index, slot) in edge_later.into_iter().flatten() {
            edge_ids[index] = on_edge[slot];
        }
        Numbering {
            face_ids,
            edge_ids,
            source,
            on_edge,
            face_row,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{ApatchSurface, SurfaceOptions};
    use algesurf_mesh::shapes::{grid, icosphere, torus};
    use algesurf_mesh::{NormalMethod, TriMesh, vertex_normals};
    use glam::DVec3;

    /// Walks the patches in order (faces by grid point, then edge patches row by row) and
    /// checks the ids against the serial rule: every id not seen before is the next one, owned
    /// by the patch that met it first; the mesh's vertices are the corners. Returns how many
    /// rays met an id an earlier patch made (shared points on mesh edges).
    fn check_walk(s: &ApatchSurface, n: usize, m: usize, what: &str) -> usize {
        let t = s.tessellate(n, m).unwrap();
        let layout = t.layout.as_ref().unwrap();
        let nv = s.hull().mesh().vertex_count();
        let (nf, ne) = (s.hull().mesh().face_count(), s.edges().len());
        let per_face = (n + 1) * (n + 2) / 2;
        let inner = (n - 1) * (m - 1);
        let mut next = nv as u32;
        let mut shared = 0;
        let mut meet = |id: u32, patch: usize, next: &mut u32| {
            assert!(
                (id as usize) < t.positions.len(),
                "{what}: id {id} out of range"
            );
            if id < nv as u32 {
                return;
            }
            if id == *next {
                assert_eq!(
                    layout.owner[id as usize], patch as u32,
                    "{what}: owner of {id}"
                );
                *next += 1;
            } else {
                assert!(id < *next, "{what}: id {id} before {next} in patch {patch}");
                if layout.owner[id as usize] != patch as u32 {
                    shared += 1;
                }
            }
        };
        for f in 0..nf {
            for &id in &layout.face_ids[f * per_face..(f + 1) * per_face] {
                meet(id, f, &mut next);
            }
        }
        for e in 0..ne {
            for &id in &layout.edge_ids[e * inner..(e + 1) * inner] {
                if id != u32::MAX {
                    meet(id, nf + e, &mut next);
                }
            }
        }
        assert_eq!(next as usize, t.positions.len(), "{what}: every vertex met");
        shared
    }

    fn surface(mesh: &TriMesh, normals: &[DVec3]) -> ApatchSurface {
        ApatchSurface::new(mesh, normals, &SurfaceOptions::default()).unwrap()
    }

    /// A plane's faces share every ray on their common edges (F vanishes there), so most edge
    /// points take the id the face before them made; on a sphere no ray stays at its start
    /// and nothing is shared; the torus has some of both.
    #[test]
    fn vertices_are_numbered_as_a_serial_walk_over_the_patches() {
        let plane = grid(6, 4);
        let up = vec![DVec3::Z; plane.vertex_count()];
        let flat = surface(&plane, &up);
        let ring = torus(12, 8, 1.5, 0.6);
        let round = surface(&ring, &vertex_normals(&ring, NormalMethod::Loop).unwrap());
        let ball = icosphere(1);
        let radial: Vec<DVec3> = ball.positions().iter().map(|p| p.normalize()).collect();
        let sphere = surface(&ball, &radial);
        for (n, m) in [(1, 1), (2, 1), (4, 3), (6, 6)] {
            let shared = check_walk(&flat, n, m, &format!("plane at ({n}, {m})"));
            assert!(n == 1 || shared > 0, "plane at ({n}, {m}): no shared ray");
            check_walk(&round, n, m, "torus");
            assert_eq!(check_walk(&sphere, n, m, "sphere"), 0);
        }
    }
}
