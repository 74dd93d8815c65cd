//! Display of the surface (§5 of Xu–Huang–Bajaj 2001): triangular grids on face A-patches,
//! n×m grids on edge A-patches, every surface point the minimal root of a shooting polynomial.
//!
//! Watertight by construction: each ray is evaluated once. The rays from a mesh edge towards a
//! face's apex are computed by the face patch and reused by the edge patch that shares them;
//! rays whose root is t = 0 (mesh vertices, zero convex edges, points where F = 0 on an edge)
//! give the same point from every side and are keyed by the mesh element, so no position
//! appears twice. Patches are evaluated in parallel and numbered as one serial walk over them
//! would number them (worked out in parallel, `numbering`), so the output is the same for
//! every run and thread count.

mod numbering;
mod rays;

use crate::surface::FaceFunction;
use crate::{ApatchError, ApatchSurface};
use algesurf_mesh::progress::{Cancelled, NoProgress, Progress, UnitTally};
use glam::DVec3;
use numbering::Numbering;
use rayon::prelude::*;
use rays::{EdgeRays, FaceRays};

/// What a patch of the output is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PatchKind {
    /// A face A-patch (4.5)/(4.6).
    Face,
    /// An edge A-patch (4.7).
    Edge,
    /// A zero convex face: the input triangle itself.
    Planar,
}

/// A triangle mesh of the surface with per-vertex normals (from ∇F) and per-triangle patch
/// ids and kinds.
#[derive(Clone, Debug, Default)]
pub struct Tessellation {
    /// Vertex positions; the first `V` are the hull mesh's vertices, in its order.
    pub positions: Vec<DVec3>,
    /// Unit normals `∇F/|∇F|`.
    pub normals: Vec<DVec3>,
    /// Triangles, oriented like the input faces.
    pub triangles: Vec<[u32; 3]>,
    /// Patch of each triangle: face patches are numbered by hull face, edge patches follow as
    /// `face_count + edge index`.
    pub triangle_patch: Vec<u32>,
    /// Kind of each triangle's patch.
    pub triangle_kind: Vec<PatchKind>,
    /// Rays whose shooting polynomial had no root in `[0, 1)` (single-sheet violations):
    /// `(patch, position of the ray's start)`. Their point is placed at the ray's end.
    pub missed_rays: Vec<(u32, DVec3)>,
    /// Rays whose chosen root is not certified simple: `(patch, point)`.
    pub multiple_roots: Vec<(u32, DVec3)>,
    /// Which ray wrote which vertex, for [`ApatchSurface::retessellate_patches`]; `None` for a
    /// tessellation not made by [`ApatchSurface::tessellate`].
    pub layout: Option<TessellationLayout>,
}

/// The ray-to-vertex map of a [`Tessellation`]: resolution, the vertex of every face grid point
/// and edge-patch interior grid point, and per vertex the patch that evaluated it and its ray's
/// flags.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TessellationLayout {
    pub(crate) n: usize,
    pub(crate) m: usize,
    /// `face_count × grid points` (order of `face_grid`).
    pub(crate) face_ids: Vec<u32>,
    /// `edge count × (n − 1)(m − 1)`, `u32::MAX` where an edge has no patch.
    pub(crate) edge_ids: Vec<u32>,
    /// Patch that evaluated each vertex (`u32::MAX`: a mesh vertex).
    pub(crate) owner: Vec<u32>,
    /// [`AT_START`], [`MISSED`], [`MULTIPLE`] of the vertex's ray.
    pub(crate) flags: Vec<u8>,
}

pub(crate) const AT_START: u8 = 1;
pub(crate) const MISSED: u8 = 2;
pub(crate) const MULTIPLE: u8 = 4;

impl RayPoint {
    pub(crate) fn flags(&self) -> u8 {
        (self.at_start as u8 * AT_START)
            | (self.missed as u8 * MISSED)
            | (self.multiple as u8 * MULTIPLE)
    }
}

