//! The rays of the tessellation, one patch at a time: everything that does not depend on the
//! ray (the patch's cubics as fixed coefficient arrays, its corners, its side) is prepared once
//! per patch, and the shooting polynomials use [`cubic::segment_masked`], which skips the
//! products with the zero coordinates of the rays' ends.
//!
//! The shooting polynomials are those of [`FaceCubic::shooting_polynomial`] and
//! [`EdgeCubic::shooting_polynomial`], operation for operation, so the points are those of
//! evaluating the cubics directly, bit for bit (up to the sign of exact zeros, which no
//! decision distinguishes); the tests below compare them. Gradients are the cubics' own
//! `gradient_at_tau`.

use super::RayPoint;
use crate::cubic::{self, Coeffs};
use crate::geometry::gradient_from_partials;
use crate::rational::face_term;
use crate::surface::FaceFunction;
use crate::{ApatchSurface, EdgeCubic, FaceCubic, SplitFace};
use algesurf_bb::extremes::max_abs;
use algesurf_bb::roots::shooting_root;
use algesurf_hull::{Convexity, Side, SimplicialHull};
use glam::DVec3;

/// Barycentric coordinates of the apex (vertex 3) of a face or sub-face tetrahedron.
const APEX: [f64; 4] = [0.0, 0.0, 0.0, 1.0];
/// Nonzero coordinates of a point on the face `τ_3 = 0` (mask of [`cubic::segment_masked`]).
const ON_FACE: u8 = 0b0111;
/// Nonzero coordinate of [`APEX`].
const AT_APEX: u8 = 0b1000;
/// Nonzero coordinates of an edge ray's start `(0, x, 1 − x, 0)` on the mesh edge.
const ON_EDGE: u8 = 0b0110;
/// Nonzero coordinates of an edge ray's end `(1 − y, 0, 0, y)` between the apexes.
const ON_APEX_EDGE: u8 = 0b1001;

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
    let scale = max_abs(&c);
    Some((t, d.abs() > 1e-10 * scale))
}

