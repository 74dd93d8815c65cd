//! The coordinates a build works in: the input's, multiplied by a power of two when its
//! coordinates are extremely large or small, then moved to an exact local origin when it lies
//! far from the origin for its size. Both steps are exact, so results move back to the input's
//! coordinates exactly ([`LocalFrame::move_to_input`]).
//!
//! Why a power of two: every tolerance of the construction is relative to the mesh's size,
//! and a power of two scales every intermediate value exactly, so the surface built on the
//! scaled input is the scaled surface, bit for bit (the test
//! `smoothing_commutes_with_scaling_by_a_power_of_two` of `algesurf-apatch` measures it).
//! What is not scale-free is the range of `f64`: areas and normals are products of up to four
//! lengths, so an icosahedron whose coordinates are ~2^-270 or ~2^260 could not be built (its
//! faces' areas underflowed and its normals overflowed: "dropped degenerate faces", "normal is
//! not a finite non-zero vector"). Inputs whose largest coordinate lies outside
//! `[2^-64, 2^64]` (5.4e-20 to 1.8e19: far beyond any measured object in any unit) are
//! therefore built at the scale where it lies in `[1, 2)`; all others at their own, so that
//! nothing changes for them. (The library refuses meshes beyond `2^±252`,
//! `algesurf_hull::HullError::CoordinatesOutOfRange`; the commands never hand it one.)

use algesurf_mesh::TriMesh;
pub(crate) use algesurf_mesh::geometry::{
    exact_scale_exponent as scale_exponent, power_of_two, scale_by_power_of_two,
};
use glam::DVec3;
use rayon::prelude::*;

/// Multiplies `points` by `2^-exponent` ([`scale_by_power_of_two`]: exact but for results
/// below `2^-1022`).
pub(crate) fn scale_down(points: &mut [DVec3], exponent: i32) {
    scale_by_power_of_two(points, -exponent);
}

/// Where a build's coordinates are in the input's: `input = (build + origin) · 2^exponent`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LocalFrame {
    /// The power of two the input was scaled by, `2^-exponent` ([`scale_exponent`]).
    pub exponent: i32,
    /// The exact local origin of the scaled input
    /// ([`algesurf_mesh::Aabb::exact_local_origin`]).
    pub origin: DVec3,
}

impl LocalFrame {
    /// Moves `tri` and `points` back by the origin only: the input's coordinates when
    /// [`LocalFrame::exponent`] is 0, else the input's scaled by `2^-exponent`.
    pub(crate) fn restore_origin(&self, tri: &mut TriMesh, points: &mut [DVec3]) {
        if self.origin == DVec3::ZERO {
            return;
        }
        let origin = self.origin;
        for p in tri.positions_mut() {
            *p += origin;
        }
        points.par_iter_mut().for_each(|p| *p += origin);
    }

    /// Scales `points` (moved back by [`LocalFrame::restore_origin`]) to the input's scale.
    pub(crate) fn restore_scale(&self, points: &mut [DVec3]) {
        if self.exponent != 0 {
            let s = power_of_two(self.exponent);
            points.par_iter_mut().for_each(|p| *p *= s);
        }
    }

    /// A length measured in the build's coordinates, in the input's.
    pub(crate) fn length(&self, d: f64) -> f64 {
        if self.exponent == 0 {
            d
        } else {
            d * power_of_two(self.exponent)
        }
    }

    /// Moves the mesh `tri` and the surface points `points` from the build's coordinates back
    /// to the input's: the input's vertices come back bit for bit (both steps there were
    /// exact), the surface points rounded once at the input's scale. Nothing to do for an
    /// input near the origin and of ordinary size (the corpus, the benchmark's bunny).
    pub(crate) fn move_to_input(&self, tri: &mut TriMesh, points: &mut [DVec3]) {
        self.restore_origin(tri, points);
        self.restore_scale(tri.positions_mut());
        self.restore_scale(points);
    }
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
            assert_eq!(scale_exponent(&pts(m)), 0, "largest coordinate {m:e}");
        }
        assert_eq!(scale_exponent(&[DVec3::ZERO]), 0);
        assert_eq!(
            scale_exponent(&[DVec3::new(f64::NAN, f64::INFINITY, 0.0)]),
            0
        );
    }

    #[test]
    fn extreme_inputs_are_brought_to_one() {
        for m in [1e-300, 3.0e-25, 2.5e30, 1e300, f64::MAX, 5e-324] {
            let mut p = vec![DVec3::new(0.25 * m, -m, m / 3.0)];
            let e = scale_exponent(&p);
            assert_ne!(e, 0, "{m:e}");
            let before = p[0];
            scale_down(&mut p, e);
            let largest = p[0].abs().max_element();
            // In [1, 2), but for the ends of the range, where the exponent is clamped to
            // ±1022: f64::MAX comes to [2, 4), the subnormal 5e-324 to 2^-52.
            if m >= f64::MIN_POSITIVE {
                assert!((1.0..4.0).contains(&largest), "{m:e} → {largest:e}");
            }
            let frame = LocalFrame {
                exponent: e,
                origin: DVec3::ZERO,
            };
            let mut back = p.clone();
            frame.restore_scale(&mut back);
            assert_eq!(back[0], before, "{m:e}: scaled and back, bit for bit");
            assert_eq!(frame.length(largest), before.abs().max_element());
        }
    }
}