/// One evaluated ray.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct RayPoint {
    pub(crate) position: DVec3,
    pub(crate) normal: DVec3,
    /// Root exactly at the ray's start (a point of the mesh).
    pub(crate) at_start: bool,
    pub(crate) missed: bool,
    pub(crate) multiple: bool,
}

/// Patches per block of [`patch_blocks`]: `count / 64`, at least 16 and at most 1024 (dozens
/// of tasks for every thread, each long enough to dwarf rayon's cost of one).
fn block_size(count: usize) -> usize {
    (count / 64).clamp(16, 1024)
}

/// `0..count` cut into consecutive blocks of [`block_size`] patches (the last one shorter).
fn patch_blocks(count: usize) -> Vec<std::ops::Range<usize>> {
    let size = block_size(count);
    (0..count.div_ceil(size))
        .map(|b| b * size..((b + 1) * size).min(count))
        .collect()
}

/// Buffers shorter than this are filled by one thread in [`filled`]: at most 1.5 MB (64 k
/// values of up to 24 bytes), a few hundred page faults, not worth a parallel pass.
const PARALLEL_FILL: usize = 1 << 16;

/// `n` copies of `x`, written in parallel. A fresh output buffer is mapped by the kernel a page
/// at a time on first write; written by one thread (`vec![x; n]`, or a zeroed allocation the
/// allocator clears), the 60 MB of the bunny's tessellation arrays kept one core zeroing pages
/// while the other waited. Written in parallel, each thread maps its own part.
///
/// Below [`PARALLEL_FILL`] values one thread writes them: a small buffer's pages are few, and
/// a parallel pass costs rayon's wake-up (divan's torus at 8 × 8, 64 k points and eight such
/// buffers, tessellated about 5 % slower with all of them parallel).
fn filled<T: Copy + Send + Sync>(n: usize, x: T) -> Vec<T> {
    if n < PARALLEL_FILL {
        return vec![x; n];
    }
    let mut v = Vec::with_capacity(n);
    v.par_extend((0..n).into_par_iter().map(|_| x));
    v
}

/// The per-vertex columns of a tessellation, `((positions, normals), (flags, owner))`, as one
/// parallel pass gathers them.
type VertexColumns = ((Vec<DVec3>, Vec<DVec3>), (Vec<u8>, Vec<u32>));

/// The rays of `count` patches of `per` rays each, in blocks of consecutive patches (see
/// [`ApatchSurface::tessellate`], pass 1).
struct RayBlocks {
    blocks: Vec<Vec<RayPoint>>,
    /// Each ray's `at_start`, in the same blocks: the numbering reads only these, a byte a
    /// ray instead of a 56-byte [`RayPoint`] (three passes over the rays themselves made the
    /// parallel numbering as slow as the serial one, fandisk at 8 × 8).
    at_start: Vec<Vec<bool>>,
    /// Patches per block.
    size: usize,
    /// Rays per patch.
    per: usize,
}

impl RayBlocks {
    /// Evaluates the blocks in parallel; `fill(patch, out)` appends the patch's `per` rays.
    /// Each finished patch is reported to `progress` as a unit ([`UnitTally`]); once it asks
    /// to stop, the blocks not yet begun are skipped and the result is [`Cancelled`].
    fn new(
        count: usize,
        per: usize,
        fill: impl Fn(usize, &mut Vec<RayPoint>) + Sync,
        progress: &dyn Progress,
    ) -> Result<Self, Cancelled> {
        let size = block_size(count);
        // Counted per patch; a block not begun once `progress` asks to stop is left empty, and
        // the tally's latched stop keeps any of them from being read.
        let tally = UnitTally::counting(progress, count);
        let (blocks, at_start) = patch_blocks(count)
            .into_par_iter()
            .map(|patches| {
                if tally.stopped() {
                    return (Vec::new(), Vec::new());
                }
                let mut out = Vec::with_capacity(patches.len() * per);
                let mut at_start = Vec::with_capacity(patches.len() * per);
                for p in patches {
                    let before = out.len();
                    fill(p, &mut out);
                    // Read while the patch's rays are in cache.
                    at_start.extend(out[before..].iter().map(|r| r.at_start));
                    tally.unit_done(p);
                }
                debug_assert_eq!(out.len() % per.max(1), 0);
                (out, at_start)
            })
            .unzip();
        tally.finish()?;
        Ok(RayBlocks {
            blocks,
            at_start,
            size,
            per,
        })
    }

