//! Display of the surface (§5 of Xu–Huang–Bajaj 2001): triangular grids on face A-patches,
//! n×m grids on edge A-patches, every surface point the minimal root of a shooting polynomial.
//!
//! Watertight by construction: each ray is evaluated once. The rays from a mesh edge towards a
//! face's apex are computed by the face patch and reused by the edge patch that shares them;
//! rays whose root is t = 0 (mesh vertices, zero convex edges, points where F = 0 on an edge)
//! give the same point from every side and are keyed by the mesh element, so no position
//! appears twice. Patches are evaluated in parallel and numbered in a serial pass, so the
//! output is the same for every run and thread count.

use crate::cubic;
use crate::geometry::gradient_from_partials;
use crate::surface::FaceFunction;
use crate::{ApatchError, ApatchSurface, EdgeCubic};
use algesurf_bb::roots::shooting_root;
use algesurf_hull::Side;
use glam::DVec3;
use rayon::prelude::*;

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

/// `(1 − t) a + t b`.
fn lerp(a: [f64; 4], b: [f64; 4], t: f64) -> [f64; 4] {
    std::array::from_fn(|i| (1.0 - t) * a[i] + t * b[i])
}

/// The smallest root of `sign · c` in [0, 1) and whether it is simple; `None` if it misses.
fn root(c: [f64; 4], sign: f64) -> Option<(f64, bool)> {
    let c = c.map(|x| sign * x);
    let r = shooting_root(c).ok().flatten()?;
    // Simple when the derivative there is not negligible: p'(t) = 3 Σ Δb_i B_i^2(t), compared
    // with the coefficient size (a double root has p'(t) = 0 up to rounding, ~1e-16 relative).
    let t = r.t;
    let s = 1.0 - t;
    let d = 3.0 * ((c[1] - c[0]) * s * s + 2.0 * (c[2] - c[1]) * t * s + (c[3] - c[2]) * t * t);
    let scale = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    Some((t, d.abs() > 1e-10 * scale))
}

/// Evaluates the ray from `q` to `apex` with shooting coefficients `c` (F along the ray) for
/// the side `sign` (+1: F ≤ 0 at q, looking for F = 0 towards the apex where F > 0).
/// `grad(t)` is ∇F at the ray's point of parameter `t` (computed from the point's barycentric
/// coordinates, which the caller knows exactly as a lerp of the ray's ends).
fn shoot(q: DVec3, apex: DVec3, c: [f64; 4], sign: f64, grad: impl Fn(f64) -> DVec3) -> RayPoint {
    // |F(q)| within the rounding of its own evaluation (a few ε times the coefficients it is
    // combined from): the ray starts on the surface. Treating it as t = 0 keeps rays from a
    // mesh edge where F vanishes identical from every side.
    let scale = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if c[0] == 0.0 || c[0].abs() <= 8.0 * f64::EPSILON * scale {
        return RayPoint {
            position: q,
            normal: grad(0.0).normalize_or_zero(),
            at_start: true,
            missed: false,
            multiple: false,
        };
    }
    match root(c, sign) {
        Some((t, simple)) => {
            let x = q + (apex - q) * t;
            RayPoint {
                position: x,
                normal: grad(t).normalize_or_zero(),
                at_start: t == 0.0,
                missed: false,
                multiple: !simple,
            }
        }
        None => RayPoint {
            position: apex,
            normal: grad(1.0).normalize_or_zero(),
            at_start: false,
            missed: true,
            multiple: false,
        },
    }
}

