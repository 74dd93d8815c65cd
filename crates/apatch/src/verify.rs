//! The pieces of F — one function on one tetrahedron each, with the mesh element it belongs
//! to — as the measurements of Theorem 4.1 see them. The measurements themselves
//! (interpolation, C1 across every interior facet, normal agreement, the tessellation's
//! topology, parameter margins) are the check battery of `algesurf-inspect`
//! (`algesurf_inspect::check`), which reads F through [`ApatchSurface::pieces`].

use crate::cubic;
use crate::geometry::gradient_from_partials;
use crate::surface::FaceFunction;
use crate::{ApatchSurface, EdgeCubic, FaceCubic, SplitSide};
use algesurf_bb::Tetrahedron;
use algesurf_hull::Side;
use glam::DVec3;

/// The mesh element a piece of F belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Owner {
    /// A face of the hull's mesh.
    Face(usize),
    /// An edge of the hull's mesh.
    Edge(usize),
}

/// One polynomial (or rational) piece of F on one tetrahedron.
#[derive(Clone, Copy, Debug)]
pub enum PieceFunction<'a> {
    /// A convex face's rational cubic.
    Face(&'a FaceCubic),
    /// Sub-tetrahedron `a` of one side of a split face.
    Split(&'a SplitSide, usize),
    /// An edge cubic.
    Edge(&'a EdgeCubic),
}

/// A piece of F with its owner and side.
#[derive(Clone, Copy, Debug)]
pub struct Piece<'a> {
    /// Face or edge of the mesh.
    pub owner: Owner,
    /// Side of the hull.
    pub side: Side,
    /// The function.
    pub function: PieceFunction<'a>,
}

impl Piece<'_> {
    /// The tetrahedron.
    pub fn tetrahedron(&self) -> &Tetrahedron {
        match self.function {
            PieceFunction::Face(c) => c.tetrahedron(),
            PieceFunction::Split(s, a) => &s.tets[a],
            PieceFunction::Edge(c) => c.tetrahedron(),
        }
    }

    /// F and ∇F at `x`.
    pub fn value_gradient(&self, x: DVec3) -> (f64, DVec3) {
        match self.function {
            PieceFunction::Face(c) => c.value_gradient(x),
            PieceFunction::Split(s, a) => (
                s.polys[a].value_at(&s.tets[a], x),
                s.polys[a].gradient_at(&s.tets[a], x),
            ),
            PieceFunction::Edge(c) => c.value_gradient(x),
        }
    }

    /// F and ∇F at the point with barycentric coordinates `tau` in the piece's tetrahedron.
    ///
    /// Unlike [`Piece::value_gradient`] this involves no Cartesian→barycentric solve, so a
    /// point given on a facet (`tau` with exact zeros) is evaluated exactly there. That matters
    /// on thin tetrahedra: a Cartesian point on a facet is rounded off it by ~ε·|x|, which is
    /// ~1e-10 in the barycentric coordinate of a tetrahedron of height 2e-5 at |x| ≈ 15 (the
    /// fandisk's edge tetrahedra), and the second derivatives of F there (~|∇F|·edge/height²)
    /// turn that offset into a 1e-8 change of ∇F that is not a property of F on the facet.
    pub fn value_gradient_at_barycentric(&self, tau: [f64; 4]) -> (f64, DVec3) {
        match self.function {
            PieceFunction::Face(c) => c.value_gradient_at_tau(tau),
            PieceFunction::Split(s, a) => {
                let (f, dp) = cubic::value_partials(&cubic::coeffs_of(&s.polys[a]), tau);
                (f, gradient_from_partials(&s.tets[a], dp, [0.0; 4]))
            }
            PieceFunction::Edge(c) => c.value_gradient_at_tau(tau),
        }
    }
}

impl ApatchSurface {
    /// The mesh element that patch `patch` of a tessellation belongs to: face patches are
    /// numbered by hull face, edge patches follow as `face_count + edge`
    /// ([`crate::Tessellation::triangle_patch`]).
    ///
    /// ```
    /// use algesurf_apatch::{ApatchSurface, Owner, SurfaceOptions};
    /// use algesurf_mesh::shapes::icosphere;
    /// let mesh = icosphere(0); // the icosahedron: 20 faces
    /// assert_eq!(mesh.face_count(), 20);
    /// let normals: Vec<_> = mesh.positions().iter().map(|p| p.normalize()).collect();
    /// let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default())?;
    /// assert_eq!(s.patch_owner(3), Owner::Face(3));
    /// assert_eq!(s.patch_owner(20 + 7), Owner::Edge(7));
    /// # Ok::<(), algesurf_apatch::ApatchError>(())
    /// ```
    pub fn patch_owner(&self, patch: u32) -> Owner {
        let nf = self.hull().mesh().face_count();
        match patch as usize {
            p if p < nf => Owner::Face(p),
            p => Owner::Edge(p - nf),
        }
    }

    /// All pieces of F: face pieces in face order, then edge pieces in edge order, the
    /// positive side before the negative.
    pub fn pieces(&self) -> Vec<Piece<'_>> {
        let owners = (0..self.faces().len())
            .map(Owner::Face)
            .chain((0..self.edges().len()).map(Owner::Edge));
        self.pieces_of(owners)
    }

    /// The pieces of the faces and edges `owners`, in that order, each owner's as in
    /// [`ApatchSurface::pieces`] (none for a planar face, an edge without tetrahedra, or an
    /// index out of range): a sample of F without listing all of it.
    ///
    /// ```
    /// use algesurf_apatch::{ApatchSurface, Owner, SurfaceOptions};
    /// use algesurf_mesh::shapes::icosphere;
    /// let mesh = icosphere(0);
    /// let normals: Vec<_> = mesh.positions().iter().map(|p| p.normalize()).collect();
    /// let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default())?;
    /// // A convex face of the icosahedron has one piece, each edge two (one per side).
    /// let some = s.pieces_of([Owner::Face(0), Owner::Edge(4)]);
    /// assert_eq!(some.len(), s.pieces().iter().filter(|p| {
    ///     p.owner == Owner::Face(0) || p.owner == Owner::Edge(4)
    /// }).count());
    /// assert!(s.pieces_of([Owner::Face(1000)]).is_empty());
    /// # Ok::<(), algesurf_apatch::ApatchError>(())
    /// ```
    pub fn pieces_of(&self, owners: impl IntoIterator<Item = Owner>) -> Vec<Piece<'_>> {
        let mut out = Vec::new();
        for owner in owners {
            match owner {
                Owner::Face(f) => match self.faces().get(f) {
                    None | Some(FaceFunction::Planar) => {}
                    Some(FaceFunction::Convex { side, cubic }) => out.push(Piece {
                        owner,
                        side: *side,
                        function: PieceFunction::Face(cubic),
                    }),
                    Some(FaceFunction::Split(split)) => {
                        for (s, side) in split.sides.iter().zip([Side::Positive, Side::Negative]) {
                            for a in 0..3 {
                                out.push(Piece {
                                    owner,
                                    side,
                                    function: PieceFunction::Split(s, a),
                                });
                            }
                        }
                    }
                },
                Owner::Edge(e) => {
                    let Some(pair) = self.edges().get(e) else {
                        continue;
                    };
                    for (c, side) in pair.iter().zip([Side::Positive, Side::Negative]) {
                        if let Some(c) = c {
                            out.push(Piece {
                                owner,
                                side,
                                function: PieceFunction::Edge(c),
                            });
                        }
                    }
                }
            }
        }
        out
    }
}
