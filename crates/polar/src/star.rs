//! The corner star of a vertex (thesis Definition 3.3.1, Lemma 3.3.2).
//!
//! Around a domain vertex `v_1` shared by patches of degree m, the corner point is
//! `z_1 = f(v_1^m)` and the star consists of the control points `z_i = f(v_1^{m−1} v_i)` for the
//! neighbouring domain vertices `v_i`. Lemma 3.3.2: if the patches meet with C^1 continuity
//! there is a unique affine map `h: A² → A³` with `h(v_i) = z_i` for the vertex and all its
//! star — namely `h(x) = f(v_1^{m−1}, x)`, the tangent-plane map. So the corner and star have
//! exactly three degrees of freedom, whatever the number of patches: the corner point and two
//! tangent directions, or any three control points over affinely independent domain points.

use crate::continuity::VERTEX_MATCH_TOLERANCE;
use crate::{AffineFrame, PolarError, PolarLabel, PolarPatch};
use glam::{DVec2, DVec3};

/// The C^1 corner star of a domain vertex: the affine map `h(x) = f(v_1^{m−1}, x)` of
/// Lemma 3.3.2, stored as the corner point `h(v_1)` and its linear part.
///
/// ```
/// use algesurf_polar::CornerStar;
/// use glam::{DVec2, DVec3};
/// // Corner at the origin, star points over (1, 0) and (0, 1) prescribed: three degrees of freedom.
/// let star = CornerStar::from_corner(
///     DVec2::ZERO, 3, DVec3::ZERO,
///     (DVec2::X, DVec3::new(1.0, 0.0, 0.5)),
///     (DVec2::Y, DVec3::new(0.0, 1.0, 0.0)),
/// ).unwrap();
/// // Every other star point follows from the affine relation of its domain vertex.
/// assert_eq!(star.star_point(DVec2::new(-1.0, -1.0)), DVec3::new(-1.0, -1.0, -0.5));
/// // The surface's tangent at the corner is m · (linear part).
/// assert_eq!(star.tangent(DVec2::X), DVec3::new(3.0, 0.0, 1.5));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerStar {
    center: DVec2,
    degree: usize,
    corner: DVec3,
    /// `h(x) = corner + jac[0] (x − center).x + jac[1] (x − center).y`.
    jac: [DVec3; 2],
}

impl CornerStar {
    /// The star from any three control points of the corner region over affinely independent
    /// domain points (the vertex itself and/or star vertices): `h(domain[i]) = points[i]`.
    /// Fails when the domain points are collinear or the degree is 0.
    pub fn from_three(
        center: DVec2,
        degree: usize,
        domain: [DVec2; 3],
        points: [DVec3; 3],
    ) -> Result<Self, PolarError> {
        if degree == 0 {
            return Err(PolarError::InvalidArgument(
                "a degree-0 patch has no corner star".into(),
            ));
        }
        if !center.is_finite() || points.iter().any(|p| !p.is_finite()) {
            return Err(PolarError::NonFinite {
                what: "corner star input",
            });
        }
        let frame = AffineFrame::from_points(domain)?;
        let comb = |w: [f64; 3]| points[0] * w[0] + points[1] * w[1] + points[2] * w[2];
        Ok(CornerStar {
            center,
            degree,
            corner: comb(frame.barycentric(center)),
            jac: [
                comb(frame.barycentric_direction(DVec2::X)),
                comb(frame.barycentric_direction(DVec2::Y)),
            ],
        })
    }

    /// The star from the corner point `z_1` over the vertex and two star points over
    /// neighbours `a.0`, `b.0` not collinear with the vertex.
    pub fn from_corner(
        center: DVec2,
        degree: usize,
        corner: DVec3,
        a: (DVec2, DVec3),
        b: (DVec2, DVec3),
    ) -> Result<Self, PolarError> {
        Self::from_three(center, degree, [center, a.0, b.0], [corner, a.1, b.1])
    }

    /// The star from the surface point and its partial derivatives `F_x`, `F_y` at the vertex
    /// (the vertex point and two tangent directions): `h(x) = F + (F_x (x−v).x + F_y (x−v).y)/m`.
    pub fn from_tangents(
        center: DVec2,
        degree: usize,
        value: DVec3,
        fx: DVec3,
        fy: DVec3,
    ) -> Result<Self, PolarError> {
        if degree == 0 {
            return Err(PolarError::InvalidArgument(
                "a degree-0 patch has no corner star".into(),
            ));
        }
        let m = degree as f64;
        Ok(CornerStar {
            center,
            degree,
            corner: value,
            jac: [fx / m, fy / m],
        })
    }

