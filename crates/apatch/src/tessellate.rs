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
use std::collections::HashMap;

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
}

/// One evaluated ray.
#[derive(Clone, Copy, Debug)]
struct RayPoint {
    position: DVec3,
    normal: DVec3,
    /// Root exactly at the ray's start (a point of the mesh).
    at_start: bool,
    missed: bool,
    multiple: bool,
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
    pub fn tessellate(&self, n: usize, m: usize) -> Result<Tessellation, ApatchError> {
        if n == 0 || m == 0 {
            return Err(ApatchError::Degenerate(
                "the resolution must be at least 1".into(),
            ));
        }
        let mesh = self.hull().mesh();
        let nf = mesh.face_count();
        let topo = mesh.topology();
        // Face grids: all points (a, b, c), a + b + c = n, in a fixed order.
        let grid: Vec<[usize; 3]> = (0..=n)
            .rev()
            .flat_map(|a| (0..=(n - a)).rev().map(move |b| [a, b, n - a - b]))
            .collect();
        let face_points: Vec<Vec<RayPoint>> = (0..nf)
            .into_par_iter()
            .map(|f| {
                grid.iter()
                    .map(|g| self.face_ray(f, g.map(|k| k as f64 / n as f64)))
                    .collect()
            })
            .collect();
        let edge_points: Vec<Vec<RayPoint>> = (0..self.edges().len())
            .into_par_iter()
            .map(|e| {
                if self.edges()[e][0].is_none() && self.edges()[e][1].is_none() {
                    return Vec::new();
                }
                let mut v = Vec::with_capacity((n - 1) * (m - 1));
                for i in 1..n {
                    for j in 1..m {
                        v.push(self.edge_ray(e, i as f64 / n as f64, j as f64 / m as f64));
                    }
                }
                v
            })
            .collect();

        let mut out = Tessellation::default();
        for (v, p) in mesh.positions().iter().enumerate() {
            out.positions.push(*p);
            out.normals
                .push(self.hull().normals()[v].normalize_or_zero());
        }
        let mut on_edge: HashMap<(u32, usize), u32> = HashMap::new();
        let push = |out: &mut Tessellation, r: &RayPoint, patch: u32| -> u32 {
            if r.missed {
                out.missed_rays.push((patch, r.position));
            }
            if r.multiple {
                out.multiple_roots.push((patch, r.position));
            }
            out.positions.push(r.position);
            out.normals.push(r.normal);
            (out.positions.len() - 1) as u32
        };
        // Rows along mesh edges, keyed by (face, edge, s) with s counted from the edge's first
        // vertex; rays that stay on the mesh edge are shared through `on_edge`.
        let mut face_row: HashMap<(u32, u32, usize), u32> = HashMap::new();
        let mut face_ids: Vec<Vec<u32>> = Vec::with_capacity(nf);
        for f in 0..nf {
            let tri = mesh.triangles()[f];
            let mut ids = Vec::with_capacity(grid.len());
            for (g, r) in grid.iter().zip(&face_points[f]) {
                let zeros = g.iter().filter(|&&k| k == 0).count();
                let id = if zeros == 2 {
                    // A mesh vertex.
                    tri[(0..3).find(|&k| g[k] == n).expect("corner")]
                } else if zeros == 1 {
                    let z = (0..3).find(|&k| g[k] == 0).expect("edge");
                    let (va, vb) = (tri[(z + 1) % 3], tri[(z + 2) % 3]);
                    let e = topo.find_edge(va, vb).expect("face edge");
                    let [e0, _] = self.hull().edges()[e as usize].vertices;
                    // Position along the edge from e0 (weight of the other vertex).
                    let wa = g[(z + 1) % 3];
                    let s = if va == e0 { n - wa } else { wa };
                    if r.at_start {
                        *on_edge
                            .entry((e, s))
                            .or_insert_with(|| push(&mut out, r, f as u32))
                    } else {
                        let id = push(&mut out, r, f as u32);
                        face_row.insert((f as u32, e, s), id);
                        id
                    }
                } else {
                    push(&mut out, r, f as u32)
                };
                ids.push(id);
            }
            face_ids.push(ids);
        }
        // Face patch triangles.
        let index = |a: usize, b: usize| -> usize {
            // Position of (a, b, n − a − b) in `grid`: rows of decreasing a, within a row
            // decreasing b.
            let before: usize = (a + 1..=n).map(|x| n - x + 1).sum();
            before + (n - a - b)
        };
        for f in 0..nf {
            let kind = if matches!(self.faces()[f], FaceFunction::Planar) {
                PatchKind::Planar
            } else {
                PatchKind::Face
            };
            let ids = &face_ids[f];
            for a in 0..n {
                for b in 0..(n - a) {
                    // Upward triangle (a+1,b,c) (a,b+1,c) (a,b,c+1), then the downward one.
                    let t1 = [ids[index(a + 1, b)], ids[index(a, b + 1)], ids[index(a, b)]];
                    out.triangles.push(t1);
                    out.triangle_patch.push(f as u32);
                    out.triangle_kind.push(kind);
                    if a + b + 2 <= n {
                        let t2 = [
                            ids[index(a + 1, b)],
                            ids[index(a + 1, b + 1)],
                            ids[index(a, b + 1)],
                        ];
                        out.triangles.push(t2);
                        out.triangle_patch.push(f as u32);
                        out.triangle_kind.push(kind);
                    }
                }
            }
        }
        // Edge patches.
        for (e, he) in self.hull().edges().iter().enumerate() {
            if edge_points[e].is_empty() {
                continue;
            }
            let patch = (nf + e) as u32;
            let fl = he.face_l.expect("edge patches are interior");
            let [vi, vj] = he.vertices;
            // Grid id at (i, j): i along the edge (x = i/n, x = 1 at p_i), j across (y = j/m,
            // y = 1 at the k side).
            let id_at = |out: &mut Tessellation,
                         on_edge: &mut HashMap<(u32, usize), u32>,
                         i: usize,
                         j: usize|
             -> u32 {
                if i == 0 {
                    return vj;
                }
                if i == n {
                    return vi;
                }
                let s = n - i; // from e0 = vi
                if j == 0 || j == m {
                    let f = if j == m { he.face_k } else { fl };
                    if let Some(&id) = face_row.get(&(f, e as u32, s)) {
                        return id;
                    }
                    return *on_edge
                        .get(&(e as u32, s))
                        .expect("boundary ray of a face patch");
                }
                let r = &edge_points[e][(i - 1) * (m - 1) + (j - 1)];
                if r.at_start {
                    return *on_edge
                        .entry((e as u32, s))
                        .or_insert_with(|| push(out, r, patch));
                }
                push(out, r, patch)
            };
            let mut ids = vec![0u32; (n + 1) * (m + 1)];
            for i in 0..=n {
                for j in 0..=m {
                    ids[i * (m + 1) + j] = id_at(&mut out, &mut on_edge, i, j);
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
                            out.triangles.push(t);
                            out.triangle_patch.push(patch);
                            out.triangle_kind.push(PatchKind::Edge);
                        }
                    }
                }
            }
        }
        Ok(out)
    }
}