    /// Which rays of patch `p` stay at their start.
    fn at_start(&self, p: usize) -> &[bool] {
        let start = (p % self.size) * self.per;
        &self.at_start[p / self.size][start..start + self.per]
    }

    /// The rays of patch `p`.
    fn patch(&self, p: usize) -> &[RayPoint] {
        let start = (p % self.size) * self.per;
        &self.blocks[p / self.size][start..start + self.per]
    }
}

impl ApatchSurface {
    /// Triangulates the surface: face patches at resolution `n` (n + 1 points per edge), edge
    /// patches with `n` steps along the edge and `m` across.
    ///
    /// Four passes, each parallel: the rays of all patches (in blocks of patches), the
    /// numbering of the vertices (integer-only: it decides which rays share a vertex), then the
    /// vertex data and the triangles (gathers and fills whose every output slot has one
    /// writer). The numbering is that of a serial walk over the patches in order, so the
    /// output does not depend on the thread count.
    pub fn tessellate(&self, n: usize, m: usize) -> Result<Tessellation, ApatchError> {
        self.tessellate_with_progress(n, m, &NoProgress)
    }

    /// [`ApatchSurface::tessellate`], reporting its steps to `progress`: the face patches'
    /// and the edge patches' rays (counted per patch), then the numbering and the triangles
    /// (not counted; a small part of the time). The tessellation is the same, bit for bit,
    /// with any `progress`; when `progress` asks to stop (polled per block of patches), it
    /// returns [`ApatchError::Cancelled`] once the blocks under way are done.
    ///
    /// # Errors
    /// As [`ApatchSurface::tessellate`]; [`ApatchError::Cancelled`] when `progress` asked to
    /// stop.
    pub fn tessellate_with_progress(
        &self,
        n: usize,
        m: usize,
        progress: &dyn Progress,
    ) -> Result<Tessellation, ApatchError> {
        if n == 0 || m == 0 {
            return Err(ApatchError::Degenerate(
                "the resolution must be at least 1".into(),
            ));
        }
        let mesh = self.hull().mesh();
        let nf = mesh.face_count();
        let ne = self.edges().len();
        // The point count, counted before anything is allocated and without overflow: a
        // resolution too large to number (or to count in a `usize`) is an error, not an
        // allocation failure or an arithmetic overflow.
        let per_face = n
            .checked_add(1)
            .zip(n.checked_add(2))
            .and_then(|(a, b)| a.checked_mul(b))
            .map(|a| a / 2);
        let inner = (n - 1).checked_mul(m - 1);
        let points = per_face
            .and_then(|p| p.checked_mul(nf))
            .zip(inner.and_then(|i| i.checked_mul(ne)))
            .and_then(|(f, e)| f.checked_add(e))
            .and_then(|p| p.checked_add(mesh.vertex_count()));
        let fits = points.is_some_and(|p| p < u32::MAX as usize);
        let (Some(per_face), Some(inner), true) = (per_face, inner, fits) else {
            return Err(too_many_points(n, m));
        };
        if nf == 0 && (n, m) != (1, 1) {
            // Without faces (and so without edges) the resolution changes nothing but the
            // layout's record of it, and must not size a face grid that nothing reads (at
            // n = 2^30 it would have 2^59 points).
            let mut t = self.tessellate_with_progress(1, 1, progress)?;
            if let Some(layout) = &mut t.layout {
                (layout.n, layout.m) = (n, m);
            }
            return Ok(t);
        }
        let grid = face_grid(n);
        debug_assert_eq!(grid.len(), per_face);

        // 1. Rays, in blocks of consecutive patches: each block's buffer is allocated and
        // written by the thread that evaluates it, and a patch's kernels are built once.
        // One buffer per patch (174 k small ones on the bunny) had the kernel zero fresh pages
        // for half of the stage in some runs of the command; one flat buffer collected in
        // parallel made divan's repeated tessellations 10–25 % slower (a large allocation per
        // call). Blocks of `patches / 64` (at least 16, at most 1024) patches keep both cheap
        // and give every thread dozens of tasks.
        progress.start("tessellation: face patches", nf as u64);
        let face_rays = RayBlocks::new(
            nf,
            per_face,
            |f, out| {
                let rays = FaceRays::new(self, f);
                out.extend(grid.iter().map(|g| face_ray(&rays, g, n)));
            },
            progress,
        )?;
        progress.start("tessellation: edge patches", ne as u64);
        let edge_rays = RayBlocks::new(
            ne,
            inner,
            |e, out| match EdgeRays::new(self, e) {
                Some(rays) => out.extend((0..inner).map(|k| edge_ray(&rays, k, n, m))),
                None => out.extend(std::iter::repeat_n(RayPoint::default(), inner)),
            },
            progress,
        )?;

        // 2. Numbering.
        progress.start("tessellation: numbering and triangles", 0);
        let edges_of = self.face_edges();
        let num = self.number_vertices(n, m, &grid, &edges_of, &face_rays, &edge_rays);

        // 3. Vertex data: the mesh vertices, then one ray per vertex.
        let nv = mesh.vertex_count();
        let total = nv + num.source.len();
        // The ray of vertex `v ≥ nv` and the patch that evaluated it.
        let ray = |v: usize| -> (&RayPoint, u32) {
            let (patch, k) = num.source[v - nv];
            let (p, k) = (patch as usize, k as usize);
            let ray = if p < nf {
                &face_rays.patch(p)[k]
            } else {
                &edge_rays.patch(p - nf)[k]
            };
            (ray, patch)
        };
        // One pass reads each vertex's ray once for all four columns.
        let ((positions, normals), (flags, owner)): VertexColumns = (0..total)
            .into_par_iter()
            .map(|v| {
                if v < nv {
                    (
                        (
                            mesh.positions()[v],
                            self.hull().normals()[v].normalize_or_zero(),
                        ),
                        (0, u32::MAX),
                    )
                } else {
                    let (r, patch) = ray(v);
                    ((r.position, r.normal), (r.flags(), patch))
                }
            })
            .unzip();
        // The rays have been read out: their ~50 MB (the bunny at 3 × 2) go back to the
        // allocator before the triangles' buffers are taken, which can then reuse them
        // instead of fresh pages.
        drop(face_rays);
        drop(edge_rays);
        // In vertex order, like the vertices that carry them.
        let mut missed_rays = Vec::new();
        let mut multiple_roots = Vec::new();
        for (v, &fl) in flags.iter().enumerate() {
            if fl & (MISSED | MULTIPLE) != 0 {
                if fl & MISSED != 0 {
                    missed_rays.push((owner[v], positions[v]));
                }
                if fl & MULTIPLE != 0 {
                    multiple_roots.push((owner[v], positions[v]));
                }
            }
        }

        // 4. Triangles: n² per face patch, then the edge patches', in blocks of consecutive
        // patches (as the rays): a block of edge patches appends its triangles to one buffer,
        // and the output is split into one slice per block (a hundred or so), not one per
        // patch (174 k on the bunny: building those lists on one thread was a fifth of the
        // stage). The outputs are first written in parallel ([`filled`]).
        let n2 = n * n;
        let edge_ranges = patch_blocks(ne);
        let edge_blocks: Vec<(Vec<[u32; 3]>, Vec<u32>)> = edge_ranges
            .par_iter()
            .map(|edges| {
                let mut tris = Vec::with_capacity(edges.len() * 2 * n * m);
                let mut counts = Vec::with_capacity(edges.len());
                for e in edges.clone() {
                    let before = tris.len();
                    self.edge_triangles(e, n, m, &edges_of, &num, &mut tris);
                    counts.push((tris.len() - before) as u32);
                }
                (tris, counts)
            })
            .collect();
        let face_blocks = patch_blocks(nf);
        let lengths: Vec<usize> = face_blocks
            .iter()
            .map(|b| b.len() * n2)
            .chain(edge_blocks.iter().map(|b| b.0.len()))
            .collect();
        let tri_count: usize = lengths.iter().sum();
        let mut triangles = filled(tri_count, [0u32; 3]);
        let mut triangle_patch = filled(tri_count, 0u32);
        let mut triangle_kind = filled(tri_count, PatchKind::Edge);
        // Each block's first patch, and for a block of edges its index in `edge_blocks`.
        let block_patches: Vec<(usize, Option<usize>)> = face_blocks
            .iter()
            .map(|b| (b.start, None))
            .chain(
                edge_ranges
                    .iter()
                    .enumerate()
                    .map(|(k, b)| (nf + b.start, Some(k))),
            )
            .collect();
        split_by_lengths(&mut triangles, &lengths)
            .into_par_iter()
            .zip(split_by_lengths(&mut triangle_patch, &lengths))
            .zip(split_by_lengths(&mut triangle_kind, &lengths))
            .zip(block_patches)
            .for_each(
                |(((tris, patch), kind), (first, edge_block))| match edge_block {
                    None => {
                        let faces = tris.chunks_mut(n2).zip(patch.chunks_mut(n2));
                        for (f, ((tris, patch), kind)) in faces.zip(kind.chunks_mut(n2)).enumerate()
                        {
                            let p = first + f;
                            patch.fill(p as u32);
                            kind.fill(if matches!(self.faces()[p], FaceFunction::Planar) {
                                PatchKind::Planar
                            } else {
                                PatchKind::Face
                            });
                            face_triangles(
                                &num.face_ids[p * per_face..(p + 1) * per_face],
                                n,
                                tris,
                            );
                        }
                    }
                    Some(k) => {
                        let (block, counts) = &edge_blocks[k];
                        tris.copy_from_slice(block);
                        let mut at = 0;
                        for (e, &c) in counts.iter().enumerate() {
                            patch[at..at + c as usize].fill((first + e) as u32);
                            at += c as usize;
                        }
                    }
                },
            );

        Ok(Tessellation {
            positions,
            normals,
            triangles,
            triangle_patch,
            triangle_kind,
            missed_rays,
            multiple_roots,
            layout: Some(TessellationLayout {
                n,
                m,
                face_ids: num.face_ids,
                edge_ids: num.edge_ids,
                owner,
                flags,
            }),
        })
    }