/// Evaluates the ray from `q` to `apex` with shooting coefficients `c` (F along the ray) for
/// the side `sign` (+1: F ≤ 0 at q, looking for F = 0 towards the apex where F > 0).
/// `grad(t)` is ∇F at the ray's point of parameter `t` (computed from the point's barycentric
/// coordinates, which the caller knows exactly as a lerp of the ray's ends). `on_surface`:
/// `q` is a point of a mesh edge where F vanishes ([`edge_point_on_surface`]), so the ray
/// starts on the surface whatever `c[0]` says.
#[inline]
fn shoot(
    q: DVec3,
    apex: DVec3,
    c: [f64; 4],
    sign: f64,
    on_surface: bool,
    grad: impl Fn(f64) -> DVec3,
) -> RayPoint {
    // |F(q)| within the rounding of its own evaluation (a few ε times the coefficients it is
    // combined from): the ray starts on the surface. Treating it as t = 0 keeps rays from a
    // mesh edge where F vanishes identical from every side.
    let scale = max_abs(&c);
    if on_surface || c[0] == 0.0 || c[0].abs() <= 8.0 * f64::EPSILON * scale {
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

/// Whether the surface passes through the point `q` of hull edge `e` whose weight of the
/// edge's second vertex is `w / n` (`0 < w < n`), up to the rounding of `q`'s coordinates;
/// decided from the edge's data alone, so that every patch whose rays start at `q` (the two
/// faces' and the edge patch's) decides alike, and they share `q`'s vertex.
///
/// Along the edge `p_0 → p_1` F is the cubic with Bernstein coefficients
/// `0, b_1, b_2, 0`, `b_1 = (p_1 − p_0)ᵀ∇F(p_0) / 3` and `b_2 = (p_0 − p_1)ᵀ∇F(p_1) / 3`
/// (the values and the edge's directional derivatives at its ends, which every cubic on the
/// edge shares: [`algesurf_bb::continuity::vertex_and_neighbours`]), so
/// `F(q) = 3 s (1 − s) ((1 − s) b_1 + s b_2)` at `s = w / n`. The surface passes through `q`:
///
/// * on a zero convex interior edge, everywhere: its normals are perpendicular to it up to
///   [`algesurf_hull::HullOptions::zero_tolerance`], which accepts normals a few ulps off
///   (Loop normals of a remeshed plate's rims lean 5e-15 along the edge) and leaves `F(q)` at
///   ~20 ε of a ray's coefficients, beyond [`shoot`]'s own rounding test: the two sides' rays
///   then stopped a few ulps apart instead of sharing a point, and the tessellation cracked;
/// * where `|F(q)| / |∇F|` (the distance from `q` to the surface, to first order; `|∇F|`
///   bounded by the ends' gradients) is at most 16 ulps of `q`'s largest coordinate or of the
///   edge's length, whichever is larger: the scale at which positions round. A
///   nonconvex edge whose surface crosses it next to a grid point (a washer after
///   refinement, by symmetry: 3 ulps from the edge's midpoint) gave rays from `q` that each
///   stopped within 1e-16 of it in their own directions, five vertices where one belongs and
///   two of them at the same position.
///
/// Boundary edges are not shared and are never decided here.
fn edge_point_on_surface(hull: &SimplicialHull, e: usize, w: usize, n: usize) -> bool {
    let edge = &hull.edges()[e];
    if edge.is_boundary() {
        return false;
    }
    if edge.convexity == Convexity::ZeroConvex {
        return true;
    }
    let [v0, v1] = edge.vertices.map(|v| v as usize);
    let (p, g) = (hull.mesh().positions(), hull.normals());
    let d = p[v1] - p[v0];
    let b1 = d.dot(g[v0]) / 3.0;
    let b2 = -d.dot(g[v1]) / 3.0;
    let s = w as f64 / n as f64;
    let value = 3.0 * s * (1.0 - s) * ((1.0 - s) * b1 + s * b2);
    // Without square roots (this runs for every ray from a mesh edge, ~630 k on the bunny at
    // 3 × 2): the largest components stand in for the lengths, `|x|∞ ≤ |x| < 2 |x|∞`, so the
    // bound is within a factor of two of the one stated above, either way.
    let gradient = 2.0 * g[v0].abs().max(g[v1].abs()).max_element();
    let q = p[v0] + d * s;
    let scale = q.abs().max(d.abs()).max_element();
    value.abs() <= 16.0 * f64::EPSILON * scale * gradient
}

/// A face cubic with its polynomial part as a fixed array.
struct FaceKernel<'a> {
    cubic: &'a FaceCubic,
    coeffs: Coeffs,
}

impl<'a> FaceKernel<'a> {
    fn new(cubic: &'a FaceCubic) -> Self {
        FaceKernel {
            cubic,
            coeffs: cubic::coeffs_of(cubic.polynomial()),
        }
    }

    /// [`FaceCubic::shooting_polynomial`] from the face point `a` (`a[3] = 0`).
    #[inline]
    fn shooting(&self, a: [f64; 4]) -> [f64; 4] {
        let c = cubic::segment_masked::<ON_FACE, AT_APEX>(&self.coeffs, a, APEX);
        [
            c[0] + face_term(a, self.cubic.rational()).0,
            c[1],
            c[2],
            c[3],
        ]
    }

    /// `FaceCubic::gradient_at_tau`.
    #[inline]
    fn gradient(&self, tau: [f64; 4]) -> DVec3 {
        self.cubic.gradient_at_tau(tau)
    }
}

/// The rays of one face patch.
pub(super) struct FaceRays<'a> {
    /// The face's corners.
    p: [DVec3; 3],
    kind: FaceKind<'a>,
    /// For each local edge `z` (opposite corner `z`): its hull edge and the local corner that
    /// is that edge's second vertex, for [`edge_point_on_surface`].
    edges: [(usize, usize); 3],
    hull: &'a SimplicialHull,
}

