//! Small geometric helpers shared by the modules: bounding boxes, polygon (Newell) normals,
//! triangle areas and the relative tolerances derived from the bounding-box diagonal.

use glam::DVec3;

/// An axis-aligned bounding box in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: DVec3,
    /// Maximum corner.
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (min = +inf, max = -inf); `extend` makes it non-empty.
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };

    /// A box from two corners (taken componentwise, so their order does not matter).
    pub fn new(a: DVec3, b: DVec3) -> Aabb {
        Aabb {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The bounding box of the finite points among `points` (non-finite ones are skipped).
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a DVec3>) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            if p.is_finite() {
                b.extend(*p);
            }
        }
        b
    }

    /// Grows the box to contain `p`.
    pub fn extend(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// True when the box contains no point.
    pub fn is_empty(&self) -> bool {
        !(self.min.cmple(self.max).all())
    }

    /// Length of the diagonal (0 for an empty box or a single point).
    pub fn diagonal(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            (self.max - self.min).length()
        }
    }

    /// True when the two (closed) boxes share at least one point.
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// True when the (closed) box contains `p`.
    pub fn contains(&self, p: DVec3) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }

    /// Squared distance from `p` to the box (0 inside).
    pub fn distance_squared(&self, p: DVec3) -> f64 {
        let d = (self.min - p).max(p - self.max).max(DVec3::ZERO);
        d.length_squared()
    }

    /// An origin for the points of a box that lies far from the global origin, chosen so
    /// that moving there is exact: for every point `p` in the box, `p − o` is computed
    /// without rounding and `(p − o) + o == p`. `DVec3::ZERO` in the axes (or the whole box)
    /// where the box is not far.
    ///
    /// Why: a mesh of size `d` placed at distance `D ≫ d` from the origin carries absolute
    /// coordinates whose rounding, `ε·D`, is `ε·D/d` relative to the mesh, and every quantity
    /// formed from them (a face's centroid, an apex on a line through it, a quadric's value)
    /// inherits it. The A-patch surface's split faces need their apexes and centroids
    /// collinear to ~1e-8 of the face size: the corpus's cow and Suzanne moved by 1000 failed
    /// to build ("the split-face constraints are inconsistent"), a torus of radius 2 from
    /// 10⁵, and the C1 figures grew in proportion to `D` before that. In coordinates about
    /// `o` the same mesh is as precise as one at the origin.
    ///
    /// Per axis `k`, `o_k` is the box's midpoint when that is farther from 0 than the box's
    /// diagonal, else 0. Then every coordinate `x` of the box lies in `[o_k/2, 2 o_k]` (the
    /// box's extent is at most its diagonal), so `x − o_k` is exact by Sterbenz's lemma
    /// (Goldberg, "What every computer scientist should know about floating-point
    /// arithmetic", Theorem 11), and adding `o_k` back gives the representable `x`
    /// exactly. The condition is checked on the computed midpoint, not assumed.
    ///
    /// ```
    /// use algesurf_mesh::Aabb;
    /// use glam::DVec3;
    ///
    /// let p = [DVec3::new(1000.1, -3.0, 0.25), DVec3::new(1000.7, 3.0, 0.5)];
    /// let b = Aabb::from_points(&p);
    /// let o = b.exact_local_origin();
    /// // Only x is far (y straddles 0, z is within the diagonal of 0).
    /// assert!(o.x > 1000.0 && o.y == 0.0 && o.z == 0.0);
    /// for q in p {
    ///     assert_eq!((q - o) + o, q);
    /// }
    /// ```
    pub fn exact_local_origin(&self) -> DVec3 {
        if self.is_empty() || !(self.min.is_finite() && self.max.is_finite()) {
            return DVec3::ZERO;
        }
        let diagonal = self.diagonal();
        // `0.5·lo + 0.5·hi` cannot overflow; its rounding does not matter, as the Sterbenz
        // interval is checked with the value computed.
        let axis = |lo: f64, hi: f64| -> f64 {
            let c = 0.5 * lo + 0.5 * hi;
            let far = c.abs() > diagonal && c.is_normal();
            let sterbenz = if c > 0.0 {
                lo >= 0.5 * c && hi <= 2.0 * c
            } else {
                hi <= 0.5 * c && lo >= 2.0 * c
            };
            if far && sterbenz { c } else { 0.0 }
        };
        DVec3::new(
            axis(self.min.x, self.max.x),
            axis(self.min.y, self.max.y),
            axis(self.min.z, self.max.z),
        )
    }
}