    /// The most triangles [`ApatchSurface::tessellate`]`(n, m)` makes, counted without
    /// tessellating: `n²` per face patch and `2m(n − 1)` per edge patch. An edge patch's
    /// `n × m` cells would give `2nm`, but its first and last rows along the edge end in a
    /// mesh vertex, where one triangle of each of their cells collapses to a segment and is
    /// dropped. Fewer triangles are made only where other boundary rays of an edge patch meet
    /// at the mesh edge (rays that stay at their start), which collapses more of its cells.
    ///
    /// For choosing a resolution before paying for it (the command's `--resolution auto`).
    /// Zero when `n` or `m` is (`tessellate` refuses those).
    ///
    /// ```
    /// use algesurf_apatch::{ApatchSurface, SurfaceOptions};
    /// use algesurf_mesh::shapes::icosphere;
    /// let mesh = icosphere(0); // the icosahedron
    /// let normals: Vec<_> = mesh.positions().iter().map(|p| p.normalize()).collect();
    /// let surface = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
    /// // 20 face patches of 4 × 4 = 16 and 30 edge patches of 2·2·3 = 12 triangles.
    /// assert_eq!(surface.max_triangle_count(4, 2), 20 * 16 + 30 * 12);
    /// assert_eq!(surface.tessellate(4, 2).unwrap().triangles.len(), 680);
    /// ```
    pub fn max_triangle_count(&self, n: usize, m: usize) -> usize {
        let edge_patches = (0..self.edges().len())
            .filter(|&e| self.has_edge_patch(e))
            .count();
        let faces = self.hull().mesh().face_count();
        faces.saturating_mul(n.saturating_mul(n)).saturating_add(
            edge_patches
                .saturating_mul(2usize.saturating_mul(m).saturating_mul(n.saturating_sub(1))),
        )
    }

