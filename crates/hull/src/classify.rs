//! Edge and face convexity (§3) and the apex parameters of the face tetrahedra (§3.1).

use glam::DVec3;

/// The convexity class of an edge or a face (§3, Fig. 5).
///
/// For an edge `[p_i p_j]` with vertex normals `n_i`, `n_j` let `a = (p_j − p_i)ᵀ n_j` and
/// `b = (p_i − p_j)ᵀ n_i` (see [`edge_slopes`]). The edge is
/// * [`Convexity::PositiveConvex`] if `a·b ≥ 0` and at least one of them is positive,
/// * [`Convexity::ZeroConvex`] if both are zero,
/// * [`Convexity::NegativeConvex`] if `a·b ≥ 0` and at least one is negative,
/// * [`Convexity::Nonconvex`] if `a·b < 0`.
///
/// A face is positive convex if its three edges are positive or zero convex and at least one is
/// positive convex, zero convex if all three are zero convex, negative convex likewise, and
/// nonconvex otherwise ([`classify_face`]).
///
/// Consequences used by the hull (§3.2): a positive convex edge has no negative convex or zero
/// convex face (such faces have no positive edge), so both its faces carry a positive apex
/// `u`; a nonconvex edge makes both its faces nonconvex, so both carry `u` and `v`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Convexity {
    /// Curved towards the positive side: the surface lies in the positive face tetrahedra.
    PositiveConvex,
    /// Flat: the surface is the planar face (or straight edge) itself; no tetrahedra.
    ZeroConvex,
    /// Curved towards the negative side.
    NegativeConvex,
    /// Mixed: tetrahedra on both sides.
    Nonconvex,
}

impl Convexity {
    /// True when elements of this class carry positive tetrahedra (apex `u`): positive
    /// convex or nonconvex (§3.1).
    pub fn has_positive_side(self) -> bool {
        matches!(self, Convexity::PositiveConvex | Convexity::Nonconvex)
    }
    /// True when elements of this class carry negative tetrahedra (apex `v`): negative convex
    /// or nonconvex (§3.1).
    pub fn has_negative_side(self) -> bool {
        matches!(self, Convexity::NegativeConvex | Convexity::Nonconvex)
    }
}

/// The side of the surface a tetrahedron lies on: positive is where the vertex normals point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// Apex `u`, `t ≥ 0` along the face normal.
    Positive,
    /// Apex `v`, `t ≤ 0` along the face normal.
    Negative,
}

impl Side {
    /// "positive" or "negative".
    pub fn name(self) -> &'static str {
        match self {
            Side::Positive => "positive",
            Side::Negative => "negative",
        }
    }
}

/// The two numbers of §3 for edge `[p_i p_j]`: `[a, b] = [(p_j − p_i)ᵀ n_j, (p_i − p_j)ᵀ n_i]`.
///
/// `a > 0` means `p_i` lies below the tangent plane at `p_j` (on the negative side), and
/// likewise for `b`.
pub fn edge_slopes(pi: DVec3, pj: DVec3, ni: DVec3, nj: DVec3) -> [f64; 2] {
    let d = pj - pi;
    [d.dot(nj), -d.dot(ni)]
}

/// Classifies edge `[p_i p_j]` (§3).
///
/// `a` counts as zero when `|a| ≤ tol · |p_j − p_i| · |n_j|` (and `b` likewise with `n_i`): with
/// unit normals `a / |p_j − p_i|` is the sine of the angle between the edge and the tangent
/// plane at `p_j`, so `tol` is an angle in radians. See [`crate::HullOptions::zero_tolerance`]
/// for why its default is `1e-9`.
pub fn classify_edge(pi: DVec3, pj: DVec3, ni: DVec3, nj: DVec3, tol: f64) -> Convexity {
    let [a, b] = edge_slopes(pi, pj, ni, nj);
    let len = pi.distance(pj);
    let sign = |x: f64, n: DVec3| -> i8 {
        if x.abs() <= tol * len * n.length() {
            0
        } else if x > 0.0 {
            1
        } else {
            -1
        }
    };
    match (sign(a, nj), sign(b, ni)) {
        (0, 0) => Convexity::ZeroConvex,
        (x, y) if x * y < 0 => Convexity::Nonconvex,
        (x, y) if x > 0 || y > 0 => Convexity::PositiveConvex,
        _ => Convexity::NegativeConvex,
    }
}

