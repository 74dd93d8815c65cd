//! [`PolarPatch`]: a triangular Bézier patch in R^3 given by its polar form over an affine frame
//! (thesis §2.7.3–2.7.4).

use crate::{AffineFrame, IntervalFrame, PolarCurve, PolarError, PolarLabel};
use algesurf_bb::BbPoly;
use algesurf_bb::multi_index::{self, count, rank};
use glam::{DAffine2, DVec2, DVec3};

/// Relative tolerance of [`PolarPatch::normal`]: the patch is called singular at a point where
/// `|F_x × F_y| < SINGULAR_NORMAL_TOLERANCE · scale²`, with
/// `scale = n · net_size / frame diameter` the natural size of a first derivative.
pub const SINGULAR_NORMAL_TOLERANCE: f64 = 1e-10;

/// Largest level accepted by [`PolarPatch::tessellate`] (4^12 ≈ 16.8 M triangles).
pub const MAX_TESSELLATION_LEVEL: u32 = 12;

/// The diagonal of the bounding box of a set of points (0 for none).
pub(crate) fn bbox_diagonal(points: &[DVec3]) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for p in points {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    if points.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    }
}

/// A triangular Bézier patch `F: A² → A³` of degree n, given by the control net
/// `b_{ijk} = f(r^i s^j t^k)` of its polar form `f` over the affine frame Δrst
/// (thesis Lemma 2.7.1).
///
/// The patch is a polynomial on the whole plane; the frame only fixes which polar values are
/// stored. Every operation takes and returns Cartesian domain points (`DVec2`), so the same
/// surface has the same values whatever frame its net is written in
/// ([`PolarPatch::reparametrize`]).
///
/// ```
/// use algesurf_polar::{AffineFrame, PolarLabel, PolarPatch};
/// use glam::{DVec2, DVec3};
/// // The quadratic patch z = x² + y² (a paraboloid) over the unit frame.
/// let frame = AffineFrame::unit();
/// let f = |l: PolarLabel| {
///     // f(a1, a2) = (x, y, x1·x2 + y1·y2) averaged over the arguments' symmetric product.
///     let pts: Vec<DVec2> = [frame.r(), frame.s(), frame.t()]
///         .iter()
///         .zip([l.i, l.j, l.k])
///         .flat_map(|(p, m)| std::iter::repeat_n(*p, m))
///         .collect();
///     let m = (pts[0] + pts[1]) / 2.0;
///     DVec3::new(m.x, m.y, pts[0].dot(pts[1]))
/// };
/// let patch = PolarPatch::from_fn(frame, 2, f);
/// let p = DVec2::new(0.3, 0.4);
/// assert!((patch.eval(p) - DVec3::new(0.3, 0.4, 0.25)).length() < 1e-15);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PolarPatch {
    frame: AffineFrame,
    net: BbPoly<DVec3, 3>,
}

impl PolarPatch {
    /// A patch from its control points in storage order (see [`crate::label`]).
    pub fn new(frame: AffineFrame, degree: usize, points: Vec<DVec3>) -> Result<Self, PolarError> {
        Ok(PolarPatch {
            frame,
            net: BbPoly::new(degree, points)?,
        })
    }

    /// A patch whose control point `f(r^i s^j t^k)` is `f(label)`.
    pub fn from_fn(
        frame: AffineFrame,
        degree: usize,
        mut f: impl FnMut(PolarLabel) -> DVec3,
    ) -> Self {
        PolarPatch {
            frame,
            net: BbPoly::from_fn(degree, |m| f(PolarLabel::from_multi_index(m))),
        }
    }

    /// A patch from a Bernstein–Bézier polynomial whose barycentric variables are those of
    /// `frame` (in the order r, s, t).
    pub fn from_bb(frame: AffineFrame, net: BbPoly<DVec3, 3>) -> Self {
        PolarPatch { frame, net }
    }

    /// The degree n.
    #[inline]
    pub fn degree(&self) -> usize {
        self.net.degree()
    }

    /// The affine frame Δrst of the control net.
    #[inline]
    pub fn frame(&self) -> &AffineFrame {
        &self.frame
    }