    /// Whether edge `e` carries an edge patch (it has edge tetrahedra).
    fn has_edge_patch(&self, e: usize) -> bool {
        self.edges()[e][0].is_some() || self.edges()[e][1].is_some()
    }

    /// The triangles of edge `e`'s patch (empty without one).
    fn edge_triangles(
        &self,
        e: usize,
        n: usize,
        m: usize,
        edges_of: &[[usize; 3]],
        num: &Numbering,
        out: &mut Vec<[u32; 3]>,
    ) {
        let inner = (n - 1) * (m - 1);
        if !self.has_edge_patch(e) {
            return;
        }
        let he = &self.hull().edges()[e];
        let fl = he.face_l.expect("edge patches are interior") as usize;
        let [vi, vj] = he.vertices;
        let local = |f: usize| (0..3).find(|&z| edges_of[f][z] == e).expect("face edge");
        let (zk, zl) = (local(he.face_k as usize), local(fl));
        // Grid id at (i, j): i along the edge (x = i/n, x = 1 at p_i), j across (y = j/m,
        // y = 1 at the k side).
        let mut ids = vec![0u32; (n + 1) * (m + 1)];
        for i in 0..=n {
            for j in 0..=m {
                let s = n - i; // from e0 = vi
                ids[i * (m + 1) + j] = if i == 0 {
                    vj
                } else if i == n {
                    vi
                } else if j == 0 || j == m {
                    let (f, z) = if j == m {
                        (he.face_k as usize, zk)
                    } else {
                        (fl, zl)
                    };
                    match num.face_row[(f * 3 + z) * (n + 1) + s] {
                        u32::MAX => {
                            let id = num.on_edge[e * (n + 1) + s];
                            debug_assert_ne!(id, u32::MAX, "boundary ray of a face patch");
                            id
                        }
                        id => id,
                    }
                } else {
                    num.edge_ids[e * inner + (i - 1) * (m - 1) + (j - 1)]
                };
            }
        }
        for i in 0..n {
            for j in 0..m {
                let a = ids[i * (m + 1) + j];
                let b = ids[(i + 1) * (m + 1) + j];
                let c = ids[(i + 1) * (m + 1) + j + 1];
                let d = ids[i * (m + 1) + j + 1];
                for t in [[a, c, b], [a, d, c]] {
                    if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                        out.push(t);
                    }
                }
            }
        }
    }

    /// The rays of face `f` at every point of `grid` (level `n`); the corners (mesh vertices,
    /// whose vertex is the mesh's) are left at `RayPoint::default()`.
    pub(crate) fn face_rays(&self, f: usize, grid: &[[usize; 3]], n: usize) -> Vec<RayPoint> {
        let rays = FaceRays::new(self, f);
        grid.iter().map(|g| face_ray(&rays, g, n)).collect()
    }

    /// The interior rays of edge `e`'s patch, `(i, j)` for `i < n`, `j < m`, row-major; empty
    /// when the edge has no edge tetrahedra.
    pub(crate) fn edge_rays(&self, e: usize, n: usize, m: usize) -> Vec<RayPoint> {
        let Some(rays) = EdgeRays::new(self, e) else {
            return Vec::new();
        };
        (0..(n - 1) * (m - 1))
            .map(|k| edge_ray(&rays, k, n, m))
            .collect()
    }

    /// Hull edge of each face's local edge `z` (opposite vertex `z`).
    pub(crate) fn face_edges(&self) -> Vec<[usize; 3]> {
        let mesh = self.hull().mesh();
        let topo = mesh.topology();
        mesh.triangles()
            .par_iter()
            .map(|tri| {
                std::array::from_fn(|z| {
                    topo.find_edge(tri[(z + 1) % 3], tri[(z + 2) % 3])
                        .expect("face edge") as usize
                })
            })
            .collect()
    }
}

