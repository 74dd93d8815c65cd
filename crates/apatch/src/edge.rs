//! The rational cubic (4.3)/(4.4) on the edge tetrahedron `[u_l, p_i, p_j, u_k]` between the
//! face tetrahedra of the faces `[p_i p_j p_k]` (apex `u_k`) and `[p_i p_j p_l]` (apex `u_l`):
//! Steps 7 and 9 of §4.2 of Xu–Huang–Bajaj 2001.
//!
//! Every coefficient with `λ_0 ≤ 1` is fixed by C1 with the `k` side, every one with
//! `λ_3 ≤ 1` by C1 with the `l` side: each is the blossom of that side's polynomial at the
//! edge tetrahedron's vertices (Lemma 2.2 for the C1 layer, C0 for the shared face). Both sides
//! determine the coefficients with `λ_0 ≤ 1` and `λ_3 ≤ 1`; they agree when the two face cubics
//! share vertex gradients and the mid-edge gradient of the edge, and [`EdgeCubic::overlap_mismatch`]
//! measures that. The two exceptions, `λ = 1101` and `1011`, are where the rational blend
//! `(a τ0 + b τ3)/(τ0 + τ3)` takes `b` from the `k` side and `a` from the `l` side; their
//! polynomial part is zero (Step 7's "number 5" coefficients).

use crate::cubic;
use crate::geometry::{exact_barycentric, gradient_from_partials, value_gradient_with};
use crate::rational::edge_term;
use crate::surface::no_tetrahedron_on;
use crate::{ApatchError, FaceCubic, FaceFunction};
use algesurf_bb::extremes::{max_abs, max_not_nan};
use algesurf_bb::sheet::square::Tensor3;
use algesurf_bb::{BbPoly, Tetrahedron};
use algesurf_hull::Side;
use glam::DVec3;

/// The rational cubic on an edge tetrahedron.
#[derive(Clone, Debug)]
pub struct EdgeCubic {
    tet: Tetrahedron,
    poly: BbPoly<f64, 4>,
    /// `[[a_1101, b_1101], [a_1011, b_1011]]`.
    rational: [[f64; 2]; 2],
    overlap_mismatch: f64,
}

/// What an edge cubic needs from the face on one side of its edge `(p_i, p_j)`: the
/// tetrahedron with the face `[p_i p_j apex]` (apex last) and the polynomial that agrees with F
/// to first order on that face. A convex face gives its face tetrahedron and the polynomial with
/// the rational term's value on that edge folded in ([`FaceCubic::effective_polynomial`]); a
/// split face gives the sub-tetrahedron that carries the edge.
#[derive(Clone, Debug)]
pub struct EdgeNeighbour {
    /// Tetrahedron containing `p_i`, `p_j` and the apex (as vertex 3).
    pub tet: Tetrahedron,
    /// Polynomial valid to first order on the face `[p_i p_j apex]`.
    pub poly: BbPoly<f64, 4>,
}

impl FaceCubic {
    /// The [`EdgeNeighbour`] of this face for its edge `(pi, pj)`.
    pub fn edge_neighbour(&self, pi: DVec3, pj: DVec3) -> Result<EdgeNeighbour, ApatchError> {
        Ok(EdgeNeighbour {
            tet: *self.tetrahedron(),
            poly: self.effective_polynomial(self.opposite_corner(pi, pj)?),
        })
    }

    /// The local corner (0–2) opposite the face edge `(pi, pj)`.
    pub(crate) fn opposite_corner(&self, pi: DVec3, pj: DVec3) -> Result<usize, ApatchError> {
        let v = self.tetrahedron().vertices();
        let find = |p: DVec3| (0..3).find(|&a| v[a] == p);
        match (find(pi), find(pj)) {
            (Some(a), Some(b)) if a != b => Ok(3 - a - b),
            _ => Err(ApatchError::Inconsistent(
                "the face tetrahedron does not contain the edge".into(),
            )),
        }
    }
}

