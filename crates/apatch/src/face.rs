//! The rational cubic on the face tetrahedron of a convex face: (4.1)/(4.2) and Steps 1–5 of
//! §4.2 of Xu–Huang–Bajaj 2001.
//!
//! Vertex order is `[p_0, p_1, p_2, apex]` (the face in mesh order, apex last), so the apex
//! coordinate is `τ_3` and the layers `λ_3 = s` are those of the shooting polynomial (4.8).
//! Every coefficient is computed from the condition it exists for rather than transcribed
//! from the OCR'd formulas, and each condition is measured by a test:
//!
//! * Step 1: `f_{3e_a} = 0` — F vanishes at the mesh vertices.
//! * Step 2: `f_{2e_a+e_b} = (p_b − p_a)ᵀ N_a / 3` ((2.1)) — ∇F(p_a) = N_a.
//! * Step 3: the centre `f_1110` plus the rational term (4.1) make the derivative of F at the
//!   midpoint of each face edge, in the in-face direction perpendicular to that edge, equal to
//!   that of the mid-edge gradient `g = (N_b + N_c)/2` ((4.10)–(4.12)).
//! * Step 4: `f_{e_b+e_c+e_3}` makes the derivative at the same midpoint, in the direction
//!   perpendicular to the edge inside the face `[p_b p_c apex]`, equal to that of `g`.
//! * Step 5: the layer `λ_3 = 2` from the least-squares quadratic (4.13)/(4.14).
//!
//! Steps 3 and 4 fix the whole transversal gradient of F at each edge midpoint; together with
//! the vertex gradients this fixes it along the edge (a quadratic), which is what makes the C1
//! conditions with both neighbours of an edge consistent.

use crate::ApatchError;
use crate::cubic;
use crate::geometry::{foot, gradient_from_partials, value_gradient_with};
use crate::rational::face_term;
use algesurf_bb::{BbPoly, Tetrahedron, continuity, multi_index};
use glam::DVec3;
use nalgebra::DMatrix;

/// Position of a mesh vertex and the gradient of F there (the vertex normal scaled as the
/// gradient: unit normals by default, see READING-NOTES on quadric precision).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexData {
    /// Position `p_i`.
    pub position: DVec3,
    /// Gradient `N_i = ∇F(p_i)`.
    pub gradient: DVec3,
}

/// The rational cubic (4.1) on a face tetrahedron `[p_0, p_1, p_2, apex]`.
#[derive(Clone, Debug)]
pub struct FaceCubic {
    tet: Tetrahedron,
    poly: BbPoly<f64, 4>,
    rational: [f64; 3],
    /// `q_{e_a+e_3}` of the least-squares quadratic (4.13), a = 0..3: the layer-2
    /// coefficients are `(f_0003 + 2 q_{e_a+e_3}) / 3` (4.14).
    q_layer1: [f64; 3],
    /// Residual of the least-squares fit (4.13), relative to the largest coefficient: 0 when
    /// the data come from a quadric.
    fit_residual: f64,
}

/// Solves `D_d F(m) = target` for the coefficient at `lambda`, all others fixed: the
/// directional derivative is affine in each coefficient, with slope `D_d B_λ(m)`.
fn solve_coefficient(
    poly: &mut BbPoly<f64, 4>,
    lambda: [usize; 4],
    m: [f64; 4],
    d: [f64; 4],
    target: f64,
    what: &str,
) -> Result<(), ApatchError> {
    // D_d F(m) = 3 b[d, m, m] (see `cubic`): a linear form in the coefficients with weights
    // 3·w_μ, so the slope is 3·w_λ and the rest the sum over the other coefficients.
    let w = crate::cubic::blossom_weights(d, m, m);
    let r = algesurf_bb::multi_index::rank(&lambda);
    poly.set(lambda, 0.0);
    let rest = 3.0 * w.iter().zip(poly.coeffs()).map(|(a, b)| a * b).sum::<f64>();
    let slope = 3.0 * w[r];
    let scale = d.iter().map(|x| x.abs()).fold(0.0, f64::max);
    // The slope is 3·(1/4)·δ_c·(multiplicity) for the direction component δ_c crossing the
    // edge; below 1e-12 of the direction's size the direction runs along the edge.
    if slope.abs() <= 1e-12 * scale {
        return Err(ApatchError::Degenerate(format!(
            "{what}: the direction does not cross the edge"
        )));
    }
    poly.set(lambda, (target - rest) / slope);
    Ok(())
}

/// The fixed least-squares problem of Step 5 (4.13): the degree elevation of a quadratic's 10
/// BB coefficients to the 16 cubic coefficients of the layers `λ_3 ≤ 1`, and its
/// pseudo-inverse.
///
/// The matrix depends on nothing but the multi-indices, so its SVD is taken once, not per
/// face. Its singular values are O(1) (elevation weights `λ_i/3`); the cut 1e-12 drops
/// exactly the direction of `q_0002`, which no row of `λ_3 ≤ 1` involves, so the
/// minimum-norm solution sets it to 0 as the per-face SVD did.
struct Step5 {
    /// The multi-indices of the 16 rows (cubic coefficients with `λ_3 ≤ 1`).
    rows: [[usize; 4]; 16],
    /// Row `r`: `Σ_i (λ_i/3) q_{λ−e_i}`, the elevated coefficient, as weights of the 10 `q`s.
    elevation: [[f64; 10]; 16],
    /// `elevation⁺` (10 × 16).
    pinv: [[f64; 16]; 10],
}