/// The ray of a face patch at grid point `g` (level `n`); a corner (a mesh vertex, whose
/// vertex is the mesh's) gets `RayPoint::default()`.
fn face_ray(rays: &FaceRays, g: &[usize; 3], n: usize) -> RayPoint {
    match grid_point(g, n) {
        GridPoint::Corner(_) => RayPoint::default(),
        GridPoint::Edge(_) => rays.ray(g.map(|k| k as f64 / n as f64), rays.on_surface(g, n)),
        GridPoint::Interior => rays.ray(g.map(|k| k as f64 / n as f64), false),
    }
}

/// Interior ray `k` of an edge patch: row `i = k / (m − 1) + 1` of `n − 1` along the edge,
/// column `j = k mod (m − 1) + 1` of `m − 1` across.
fn edge_ray(rays: &EdgeRays, k: usize, n: usize, m: usize) -> RayPoint {
    let (i, j) = (k / (m - 1) + 1, k % (m - 1) + 1);
    rays.ray(
        i as f64 / n as f64,
        j as f64 / m as f64,
        rays.row_on_surface(i, n),
    )
}

/// Where a face grid point lies.
pub(crate) enum GridPoint {
    /// At local vertex `k`.
    Corner(usize),
    /// On the face edge opposite local vertex `z`.
    Edge(usize),
    /// Inside the face.
    Interior,
}

