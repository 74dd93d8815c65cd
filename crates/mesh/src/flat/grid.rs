//! Uniform grids over a region's frame (`[1, 3]²`, see `remesh::Frame`): its old faces, to
//! find the face a point lies in, and its boundary edges and points, to find those near a
//! point. About one item per cell, so each query reads a few.

use glam::DVec2;

/// Items bucketed by the cells their boxes overlap.
pub(super) struct Grid {
    cells: usize,
    buckets: Vec<Vec<u32>>,
}

impl Grid {
    /// An empty grid of about `items` cells.
    pub(super) fn new(items: usize) -> Grid {
        let cells = (items as f64).sqrt().ceil().clamp(1.0, 4096.0) as usize;
        Grid {
            cells,
            buckets: vec![Vec::new(); cells * cells],
        }
    }

    /// The cell column (or row) of the coordinate `x`, clamped to the grid.
    fn cell(&self, x: f64) -> usize {
        let c = (x - 1.0) * 0.5 * self.cells as f64;
        // NaN and values below 1 go to the first cell (`as` saturates).
        (c.max(0.0) as usize).min(self.cells - 1)
    }

    /// Adds item `id` with the box `lo..hi`.
    pub(super) fn insert(&mut self, id: u32, lo: DVec2, hi: DVec2) {
        for y in self.cell(lo.y)..=self.cell(hi.y) {
            for x in self.cell(lo.x)..=self.cell(hi.x) {
                self.buckets[y * self.cells + x].push(id);
            }
        }
    }

    /// The items in the cells the box `lo..hi` overlaps (an item once per cell it is in).
    pub(super) fn near(&self, lo: DVec2, hi: DVec2) -> impl Iterator<Item = u32> + '_ {
        let (x0, x1, y0, y1) = (
            self.cell(lo.x),
            self.cell(hi.x),
            self.cell(lo.y),
            self.cell(hi.y),
        );
        (y0..=y1).flat_map(move |y| {
            (x0..=x1).flat_map(move |x| self.buckets[y * self.cells + x].iter().copied())
        })
    }
}

/// Twice the signed area of `(a, b, c)`.
pub(super) fn signed_area2(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let (u, v) = (b - a, c - a);
    u.x * v.y - u.y * v.x
}

/// The region's old faces in its frame, and a grid of them.
pub(super) struct FaceGrid {
    faces: Vec<[DVec2; 3]>,
    grid: Grid,
}

impl FaceGrid {
    pub(super) fn new(faces: Vec<[DVec2; 3]>) -> FaceGrid {
        let mut grid = Grid::new(faces.len());
        for (i, t) in faces.iter().enumerate() {
            grid.insert(i as u32, t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
        }
        FaceGrid { faces, grid }
    }

    /// The face `c` lies in most deeply: the one whose least barycentric coordinate of `c` is
    /// largest (≥ 0 inside; the nearest where rounding puts `c` just outside all), the lower
    /// index on ties, with that coordinate; `None` when no face's box reaches `c`'s cell.
    pub(super) fn locate(&self, c: DVec2) -> Option<(u32, f64)> {
        self.grid
            .near(c, c)
            .map(|i| {
                let t = &self.faces[i as usize];
                let a = signed_area2(t[0], t[1], t[2]);
                let l = signed_area2(c, t[1], t[2])
                    .min(signed_area2(t[0], c, t[2]))
                    .min(signed_area2(t[0], t[1], c));
                (i, l / a)
            })
            .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
    }
}