/// Inputs whose largest absolute coordinate lies in `[2^-64, 2^64]` keep their scale
/// ([`exact_scale_exponent`]).
pub const ORDINARY_SCALE_EXPONENT: i32 = 64;

/// `2^e`, exactly, for `e` in `[-1022, 1023]` (the exponents of normal `f64`s; others are
/// clamped to that range).
///
/// ```
/// use algesurf_mesh::geometry::power_of_two;
/// assert_eq!(power_of_two(-3), 0.125);
/// assert_eq!(power_of_two(1023), 2f64.powi(1023));
/// ```
pub fn power_of_two(e: i32) -> f64 {
    f64::from_bits(((1023 + e.clamp(-1022, 1023)) as u64) << 52)
}

/// The exponent `e` at which to work on `points` scaled by `2^-e`: 0 when their largest
/// finite absolute coordinate `m` lies in `[2^-64, 2^64]` (or is 0), else the exponent of `m`,
/// so that `m · 2^-e` lies in `[1, 2)` (kept within `[-1022, 1022]`, where both `2^e` and
/// `2^-e` are normal numbers).
///
/// Why: this crate's tolerances are relative to the mesh's size, and scaling by a power of
/// two is exact, so repairing or validating a scaled copy and scaling the result back gives
/// the same result, bit for bit, as long as nothing leaves `f64`'s range. What does leave it
/// are the products of lengths: areas (and the squared diagonal they are compared with)
/// underflow to 0 for coordinates near `2^-270` and overflow near `2^260` in the A-patch
/// construction's fourfold products. Ordinary inputs (5.4e-20 to 1.8e19 in any unit) keep
/// their own scale, so that nothing at all changes for them.
///
/// ```
/// use algesurf_mesh::geometry::{exact_scale_exponent, power_of_two};
/// use glam::DVec3;
/// assert_eq!(exact_scale_exponent(&[DVec3::new(1e6, -3.0, 0.5)]), 0);
/// let tiny = [DVec3::new(3.0 * power_of_two(-300), 0.0, -1e-95)];
/// let e = exact_scale_exponent(&tiny);
/// assert_eq!(e, -299); // 3·2^-300 = 1.5·2^-299
/// assert_eq!(tiny[0].x * power_of_two(-e), 1.5);
/// ```
pub fn exact_scale_exponent(points: &[DVec3]) -> i32 {
    let m = points
        .iter()
        .flat_map(|p| p.to_array())
        .filter(|x| x.is_finite())
        .map(f64::abs)
        .fold(0.0, f64::max);
    let ordinary = power_of_two(-ORDINARY_SCALE_EXPONENT)..=power_of_two(ORDINARY_SCALE_EXPONENT);
    if m == 0.0 || ordinary.contains(&m) {
        return 0;
    }
    // The biased exponent field; 0 for subnormal numbers, which are below 2^-1022 anyway.
    let biased = ((m.to_bits() >> 52) & 0x7ff) as i32;
    (biased - 1023).clamp(-1022, 1022)
}

/// Multiplies `points` by `2^e`: exact, but for results below `2^-1022` (a subnormal result
/// keeps fewer bits), which only an input spanning ~2^1000 between its largest and its
/// smallest non-zero coordinate meets, far below its own rounding.
pub fn scale_by_power_of_two(points: &mut [DVec3], e: i32) {
    if e != 0 {
        let s = power_of_two(e);
        points.iter_mut().for_each(|p| *p *= s);
    }
}

/// Newell's normal of a polygon: a vector perpendicular to the best-fit plane whose length is
/// twice the polygon's (vector) area. Robust for non-convex and slightly non-planar polygons.
pub fn newell_normal(points: &[DVec3]) -> DVec3 {
    let n = points.len();
    if n < 3 {
        return DVec3::ZERO;
    }
    // Work relative to the first point: this removes the translation-dependent cancellation.
    let o = points[0];
    let mut s = DVec3::ZERO;
    for i in 1..n - 1 {
        s += (points[i] - o).cross(points[i + 1] - o);
    }
    s
}

/// Twice the area vector of the triangle `(a, b, c)`: `(b - a) × (c - a)`.
pub fn triangle_normal(a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    (b - a).cross(c - a)
}

/// Area of the triangle `(a, b, c)`.
pub fn triangle_area(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    0.5 * triangle_normal(a, b, c).length()
}