impl Step5 {
    fn get() -> &'static Step5 {
        static STEP5: std::sync::OnceLock<Step5> = std::sync::OnceLock::new();
        STEP5.get_or_init(|| {
            let mut rows = [[0usize; 4]; 16];
            for (slot, l) in rows
                .iter_mut()
                .zip(multi_index::iter::<4>(3).filter(|l| l[3] <= 1))
            {
                *slot = l;
            }
            let mut elevation = [[0.0; 10]; 16];
            for (row, l) in elevation.iter_mut().zip(&rows) {
                for i in 0..4 {
                    if l[i] > 0 {
                        let mut k = *l;
                        k[i] -= 1;
                        row[multi_index::rank(&k)] += l[i] as f64 / 3.0;
                    }
                }
            }
            let a = DMatrix::<f64>::from_fn(16, 10, |r, c| elevation[r][c]);
            let pinv = a
                .svd(true, true)
                .pseudo_inverse(1e-12)
                .expect("the SVD was asked for both U and V");
            Step5 {
                rows,
                elevation,
                pinv: std::array::from_fn(|i| std::array::from_fn(|r| pinv[(i, r)])),
            }
        })
    }
}

impl FaceCubic {
    /// Builds the face cubic from the three vertices (face order), the apex, the mid-edge
    /// gradients `mid_gradients[a]` of the edge opposite vertex `a` (shared with the
    /// neighbouring face, normally `(N_b + N_c)/2`), and the free parameter `f_0003`.
    pub fn new(
        vertices: [VertexData; 3],
        apex: DVec3,
        mid_gradients: [DVec3; 3],
        f0003: f64,
    ) -> Result<Self, ApatchError> {
        let p = vertices.map(|v| v.position);
        let tet = Tetrahedron::new([p[0], p[1], p[2], apex])?;
        let mut poly = BbPoly::<f64, 4>::zero(3);
        // Steps 1–2: value 0 and gradient N_a at each face vertex, (2.1).
        for (a, v) in vertices.iter().enumerate() {
            for (l, c) in continuity::vertex_and_neighbours(tet.vertices(), 3, a, 0.0, v.gradient)?
            {
                poly.set(l, c);
            }
        }
        // Step 3: effective centre coefficient per edge, in-face perpendicular direction.
        let mut effective = [0.0; 3];
        let centre = [1, 1, 1, 0];
        for a in 0..3 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let d = p[a] - foot(p[a], p[b], p[c]);
            let mut m = [0.0; 4];
            m[b] = 0.5;
            m[c] = 0.5;
            let dir = tet.barycentric_direction(d);
            let mut trial = poly.clone();
            solve_coefficient(
                &mut trial,
                centre,
                m,
                dir,
                d.dot(mid_gradients[a]),
                "Step 3",
            )?;
            effective[a] = trial.coeff(centre);
        }
        let mean = (effective[0] + effective[1] + effective[2]) / 3.0;
        poly.set(centre, mean);
        let rational = effective.map(|e| e - mean);
        // Step 4: f_{e_b+e_c+e_3}, direction perpendicular to the edge in [p_b p_c apex].
        for a in 0..3 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let d = apex - foot(apex, p[b], p[c]);
            let mut m = [0.0; 4];
            m[b] = 0.5;
            m[c] = 0.5;
            let mut l = [0; 4];
            l[b] = 1;
            l[c] = 1;
            l[3] = 1;
            let dir = tet.barycentric_direction(d);
            solve_coefficient(&mut poly, l, m, dir, d.dot(mid_gradients[a]), "Step 4")?;
        }
        // Step 5 (4.13): least-squares quadratic q (10 BB coefficients) whose degree
        // elevation matches the coefficients of layers 0 and 1 (16 equations). The matrix is
        // the same for every face, so its pseudo-inverse is computed once (`Step5::get`).
        let step5 = Step5::get();
        let rhs: [f64; 16] = step5.rows.map(|l| poly.coeff(l));
        let q: [f64; 10] =
            std::array::from_fn(|i| step5.pinv[i].iter().zip(&rhs).map(|(a, b)| a * b).sum());
        let residual = step5
            .elevation
            .iter()
            .zip(&rhs)
            .map(|(row, r)| (row.iter().zip(&q).map(|(a, b)| a * b).sum::<f64>() - r).abs())
            .fold(0.0f64, f64::max);
        let scale = algesurf_bb::extremes::max_abs(&rhs).max(f64::MIN_POSITIVE);
        let q_layer1 = [0, 1, 2].map(|a| {
            let mut k = [0; 4];
            k[a] = 1;
            k[3] = 1;
            q[multi_index::rank(&k)]
        });
        let mut face = FaceCubic {
            tet,
            poly,
            rational,
            q_layer1,
            fit_residual: residual / scale,
        };
        face.set_f0003(f0003);
        Ok(face)
    }

    /// Sets the free parameter `f_0003` (Step 8) and the layer-2 coefficients that depend on
    /// it linearly through (4.14).
    pub fn set_f0003(&mut self, f0003: f64) {
        for a in 0..3 {
            let mut l = [0; 4];
            l[a] = 1;
            l[3] = 2;
            self.poly.set(l, (f0003 + 2.0 * self.q_layer1[a]) / 3.0);
        }
        self.poly.set([0, 0, 0, 3], f0003);
    }

    /// The free parameter `f_0003`.
    pub fn f0003(&self) -> f64 {
        self.poly.coeff([0, 0, 0, 3])
    }

    /// The face tetrahedron `[p_0, p_1, p_2, apex]`.
    pub fn tetrahedron(&self) -> &Tetrahedron {
        &self.tet
    }

    /// The polynomial part (centre coefficient = mean of the three effective ones).
    pub fn polynomial(&self) -> &BbPoly<f64, 4> {
        &self.poly
    }

    /// The rational coefficients `(a, b, c)` of (4.1), indexed by the opposite vertex.
    pub fn rational(&self) -> [f64; 3] {
        self.rational
    }

    /// Relative residual of the Step 5 fit (0 for quadric data).
    pub fn fit_residual(&self) -> f64 {
        self.fit_residual
    }

    /// The polynomial that agrees with F to first order on the face `τ_a = 0` of the
    /// tetrahedron (the face `[p_b p_c apex]` shared with an edge tetrahedron): the rational
    /// term contributes exactly `rational[a]` to the centre coefficient there.
    pub fn effective_polynomial(&self, a: usize) -> BbPoly<f64, 4> {
        BbPoly::new(3, self.effective_coeffs(a).to_vec()).expect("20 coefficients")
    }

    /// The coefficients of [`FaceCubic::effective_polynomial`], without allocating.
    pub(crate) fn effective_coeffs(&self, a: usize) -> cubic::Coeffs {
        let mut c = cubic::coeffs_of(&self.poly);
        c[cubic::rank3([1, 1, 1, 0])] += self.rational[a];
        c
    }

    /// F at barycentric coordinates `tau`.
    pub fn value(&self, tau: [f64; 4]) -> f64 {
        cubic::value(&cubic::coeffs_of(&self.poly), tau) + face_term(tau, self.rational).0
    }

    /// F and its Cartesian gradient at the point `x`.
    pub fn value_gradient(&self, x: DVec3) -> (f64, DVec3) {
        value_gradient_with(&self.tet, &self.poly, x, |tau| {
            face_term(tau, self.rational)
        })
    }

    /// Coefficients `[B_0(q), B_1(q), B_2(q), B_3]` of the shooting polynomial (4.8) from the
    /// face point with barycentric coordinates `q` (on `[p_0 p_1 p_2]`) to the apex.
    pub fn shooting_polynomial(&self, q: [f64; 3]) -> [f64; 4] {
        let a = [q[0], q[1], q[2], 0.0];
        let c = cubic::segment(&cubic::coeffs_of(&self.poly), a, [0.0, 0.0, 0.0, 1.0]);
        [c[0] + face_term(a, self.rational).0, c[1], c[2], c[3]]
    }

    /// Coefficients of the polynomial part along the segment from the face point `q` to the
    /// mirrored apex `2q − apex` (the backward ray of (4.5)), i.e. with end point
    /// `(2q, −1)` in barycentric coordinates.
    pub(crate) fn backward_polynomial(&self, q: [f64; 3]) -> [f64; 4] {
        let a = [q[0], q[1], q[2], 0.0];
        let b = [2.0 * q[0], 2.0 * q[1], 2.0 * q[2], -1.0];
        cubic::segment(&cubic::coeffs_of(&self.poly), a, b)
    }

    /// Cartesian gradient of F at barycentric coordinates `tau` (no Cartesian→barycentric
    /// solve: the rays of the tessellation know their point's coordinates).
    pub(crate) fn gradient_at_tau(&self, tau: [f64; 4]) -> DVec3 {
        self.value_gradient_at_tau(tau).1
    }

    /// [`FaceCubic::value`] and the Cartesian gradient at `tau`, from one pass of de
    /// Casteljau's algorithm (the value's bits are [`FaceCubic::value`]'s).
    pub(crate) fn value_gradient_at_tau(&self, tau: [f64; 4]) -> (f64, DVec3) {
        let (fp, dp) = cubic::value_partials(&cubic::coeffs_of(&self.poly), tau);
        let (fr, dr) = face_term(tau, self.rational);
        (fp + fr, gradient_from_partials(&self.tet, dp, dr))
    }
}