impl ApatchSurface {
    /// The ray of face `f` from the face point with barycentric coordinates `alpha`.
    fn face_ray(&self, f: usize, alpha: [f64; 3]) -> RayPoint {
        let m = self.hull().mesh();
        let tri = m.triangles()[f];
        let p = tri.map(|v| m.positions()[v as usize]);
        let q = p[0] * alpha[0] + p[1] * alpha[1] + p[2] * alpha[2];
        match &self.faces()[f] {
            FaceFunction::Planar => RayPoint {
                position: q,
                normal: m.face_normal(f),
                at_start: true,
                missed: false,
                multiple: false,
            },
            FaceFunction::Convex { side, cubic } => {
                let sign = if *side == Side::Positive { 1.0 } else { -1.0 };
                let apex = cubic.tetrahedron().vertex(3);
                let c = cubic.shooting_polynomial(alpha);
                let a = [alpha[0], alpha[1], alpha[2], 0.0];
                if sign * c[0] <= 0.0 {
                    let b = [0.0, 0.0, 0.0, 1.0];
                    shoot(q, apex, c, sign, |t| cubic.gradient_at_tau(lerp(a, b, t)))
                } else {
                    // (4.5): F(q) on the wrong side — the patch dips below the face; shoot
                    // backwards along the same line, towards 2q − apex. Along that ray the
                    // polynomial part restricts as usual and the rational term scales as
                    // (1 + s)³, whose Bernstein coefficients on [0, 1] are 2^k.
                    let back = [2.0 * alpha[0], 2.0 * alpha[1], 2.0 * alpha[2], -1.0];
                    let poly = cubic.backward_polynomial(alpha);
                    let r = c[0] - poly[0];
                    let cb: [f64; 4] = std::array::from_fn(|k| poly[k] + r * (1u32 << k) as f64);
                    shoot(q, q * 2.0 - apex, cb, -sign, |t| {
                        cubic.gradient_at_tau(lerp(a, back, t))
                    })
                }
            }
            FaceFunction::Split(split) => {
                // Sub-triangle a = argmin α; coordinates on [p_b, p_c, centroid].
                let a = (0..3)
                    .min_by(|&i, &j| alpha[i].total_cmp(&alpha[j]))
                    .expect("three");
                let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
                let tau = [
                    alpha[b] - alpha[a],
                    alpha[cc] - alpha[a],
                    3.0 * alpha[a],
                    0.0,
                ];
                // (4.6): towards u where F(q) ≤ 0, else towards v. The side is decided by the
                // same b_0 = F(q) the ray uses, so rounding cannot send a ray the wrong way.
                let apex = [0.0, 0.0, 0.0, 1.0];
                let coeffs = [0, 1].map(|s| cubic::coeffs_of(&split.sides[s].polys[a]));
                let ray = |s: usize| cubic::segment(&coeffs[s], tau, apex);
                let c_up = ray(0);
                let (s, sign, c) = if c_up[0] <= 0.0 {
                    (0, 1.0, c_up)
                } else {
                    (1, -1.0, ray(1))
                };
                let tet = &split.sides[s].tets[a];
                shoot(q, tet.vertex(3), c, sign, |t| {
                    let (_, dp) = cubic::value_partials(&coeffs[s], lerp(tau, apex, t));
                    gradient_from_partials(tet, dp, [0.0; 4])
                })
            }
        }
    }

    /// The ray of edge `e` from `q = x p_i + (1 − x) p_j` towards `y u_k + (1 − y) u_l`.
    fn edge_ray(&self, e: usize, x: f64, y: f64) -> RayPoint {
        let m = self.hull().mesh();
        let he = &self.hull().edges()[e];
        let pi = m.positions()[he.vertices[0] as usize];
        let pj = m.positions()[he.vertices[1] as usize];
        let q = pi * x + pj * (1.0 - x);
        let [pos, neg] = &self.edges()[e];
        // (4.7): positive edge tetrahedron where F(q) ≤ 0, else negative; decided by the b_0
        // of the ray itself.
        let (cubic, sign, c) = match (pos, neg) {
            (Some(p), Some(n)) => {
                let cp = p.shooting_polynomial(x, y);
                if cp[0] <= 0.0 {
                    (p, 1.0, cp)
                } else {
                    (n, -1.0, n.shooting_polynomial(x, y))
                }
            }
            (Some(p), None) => (p, 1.0, p.shooting_polynomial(x, y)),
            (None, Some(n)) => (n, -1.0, n.shooting_polynomial(x, y)),
            (None, None) => unreachable!("edge patches exist only where edge tetrahedra do"),
        };
        let t = cubic.tetrahedron();
        let target = t.vertex(3) * y + t.vertex(0) * (1.0 - y);
        let (a, b) = EdgeCubic::ray_ends(x, y);
        shoot(q, target, c, sign, |t| cubic.gradient_at_tau(lerp(a, b, t)))
    }