/// The shape of the triangle `(a, b, c)`: twice its area over its longest edge squared, so
/// `√3/2 ≈ 0.87` for an equilateral triangle, `h / l` for one of height `h` over its longest
/// edge `l`, 0 for a flat one and NaN for three equal points. Faces below
/// [`THIN_FACE_SHAPE`] are *thin*.
///
/// ```
/// use algesurf_mesh::geometry::triangle_shape;
/// use glam::DVec3;
/// let s = triangle_shape(DVec3::ZERO, DVec3::X, DVec3::new(0.5, 0.75f64.sqrt(), 0.0));
/// assert!((s - 0.75f64.sqrt()).abs() < 1e-15);
/// assert!(triangle_shape(DVec3::ZERO, DVec3::X, DVec3::new(0.5, 0.01, 0.0)) < 0.05);
/// ```
pub fn triangle_shape(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let longest = a
        .distance_squared(b)
        .max(b.distance_squared(c))
        .max(c.distance_squared(a));
    triangle_normal(a, b, c).length() / longest
}

/// The smallest interior angle of the triangle `(a, b, c)`, in radians (`atan2` of each
/// corner's cross and dot products, accurate for needles and caps alike; 0 for collinear or
/// coinciding corners).
///
/// ```
/// use algesurf_mesh::geometry::triangle_min_angle;
/// use glam::DVec3;
/// let a = triangle_min_angle(DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0));
/// assert!((a - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
/// ```
pub fn triangle_min_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let angle = |p: DVec3, q: DVec3, r: DVec3| {
        let (u, v) = (q - p, r - p);
        u.cross(v).length().atan2(u.dot(v))
    };
    angle(a, b, c).min(angle(b, c, a)).min(angle(c, a, b))
}

/// The [`triangle_shape`] below which a face is *thin*: a height of 1/20 of its longest edge.
/// The simplicial hull's tetrahedra inherit their face's shape, and the Butterfly point of a
/// thin face's long edge moves off the face by about as much as the face is wide, so bisecting
/// thin faces folds the surface instead of separating overlapping tetrahedra
/// (`docs/ARCHITECTURE.md`). The corpus meshes that build have at most 0.1 % of such faces.
pub const THIN_FACE_SHAPE: f64 = 0.05;

/// Signed volume enclosed by the triangles `tris` (positive for an outward-oriented closed
/// surface), computed relative to `origin` to limit cancellation.
pub fn signed_volume(origin: DVec3, tris: impl IntoIterator<Item = [DVec3; 3]>) -> f64 {
    let mut v = 0.0;
    for [a, b, c] in tris {
        let (a, b, c) = (a - origin, b - origin, c - origin);
        v += a.dot(b.cross(c));
    }
    v / 6.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_of_two_are_exact() {
        for e in [-1022, -64, -1, 0, 1, 52, 64, 1023] {
            assert_eq!(power_of_two(e), 2f64.powi(e), "2^{e}");
        }
    }

    #[test]
    fn ordinary_inputs_keep_their_scale() {
        let pts = |m: f64| vec![DVec3::new(m, -0.5 * m, 0.0), DVec3::ZERO];
        for m in [
            power_of_two(-64),
            1e-9,
            1.0,
            1000.0,
            6.0e6,
            power_of_two(64),
        ] {
            assert_eq!(exact_scale_exponent(&pts(m)), 0, "largest coordinate {m:e}");
        }
        assert_eq!(exact_scale_exponent(&[DVec3::ZERO]), 0);
        assert_eq!(
            exact_scale_exponent(&[DVec3::new(f64::NAN, f64::INFINITY, 0.0)]),
            0
        );
    }

    #[test]
    fn extreme_inputs_are_brought_to_one_and_back() {
        for m in [1e-300, 3.0e-25, 2.5e30, 1e300, f64::MAX, 5e-324] {
            let mut p = vec![DVec3::new(0.25 * m, -m, m / 3.0)];
            let e = exact_scale_exponent(&p);
            assert_ne!(e, 0, "{m:e}");
            let before = p[0];
            scale_by_power_of_two(&mut p, -e);
            let largest = p[0].abs().max_element();
            // In [1, 2), but for the ends of the range, where the exponent is clamped to
            // ±1022: f64::MAX comes to [2, 4), the subnormal 5e-324 to 2^-52.
            if m >= f64::MIN_POSITIVE {
                assert!((1.0..4.0).contains(&largest), "{m:e} → {largest:e}");
            }
            scale_by_power_of_two(&mut p, e);
            assert_eq!(p[0], before, "{m:e}: scaled and back, bit for bit");
        }
    }
}
