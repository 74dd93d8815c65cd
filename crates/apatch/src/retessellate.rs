//! Incremental re-tessellation after a free-parameter change (§5.3 of Xu–Huang–Bajaj 2001).
//!
//! [`ApatchSurface::tessellate`] records which ray wrote which vertex
//! ([`crate::tessellate::TessellationLayout`]). After [`ApatchSurface::set_free_parameter`]
//! only the rays of the [`UpdatedPatches`] can change, and each is re-evaluated by the same
//! function the full tessellation uses, so the overwritten points are bit-for-bit those of a
//! full tessellation of the updated surface. The topology (which rays share a vertex) depends
//! on each ray's `at_start` decision; F on the face plane does not depend on the apex values
//! (the lift `τ_apex²` vanishes there to second order), but the decision compares `F(q)` with
//! the size of all four shooting coefficients, so it can flip in borderline cases. When any
//! re-evaluated ray's decision differs, the whole tessellation is redone instead
//! ([`Retessellation::Full`]), which keeps the result equal to a full tessellation always.

use crate::tessellate::{AT_START, GridPoint, MISSED, MULTIPLE, RayPoint, face_grid, grid_point};
use crate::{ApatchError, ApatchSurface, Tessellation, UpdatedPatches};

/// How [`ApatchSurface::retessellate_patches`] brought a tessellation up to date.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Retessellation {
    /// Only the rays of the updated patches were re-evaluated and their vertices overwritten.
    Incremental {
        /// Rays evaluated.
        rays: usize,
    },
    /// A ray's start-on-surface decision changed (so the vertex sharing would), or the
    /// tessellation had no layout: it was rebuilt in full.
    Full,
}

impl ApatchSurface {
    /// Brings `tess` (made by [`ApatchSurface::tessellate`] on this surface before the
    /// parameter changes that returned `updated`) up to date, re-evaluating only the rays of
    /// the updated patches and keeping the topology. The result equals, bit for bit, a fresh
    /// `tessellate` at the same resolution.
    pub fn retessellate_patches(
        &self,
        tess: &mut Tessellation,
        updated: &UpdatedPatches,
    ) -> Result<Retessellation, ApatchError> {
        let Some(layout) = tess.layout.as_ref() else {
            return Err(ApatchError::Inconsistent(
                "the tessellation has no ray layout (not made by ApatchSurface::tessellate)".into(),
            ));
        };
        let (n, m) = (layout.n, layout.m);
        let nf = self.hull().mesh().face_count();
        if layout.face_ids.len() != nf * (n + 1) * (n + 2) / 2
            || layout.edge_ids.len() != self.edges().len() * (n - 1) * (m - 1)
        {
            return Err(ApatchError::Inconsistent(
                "the tessellation was made from another surface".into(),
            ));
        }
        // Evaluate first, write afterwards: a topology change leaves `tess` untouched until
        // the full rebuild replaces it.
        let grid = face_grid(n);
        let mut writes: Vec<(u32, u32, RayPoint)> = Vec::new();
        for &f in &updated.faces {
            let rays = self.face_rays(f, &grid, n);
            let ids = &layout.face_ids[f * grid.len()..(f + 1) * grid.len()];
            for ((g, r), &id) in grid.iter().zip(rays).zip(ids) {
                if !matches!(grid_point(g, n), GridPoint::Corner(_)) {
                    writes.push((id, f as u32, r));
                }
            }
        }
        let inner = (n - 1) * (m - 1);
        for &e in &updated.edges {
            let rays = self.edge_rays(e, n, m);
            let ids = &layout.edge_ids[e * inner..(e + 1) * inner];
            for (r, &id) in rays.into_iter().zip(ids) {
                writes.push((id, (nf + e) as u32, r));
            }
        }
        let topology_kept = writes
            .iter()
            .all(|(id, _, r)| r.at_start == (layout.flags[*id as usize] & AT_START != 0));
        if !topology_kept {
            *tess = self.tessellate(n, m)?;
            return Ok(Retessellation::Full);
        }
        let layout = tess.layout.as_mut().expect("checked above");
        let mut flagged = false;
        for (id, patch, r) in &writes {
            let i = *id as usize;
            // A shared (t = 0) vertex keeps the value of the patch that created it.
            if layout.owner[i] != *patch {
                continue;
            }
            flagged |= layout.flags[i] & (MISSED | MULTIPLE) != 0 || r.missed || r.multiple;
            tess.positions[i] = r.position;
            tess.normals[i] = r.normal;
            layout.flags[i] = r.flags();
        }
        if flagged {
            // The lists are in vertex order (vertices are created in the order rays are
            // listed); rebuild them from the per-vertex flags.
            tess.missed_rays.clear();
            tess.multiple_roots.clear();
            for (i, (&fl, &owner)) in layout.flags.iter().zip(&layout.owner).enumerate() {
                if fl & MISSED != 0 {
                    tess.missed_rays.push((owner, tess.positions[i]));
                }
                if fl & MULTIPLE != 0 {
                    tess.multiple_roots.push((owner, tess.positions[i]));
                }
            }
        }
        Ok(Retessellation::Incremental { rays: writes.len() })
    }
}