pub(crate) fn grid_point(g: &[usize; 3], n: usize) -> GridPoint {
    match g.iter().filter(|&&k| k == 0).count() {
        2 => GridPoint::Corner((0..3).find(|&k| g[k] == n).expect("corner")),
        1 => GridPoint::Edge((0..3).find(|&k| g[k] == 0).expect("edge")),
        _ => GridPoint::Interior,
    }
}

/// The error of a resolution whose tessellation has more points than `u32` vertex ids number.
fn too_many_points(n: usize, m: usize) -> ApatchError {
    ApatchError::Degenerate(format!(
        "the tessellation at resolution {n} × {m} has more points than 32-bit vertex ids can \
         number"
    ))
}

/// Face grids: all points (a, b, c), a + b + c = n, rows of decreasing a, within a row
/// decreasing b.
pub(crate) fn face_grid(n: usize) -> Vec<[usize; 3]> {
    (0..=n)
        .rev()
        .flat_map(|a| (0..=(n - a)).rev().map(move |b| [a, b, n - a - b]))
        .collect()
}

/// Position of (a, b, n − a − b) in [`face_grid`].
fn grid_index(n: usize, a: usize, b: usize) -> usize {
    // Rows a' = n … a + 1 hold n − a' + 1 points each: Σ_{k=1}^{n−a} k.
    let before = (n - a) * (n - a + 1) / 2;
    before + (n - a - b)
}

/// The `n²` triangles of a face patch from the vertex ids of its grid (`face_grid` order).
fn face_triangles(ids: &[u32], n: usize, out: &mut [[u32; 3]]) {
    let mut k = 0;
    for a in 0..n {
        for b in 0..(n - a) {
            // Upward triangle (a+1,b,c) (a,b+1,c) (a,b,c+1), then the downward one.
            out[k] = [
                ids[grid_index(n, a + 1, b)],
                ids[grid_index(n, a, b + 1)],
                ids[grid_index(n, a, b)],
            ];
            k += 1;
            if a + b + 2 <= n {
                out[k] = [
                    ids[grid_index(n, a + 1, b)],
                    ids[grid_index(n, a + 1, b + 1)],
                    ids[grid_index(n, a, b + 1)],
                ];
                k += 1;
            }
        }
    }
    debug_assert_eq!(k, out.len(), "a face patch has n² triangles");
}

/// `s` cut into consecutive pieces of the given lengths (which sum to `s.len()`).
fn split_by_lengths<'a, T>(mut s: &'a mut [T], lengths: &[usize]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(lengths.len());
    for &l in lengths {
        let (a, b) = std::mem::take(&mut s).split_at_mut(l);
        out.push(a);
        s = b;
    }
    debug_assert!(s.is_empty(), "the lengths cover the slice");
    out
}