/// Classifies a face from the classes of its three edges (§3).
pub fn classify_face(edges: [Convexity; 3]) -> Convexity {
    use Convexity::*;
    if edges.iter().all(|&e| e == ZeroConvex) {
        ZeroConvex
    } else if edges
        .iter()
        .all(|&e| matches!(e, PositiveConvex | ZeroConvex))
    {
        PositiveConvex
    } else if edges
        .iter()
        .all(|&e| matches!(e, NegativeConvex | ZeroConvex))
    {
        NegativeConvex
    } else {
        Nonconvex
    }
}

/// `α(c, p_m, p_l) = [2(c − p_l) + (c − p_m)]ᵀ(p_m − p_l) / ‖p_m − p_l‖²`, equation (3.1), in
/// the paper's argument order.
///
/// Meaning (derived, and checked by the tests): with `s` the parameter of the foot of `c` on
/// the line `p_m + s (p_l − p_m)`, `α = 2 − 3s`. It is the weight that makes the mid-edge
/// coefficient of a cubic on the triangle `[c p_m p_l]` interpolate the averaged normal
/// derivative at the edge midpoint (Steps 3–4 of §4.2, [`mid_edge_coefficient`]).
/// `α(c, p_l, p_m) = 1 − α(c, p_m, p_l)`.
pub fn alpha(c: DVec3, pm: DVec3, pl: DVec3) -> f64 {
    let d = pm - pl;
    (2.0 * (c - pl) + (c - pm)).dot(d) / d.length_squared()
}

/// The mid-edge Bézier coefficient of Steps 3–4 of §4.2 for the edge `[p_a p_b]` of the
/// triangle `[w p_a p_b]`, with `F(p_a) = F(p_b) = 0` and `∇F(p_a) = n_a`, `∇F(p_b) = n_b`:
///
/// `½ [A_a + A_b + α E_a + (1 − α) E_b]`, `A_x = ⅓ (w − p_x)ᵀ n_x`, `E_a = ⅓ (p_b − p_a)ᵀ n_a`,
/// `E_b = ⅓ (p_a − p_b)ᵀ n_b`, `α = α(w, p_a, p_b)` (3.1).
///
/// With `w = p_k` this is the right side of (4.10)–(4.12); with `w = u_ijk` it is
/// `f_0111`, `f_1101`, `f_1011` of Step 4, which `t_lm` of §3.1 makes nonnegative.
pub fn mid_edge_coefficient(w: DVec3, pa: DVec3, pb: DVec3, na: DVec3, nb: DVec3) -> f64 {
    let al = alpha(w, pa, pb);
    let aa = (w - pa).dot(na) / 3.0;
    let ab = (w - pb).dot(nb) / 3.0;
    let ea = (pb - pa).dot(na) / 3.0;
    let eb = (pa - pb).dot(nb) / 3.0;
    0.5 * (aa + ab + al * ea + (1.0 - al) * eb)
}

/// The parameters of §3.1 for one face `[p_i p_j p_k]`: `u = c + t_max n_ijk`,
/// `v = c + t_min n_ijk`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApexParameters {
    /// `t_i, t_j, t_k`: `(c − p_l + t_l n_ijk)ᵀ n_l = 0`, i.e. `t_l = (p_l − c)ᵀn_l / n_ijkᵀn_l`.
    /// For `t > t_l` the point `c + t n_ijk` is above the tangent plane at `p_l`.
    pub t_vertex: [f64; 3],
    /// `t_ij, t_jk, t_ik` (the paper's order): for `t ≥ t_lm` the Step 4 coefficient of the
    /// edge `[p_l p_m]` is nonnegative (see [`mid_edge_coefficient`]), for `t ≤ t_lm`
    /// nonpositive.
    pub t_edge: [f64; 3],
    /// The `ε > 0` used.
    pub epsilon: f64,
    /// `max{0, t_i + ε, t_j + ε, t_k + ε, t_ij, t_jk, t_ik}`.
    pub t_max: f64,
    /// `min{0, t_i − ε, t_j − ε, t_k − ε, t_ij, t_jk, t_ik}`.
    pub t_min: f64,
}