/// What [`FaceFunction::edge_neighbour`] gives, borrowed: the face function's tetrahedron with
/// the face `[p_i p_j apex]`, and its polynomial there, whose coefficients are read only when
/// asked for (Step 6's lift needs only the tetrahedron; the edge cubics copy the coefficients
/// to the stack, where `edge_neighbour` allocates a polynomial).
pub(crate) struct EdgePiece<'a> {
    /// The tetrahedron, apex last.
    pub(crate) tet: &'a Tetrahedron,
    poly: PiecePoly<'a>,
}

/// The polynomial of an [`EdgePiece`].
enum PiecePoly<'a> {
    /// A convex face's cubic with the rational term of the edge opposite corner `a` folded in
    /// ([`FaceCubic::effective_coeffs`]).
    Convex(&'a FaceCubic, usize),
    /// The split face's sub-tetrahedron cubic.
    Split(&'a BbPoly<f64, 4>),
}

impl EdgePiece<'_> {
    /// The polynomial's coefficients.
    pub(crate) fn coeffs(&self) -> cubic::Coeffs {
        match self.poly {
            PiecePoly::Convex(c, a) => c.effective_coeffs(a),
            PiecePoly::Split(p) => cubic::coeffs_of(p),
        }
    }
}

impl FaceFunction {
    /// The piece of F on `side` next to the face edge `(pi, pj)` ([`EdgePiece`]).
    pub(crate) fn edge_piece(
        &self,
        side: Side,
        pi: DVec3,
        pj: DVec3,
    ) -> Result<EdgePiece<'_>, ApatchError> {
        match (self, side) {
            (FaceFunction::Convex { side: s, cubic }, _) if *s == side => Ok(EdgePiece {
                tet: cubic.tetrahedron(),
                poly: PiecePoly::Convex(cubic, cubic.opposite_corner(pi, pj)?),
            }),
            (FaceFunction::Split(split), Side::Positive | Side::Negative) => {
                let half = &split.sides[(side == Side::Negative) as usize];
                let a = half.sub_tetrahedron_on(pi, pj)?;
                Ok(EdgePiece {
                    tet: &half.tets[a],
                    poly: PiecePoly::Split(&half.polys[a]),
                })
            }
            _ => Err(no_tetrahedron_on(side)),
        }
    }
}

impl crate::SplitSide {
    /// The [`EdgeNeighbour`] of this side for the face edge `(pi, pj)`: the sub-tetrahedron
    /// `[p_b, p_c, centroid, apex]` that carries it.
    pub fn edge_neighbour(&self, pi: DVec3, pj: DVec3) -> Result<EdgeNeighbour, ApatchError> {
        let a = self.sub_tetrahedron_on(pi, pj)?;
        Ok(EdgeNeighbour {
            tet: self.tets[a],
            poly: self.polys[a].clone(),
        })
    }

    /// Which sub-tetrahedron carries the face edge `(pi, pj)`.
    pub(crate) fn sub_tetrahedron_on(&self, pi: DVec3, pj: DVec3) -> Result<usize, ApatchError> {
        (0..3)
            .find(|&a| {
                let t = &self.tets[a];
                let has = |p: DVec3| t.vertex(0) == p || t.vertex(1) == p;
                has(pi) && has(pj) && pi != pj
            })
            .ok_or_else(|| {
                ApatchError::Inconsistent(
                    "no sub-tetrahedron of the split face carries the edge".into(),
                )
            })
    }
}

