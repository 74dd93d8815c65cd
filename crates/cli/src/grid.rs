//! `--resolution` and `--across`: how finely `smooth` and `render --smooth` tessellate, and
//! the `auto` resolution that keeps the output of a large mesh to a sensible size.

use algesurf_apatch::ApatchSurface;

/// The tessellation resolution (shared by `smooth` and `render --smooth`).
#[derive(clap::Args, Debug, Clone)]
pub struct GridArgs {
    /// Points per patch edge minus one: face patches are triangular grids of this
    /// resolution, edge patches have this many steps along the mesh edge. `auto`: 8, or less
    /// where that would make more than 2 M triangles (the largest that does not; at least 1).
    #[arg(long, default_value = "auto", value_parser = parse_resolution)]
    pub resolution: Resolution,
    /// Steps across each edge patch (default: the resolution).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub across: Option<u32>,
}

/// `--resolution`: a number of steps, or chosen from the surface's patch counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resolution {
    /// [`AUTO_RESOLUTION`], or the largest below it whose output stays within
    /// [`AUTO_TRIANGLES`].
    Auto,
    /// This many steps (1–1024).
    Steps(u32),
}

/// The resolution `auto` gives a mesh small enough: a coarse mesh's patches are visibly
/// round at 8 steps (the built-in icosahedron: 4 640 triangles).
pub const AUTO_RESOLUTION: u32 = 8;

/// The most triangles `auto` makes (unless one step already makes more): about 100 MB of
/// binary PLY with normals and patch ids. The fixed default of 8 made 16.1 M triangles and a
/// 759 MB file from the Stanford bunny (69 451 faces), 43 % of the command's 9 s spent
/// writing it; `auto` takes 3 steps there (1.88 M triangles). Spot (5 856 faces, 1.36 M
/// triangles at 8) keeps 8.
pub const AUTO_TRIANGLES: usize = 2_000_000;

/// Memory a tessellation takes per output triangle, on top of the surface, in bytes: its
/// points, normals and patch ids, its triangles, and the writer's buffers. Measured with
/// `algesurf smooth spot.obj` at 8, 16 and 24 steps (1.36 M, 5.73 M and 13.1 M triangles):
/// resident peaks of 194, 534 and 1 105 MB, of which ~45 MB is the surface, so 110, 85 and
/// 81 bytes a triangle.
pub const BYTES_PER_TRIANGLE: u64 = 90;

/// `Err` naming the grid, its size and the way out when `triangles` output triangles (at
/// [`BYTES_PER_TRIANGLE`]) need more memory than `available`; `Ok` where the available memory
/// is not known. Without this, a resolution far too fine for the mesh ends, after minutes of
/// work, in an allocation failure (an abort) or the system's out-of-memory killer: spot at
/// `--resolution 200` would make 933 M triangles, ~84 GB.
pub fn check_memory(
    (n, m): (usize, usize),
    triangles: usize,
    available: Option<u64>,
) -> Result<(), String> {
    let Some(available) = available else {
        return Ok(());
    };
    let need = (triangles as u64).saturating_mul(BYTES_PER_TRIANGLE);
    if need <= available {
        return Ok(());
    }
    let gb = |b: u64| b as f64 / 1e9;
    Err(format!(
        "resolution {n} × {m} would make {:.1} M triangles, about {:.1} GB of memory at \
         {BYTES_PER_TRIANGLE} bytes each, more than the {:.1} GB available: choose a smaller \
         --resolution (or --across), or `auto` (at most {} M triangles)",
        triangles as f64 / 1e6,
        gb(need),
        gb(available),
        AUTO_TRIANGLES / 1_000_000
    ))
}

/// Parses `--resolution`: `auto` or an integer 1–1024.
fn parse_resolution(s: &str) -> Result<Resolution, String> {
    if s.eq_ignore_ascii_case("auto") {
        return Ok(Resolution::Auto);
    }
    match s.parse::<u32>() {
        Ok(n) if (1..=1024).contains(&n) => Ok(Resolution::Steps(n)),
        _ => Err(format!(
            "`{s}` is not `auto` or a number of steps from 1 to 1024"
        )),
    }
}

impl GridArgs {
    /// `(n, m)`: steps along and across the patches of `surface`, with `auto` resolved
    /// ([`Resolution::Auto`]: the largest `n ≤ 8` whose
    /// [`ApatchSurface::max_triangle_count`] is at most [`AUTO_TRIANGLES`], with `m = n`
    /// unless `--across` is given).
    pub fn steps(&self, surface: &ApatchSurface) -> (usize, usize) {
        self.steps_by(|n, m| surface.max_triangle_count(n, m))
    }

    /// [`GridArgs::steps`], refused by [`check_memory`] when the output would not fit in the
    /// memory the system has available.
    pub fn fitting_steps(&self, surface: &ApatchSurface) -> Result<(usize, usize), String> {
        let steps = self.steps(surface);
        check_memory(
            steps,
            surface.max_triangle_count(steps.0, steps.1),
            crate::memory::available_bytes(),
        )?;
        Ok(steps)
    }

