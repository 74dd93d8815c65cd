//! Changing the free parameters `f_0003` after construction (§5.3 of Xu–Huang–Bajaj 2001:
//! "the free parameters can be used to adjust the shape interactively").
//!
//! # What a parameter reaches
//!
//! The apex value `b = f_0003` of a face side enters F in exactly two places:
//!
//! * the face's own pieces on that side: for a convex face the apex coefficient and the layer-2
//!   coefficients `(f_0003 + 2 q_{e_a+e_3})/3` of (4.14); for a split face `δ·τ_apex²` on each
//!   of the three sub-cubics (the constrained least-squares solution moves by exactly that, see
//!   `geometry::apex_square`);
//! * through C1 across the facets `[p_i p_j u]` shared with the edge tetrahedra (Step 7,
//!   (4.15)–(4.17): the edge cubic's coefficients with `λ_0 ≤ 1` are the blossoms of the face's
//!   polynomial at the edge tetrahedron's vertices), the edge cubic *on the same side* of each of
//!   the face's three edges.
//!
//! Nothing else depends on it: the other side of a split face has its own apex value, the edge
//! tetrahedra of the other side share no facet with this side's tetrahedra, and the edge cubics
//! of other faces' edges are blossoms of other faces' polynomials. [`UpdatedPatches`] lists the
//! face and those edges, and [`ApatchSurface::set_free_parameter`] touches nothing else.
//!
//! # Admissibility (Step 6)
//!
//! A value is admissible when (1) it is strictly beyond the face's single-sheet bound
//! ([`FreeParameter::bound`], Lemma 2.3 over the face's rays), and (2) every affected edge
//! tetrahedron still satisfies its own Step 6 bound `B_ijkl` with no further increment (the
//! least common increment `b` of its two faces' apex values that Lemma 2.3 needs on its rays,
//! bounded like construction does, over every ray, is negative). Construction *raised* both faces of an edge to meet (2); a later change of one
//! face cannot silently raise its neighbours (that would change parameters the caller did not
//! touch), so a value that breaks (2) is rejected and the surface is left exactly as it was. A
//! one-sided change is not a common lift of both faces, so no monotonicity is claimed: the edge
//! bounds are simply re-established after every change.

use crate::surface::{FaceFunction, edge_cubic, edge_need};
use crate::{ApatchError, ApatchSurface, EdgeCubic, FreeParameter};
use algesurf_hull::Side;

/// The patches a parameter change touched: the face (its pieces on `side`) and the edge
/// tetrahedra on the same side of its edges. Patch ids as in
/// [`crate::Tessellation::triangle_patch`]: faces by index, edges as `face_count + edge`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct UpdatedPatches {
    /// Faces whose pieces changed, ascending.
    pub faces: Vec<usize>,
    /// Hull edges whose edge cubic changed, ascending.
    pub edges: Vec<usize>,
}

impl UpdatedPatches {
    /// Adds another update's patches (kept sorted and unique).
    pub fn merge(&mut self, other: &UpdatedPatches) {
        self.faces.extend_from_slice(&other.faces);
        self.edges.extend_from_slice(&other.edges);
        self.faces.sort_unstable();
        self.faces.dedup();
        self.edges.sort_unstable();
        self.edges.dedup();
    }
}

fn slot(side: Side) -> usize {
    if side == Side::Positive { 0 } else { 1 }
}

impl ApatchSurface {
    /// The free parameter of `face`'s apex on `side`, if that side has a tetrahedron.
    pub fn free_parameter(&self, face: usize, side: Side) -> Option<&FreeParameter> {
        let start = self.parameters.partition_point(|p| p.face < face);
        self.parameters[start..]
            .iter()
            .take_while(|p| p.face == face)
            .find(|p| p.side == side)
    }