/// The coefficient at `lambda` (indices on `verts`, given in the side's barycentric
/// coordinates) of the side's polynomial re-expressed on the edge tetrahedron.
///
/// Most arguments are exact unit vectors: the edge's ends and the side's own apex are vertices
/// of the side's tetrahedron (`exact_barycentric`). With at most one other argument `v` the
/// blossom is one sum, `Σ_k v_k c_{μ+e_k}` (`μ` the unit arguments' indices), or a coefficient
/// (`v` a unit vector too). That is bit for bit what [`cubic::blossom`]'s three de Casteljau
/// steps give, whatever the argument order: a step with a unit vector adds one product with 1
/// and three exact zeros, and a step with `v` forms that same sum in the same order.
fn blossom_at(poly: &cubic::Coeffs, verts: &Verts, lambda: [usize; 4]) -> f64 {
    let mut mu = [0usize; 4];
    let mut general = None;
    for (s, &times) in lambda.iter().enumerate() {
        for _ in 0..times {
            match verts.unit[s] {
                Some(k) => mu[k] += 1,
                None if general.is_none() => general = Some(verts.at[s]),
                None => {
                    let [a, b, d] = cubic::blossom_args(&verts.at, lambda);
                    return cubic::blossom(poly, a, b, d);
                }
            }
        }
    }
    match general {
        None => poly[cubic::rank3(mu)],
        Some(v) => {
            let up = |k: usize| {
                let mut l = mu;
                l[k] += 1;
                poly[cubic::rank3(l)]
            };
            v[0] * up(0) + v[1] * up(1) + v[2] * up(2) + v[3] * up(3)
        }
    }
}

/// The edge tetrahedron's vertices in one side's barycentric coordinates, and which of them
/// are exact unit vectors (`unit[s] = Some(k)` for `e_k`), for [`blossom_at`].
struct Verts {
    at: [[f64; 4]; 4],
    unit: [Option<usize>; 4],
}

impl Verts {
    fn new(at: [[f64; 4]; 4]) -> Verts {
        Verts {
            unit: at.map(|v| unit_index(&v)),
            at,
        }
    }
}

/// `Some(k)` when `v` is the unit vector `e_k` exactly.
fn unit_index(v: &[f64; 4]) -> Option<usize> {
    let k = v.iter().position(|&x| x == 1.0)?;
    v.iter()
        .enumerate()
        .all(|(i, &x)| i == k || x == 0.0)
        .then_some(k)
}

impl EdgeCubic {
    /// Builds the edge cubic for the mesh edge `(p_i, p_j)` from the face cubics on its two
    /// sides: `face_k` (apex `u_k`) and `face_l` (apex `u_l`). The free parameters of both
    /// faces must already be set (the edge cubic depends on them linearly).
    pub fn new(
        pi: DVec3,
        pj: DVec3,
        face_k: &FaceCubic,
        face_l: &FaceCubic,
    ) -> Result<Self, ApatchError> {
        Self::from_neighbours(
            pi,
            pj,
            &face_k.edge_neighbour(pi, pj)?,
            &face_l.edge_neighbour(pi, pj)?,
        )
    }

    /// Builds the edge cubic from the two sides' [`EdgeNeighbour`]s (convex or split faces).
    pub fn from_neighbours(
        pi: DVec3,
        pj: DVec3,
        k: &EdgeNeighbour,
        l: &EdgeNeighbour,
    ) -> Result<Self, ApatchError> {
        let tet = Tetrahedron::new([l.tet.vertex(3), pi, pj, k.tet.vertex(3)])?;
        Ok(Self::from_parts(
            tet,
            (&k.tet, &cubic::coeffs_of(&k.poly)),
            (&l.tet, &cubic::coeffs_of(&l.poly)),
        ))
    }

    /// The edge cubic on the edge tetrahedron `tet` = `[u_l, p_i, p_j, u_k]` between the faces
    /// `face_k` and `face_l` ([`EdgeCubic::from_neighbours`] of their
    /// [`FaceFunction::edge_neighbour`]s on `side`, without copying a face's tetrahedron or
    /// allocating a polynomial). `tet` is the hull's edge tetrahedron
    /// ([`algesurf_hull::EdgeTetrahedron`]), built once by the hull and not again here.
    pub(crate) fn between(
        face_k: &FaceFunction,
        face_l: &FaceFunction,
        side: Side,
        tet: &Tetrahedron,
    ) -> Result<Self, ApatchError> {
        let (pi, pj) = (tet.vertex(1), tet.vertex(2));
        let (k, l) = (
            face_k.edge_piece(side, pi, pj)?,
            face_l.edge_piece(side, pi, pj)?,
        );
        Ok(Self::from_parts(
            *tet,
            (k.tet, &k.coeffs()),
            (l.tet, &l.coeffs()),
        ))
    }

