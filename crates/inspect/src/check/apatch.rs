//! [`PatchSurface`] for the cubic A-patches of [`ApatchSurface`] (Xu–Huang–Bajaj 2001).

use super::{Element, InputTopology, PatchSurface, Tessellated};
use crate::InspectError;
use algesurf_apatch::{ApatchSurface, Owner, Piece, PieceFunction};
use algesurf_hull::Side;
use glam::DVec3;
use std::collections::HashMap;

/// An [`ApatchSurface`] seen by the check battery: its pieces (one rational cubic per convex
/// face, three cubics per side of a split face, one rational cubic per edge tetrahedron)
/// listed once, and its patches (face patches numbered by hull face, edge patches as
/// `face_count + edge`, as in [`algesurf_apatch::Tessellation`]).
#[derive(Debug)]
pub struct ApatchView<'a> {
    surface: &'a ApatchSurface,
    pieces: Vec<Piece<'a>>,
    by_owner: HashMap<Owner, Vec<usize>>,
}

impl<'a> ApatchView<'a> {
    /// Lists the pieces of `surface`.
    pub fn new(surface: &'a ApatchSurface) -> Self {
        Self::with_pieces(surface, surface.pieces())
    }

    /// A view of the pieces of the faces and edges `owners` alone
    /// ([`ApatchSurface::pieces_of`]): the measures see only those, so
    /// [`crate::check::continuity`] on it measures the facets they share, a sample that costs
    /// far less than every piece (`algesurf smooth`'s continuity figures). The patches and the
    /// tessellation are still the whole surface's.
    pub fn of_owners(surface: &'a ApatchSurface, owners: impl IntoIterator<Item = Owner>) -> Self {
        Self::with_pieces(surface, surface.pieces_of(owners))
    }

    fn with_pieces(surface: &'a ApatchSurface, pieces: Vec<Piece<'a>>) -> Self {
        let mut by_owner: HashMap<Owner, Vec<usize>> = HashMap::new();
        for (i, p) in pieces.iter().enumerate() {
            by_owner.entry(p.owner).or_default().push(i);
        }
        ApatchView {
            surface,
            pieces,
            by_owner,
        }
    }

    /// The surface.
    pub fn surface(&self) -> &'a ApatchSurface {
        self.surface
    }

    /// The pieces, in the order of their indices.
    pub fn pieces(&self) -> &[Piece<'a>] {
        &self.pieces
    }

    fn owner_of(&self, patch: u32) -> Owner {
        self.surface.patch_owner(patch)
    }
}

fn element(owner: Owner, side: Option<Side>) -> Element {
    match owner {
        Owner::Face(f) => Element::Face(f, side),
        Owner::Edge(e) => Element::Edge(e, side),
    }
}

impl PatchSurface for ApatchView<'_> {
    fn piece_count(&self) -> usize {
        self.pieces.len()
    }

    fn piece_element(&self, piece: usize) -> Element {
        let p = &self.pieces[piece];
        match (p.owner, p.function) {
            (Owner::Face(f), PieceFunction::Split(_, a)) => Element::SplitFace(f, p.side, a),
            (owner, _) => element(owner, Some(p.side)),
        }
    }

    fn piece_simplex(&self, piece: usize) -> [DVec3; 4] {
        *self.pieces[piece].tetrahedron().vertices()
    }

    fn value_gradient(&self, piece: usize, x: DVec3) -> (f64, DVec3) {
        self.pieces[piece].value_gradient(x)
    }

    fn value_gradient_barycentric(&self, piece: usize, tau: [f64; 4]) -> (f64, DVec3) {
        self.pieces[piece].value_gradient_at_barycentric(tau)
    }

    fn interpolation_targets(&self) -> (&[DVec3], &[DVec3]) {
        let hull = self.surface.hull();
        (hull.mesh().positions(), hull.normals())
    }

    fn tessellate(&self, resolution: usize) -> Result<Tessellated, InspectError> {
        let t = self
            .surface
            .tessellate(resolution, resolution)
            .map_err(|e| InspectError::Measurement(format!("cannot tessellate: {e}")))?;
        Ok(Tessellated {
            positions: t.positions,
            triangles: t.triangles,
            triangle_patch: t.triangle_patch,
            missed_rays: t.missed_rays,
            multiple_roots: t.multiple_roots,
            interpolated_vertices: self.surface.hull().mesh().vertex_count(),
        })
    }

    fn patch_element(&self, patch: u32) -> Element {
        element(self.owner_of(patch), None)
    }

    fn patch_pieces(&self, patch: u32) -> Vec<usize> {
        self.by_owner
            .get(&self.owner_of(patch))
            .cloned()
            .unwrap_or_default()
    }

    fn parameter_margins(&self) -> Vec<(Element, f64)> {
        self.surface
            .free_parameters()
            .iter()
            .map(|p| {
                // Step 6: the apex value must lie above the bound on the positive side and
                // below it on the negative side; the signed distance is the margin.
                let sign = if p.side == Side::Positive { 1.0 } else { -1.0 };
                let margin = sign * (p.value - p.bound) / p.scale;
                (Element::Face(p.face, Some(p.side)), margin)
            })
            .collect()
    }

    fn input_topology(&self) -> InputTopology {
        let mesh = self.surface.hull().mesh();
        InputTopology {
            closed: mesh.boundary_loops().is_empty(),
            euler_characteristic: mesh.euler_characteristic(),
        }
    }
}