    /// The star read off a patch at its frame point `vertex` (0 = r, 1 = s, 2 = t): the corner
    /// `f(v^m)` and the two star points `f(v^{m−1} w)` of the patch.
    pub fn of_patch(patch: &PolarPatch, vertex: usize) -> Result<Self, PolarError> {
        if vertex > 2 {
            return Err(PolarError::InvalidArgument(format!(
                "frame point {vertex} (a frame has points 0, 1, 2)"
            )));
        }
        let m = patch.degree();
        if m == 0 {
            return Err(PolarError::InvalidArgument(
                "a degree-0 patch has no corner star".into(),
            ));
        }
        let pts = patch.frame().points();
        let others = [(vertex + 1) % 3, (vertex + 2) % 3];
        let star_label = |w: usize| {
            let mut l = [0; 3];
            l[vertex] = m - 1;
            l[w] += 1;
            PolarLabel::from_multi_index(l)
        };
        let get = |l: PolarLabel| patch.control_point(l).expect("degree-m label");
        Self::from_three(
            pts[vertex],
            m,
            [pts[vertex], pts[others[0]], pts[others[1]]],
            [
                get(PolarLabel::corner(m, vertex)),
                get(star_label(others[0])),
                get(star_label(others[1])),
            ],
        )
    }

    /// The domain vertex `v_1`.
    #[inline]
    pub fn center(&self) -> DVec2 {
        self.center
    }

    /// The degree m of the patches.
    #[inline]
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The corner point `z_1 = f(v_1^m)` (the surface point at the vertex).
    #[inline]
    pub fn corner(&self) -> DVec3 {
        self.corner
    }

    /// The star point `h(v) = f(v_1^{m−1}, v)` over the domain point `v` (Lemma 3.3.2).
    #[inline]
    pub fn star_point(&self, v: DVec2) -> DVec3 {
        let d = v - self.center;
        self.corner + self.jac[0] * d.x + self.jac[1] * d.y
    }

    /// The surface's directional derivative `D_u F(v_1) = m (h(v_1 + u) − h(v_1))`.
    #[inline]
    pub fn tangent(&self, u: DVec2) -> DVec3 {
        (self.jac[0] * u.x + self.jac[1] * u.y) * self.degree as f64
    }

    fn vertex_of(&self, patch: &PolarPatch) -> Result<usize, PolarError> {
        if patch.degree() != self.degree {
            return Err(PolarError::DegreeMismatch {
                left: self.degree,
                right: patch.degree(),
            });
        }
        patch
            .frame()
            .vertex_index(self.center, VERTEX_MATCH_TOLERANCE)
            .ok_or(PolarError::NotAVertex {
                x: self.center.x,
                y: self.center.y,
            })
    }

    /// Writes the corner point and the two star points of `patch` at the vertex (which must be
    /// one of its frame points, and the degrees must agree).
    pub fn apply(&self, patch: &mut PolarPatch) -> Result<(), PolarError> {
        let v = self.vertex_of(patch)?;
        let m = self.degree;
        let pts = patch.frame().points();
        patch.set_control_point(PolarLabel::corner(m, v), self.corner)?;
        for w in [(v + 1) % 3, (v + 2) % 3] {
            let mut l = [0; 3];
            l[v] = m - 1;
            l[w] += 1;
            patch.set_control_point(PolarLabel::from_multi_index(l), self.star_point(pts[w]))?;
        }
        Ok(())
    }

    /// How far `patch`'s corner and star points at the vertex are from this star: the largest
    /// distance divided by the patch's [`PolarPatch::net_size`] (absolute for a point net).
    pub fn residual(&self, patch: &PolarPatch) -> Result<f64, PolarError> {
        let v = self.vertex_of(patch)?;
        let other = Self::of_patch(patch, v)?;
        let pts = patch.frame().points();
        let worst = [pts[v], pts[(v + 1) % 3], pts[(v + 2) % 3]]
            .iter()
            .map(|x| (self.star_point(*x) - other.star_point(*x)).length())
            .fold(0.0, f64::max);
        let size = patch.net_size();
        Ok(if size > 0.0 { worst / size } else { worst })
    }
}

/// The Lemma 3.3.2 checker: patches around the common domain vertex `center` have a
/// consistent C^1 corner star (all corner and star points are images of their domain points
/// under one affine map) iff this is ~0. Returns the largest [`CornerStar::residual`] of the
/// patches against the star of the first one. Fails on an empty list, a degree mismatch or a
/// patch without `center` among its frame points.
pub fn corner_star_residual(center: DVec2, patches: &[PolarPatch]) -> Result<f64, PolarError> {
    let first = patches
        .first()
        .ok_or_else(|| PolarError::InvalidArgument("no patches around the vertex".into()))?;
    let v = first
        .frame()
        .vertex_index(center, VERTEX_MATCH_TOLERANCE)
        .ok_or(PolarError::NotAVertex {
            x: center.x,
            y: center.y,
        })?;
    let star = CornerStar::of_patch(first, v)?;
    let mut worst: f64 = 0.0;
    for p in patches {
        worst = worst.max(star.residual(p)?);
    }
    Ok(worst)
}