    /// [`EdgeCubic::from_neighbours`] from the edge tetrahedron `[u_l, p_i, p_j, u_k]` and each
    /// side's tetrahedron (apex `u_k`, `u_l` last) and coefficients.
    fn from_parts(
        tet: Tetrahedron,
        (tk, pk): (&Tetrahedron, &cubic::Coeffs),
        (tl, pl): (&Tetrahedron, &cubic::Coeffs),
    ) -> Self {
        let [ul, pi, pj, uk] = *tet.vertices();
        debug_assert_eq!(
            (tk.vertex(3), tl.vertex(3)),
            (uk, ul),
            "the edge tetrahedron's apexes are its neighbours'"
        );
        let verts = |t: &Tetrahedron| {
            let bary = |p: DVec3| exact_barycentric(t, p);
            Verts::new([bary(ul), bary(pi), bary(pj), bary(uk)])
        };
        let (vk, vl) = (verts(tk), verts(tl));
        // Running extremes from 0 (`algesurf_bb::extremes`): the same values as `f64::max`.
        let scale = max_not_nan(max_not_nan(max_abs(pk), max_abs(pl)), f64::MIN_POSITIVE);
        let mut coeffs = [0.0; 20];
        let mut mismatch: f64 = 0.0;
        let mut rational = [[0.0; 2]; 2];
        for (lambda, slot) in cubic::INDICES3.into_iter().zip(coeffs.iter_mut()) {
            let from_k = (lambda[0] <= 1).then(|| blossom_at(pk, &vk, lambda));
            let from_l = (lambda[3] <= 1).then(|| blossom_at(pl, &vl, lambda));
            match lambda {
                [1, 1, 0, 1] | [1, 0, 1, 1] => {
                    let m = if lambda[1] == 1 { 0 } else { 1 };
                    rational[m] = [from_l.expect("λ3 = 1"), from_k.expect("λ0 = 1")];
                }
                _ => match (from_k, from_l) {
                    (Some(k), Some(l)) => {
                        mismatch = max_not_nan(mismatch, (k - l).abs() / scale);
                        *slot = k;
                    }
                    (Some(k), None) => *slot = k,
                    (None, Some(l)) => *slot = l,
                    (None, None) => unreachable!("λ0 + λ3 ≤ 3 means one of them is ≤ 1"),
                },
            }
        }
        EdgeCubic {
            tet,
            poly: BbPoly::new(3, coeffs.to_vec()).expect("20 coefficients"),
            rational,
            overlap_mismatch: mismatch,
        }
    }