#[cfg(test)]
mod tests {
    use crate::{ApatchSurface, SurfaceOptions};
    use algesurf_mesh::shapes::icosphere;
    use std::collections::HashMap;

    /// Every undirected edge of the triangles is shared by exactly two of them, in opposite
    /// directions: a closed, consistently oriented surface without holes.
    fn assert_closed(t: &[[u32; 3]], what: &str) {
        let mut uses: HashMap<(u32, u32), i32> = HashMap::new();
        for tri in t {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                *uses.entry((a.min(b), a.max(b))).or_default() += if a < b { 1 } else { -1 };
                *uses.entry((a.max(b), a.min(b))).or_default() += 1;
            }
        }
        for ((a, b), c) in &uses {
            if a < b {
                assert_eq!(*c, 0, "{what}: edge ({a}, {b}) is not used once each way");
            } else {
                assert_eq!(
                    *c, 2,
                    "{what}: edge ({b}, {a}) is not shared by two triangles"
                );
            }
        }
    }

    /// The blocks cut `0..count` into consecutive ranges, every patch once, with the sizes
    /// [`super::block_size`] promises; [`super::filled`] gives `n` copies.
    #[test]
    fn patch_blocks_cover_every_patch_once() {
        for count in [0, 1, 15, 16, 17, 1023, 1024, 1025, 70_000, 200_000] {
            let blocks = super::patch_blocks(count);
            let size = super::block_size(count);
            let mut next = 0;
            for (k, b) in blocks.iter().enumerate() {
                assert_eq!(b.start, next, "count {count}, block {k}");
                assert!(!b.is_empty() && b.len() <= size, "count {count}, block {k}");
                assert!(b.len() == size || k + 1 == blocks.len(), "count {count}");
                next = b.end;
            }
            assert_eq!(next, count);
        }
        assert_eq!(super::filled(5, [1u32, 2, 3]), vec![[1, 2, 3]; 5]);
        assert!(super::filled(0, 7u8).is_empty());
        let long = super::filled(super::PARALLEL_FILL + 3, 9u16);
        assert_eq!(long.len(), super::PARALLEL_FILL + 3);
        assert!(long.iter().all(|&x| x == 9));
    }

    /// With one step across (`m = 1`) the edge patches have no interior rays but still close
    /// the gap between the face patches' rows (they were once skipped, leaving holes).
    #[test]
    fn coarse_grids_stay_closed_including_one_step_across_edge_patches() {
        let mesh = icosphere(1);
        let normals: Vec<_> = mesh.positions().iter().map(|p| p.normalize()).collect();
        let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
        for (n, m) in [(1, 1), (1, 3), (4, 1), (2, 2), (3, 4)] {
            let t = s.tessellate(n, m).unwrap();
            assert_closed(&t.triangles, &format!("tessellate({n}, {m})"));
        }
    }

    /// The count a resolution is chosen by is the tessellation's: on a closed sphere and a
    /// torus (where no edge patch's boundary rays meet) exactly, at coarse and fine grids.
    #[test]
    fn max_triangle_count_is_the_tessellations_count() {
        let sphere = icosphere(1);
        let torus = algesurf_mesh::shapes::torus(12, 8, 1.5, 0.6);
        for (what, mesh, normals) in [
            (
                "icosphere(1)",
                &sphere,
                sphere
                    .positions()
                    .iter()
                    .map(|p| p.normalize())
                    .collect::<Vec<_>>(),
            ),
            (
                "torus",
                &torus,
                algesurf_mesh::vertex_normals(&torus, algesurf_mesh::NormalMethod::Loop).unwrap(),
            ),
        ] {
            let s = ApatchSurface::new(mesh, &normals, &SurfaceOptions::default()).unwrap();
            for (n, m) in [(1, 1), (1, 3), (2, 1), (3, 2), (5, 5), (8, 3)] {
                let made = s.tessellate(n, m).unwrap().triangles.len();
                assert_eq!(s.max_triangle_count(n, m), made, "{what} at ({n}, {m})");
            }
            assert_eq!(s.max_triangle_count(0, 4), 0);
        }
    }
}