    /// Triangulates the surface: face patches at resolution `n` (n + 1 points per edge), edge
    /// patches with `n` steps along the edge and `m` across.
    ///
    /// Four passes: the rays of all patches (parallel, into flat buffers), the numbering of
    /// the vertices (serial and integer-only: it decides which rays share a vertex, in patch
    /// order), then the vertex data and the triangles (parallel gathers and fills whose every
    /// output slot has one writer). The numbering is that of a serial pass over the patches, so
    /// the output does not depend on the thread count.
    pub fn tessellate(&self, n: usize, m: usize) -> Result<Tessellation, ApatchError> {
        if n == 0 || m == 0 {
            return Err(ApatchError::Degenerate(
                "the resolution must be at least 1".into(),
            ));
        }
        let mesh = self.hull().mesh();
        let nf = mesh.face_count();
        let ne = self.edges().len();
        let grid = face_grid(n);
        let per_face = grid.len();
        let inner = (n - 1) * (m - 1);
        let face_ray_count = nf * per_face;
        if face_ray_count + ne * inner + mesh.vertex_count() >= u32::MAX as usize {
            return Err(ApatchError::Degenerate(
                "the tessellation has more points than 32-bit vertex ids can number".into(),
            ));
        }

        // 1. Rays.
        let mut face_rays = vec![RayPoint::default(); face_ray_count];
        face_rays
            .par_chunks_mut(per_face)
            .enumerate()
            .for_each(|(f, out)| self.face_rays_into(f, &grid, n, out));
        let mut edge_rays = vec![RayPoint::default(); ne * inner];
        // `inner = 0` (n or m = 1): no interior rays, and no chunks to split into.
        if inner > 0 {
            edge_rays
                .par_chunks_mut(inner)
                .enumerate()
                .for_each(|(e, out)| self.edge_rays_into(e, n, m, out));
        }

        // 2. Numbering.
        let edges_of = self.face_edges();
        let num = self.number_vertices(n, m, &grid, &edges_of, &face_rays, &edge_rays);

        // 3. Vertex data: the mesh vertices, then one ray per vertex.
        let nv = mesh.vertex_count();
        let total = nv + num.source.len();
        let ray = |v: usize| -> &RayPoint {
            let r = num.source[v - nv] as usize;
            if r < face_ray_count {
                &face_rays[r]
            } else {
                &edge_rays[r - face_ray_count]
            }
        };
        let owner_of = |v: usize| -> u32 {
            if v < nv {
                return u32::MAX;
            }
            let r = num.source[v - nv] as usize;
            if r < face_ray_count {
                (r / per_face) as u32
            } else {
                (nf + (r - face_ray_count) / inner) as u32
            }
        };
        let positions: Vec<DVec3> = (0..total)
            .into_par_iter()
            .map(|v| {
                if v < nv {
                    mesh.positions()[v]
                } else {
                    ray(v).position
                }
            })
            .collect();
        let normals: Vec<DVec3> = (0..total)
            .into_par_iter()
            .map(|v| {
                if v < nv {
                    self.hull().normals()[v].normalize_or_zero()
                } else {
                    ray(v).normal
                }
            })
            .collect();
        let flags: Vec<u8> = (0..total)
            .into_par_iter()
            .map(|v| if v < nv { 0 } else { ray(v).flags() })
            .collect();
        let owner: Vec<u32> = (0..total).into_par_iter().map(owner_of).collect();
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

        // 4. Triangles: n² per face patch, then the edge patches'.
        let n2 = n * n;
        let edge_tris: Vec<Vec<[u32; 3]>> = (0..ne)
            .into_par_iter()
            .map(|e| self.edge_triangles(e, n, m, &edges_of, &num))
            .collect();
        let lengths: Vec<usize> = std::iter::repeat_n(n2, nf)
            .chain(edge_tris.iter().map(Vec::len))
            .collect();
        let tri_count: usize = lengths.iter().sum();
        let mut triangles = vec![[0u32; 3]; tri_count];
        let mut triangle_patch = vec![0u32; tri_count];
        let mut triangle_kind = vec![PatchKind::Edge; tri_count];
        split_by_lengths(&mut triangles, &lengths)
            .into_par_iter()
            .zip(split_by_lengths(&mut triangle_patch, &lengths))
            .zip(split_by_lengths(&mut triangle_kind, &lengths))
            .enumerate()
            .for_each(|(p, ((tris, patch), kind))| {
                patch.fill(p as u32);
                if p < nf {
                    let k = if matches!(self.faces()[p], FaceFunction::Planar) {
                        PatchKind::Planar
                    } else {
                        PatchKind::Face
                    };
                    kind.fill(k);
                    face_triangles(&num.face_ids[p * per_face..(p + 1) * per_face], n, tris);
                } else {
                    tris.copy_from_slice(&edge_tris[p - nf]);
                }
            });

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

    /// Numbers the vertices in patch order: face patches by face, each in grid order, then edge
    /// patches by edge, each row by row; a ray gets a new vertex unless it stays at its start
    /// on a mesh edge (t = 0) and an earlier patch already made that point.
    fn number_vertices(
        &self,
        n: usize,
        m: usize,
        grid: &[[usize; 3]],
        edges_of: &[[usize; 3]],
        face_rays: &[RayPoint],
        edge_rays: &[RayPoint],
    ) -> Numbering {
        let mesh = self.hull().mesh();
        let hull_edges = self.hull().edges();
        let (nf, ne) = (mesh.face_count(), self.edges().len());
        let nv = mesh.vertex_count();
        let per_face = grid.len();
        let inner = (n - 1) * (m - 1);
        let classes: Vec<GridPoint> = grid.iter().map(|g| grid_point(g, n)).collect();
        let mut num = Numbering {
            face_ids: vec![0; nf * per_face],
            edge_ids: vec![u32::MAX; ne * inner],
            source: Vec::with_capacity(face_rays.len() + edge_rays.len()),
            on_edge: vec![u32::MAX; ne * (n + 1)],
            face_row: vec![u32::MAX; nf * 3 * (n + 1)],
        };
        // The next vertex id for ray `r`.
        let new = |source: &mut Vec<u32>, r: usize| -> u32 {
            source.push(r as u32);
            (nv + source.len() - 1) as u32
        };
        for f in 0..nf {
            let tri = mesh.triangles()[f];
            let ef = edges_of[f];
            // Whether the face edge opposite z runs against its hull edge: the position s along
            // the hull edge counts from the hull edge's first vertex.
            let reversed: [bool; 3] =
                std::array::from_fn(|z| tri[(z + 1) % 3] == hull_edges[ef[z]].vertices[0]);
            for (k, (g, class)) in grid.iter().zip(&classes).enumerate() {
                let r = f * per_face + k;
                let id = match *class {
                    GridPoint::Corner(c) => tri[c],
                    GridPoint::Edge(z) => {
                        let e = ef[z];
                        // Weight of the edge's other vertex.
                        let wa = g[(z + 1) % 3];
                        let s = if reversed[z] { n - wa } else { wa };
                        if face_rays[r].at_start {
                            let slot = &mut num.on_edge[e * (n + 1) + s];
                            if *slot == u32::MAX {
                                *slot = new(&mut num.source, r);
                            }
                            *slot
                        } else {
                            let id = new(&mut num.source, r);
                            num.face_row[(f * 3 + z) * (n + 1) + s] = id;
                            id
                        }
                    }
                    GridPoint::Interior => new(&mut num.source, r),
                };
                num.face_ids[r] = id;
            }
        }
        if inner > 0 {
            for e in (0..ne).filter(|&e| self.has_edge_patch(e)) {
                for k in 0..inner {
                    let r = e * inner + k;
                    let s = n - (k / (m - 1) + 1);
                    let id = if edge_rays[r].at_start {
                        let slot = &mut num.on_edge[e * (n + 1) + s];
                        if *slot == u32::MAX {
                            *slot = new(&mut num.source, face_rays.len() + r);
                        }
                        *slot
                    } else {
                        new(&mut num.source, face_rays.len() + r)
                    };
                    num.edge_ids[r] = id;
                }
            }
        }
        num
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
    ) -> Vec<[u32; 3]> {
        let inner = (n - 1) * (m - 1);
        if !self.has_edge_patch(e) {
            return Vec::new();
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
        let mut out = Vec::with_capacity(2 * n * m);
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
        out
    }

    /// The rays of face `f` at every point of `grid` (level `n`); the corners (mesh vertices,
    /// whose vertex is the mesh's) are left at `RayPoint::default()`.
    pub(crate) fn face_rays(&self, f: usize, grid: &[[usize; 3]], n: usize) -> Vec<RayPoint> {
        let mut out = vec![RayPoint::default(); grid.len()];
        self.face_rays_into(f, grid, n, &mut out);
        out
    }

    /// [`Self::face_rays`] into `out` (`grid.len()` long).
    fn face_rays_into(&self, f: usize, grid: &[[usize; 3]], n: usize, out: &mut [RayPoint]) {
        for (g, r) in grid.iter().zip(out) {
            if !matches!(grid_point(g, n), GridPoint::Corner(_)) {
                *r = self.face_ray(f, g.map(|k| k as f64 / n as f64));
            }
        }
    }

    /// The interior rays of edge `e`'s patch, `(i, j)` for `i < n`, `j < m`, row-major; empty
    /// when the edge has no edge tetrahedra.
    pub(crate) fn edge_rays(&self, e: usize, n: usize, m: usize) -> Vec<RayPoint> {
        if !self.has_edge_patch(e) {
            return Vec::new();
        }
        let mut v = vec![RayPoint::default(); (n - 1) * (m - 1)];
        self.edge_rays_into(e, n, m, &mut v);
        v
    }

    /// [`Self::edge_rays`] into `out` (`(n − 1)(m − 1)` long); untouched without a patch.
    fn edge_rays_into(&self, e: usize, n: usize, m: usize, out: &mut [RayPoint]) {
        if !self.has_edge_patch(e) {
            return;
        }
        let mut k = 0;
        for i in 1..n {
            for j in 1..m {
                out[k] = self.edge_ray(e, i as f64 / n as f64, j as f64 / m as f64);
                k += 1;
            }
        }
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

/// The vertex numbering of a tessellation (see [`ApatchSurface::tessellate`]).
struct Numbering {
    /// Vertex of every face grid point, `face × grid point`.
    face_ids: Vec<u32>,
    /// Vertex of every edge-patch interior point, `u32::MAX` where an edge has no patch.
    edge_ids: Vec<u32>,
    /// Ray of each vertex after the mesh vertices: face rays first (`face × grid point`),
    /// then edge rays (`face rays + edge × interior point`).
    source: Vec<u32>,
    /// Rays that stay on a mesh edge (t = 0), shared by every patch: `(edge, s)` with `s`
    /// counted from the edge's first vertex. `u32::MAX`: none.
    on_edge: Vec<u32>,
    /// Rows of face patches along mesh edges that leave the edge: `(face, local edge, s)`.
    face_row: Vec<u32>,
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