    /// [`EdgeCubic::from_neighbours`] for neighbours whose polynomials are both the apex square
    /// `τ_apex²` (as [`crate::geometry::add_apex_square`] adds it): the lift of Step 6, how the
    /// edge cubic moves per unit of a common increment of the two faces' apex values. `tet_k`,
    /// `tet_l` are the neighbours' tetrahedra (apex last, containing `p_i` and `p_j`).
    ///
    /// In closed form instead of 40 general blossoms: `τ²` elevated to a cubic has the blossom
    /// `(τ(x)τ(y) + τ(x)τ(z) + τ(y)τ(z))/3`, and at the edge tetrahedron's vertices
    /// `[u_l, p_i, p_j, u_k]` the `k` side's apex coordinate is `[α_k, 0, 0, 1]` (`p_i`, `p_j`
    /// are its face vertices, `u_k` its apex; `α_k` that of `u_l`), the `l` side's
    /// `[1, 0, 0, α_l]`. The coefficients with `λ_0 ≤ 1` come from `k`, the others from `l`, as
    /// in `from_neighbours`; both agree on the overlap (exactly, in exact arithmetic), so the
    /// mismatch is 0.
    ///
    /// `edge` is the edge cubic between the same two neighbours on the same side, whose
    /// tetrahedron `[u_l, p_i, p_j, u_k]` the lift shares: copied, not built again (Step 6 runs
    /// for every edge tetrahedron, 146 k on the Stanford bunny, and building one inverts its
    /// edge matrix).
    pub(crate) fn apex_square_lift(
        edge: &EdgeCubic,
        tet_k: &Tetrahedron,
        tet_l: &Tetrahedron,
    ) -> Self {
        let tet = edge.tet;
        let (uk, ul) = (tet_k.vertex(3), tet_l.vertex(3));
        debug_assert_eq!(
            (tet.vertex(0), tet.vertex(3)),
            (ul, uk),
            "the same neighbours"
        );
        let alpha_k = exact_barycentric(tet_k, ul)[3];
        let alpha_l = exact_barycentric(tet_l, uk)[3];
        let tau_k = [alpha_k, 0.0, 0.0, 1.0];
        let tau_l = [1.0, 0.0, 0.0, alpha_l];
        // The elevated blossom of τ² at the vertices repeated as λ says.
        let blossom = |tau: &[f64; 4], lambda: [usize; 4]| {
            let [x, y, z] = cubic::arg_vertices(lambda).map(|s| tau[s]);
            (x * y + x * z + y * z) / 3.0
        };
        // A loop, not `INDICES3.map`: the map's closure was compiled out of line, a call per
        // coefficient (104 M instructions on the bunny's 2.9 M edge cubics, `callgrind`).
        let mut coeffs = [0.0; 20];
        for (x, &lambda) in coeffs.iter_mut().zip(&cubic::INDICES3) {
            *x = match lambda {
                // The rational term's coefficients; the polynomial part is zero there.
                [1, 1, 0, 1] | [1, 0, 1, 1] => 0.0,
                _ if lambda[0] <= 1 => blossom(&tau_k, lambda),
                _ => blossom(&tau_l, lambda),
            };
        }
        let at = |lambda| [blossom(&tau_l, lambda), blossom(&tau_k, lambda)];
        EdgeCubic {
            tet,
            poly: BbPoly::new(3, coeffs.to_vec()).expect("20 coefficients"),
            rational: [at([1, 1, 0, 1]), at([1, 0, 1, 1])],
            overlap_mismatch: 0.0,
        }
    }

    /// Largest disagreement, relative to the coefficient size, between the coefficients both
    /// neighbours determine: ~1e-16 when the face cubics are consistent along the edge.
    pub fn overlap_mismatch(&self) -> f64 {
        self.overlap_mismatch
    }

    /// The edge tetrahedron `[u_l, p_i, p_j, u_k]`.
    pub fn tetrahedron(&self) -> &Tetrahedron {
        &self.tet
    }

    /// The polynomial part.
    pub fn polynomial(&self) -> &BbPoly<f64, 4> {
        &self.poly
    }

    /// `[[a_1101, b_1101], [a_1011, b_1011]]` of (4.3).
    pub fn rational(&self) -> [[f64; 2]; 2] {
        self.rational
    }

    /// F at barycentric coordinates `tau`.
    pub fn value(&self, tau: [f64; 4]) -> f64 {
        cubic::value(&cubic::coeffs_of(&self.poly), tau) + edge_term(tau, self.rational).0
    }

    /// F and its Cartesian gradient at `x`.
    pub fn value_gradient(&self, x: DVec3) -> (f64, DVec3) {
        value_gradient_with(&self.tet, &self.poly, x, |tau| {
            edge_term(tau, self.rational)
        })
    }

    /// Barycentric end points of the ray (4.9) from `q = x p_i + (1 − x) p_j` to
    /// `u = y u_k + (1 − y) u_l`.
    pub(crate) fn ray_ends(x: f64, y: f64) -> ([f64; 4], [f64; 4]) {
        ([0.0, x, 1.0 - x, 0.0], [1.0 - y, 0.0, 0.0, y])
    }

    /// Cartesian gradient of F at barycentric coordinates `tau`.
    pub(crate) fn gradient_at_tau(&self, tau: [f64; 4]) -> DVec3 {
        self.value_gradient_at_tau(tau).1
    }

