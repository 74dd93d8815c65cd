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