    /// [`GridArgs::steps`] with the triangle count of `(n, m)` given by `triangles`.
    fn steps_by(&self, triangles: impl Fn(usize, usize) -> usize) -> (usize, usize) {
        let across = |n: u32| self.across.unwrap_or(n) as usize;
        let n = match self.resolution {
            Resolution::Steps(n) => n,
            Resolution::Auto => (1..=AUTO_RESOLUTION)
                .rev()
                .find(|&n| triangles(n as usize, across(n)) <= AUTO_TRIANGLES)
                .unwrap_or(1),
        };
        (n as usize, across(n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(resolution: Resolution, across: Option<u32>) -> GridArgs {
        GridArgs { resolution, across }
    }

    /// A closed mesh's count: `faces` face patches of `n²` and `1.5 faces` edge patches of
    /// `2m(n − 1)` triangles ([`ApatchSurface::max_triangle_count`]).
    fn closed(faces: usize) -> impl Fn(usize, usize) -> usize {
        move |n, m| faces * n * n + 3 * faces / 2 * 2 * m * (n - 1)
    }

    #[test]
    fn auto_keeps_eight_steps_for_a_coarse_mesh() {
        assert_eq!(grid(Resolution::Auto, None).steps_by(closed(20)), (8, 8));
        // Spot's count: 1.36 M triangles at 8.
        assert_eq!(grid(Resolution::Auto, None).steps_by(closed(5856)), (8, 8));
    }

    /// The bunny's 69 659 hull faces: 16.1 M triangles at 8, 1.88 M at 3, 3.62 M at 4.
    #[test]
    fn auto_takes_the_finest_grid_within_the_budget() {
        let count = closed(69_659);
        let (n, m) = grid(Resolution::Auto, None).steps_by(&count);
        assert_eq!((n, m), (3, 3));
        assert!(count(n, m) <= AUTO_TRIANGLES && count(n + 1, n + 1) > AUTO_TRIANGLES);
        // A given `--across` is kept, and the budget counted with it.
        assert_eq!(grid(Resolution::Auto, Some(1)).steps_by(&count), (4, 1));
    }

    #[test]
    fn auto_falls_back_to_one_step_and_a_given_resolution_is_kept() {
        assert_eq!(
            grid(Resolution::Auto, None).steps_by(closed(2_000_000)),
            (1, 1)
        );
        assert_eq!(
            grid(Resolution::Steps(12), None).steps_by(closed(69_659)),
            (12, 12)
        );
        assert_eq!(
            grid(Resolution::Steps(5), Some(2)).steps_by(closed(20)),
            (5, 2)
        );
    }

    /// A grid fits when its triangles at [`BYTES_PER_TRIANGLE`] fit in the available memory
    /// (or that is unknown); otherwise the error names the grid, the sizes and `auto`.
    #[test]
    fn a_grid_that_does_not_fit_in_memory_is_refused() {
        let gb = 1_000_000_000u64;
        // Spot at 200 steps: 933 M triangles, ~84 GB.
        let spot = |n: usize| 5856 * n * n + 8784 * 2 * n * (n - 1);
        assert_eq!(spot(200), 933_446_400);
        let e = check_memory((200, 200), spot(200), Some(16 * gb)).unwrap_err();
        for part in [
            "resolution 200 × 200",
            "933.4 M triangles",
            "84.0 GB",
            "16.0 GB",
            "`auto`",
        ] {
            assert!(e.contains(part), "{part}: {e}");
        }
        assert_eq!(check_memory((200, 200), spot(200), None), Ok(()));
        assert_eq!(check_memory((8, 8), spot(8), Some(16 * gb)), Ok(()));
        // The boundary: exactly the available bytes fit, one triangle more does not.
        let fits = (16 * gb / BYTES_PER_TRIANGLE) as usize;
        assert!(check_memory((8, 8), fits, Some(16 * gb)).is_ok());
        assert!(check_memory((8, 8), fits + 1, Some(16 * gb)).is_err());
        // No overflow for absurd counts.
        assert!(check_memory((1024, 1024), usize::MAX, Some(u64::MAX - 1)).is_err());
    }

    #[test]
    fn resolution_parses_auto_and_step_counts() {
        assert_eq!(parse_resolution("auto"), Ok(Resolution::Auto));
        assert_eq!(parse_resolution("AUTO"), Ok(Resolution::Auto));
        assert_eq!(parse_resolution("1"), Ok(Resolution::Steps(1)));
        assert_eq!(parse_resolution("1024"), Ok(Resolution::Steps(1024)));
        for bad in ["0", "1025", "-3", "2.5", "", "automatic"] {
            let e = parse_resolution(bad).unwrap_err();
            assert!(e.contains(&format!("`{bad}`")), "{e}");
        }
    }
}
