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
use algesurf_mesh::geometry::{power_of_two, scale_by_power_of_two};
use glam::DVec3;
use rayon::prelude::*;

/// Where a build's coordinates are in the input's: `input = (build + origin) · 2^exponent`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LocalFrame {
    /// The power of two the input was scaled by, `2^-exponent`
    /// ([`algesurf_mesh::geometry::exact_scale_exponent`]).
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
        scale_by_power_of_two(points, self.exponent);
    }

    /// A length measured in the build's coordinates, in the input's.
    pub(crate) fn length(&self, d: f64) -> f64 {
        d * power_of_two(self.exponent)
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
    use algesurf_mesh::geometry::exact_scale_exponent;

    /// An input taken into a frame as `build` does (scaled by `2^-e`, then moved to its exact
    /// local origin) comes back bit for bit, and lengths scale with it.
    #[test]
    fn a_frame_moves_back_exactly() {
        for (shift, m) in [(0.0, 1.0), (0.0, 1e-300), (3.0, 2.5e30), (1e5, 1e300)] {
            let input: Vec<DVec3> = [
                DVec3::new(0.25, -1.0, 1.0 / 3.0),
                DVec3::new(-0.5, 0.75, 0.125),
                DVec3::new(0.1, 0.2, -0.3),
            ]
            .iter()
            .map(|p| (*p + shift) * m)
            .collect();
            let mut tri = TriMesh::new(input.clone(), vec![[0, 1, 2]]).unwrap();
            let exponent = exact_scale_exponent(tri.positions());
            scale_by_power_of_two(tri.positions_mut(), -exponent);
            let origin = tri.bounding_box().exact_local_origin();
            tri.positions_mut().iter_mut().for_each(|p| *p -= origin);
            let frame = LocalFrame { exponent, origin };
            let mut points = tri.positions().to_vec();
            frame.move_to_input(&mut tri, &mut points);
            assert_eq!(tri.positions(), &input[..], "shift {shift}, size {m:e}");
            assert_eq!(points, input, "shift {shift}, size {m:e}");
            assert_eq!(frame.length(2.0), 2.0 * power_of_two(exponent));
        }
    }
}