    /// Sets the value of F at the apex of `face` on `side` (`f_0003`), updating every
    /// coefficient that depends on it (see the module documentation), and returns the patches
    /// that changed (for [`ApatchSurface::retessellate_patches`]).
    ///
    /// Errors, leaving the surface unchanged: no such free parameter, a non-finite value, a
    /// value not strictly beyond the face's single-sheet bound, or one that breaks the Step 6
    /// bound of an edge tetrahedron of the face.
    pub fn set_free_parameter(
        &mut self,
        face: usize,
        side: Side,
        value: f64,
    ) -> Result<UpdatedPatches, ApatchError> {
        let param = *self.free_parameter(face, side).ok_or_else(|| {
            ApatchError::Inconsistent(format!(
                "face {face} has no free parameter on the {} side",
                side.name()
            ))
        })?;
        let sign = if side == Side::Positive { 1.0 } else { -1.0 };
        if !value.is_finite() {
            return Err(ApatchError::Degenerate(format!(
                "face {face}, {} side: f_0003 = {value} is not admissible: it must be a finite \
                 number",
                side.name()
            )));
        }
        if sign * value <= sign * param.bound {
            return Err(ApatchError::Degenerate(format!(
                "face {face}, {} side: f_0003 = {value:e} is not admissible: it must be {} the \
                 single-sheet bound {:e} (Step 6)",
                side.name(),
                if sign > 0.0 { "above" } else { "below" },
                param.bound
            )));
        }
        let old_face = self.faces[face].clone();
        let delta = value - param.value;
        match &mut self.faces[face] {
            FaceFunction::Convex { cubic, .. } => cubic.set_f0003(value),
            FaceFunction::Split(split) => split.sides[slot(side)].raise_apex(delta),
            FaceFunction::Planar => unreachable!("planar faces have no free parameter"),
        }
        // The edge cubics on this side of the face's three edges.
        let mesh = self.hull.mesh();
        let tri = mesh.triangles()[face];
        let topo = mesh.topology();
        let mut edges = Vec::with_capacity(3);
        for a in 0..3 {
            let e = topo
                .find_edge(tri[a], tri[(a + 1) % 3])
                .ok_or_else(|| ApatchError::Inconsistent(format!("face {face}: missing edge")))?
                as usize;
            if self.edges[e][slot(side)].is_some() {
                edges.push(e);
            }
        }
        edges.sort_unstable();
        let old_edges: Vec<Option<EdgeCubic>> = edges
            .iter()
            .map(|&e| self.edges[e][slot(side)].clone())
            .collect();
        let rebuilt = edges.iter().try_for_each(|&e| -> Result<(), ApatchError> {
            let cubic = edge_cubic(&self.hull, &self.faces, e, side)?;
            self.edges[e][slot(side)] = Some(cubic);
            let need = edge_need(
                &self.hull,
                &self.faces,
                &self.edges,
                e,
                slot(side),
                // Only `need ≥ 0` is rejected: anything below it may stop early.
                -f64::MIN_POSITIVE,
            )?;
            if need >= 0.0 {
                return Err(ApatchError::Degenerate(format!(
                    "face {face}, {} side: f_0003 = {value:e} is not admissible: the edge \
                         tetrahedron of hull edge {e} would need its faces' apex values raised \
                         by {need:e} (Step 6, edge bound)",
                    side.name()
                )));
            }
            Ok(())
        });
        if let Err(err) = rebuilt {
            self.faces[face] = old_face;
            for (&e, old) in edges.iter().zip(old_edges) {
                self.edges[e][slot(side)] = old;
            }
            return Err(err);
        }
        let start = self.parameters.partition_point(|p| p.face < face);
        for p in self.parameters[start..]
            .iter_mut()
            .take_while(|p| p.face == face)
            .filter(|p| p.side == side)
        {
            p.value = value;
            p.relative_margin = (value - p.bound).abs() / p.scale;
        }
        Ok(UpdatedPatches {
            faces: vec![face],
            edges,
        })
    }

    /// Sets several free parameters in turn (see [`ApatchSurface::set_free_parameter`]); on the
    /// first error the ones before it stay set and the error is returned.
    pub fn set_free_parameters(
        &mut self,
        values: &[(usize, Side, f64)],
    ) -> Result<UpdatedPatches, ApatchError> {
        let mut all = UpdatedPatches::default();
        for &(face, side, value) in values {
            all.merge(&self.set_free_parameter(face, side, value)?);
        }
        Ok(all)
    }
}