enum FaceKind<'a> {
    Planar {
        /// The face's unit normal (the positive side's).
        normal: DVec3,
    },
    Convex {
        sign: f64,
        k: FaceKernel<'a>,
    },
    /// Boxed: six cubics are large next to the other variants.
    Split {
        split: &'a SplitFace,
        coeffs: Box<[[Coeffs; 3]; 2]>,
    },
}

impl<'a> FaceRays<'a> {
    /// The rays of face `f` of `surface`.
    pub(super) fn new(surface: &'a ApatchSurface, f: usize) -> Self {
        let m = surface.hull().mesh();
        let tri = m.triangles()[f];
        let p = tri.map(|v| m.positions()[v as usize]);
        let kind = match &surface.faces()[f] {
            // `face_normal` is twice the area vector: the tessellation's normals are unit
            // vectors (`Tessellation::normals`), and PLY and OBJ write them as they are.
            FaceFunction::Planar => FaceKind::Planar {
                normal: m.face_normal(f).normalize_or_zero(),
            },
            FaceFunction::Convex { side, cubic } => FaceKind::Convex {
                sign: if *side == Side::Positive { 1.0 } else { -1.0 },
                k: FaceKernel::new(cubic),
            },
            FaceFunction::Split(split) => FaceKind::Split {
                split,
                coeffs: Box::new(std::array::from_fn(|s| {
                    std::array::from_fn(|a| cubic::coeffs_of(&split.sides[s].polys[a]))
                })),
            },
        };
        // Local edge z runs between corners z + 1 and z + 2: the hull face's edge
        // `(z + 1) mod 3` (its edges are [i j], [j k], [k i]).
        let hull = surface.hull();
        let hull_edges = hull.faces()[f].edges;
        let edges = std::array::from_fn(|z| {
            let e = hull_edges[(z + 1) % 3] as usize;
            let second = hull.edges()[e].vertices[1];
            let corner = (0..3)
                .find(|&c| tri[c] == second)
                .expect("the edge's vertex");
            (e, corner)
        });
        FaceRays {
            p,
            kind,
            edges,
            hull,
        }
    }

    /// Whether the face grid point `g` (level `n`) is a point of a face edge where F vanishes
    /// ([`edge_point_on_surface`]); `false` inside the face.
    pub(super) fn on_surface(&self, g: &[usize; 3], n: usize) -> bool {
        (0..3).any(|z| {
            let (e, corner) = self.edges[z];
            g[z] == 0 && edge_point_on_surface(self.hull, e, g[corner], n)
        })
    }

    /// The ray from the face point with barycentric coordinates `alpha`; `on_surface`: the
    /// point is one of a mesh edge where F vanishes ([`FaceRays::on_surface`]).
    pub(super) fn ray(&self, alpha: [f64; 3], on_surface: bool) -> RayPoint {
        let p = &self.p;
        let q = p[0] * alpha[0] + p[1] * alpha[1] + p[2] * alpha[2];
        match &self.kind {
            FaceKind::Planar { normal } => RayPoint {
                position: q,
                normal: *normal,
                at_start: true,
                missed: false,
                multiple: false,
            },
            FaceKind::Convex { sign, k } => {
                let sign = *sign;
                let apex = k.cubic.tetrahedron().vertex(3);
                let a = [alpha[0], alpha[1], alpha[2], 0.0];
                let c = k.shooting(a);
                if on_surface || sign * c[0] <= 0.0 {
                    shoot(q, apex, c, sign, on_surface, |t| {
                        k.gradient(lerp(a, APEX, t))
                    })
                } else {
                    // (4.5): F(q) on the wrong side — the patch dips below the face; shoot
                    // backwards along the same line, towards 2q − apex. Along that ray the
                    // polynomial part restricts as usual (`FaceCubic::backward_polynomial`) and
                    // the rational term scales as (1 + s)³, whose Bernstein coefficients on
                    // [0, 1] are 2^k.
                    let back = [2.0 * alpha[0], 2.0 * alpha[1], 2.0 * alpha[2], -1.0];
                    let poly = k.cubic.backward_polynomial(alpha);
                    let r = c[0] - poly[0];
                    let cb: [f64; 4] = std::array::from_fn(|j| poly[j] + r * (1u32 << j) as f64);
                    shoot(q, q * 2.0 - apex, cb, -sign, false, |t| {
                        k.gradient(lerp(a, back, t))
                    })
                }
            }
            FaceKind::Split { split, coeffs } => {
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
                let ray =
                    |s: usize| cubic::segment_masked::<ON_FACE, AT_APEX>(&coeffs[s][a], tau, APEX);
                let c_up = ray(0);
                let (s, sign, c) = if c_up[0] <= 0.0 {
                    (0, 1.0, c_up)
                } else {
                    (1, -1.0, ray(1))
                };
                let tet = &split.sides[s].tets[a];
                shoot(q, tet.vertex(3), c, sign, on_surface, |t| {
                    let (_, dp) = cubic::value_partials(&coeffs[s][a], lerp(tau, APEX, t));
                    gradient_from_partials(tet, dp, [0.0; 4])
                })
            }
        }
    }
}