    /// [`EdgeCubic::value`] and the Cartesian gradient at `tau`, from one pass of de
    /// Casteljau's algorithm (the value's bits are [`EdgeCubic::value`]'s).
    pub(crate) fn value_gradient_at_tau(&self, tau: [f64; 4]) -> (f64, DVec3) {
        let (fp, dp) = cubic::value_partials(&cubic::coeffs_of(&self.poly), tau);
        let (fr, dr) = edge_term(tau, self.rational);
        (fp + fr, gradient_from_partials(&self.tet, dp, dr))
    }

    /// The shooting polynomials (4.9) of every ray of the patch at once: coefficient `k` of
    /// [`EdgeCubic::shooting_polynomial`]`(x, y)` as a polynomial of bidegree (3, 3) in
    /// `(x, y)`, in tensor Bernstein form ([`Tensor3`], `c[i][j]` at `B_i^3(x) B_j^3(y)`).
    ///
    /// Coefficient `k` of the polynomial part is the blossom `b[q^{3−k}, u^k]` at the ray's
    /// ends `q = x e_1 + (1 − x) e_2` and `u = (1 − y) e_0 + y e_3`
    /// ([`EdgeCubic::ray_ends`]). Expanding each argument multi-affinely gives Bernstein
    /// polynomials of degree `3 − k` in `x` and `k` in `y` whose coefficients are blossoms at
    /// the tetrahedron's vertices, which are its BB coefficients: `B_i^{3−k}(x) B_j^k(y)`
    /// carries `b_{(k−j, i, 3−k−i, j)}`. The rational part of `k = 2` is
    /// `2y(1−y)(x·blend₁ + (1−x)·blend₂)` with `blend_m = (1−y)a_m + y b_m`, that is
    /// `⅔ [B_1^3(y)(x a₁ + (1−x) a₂) + B_2^3(y)(x b₁ + (1−x) b₂)]`. Degree elevation to (3, 3)
    /// is the only arithmetic, so the result is exact up to one rounding per elevation step;
    /// sampling 16 rays and interpolating ([`interpolate_tensor3`]), as Step 6 did before,
    /// costs 16 shooting polynomials and amplifies their rounding by the collocation
    /// inverse's weights (up to 18/6).
    ///
    /// [`Tensor3`]: algesurf_bb::sheet::square::Tensor3
    /// [`interpolate_tensor3`]: algesurf_bb::sheet::square::interpolate_tensor3
    pub(crate) fn shooting_tensor(&self) -> [Tensor3; 4] {
        let c = cubic::coeffs_of(&self.poly);
        let mut out = [[[0.0; 4]; 4]; 4];
        for (k, t) in out.iter_mut().enumerate() {
            // Degree 3 − k in x, k in y, then elevated to 3 in each.
            let nx = 3 - k;
            let mut low = [[0.0; 4]; 4];
            for (i, row) in low.iter_mut().enumerate().take(nx + 1) {
                for (j, v) in row.iter_mut().enumerate().take(k + 1) {
                    *v = c[cubic::rank3([k - j, i, nx - i, j])];
                }
            }
            let rows: [[f64; 4]; 4] = std::array::from_fn(|i| elevate_to_cubic(low[i], k));
            for j in 0..4 {
                let col = elevate_to_cubic(std::array::from_fn(|i| rows[i][j]), nx);
                for i in 0..4 {
                    t[i][j] = col[i];
                }
            }
        }
        let [[a1, b1], [a2, b2]] = self.rational;
        let linear = |f0: f64, f1: f64| [f0, (2.0 * f0 + f1) / 3.0, (f0 + 2.0 * f1) / 3.0, f1];
        let (ya, yb) = (linear(a2, a1), linear(b2, b1));
        for i in 0..4 {
            out[2][i][1] += 2.0 / 3.0 * ya[i];
            out[2][i][2] += 2.0 / 3.0 * yb[i];
        }
        out
    }

