//! Polar labels: the multisets of frame points `r^i s^j t^k` (i + j + k = n) whose polar values
//! `f(r^i s^j t^k)` are the control points of a degree-n patch (thesis Lemma 2.7.1), and
//! `r^i s^j` for curves.
//!
//! A label `f(r^i s^j t^k)` is the Bernstein–Bézier multi-index `(i, j, k)`, so control nets are
//! stored in the order of [`algesurf_bb::multi_index`]: `r^n` first, then `r^{n−1}s`,
//! `r^{n−1}t`, …, `t^n` last.

use algesurf_bb::multi_index;
use std::fmt;

/// The polar label `f(r^i s^j t^k)` of a control point of a triangular patch of degree
/// `i + j + k` over the frame Δrst (thesis §2.7.3).
///
/// ```
/// use algesurf_polar::PolarLabel;
/// let l = PolarLabel::new(2, 0, 1);
/// assert_eq!(l.to_string(), "f(r^2 t)");
/// assert_eq!(PolarLabel::all(3).position(|m| m == l), Some(l.rank()));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PolarLabel {
    /// Multiplicity of r.
    pub i: usize,
    /// Multiplicity of s.
    pub j: usize,
    /// Multiplicity of t.
    pub k: usize,
}

impl PolarLabel {
    /// The label `f(r^i s^j t^k)`.
    #[inline]
    pub const fn new(i: usize, j: usize, k: usize) -> Self {
        PolarLabel { i, j, k }
    }

    /// The label of frame point `v` (0 = r, 1 = s, 2 = t) repeated n times: a corner of the net.
    ///
    /// # Panics
    /// Panics when `v > 2`.
    #[inline]
    pub fn corner(n: usize, v: usize) -> Self {
        Self::from_multi_index(multi_index::vertex::<3>(n, v))
    }

    /// The degree `i + j + k`.
    #[inline]
    pub const fn degree(&self) -> usize {
        self.i + self.j + self.k
    }

    /// The multi-index `[i, j, k]` of the Bernstein–Bézier layer.
    #[inline]
    pub const fn multi_index(&self) -> [usize; 3] {
        [self.i, self.j, self.k]
    }

    /// The label of a multi-index.
    #[inline]
    pub const fn from_multi_index(m: [usize; 3]) -> Self {
        PolarLabel {
            i: m[0],
            j: m[1],
            k: m[2],
        }
    }

    /// Position of the control point in the net's storage order.
    #[inline]
    pub fn rank(&self) -> usize {
        multi_index::rank(&self.multi_index())
    }

    /// All labels of degree n in storage order.
    pub fn all(n: usize) -> impl Iterator<Item = PolarLabel> {
        multi_index::iter::<3>(n).map(Self::from_multi_index)
    }

    /// The `n` frame points of the label, as barycentric vectors (`i` copies of r, then s, t).
    pub fn arguments(&self) -> Vec<[f64; 3]> {
        let mut v = Vec::with_capacity(self.degree());
        v.extend(std::iter::repeat_n([1.0, 0.0, 0.0], self.i));
        v.extend(std::iter::repeat_n([0.0, 1.0, 0.0], self.j));
        v.extend(std::iter::repeat_n([0.0, 0.0, 1.0], self.k));
        v
    }
}

fn write_power(f: &mut fmt::Formatter<'_>, name: &str, e: usize, first: &mut bool) -> fmt::Result {
    if e == 0 {
        return Ok(());
    }
    if !*first {
        write!(f, " ")?;
    }
    *first = false;
    if e == 1 {
        write!(f, "{name}")
    } else {
        write!(f, "{name}^{e}")
    }
}

impl fmt::Display for PolarLabel {
    /// Writes `f(r^i s^j t^k)`, omitting zero powers and exponents 1.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "f(")?;
        let mut first = true;
        write_power(f, "r", self.i, &mut first)?;
        write_power(f, "s", self.j, &mut first)?;
        write_power(f, "t", self.k, &mut first)?;
        write!(f, ")")
    }
}

/// The polar label `f(r^i s^j)` of a control point of a curve of degree `i + j` over the
/// interval frame (r, s) (thesis §2.3).
///
/// ```
/// use algesurf_polar::CurveLabel;
/// assert_eq!(CurveLabel::new(1, 2).to_string(), "f(r s^2)");
/// assert_eq!(CurveLabel::new(1, 2).rank(), 2);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CurveLabel {
    /// Multiplicity of r.
    pub i: usize,
    /// Multiplicity of s.
    pub j: usize,
}

impl CurveLabel {
    /// The label `f(r^i s^j)`.
    #[inline]
    pub const fn new(i: usize, j: usize) -> Self {
        CurveLabel { i, j }
    }

    /// The degree `i + j`.
    #[inline]
    pub const fn degree(&self) -> usize {
        self.i + self.j
    }

    /// Position of the control point in storage order (`r^n` first, so the rank is `j`).
    #[inline]
    pub const fn rank(&self) -> usize {
        self.j
    }

    /// All labels of degree n in storage order: `f(r^n), f(r^{n−1} s), …, f(s^n)`.
    pub fn all(n: usize) -> impl Iterator<Item = CurveLabel> {
        (0..=n).map(move |j| CurveLabel::new(n - j, j))
    }
}

impl fmt::Display for CurveLabel {
    /// Writes `f(r^i s^j)`, omitting zero powers and exponents 1.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "f(")?;
        let mut first = true;
        write_power(f, "r", self.i, &mut first)?;
        write_power(f, "s", self.j, &mut first)?;
        write!(f, ")")
    }
}