/// An edge cubic with its polynomial part as a fixed array.
struct EdgeKernel<'a> {
    cubic: &'a EdgeCubic,
    coeffs: Coeffs,
}

impl<'a> EdgeKernel<'a> {
    fn new(cubic: &'a EdgeCubic) -> Self {
        EdgeKernel {
            cubic,
            coeffs: cubic::coeffs_of(cubic.polynomial()),
        }
    }

    /// [`EdgeCubic::shooting_polynomial`], operation for operation (see there for the rational
    /// part's contribution to `B_2`).
    #[inline]
    fn shooting(&self, x: f64, y: f64) -> [f64; 4] {
        let (a, b) = EdgeCubic::ray_ends(x, y);
        let mut c = cubic::segment_masked::<ON_EDGE, ON_APEX_EDGE>(&self.coeffs, a, b);
        let [[a1, b1], [a2, b2]] = self.cubic.rational();
        let blend1 = (1.0 - y) * a1 + y * b1;
        let blend2 = (1.0 - y) * a2 + y * b2;
        // 6 t²(1−t) = 2 B_2^3(t).
        c[2] += 2.0 * y * (1.0 - y) * (x * blend1 + (1.0 - x) * blend2);
        c
    }

    /// `EdgeCubic::gradient_at_tau`.
    #[inline]
    fn gradient(&self, tau: [f64; 4]) -> DVec3 {
        self.cubic.gradient_at_tau(tau)
    }
}

/// The rays of one edge patch.
pub(super) struct EdgeRays<'a> {
    pi: DVec3,
    pj: DVec3,
    /// The hull edge and its hull, for [`edge_point_on_surface`].
    e: usize,
    hull: &'a SimplicialHull,
    pos: Option<EdgeKernel<'a>>,
    neg: Option<EdgeKernel<'a>>,
}

impl<'a> EdgeRays<'a> {
    /// The rays of edge `e` of `surface`; `None` where the edge has no edge tetrahedra.
    pub(super) fn new(surface: &'a ApatchSurface, e: usize) -> Option<Self> {
        let [pos, neg] = &surface.edges()[e];
        if pos.is_none() && neg.is_none() {
            return None;
        }
        let m = surface.hull().mesh();
        let [vi, vj] = surface.hull().edges()[e].vertices;
        Some(EdgeRays {
            pi: m.positions()[vi as usize],
            pj: m.positions()[vj as usize],
            e,
            hull: surface.hull(),
            pos: pos.as_ref().map(EdgeKernel::new),
            neg: neg.as_ref().map(EdgeKernel::new),
        })
    }

    /// Whether the start of row `i` (`x = i / n`, `s = n − i` steps from `p_i`) is a point of
    /// the edge where F vanishes ([`edge_point_on_surface`]).
    pub(super) fn row_on_surface(&self, i: usize, n: usize) -> bool {
        edge_point_on_surface(self.hull, self.e, n - i, n)
    }