    /// The control net as a Bernstein–Bézier polynomial in the barycentric coordinates of the
    /// frame.
    #[inline]
    pub fn bb(&self) -> &BbPoly<DVec3, 3> {
        &self.net
    }

    /// The control points in storage order.
    #[inline]
    pub fn control_points(&self) -> &[DVec3] {
        self.net.coeffs()
    }

    /// The control point `f(r^i s^j t^k)`, or `None` when the label's degree is not n.
    #[inline]
    pub fn control_point(&self, label: PolarLabel) -> Option<DVec3> {
        self.net.get(label.multi_index())
    }

    /// Sets the control point `f(r^i s^j t^k)`.
    pub fn set_control_point(&mut self, label: PolarLabel, p: DVec3) -> Result<(), PolarError> {
        if label.degree() != self.degree() {
            return Err(PolarError::InvalidArgument(format!(
                "label {label} has degree {}, the patch has degree {}",
                label.degree(),
                self.degree()
            )));
        }
        self.net.set(label.multi_index(), p);
        Ok(())
    }

    /// `(label, control point)` pairs in storage order.
    pub fn net(&self) -> impl Iterator<Item = (PolarLabel, DVec3)> + '_ {
        self.net
            .iter()
            .map(|(m, p)| (PolarLabel::from_multi_index(m), p))
    }

    /// The diagonal of the control net's bounding box: the scale of relative tolerances
    /// (translation invariant).
    pub fn net_size(&self) -> f64 {
        bbox_diagonal(self.net.coeffs())
    }

    /// The polar form (blossom) `f(a_1, …, a_n)` at n domain points, not necessarily distinct
    /// (thesis Lemma 2.7.1): symmetric, affine in each argument, `f(a, …, a) = F(a)`.
    pub fn blossom(&self, args: &[DVec2]) -> Result<DVec3, PolarError> {
        if args.len() != self.degree() {
            return Err(PolarError::ArgumentCount {
                degree: self.degree(),
                found: args.len(),
            });
        }
        if args.iter().any(|a| !a.is_finite()) {
            return Err(PolarError::NonFinite {
                what: "blossom argument",
            });
        }
        let bary: Vec<[f64; 3]> = args.iter().map(|a| self.frame.barycentric(*a)).collect();
        Ok(self.net.blossom(&bary)?)
    }

    /// The homogenised polar form with arguments in barycentric coordinates of the frame:
    /// points sum to 1, vectors to 0 (the polar form is linear in each homogenised argument).
    pub fn blossom_barycentric(&self, args: &[[f64; 3]]) -> Result<DVec3, PolarError> {
        if args.len() != self.degree() {
            return Err(PolarError::ArgumentCount {
                degree: self.degree(),
                found: args.len(),
            });
        }
        Ok(self.net.blossom(args)?)
    }

    /// The surface point `F(a) = f(a, …, a)` by de Casteljau's algorithm (§2.7.4).
    #[inline]
    pub fn eval(&self, a: DVec2) -> DVec3 {
        self.net.eval(self.frame.barycentric(a))
    }

    /// The directional derivative `D_u F(a) = n f(u, a^{n−1})` (u a domain vector).
    pub fn derivative(&self, a: DVec2, u: DVec2) -> DVec3 {
        self.derivative_along(a, &[u])
    }

    /// The second derivative `D_u D_v F(a) = n(n−1) f(u, v, a^{n−2})`.
    pub fn second_derivative(&self, a: DVec2, u: DVec2, v: DVec2) -> DVec3 {
        self.derivative_along(a, &[u, v])
    }

    /// The mixed derivative `D_{u_1}⋯D_{u_r} F(a) = n!/(n−r)! f(u_1, …, u_r, a^{n−r})` of any
    /// order r (zero when r > n).
    pub fn derivative_along(&self, a: DVec2, dirs: &[DVec2]) -> DVec3 {
        let d: Vec<[f64; 3]> = dirs
            .iter()
            .map(|u| self.frame.barycentric_direction(*u))
            .collect();
        self.net
            .directional_derivative(self.frame.barycentric(a), &d)
    }

    /// The partial derivatives `[F_x, F_y]` at `a`.
    pub fn partials(&self, a: DVec2) -> [DVec3; 2] {
        [self.derivative(a, DVec2::X), self.derivative(a, DVec2::Y)]
    }

    /// The natural size of a first derivative, `n · net_size / frame diameter`.
    fn derivative_scale(&self) -> f64 {
        self.degree() as f64 * self.net_size() / self.frame.diameter()
    }

    /// The unit normal `F_x × F_y / |F_x × F_y|` at `a` (oriented by the domain's x, y axes,
    /// so it does not depend on the frame), or [`PolarError::SingularNormal`] where the patch
    /// is singular (see [`SINGULAR_NORMAL_TOLERANCE`]).
    pub fn normal(&self, a: DVec2) -> Result<DVec3, PolarError> {
        let [fx, fy] = self.partials(a);
        let c = fx.cross(fy);
        let scale = self.derivative_scale();
        let relative = if scale > 0.0 {
            c.length() / (scale * scale)
        } else {
            0.0
        };
        if relative.is_nan() || relative < SINGULAR_NORMAL_TOLERANCE {
            return Err(PolarError::SingularNormal {
                relative,
                tolerance: SINGULAR_NORMAL_TOLERANCE,
            });
        }
        Ok(c / c.length())
    }

    /// The control net of the same surface with respect to another frame Δr's't'
    /// (change of frame, thesis §2.7.3): `b'_{ijk} = f(r'^i s'^j t'^k)`. The surface is
    /// unchanged: `reparametrize(g).eval(a) == eval(a)` for every domain point `a`.
    pub fn reparametrize(&self, frame: AffineFrame) -> PolarPatch {
        let verts = frame.points().map(|p| self.frame.barycentric(p));
        PolarPatch {
            frame,
            net: self.net.reparametrize(&verts),
        }
    }

    /// The patch `F' = F ∘ ρ⁻¹` over the frame `ρ(Δrst)` for an affine reparameterisation ρ
    /// of the domain (thesis Definition 5.3.2). By Lemma 5.3.3 its control net is the same:
    /// `b'_{ijk} = b_{ijk}`, so only the frame changes. Fails when ρ is singular.
    pub fn transform_domain(&self, rho: DAffine2) -> Result<PolarPatch, PolarError> {
        Ok(PolarPatch {
            frame: self.frame.transformed(rho)?,
            net: self.net.clone(),
        })
    }

    /// Subdivision at the point `a` by de Casteljau's algorithm (thesis §2.7.4): the nets
    /// `N_ast`, `N_rat`, `N_rsa` over the frames Δast, Δrat, Δrsa (in that order), each the same
    /// surface. Fails with [`PolarError::DegenerateFrame`] when `a` lies on a line through an
    /// edge of the frame (a flat sub-frame).
    pub fn subdivide_at(&self, a: DVec2) -> Result<[PolarPatch; 3], PolarError> {
        let [r, s, t] = self.frame.points();
        let frames = [
            AffineFrame::new(a, s, t)?,
            AffineFrame::new(r, a, t)?,
            AffineFrame::new(r, s, a)?,
        ];
        let mut nets = self.net.subdivide(self.frame.barycentric(a)).into_iter();
        Ok(frames.map(|frame| PolarPatch {
            frame,
            net: nets.next().expect("subdivide returns three nets"),
        }))
    }

    /// The midpoint 4-split (thesis §2.7.4, Figure 2.5): the nets over the four frames of
    /// [`AffineFrame::midpoint_split`], `[r c b]`, `[c s a]`, `[b a t]`, `[a b c]` with a, b, c
    /// the midpoints of st, rt, rs.
    pub fn split4(&self) -> [PolarPatch; 4] {
        let frames = self.frame.midpoint_split();
        let nets = self.net.midpoint_split();
        std::array::from_fn(|i| PolarPatch {
            frame: frames[i],
            net: nets[i].clone(),
        })
    }

    /// Degree elevation by `k` through the polar form: the elevated form of degree n + 1 is
    /// `f̂(a_1, …, a_{n+1}) = (1/(n+1)) Σ_i f(a_1, …, â_i, …, a_{n+1})` (the symmetrisation of
    /// f), whose values on frame points are
    /// `f̂(r^i s^j t^k) = (i f(r^{i−1}s^j t^k) + j f(r^i s^{j−1}t^k) + k f(r^i s^j t^{k−1}))/(n+1)`.
    pub fn elevate(&self, k: usize) -> PolarPatch {
        PolarPatch {
            frame: self.frame,
            net: self.net.elevate(k),
        }
    }

    /// The curve `u ↦ F((1 − u) a + u b)` over the interval frame (0, 1), with control points
    /// `f(a^{n−j} b^j)`: the boundary curve when a, b are frame points.
    pub fn restrict_to_segment(&self, a: DVec2, b: DVec2) -> PolarCurve {
        let bb = self
            .net
            .restrict_to_segment(self.frame.barycentric(a), self.frame.barycentric(b));
        PolarCurve::from_bb(IntervalFrame::unit(), bb)
    }

    /// The domain points of the vertices of [`PolarPatch::tessellate`]`(level)`: the vertex of
    /// integer label `(i, j, k)` (i + j + k = 2^level) at index `rank(i, j, k)` lies at
    /// `(i r + j s + k t) / 2^level`.
    pub fn tessellation_domain_points(&self, level: u32) -> Vec<DVec2> {
        let m = 1usize << level.min(MAX_TESSELLATION_LEVEL);
        let inv = 1.0 / m as f64;
        multi_index::iter::<3>(m)
            .map(|l| {
                self.frame
                    .point([l[0] as f64 * inv, l[1] as f64 * inv, l[2] as f64 * inv])
            })
            .collect()
    }

    /// A triangle mesh of the patch over its frame triangle for display, by `level` recursive
    /// midpoint 4-splits (thesis §2.7.4): `4^level` triangles with shared vertices, the
    /// `(m+1)(m+2)/2` surface points (m = 2^level) read off the corner control points of the
    /// leaf nets. Vertices are indexed as in [`PolarPatch::tessellation_domain_points`], so
    /// every interior edge belongs to exactly two triangles (watertight); triangles keep the
    /// frame's orientation.
    ///
    /// # Panics
    /// Panics when `level > MAX_TESSELLATION_LEVEL`.
    pub fn tessellate(&self, level: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        assert!(
            level <= MAX_TESSELLATION_LEVEL,
            "tessellation level {level} exceeds {MAX_TESSELLATION_LEVEL}"
        );
        let m = 1usize << level;
        let n = self.degree();
        let corner_ranks = [0, rank(&[0, n, 0]), count::<3>(n) - 1];
        let mut verts: Vec<Option<DVec3>> = vec![None; count::<3>(m)];
        let mut tris = Vec::with_capacity(1 << (2 * level));
        // Depth-first: (net, integer barycentric labels of its three corners, depth).
        let mut stack = vec![(self.net.clone(), [[m, 0, 0], [0, m, 0], [0, 0, m]], 0u32)];
        while let Some((net, c, depth)) = stack.pop() {
            if depth == level {
                let mut tri = [0u32; 3];
                for v in 0..3 {
                    let idx = rank(&c[v]);
                    verts[idx].get_or_insert(net.coeffs()[corner_ranks[v]]);
                    tri[v] = idx as u32;
                }
                tris.push(tri);
                continue;
            }
            let mid = |a: [usize; 3], b: [usize; 3]| {
                [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2]
            };
            let (m01, m02, m12) = (mid(c[0], c[1]), mid(c[0], c[2]), mid(c[1], c[2]));
            let kids = [
                [c[0], m01, m02],
                [m01, c[1], m12],
                [m02, m12, c[2]],
                [m12, m02, m01],
            ];
            let nets = net.midpoint_split();
            // Push in reverse so that triangles come out in split order.
            for (sub, corners) in nets.into_iter().zip(kids).rev() {
                stack.push((sub, corners, depth + 1));
            }
        }
        // Every grid label is a corner of some leaf, so no NaN remains.
        let verts = verts.into_iter().map(|v| v.unwrap_or(DVec3::NAN)).collect();
        (verts, tris)
    }
}