    /// Coefficients of the shooting polynomial (4.9) from `q = x p_i + (1 − x) p_j` to
    /// `u = y u_k + (1 − y) u_l`.
    pub fn shooting_polynomial(&self, x: f64, y: f64) -> [f64; 4] {
        let (a, b) = Self::ray_ends(x, y);
        let mut c = cubic::segment(&cubic::coeffs_of(&self.poly), a, b);
        // The rational part only touches B_2 (4.9): along the segment τ = (1−t)a + t b the
        // term is 6 t²(1−t) (x or 1−x) y(1−y) · blend, with blend = (1−y)·a_m + y·b_m because
        // τ0 : τ3 = (1 − y) : y is constant along the segment.
        let [[a1, b1], [a2, b2]] = self.rational;
        let blend1 = (1.0 - y) * a1 + y * b1;
        let blend2 = (1.0 - y) * a2 + y * b2;
        // 6 t²(1−t) = 2 B_2^3(t).
        c[2] += 2.0 * y * (1.0 - y) * (x * blend1 + (1.0 - x) * blend2);
        c
    }
}

/// The Bernstein coefficients of degree 3 of the polynomial with coefficients `c[..=n]` of
/// degree `n ≤ 3`: `c'_r = Σ_i C(n, i) C(3 − n, r − i) / C(3, r) · c_i` (degree elevation,
/// Farin, *Curves and Surfaces for CAGD*, §6.9, applied 3 − n times at once).
fn elevate_to_cubic(c: [f64; 4], n: usize) -> [f64; 4] {
    match n {
        0 => [c[0]; 4],
        1 => [
            c[0],
            (2.0 * c[0] + c[1]) / 3.0,
            (c[0] + 2.0 * c[1]) / 3.0,
            c[1],
        ],
        2 => [
            c[0],
            (c[0] + 2.0 * c[1]) / 3.0,
            (2.0 * c[1] + c[2]) / 3.0,
            c[2],
        ],
        _ => c,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use algesurf_bb::sheet::square::{interpolate_tensor3, tensor3_value};
    use algesurf_mesh::test_rng::Lcg;

    /// The shortcut of `blossom_at` gives the three-step blossom's bits, for every coefficient
    /// with unit vectors and one general point among the arguments, in every position.
    #[test]
    fn blossom_at_unit_vectors_is_the_full_blossom_bit_for_bit() {
        let mut rng = Lcg(11);
        for _ in 0..50 {
            let poly: cubic::Coeffs = std::array::from_fn(|_| 2.0 * rng.centred() - 1.0);
            let general = [0.3, -0.2, 1.1, -0.2].map(|x| x + 0.1 * rng.centred());
            for g in 0..4 {
                // Vertex `g` general, the others unit vectors in some order.
                let mut verts = [[0.0; 4]; 4];
                let mut next = 0;
                for (s, v) in verts.iter_mut().enumerate() {
                    if s == g {
                        *v = general;
                    } else {
                        v[(next + g) % 4] = 1.0;
                        next += 1;
                    }
                }
                for lambda in cubic::INDICES3 {
                    let [a, b, d] = cubic::blossom_args(&verts, lambda);
                    let full = cubic::blossom(&poly, a, b, d);
                    let fast = blossom_at(&poly, &Verts::new(verts), lambda);
                    assert_eq!(full.to_bits(), fast.to_bits(), "{verts:?} {lambda:?}");
                }
            }
        }
    }

    /// The closed-form lift is `from_neighbours` with both polynomials the apex square: every
    /// coefficient and rational term to rounding, on random neighbour tetrahedra.
    #[test]
    fn apex_square_lift_is_the_edge_cubic_of_two_apex_squares() {
        let mut rng = Lcg(5);
        for case in 0..30 {
            let pi = DVec3::new(-1.0, 0.0, 0.0) + 0.2 * rng.vec();
            let pj = DVec3::new(1.0, 0.0, 0.0) + 0.2 * rng.vec();
            let tet = |rng: &mut Lcg, y: f64| {
                Tetrahedron::new([
                    pi,
                    pj,
                    DVec3::new(0.0, y, -0.5) + 0.2 * rng.vec(),
                    DVec3::new(0.0, 0.3 * y, 1.0) + 0.2 * rng.vec(),
                ])
                .unwrap()
            };
            let (tk, tl) = (tet(&mut rng, 1.0), tet(&mut rng, -1.0));
            let sq = crate::geometry::apex_square();
            let general = EdgeCubic::from_neighbours(
                pi,
                pj,
                &EdgeNeighbour {
                    tet: tk,
                    poly: sq.clone(),
                },
                &EdgeNeighbour { tet: tl, poly: sq },
            )
            .unwrap();
            let lift = EdgeCubic::apex_square_lift(&general, &tk, &tl);
            let scale = general.polynomial().max_coeff_norm();
            for (a, b) in lift
                .polynomial()
                .coeffs()
                .iter()
                .zip(general.polynomial().coeffs())
            {
                assert!((a - b).abs() <= 1e-14 * scale, "case {case}: {a} {b}");
            }
            for (a, b) in lift
                .rational()
                .iter()
                .flatten()
                .zip(general.rational().iter().flatten())
            {
                assert!((a - b).abs() <= 1e-14 * scale, "case {case}: {a} {b}");
            }
            assert!(
                lift.rational().iter().flatten().any(|v| v.abs() > 1e-3),
                "case {case}: the rational terms are exercised"
            );
        }
    }

    /// The tensor form of the shooting polynomials is every ray's shooting polynomial: at
    /// random `(x, y)`, and against interpolating 16 rays, for random cubics on both sides
    /// (so the rational terms are nonzero).
    #[test]
    fn shooting_tensor_gives_every_rays_shooting_polynomial() {
        let mut rng = Lcg(31);
        for case in 0..20 {
            let pi = DVec3::new(-1.0, 0.0, 0.0) + 0.2 * rng.vec();
            let pj = DVec3::new(1.0, 0.0, 0.0) + 0.2 * rng.vec();
            let side = |rng: &mut Lcg, y: f64| EdgeNeighbour {
                tet: Tetrahedron::new([
                    pi,
                    pj,
                    DVec3::new(0.0, y, -0.5) + 0.2 * rng.vec(),
                    DVec3::new(0.0, 0.3 * y, 1.0) + 0.2 * rng.vec(),
                ])
                .unwrap(),
                poly: BbPoly::new(3, (0..20).map(|_| 2.0 * rng.centred() - 1.0).collect()).unwrap(),
            };
            let (k, l) = (side(&mut rng, 1.0), side(&mut rng, -1.0));
            let e = EdgeCubic::from_neighbours(pi, pj, &k, &l).unwrap();
            let r = e.rational();
            assert!(
                r.iter().flatten().any(|v| v.abs() > 1e-3),
                "case {case}: {r:?}"
            );
            let t = e.shooting_tensor();
            let nodes = |k: usize| -> Tensor3 {
                std::array::from_fn(|a| {
                    std::array::from_fn(|b| {
                        e.shooting_polynomial(a as f64 / 3.0, b as f64 / 3.0)[k]
                    })
                })
            };
            for k in 0..4 {
                let sampled = interpolate_tensor3(&nodes(k));
                for i in 0..4 {
                    for j in 0..4 {
                        assert!(
                            (t[k][i][j] - sampled[i][j]).abs() < 1e-13,
                            "case {case}, k {k}, ({i}, {j}): {} vs {}",
                            t[k][i][j],
                            sampled[i][j]
                        );
                    }
                }
            }
            for _ in 0..10 {
                let (x, y) = (rng.centred(), rng.centred());
                let direct = e.shooting_polynomial(x, y);
                for k in 0..4 {
                    let v = tensor3_value(&t[k], x, y);
                    assert!(
                        (v - direct[k]).abs() < 1e-13,
                        "case {case}: {v} vs {}",
                        direct[k]
                    );
                }
            }
        }
    }
}