    /// The ray from `q = x p_i + (1 − x) p_j` towards `y u_k + (1 − y) u_l`; `on_surface`: `q`
    /// is a point of the edge where F vanishes ([`EdgeRays::row_on_surface`]).
    pub(super) fn ray(&self, x: f64, y: f64, on_surface: bool) -> RayPoint {
        let q = self.pi * x + self.pj * (1.0 - x);
        // (4.7): positive edge tetrahedron where F(q) ≤ 0, else negative; decided by the b_0
        // of the ray itself.
        let (k, sign, c) = match (&self.pos, &self.neg) {
            (Some(p), Some(n)) => {
                let cp = p.shooting(x, y);
                if cp[0] <= 0.0 {
                    (p, 1.0, cp)
                } else {
                    (n, -1.0, n.shooting(x, y))
                }
            }
            (Some(p), None) => (p, 1.0, p.shooting(x, y)),
            (None, Some(n)) => (n, -1.0, n.shooting(x, y)),
            (None, None) => unreachable!("EdgeRays::new requires an edge tetrahedron"),
        };
        let t = k.cubic.tetrahedron();
        let target = t.vertex(3) * y + t.vertex(0) * (1.0 - y);
        let (a, b) = EdgeCubic::ray_ends(x, y);
        shoot(q, target, c, sign, on_surface, |t| {
            k.gradient(lerp(a, b, t))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SurfaceOptions;
    use crate::examples::WorkedExample;
    use algesurf_mesh::{NormalMethod, shapes, vertex_normals};

    /// Equal values with the same bits, ±0 alike.
    fn same(x: f64, y: f64) -> bool {
        x == y && (x == 0.0 || x.to_bits() == y.to_bits())
    }

    fn same4(x: [f64; 4], y: [f64; 4]) -> bool {
        (0..4).all(|i| same(x[i], y[i]))
    }

    fn surfaces() -> Vec<ApatchSurface> {
        let mut out = Vec::new();
        let m = shapes::icosphere(1);
        let n = vertex_normals(&m, NormalMethod::Loop).expect("normals");
        out.push(ApatchSurface::new(&m, &n, &SurfaceOptions::default()).expect("surface"));
        for ex in WorkedExample::ALL {
            let (m, n) = ex.mesh_and_normals();
            out.push(ApatchSurface::new(&m, &n, &SurfaceOptions::default()).expect("surface"));
        }
        out
    }

    /// Points inside, on the edges and at the corners of the unit triangle / square.
    fn params() -> Vec<(f64, f64)> {
        let mut v = Vec::new();
        for i in 0..=6 {
            for j in 0..=6 {
                v.push((i as f64 / 6.0, j as f64 / 6.0));
            }
        }
        v
    }

    #[test]
    fn face_kernels_equal_the_face_cubics_bit_for_bit() {
        let mut checked = 0;
        for s in surfaces() {
            for f in s.faces() {
                let FaceFunction::Convex { cubic, .. } = f else {
                    continue;
                };
                let k = FaceKernel::new(cubic);
                for (u, v) in params() {
                    let alpha = [u * (1.0 - v), v, 1.0 - u * (1.0 - v) - v];
                    let a = [alpha[0], alpha[1], alpha[2], 0.0];
                    assert!(same4(k.shooting(a), cubic.shooting_polynomial(alpha)));
                    checked += 1;
                }
            }
        }
        assert!(checked > 0, "no convex face");
    }

    #[test]
    fn edge_kernels_equal_the_edge_cubics_bit_for_bit() {
        let mut checked = 0;
        for s in surfaces() {
            for cubic in s.edges().iter().flatten().flatten() {
                let k = EdgeKernel::new(cubic);
                for (x, y) in params() {
                    assert!(same4(k.shooting(x, y), cubic.shooting_polynomial(x, y)));
                    checked += 1;
                }
            }
        }
        assert!(checked > 0, "no edge cubic");
    }
}