/// Computes [`ApexParameters`] for the face with corners `p`, vertex normals (gradients) `n`
/// and unit face normal `face_normal` (pointing to the positive side).
///
/// `t_lm` (§3.1), derived from Step 4 of §4.2: the coefficient
/// `½[(u − p_l)ᵀn_l + (u − p_m)ᵀn_m + α (p_m − p_l)ᵀn_l + (1 − α)(p_l − p_m)ᵀn_m] / 3` with
/// `u = c + t n_ijk` and `α = α(u, p_l, p_m) = α(c, p_l, p_m)` (the foot of `u` on the edge is
/// the foot of `c`, as `n_ijk` is orthogonal to the edge) is affine in `t` with slope
/// `(n_l + n_m)ᵀ n_ijk / 6 > 0` and vanishes at
///
/// `t_lm = {[p_l − c + α(c, p_l, p_m)(p_l − p_m)]ᵀn_l + [p_m − c + α(c, p_m, p_l)(p_m − p_l)]ᵀn_m}
///         / (n_l + n_m)ᵀ n_ijk`,
///
/// which is the paper's formula.
///
/// # Errors
/// `Err(corner)` for the first corner `l` with `n_ijkᵀ n_l ≤ 0` (or not finite).
pub fn apex_parameters(
    p: [DVec3; 3],
    n: [DVec3; 3],
    face_normal: DVec3,
    epsilon: f64,
) -> Result<ApexParameters, usize> {
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let mut cos = [0.0; 3];
    for l in 0..3 {
        cos[l] = face_normal.dot(n[l]);
        if !(cos[l] > 0.0 && cos[l].is_finite()) {
            return Err(l);
        }
    }
    let t_vertex: [f64; 3] = std::array::from_fn(|l| (p[l] - c).dot(n[l]) / cos[l]);
    let pairs = [(0, 1), (1, 2), (0, 2)];
    let t_edge: [f64; 3] = std::array::from_fn(|e| {
        let (l, m) = pairs[e];
        let al = alpha(c, p[l], p[m]);
        let am = 1.0 - al; // = alpha(c, p[m], p[l])
        let num =
            (p[l] - c + al * (p[l] - p[m])).dot(n[l]) + (p[m] - c + am * (p[m] - p[l])).dot(n[m]);
        num / (cos[l] + cos[m])
    });
    let mut t_max: f64 = 0.0;
    let mut t_min: f64 = 0.0;
    for l in 0..3 {
        t_max = t_max.max(t_vertex[l] + epsilon).max(t_edge[l]);
        t_min = t_min.min(t_vertex[l] - epsilon).min(t_edge[l]);
    }
    Ok(ApexParameters {
        t_vertex,
        t_edge,
        epsilon,
        t_max,
        t_min,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn alpha_is_two_minus_three_s() {
        let (a, b) = (v(0.3, -1.0, 2.0), v(2.5, 0.7, 1.0));
        for s in [-0.5, 0.0, 0.25, 0.5, 1.0, 1.7] {
            let off = (b - a).normalize().any_orthonormal_vector() * 0.8;
            let w = a + s * (b - a) + off;
            assert!((alpha(w, a, b) - (2.0 - 3.0 * s)).abs() < 1e-12);
            assert!((alpha(w, a, b) + alpha(w, b, a) - 1.0).abs() < 1e-12);
        }
    }

    /// The mid-edge coefficient is the one that makes the cubic interpolate the averaged normal
    /// derivative at the edge midpoint: check against a direct derivative of the BB cubic on
    /// the triangle [w a b] with F(a) = F(b) = 0, ∇F(a) = n_a, ∇F(b) = n_b.
    #[test]
    fn mid_edge_coefficient_interpolates_the_normal_derivative() {
        let (w, a, b) = (v(0.2, 1.5, 0.3), v(-1.0, 0.0, 0.1), v(1.2, 0.1, -0.2));
        let (na, nb) = (v(0.1, 0.3, 1.0), v(-0.2, 0.4, 0.9));
        let m = mid_edge_coefficient(w, a, b, na, nb);
        // Coefficients indexed (λ_w, λ_a, λ_b).
        let c = |l: [usize; 3]| -> f64 {
            match l {
                [0, 3, 0] | [0, 0, 3] => 0.0,
                [1, 2, 0] => (w - a).dot(na) / 3.0,
                [1, 0, 2] => (w - b).dot(nb) / 3.0,
                [0, 2, 1] => (b - a).dot(na) / 3.0,
                [0, 1, 2] => (a - b).dot(nb) / 3.0,
                [1, 1, 1] => m,
                _ => f64::NAN,
            }
        };
        // Derivative at (0, ½, ½) in the barycentric direction d: 3 Σ_{|μ|=2, μ_w=0} B_μ(½,½) Σ_k d_k c(μ+e_k).
        let deriv = |d: [f64; 3]| {
            let mut s = 0.0;
            for (mu, bw) in [([0, 2, 0], 0.25), ([0, 1, 1], 0.5), ([0, 0, 2], 0.25)] {
                for k in 0..3 {
                    let mut l = mu;
                    l[k] += 1;
                    if d[k] != 0.0 {
                        s += bw * d[k] * c(l);
                    }
                }
            }
            3.0 * s
        };
        // Direction in the plane, perpendicular to the edge: w − foot.
        let sft = (w - a).dot(b - a) / (b - a).length_squared();
        let dir = [1.0, -(1.0 - sft), -sft];
        let target = 0.5 * (w - (a + sft * (b - a))).dot(na + nb);
        assert!(
            (deriv(dir) - target).abs() < 1e-12,
            "{} vs {target}",
            deriv(dir)
        );
    }

    #[test]
    fn t_lm_zeroes_the_step4_coefficient() {
        let p = [v(-1.0, 0.0, 0.0), v(1.2, 0.1, 0.2), v(0.1, 1.4, -0.1)];
        let n = [
            v(-0.3, -0.2, 1.0).normalize(),
            v(0.4, -0.1, 1.0).normalize(),
            v(0.0, 0.5, 1.0).normalize(),
        ];
        let nf = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let c = (p[0] + p[1] + p[2]) / 3.0;
        let ap = apex_parameters(p, n, nf, 0.1).unwrap();
        for (e, (l, m)) in [(0, 1), (1, 2), (0, 2)].into_iter().enumerate() {
            let u = c + ap.t_edge[e] * nf;
            assert!(mid_edge_coefficient(u, p[l], p[m], n[l], n[m]).abs() < 1e-12);
            let u = c + (ap.t_edge[e] + 0.1) * nf;
            assert!(mid_edge_coefficient(u, p[l], p[m], n[l], n[m]) > 0.0);
        }
        for l in 0..3 {
            let u = c + ap.t_vertex[l] * nf;
            assert!((u - p[l]).dot(n[l]).abs() < 1e-12);
        }
        assert!(ap.t_max >= ap.t_vertex.iter().fold(0.0f64, |a, &b| a.max(b)) + 0.1);
        assert!(apex_parameters(p, [n[0], n[1], -nf], nf, 0.1) == Err(2));
    }

    #[test]
    fn classification_table() {
        use Convexity::*;
        let (a, b) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0));
        let up = DVec3::Z;
        assert_eq!(classify_edge(a, b, up, up, 1e-9), ZeroConvex);
        // Tilts of 1e-12 rad count as zero, 1e-6 do not.
        let t = |x: f64| v(x, 0.0, 1.0).normalize();
        assert_eq!(classify_edge(a, b, t(-1e-12), t(1e-12), 1e-9), ZeroConvex);
        assert_eq!(classify_edge(a, b, t(-1e-6), t(1e-6), 1e-9), PositiveConvex);
        assert_eq!(classify_edge(a, b, up, t(1e-6), 1e-9), PositiveConvex);
        assert_eq!(classify_edge(a, b, t(1e-6), t(-1e-6), 1e-9), NegativeConvex);
        assert_eq!(classify_edge(a, b, t(1e-6), t(1e-6), 1e-9), Nonconvex);
        // Scale invariance of the tolerance.
        assert_eq!(
            classify_edge(a * 1e6, b * 1e6, t(-1e-12), t(1e-12), 1e-9),
            ZeroConvex
        );
        assert_eq!(
            classify_face([PositiveConvex, ZeroConvex, ZeroConvex]),
            PositiveConvex
        );
        assert_eq!(classify_face([ZeroConvex; 3]), ZeroConvex);
        assert_eq!(
            classify_face([NegativeConvex, ZeroConvex, NegativeConvex]),
            NegativeConvex
        );
        assert_eq!(
            classify_face([PositiveConvex, NegativeConvex, ZeroConvex]),
            Nonconvex
        );
        assert_eq!(
            classify_face([PositiveConvex, Nonconvex, PositiveConvex]),
            Nonconvex
        );
    }
}
