//! Measurements of the properties the paper claims for F and its A-patches (Theorem 4.1):
//! interpolation of vertices and normals, C1 across every interior facet of the hull, normal
//! agreement across patch boundaries. Tests, `algesurf smooth` and `algesurf check` use them.

use crate::surface::FaceFunction;
use crate::{ApatchSurface, EdgeCubic, FaceCubic, SplitSide, Tessellation};
use algesurf_bb::Tetrahedron;
use algesurf_hull::Side;
use glam::DVec3;
use std::collections::HashMap;

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
}

/// Worst case of a measured property and where it happened.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Worst<T> {
    /// The worst value (0 when nothing was measured).
    pub value: f64,
    /// Where.
    pub at: Option<T>,
}

impl<T> Default for Worst<T> {
    fn default() -> Self {
        Worst {
            value: 0.0,
            at: None,
        }
    }
}

impl<T: Copy> Worst<T> {
    fn update(&mut self, v: f64, at: T) {
        if v > self.value || self.at.is_none() && v >= self.value {
            self.value = v;
            self.at = Some(at);
        }
    }
}

/// C1 across the interior facets of the hull.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContinuityReport {
    /// Interior facets checked (pairs of pieces sharing a face).
    pub facets: usize,
    /// Sample points in all.
    pub samples: usize,
    /// `|F₁ − F₂| / (|∇F| · facet diameter)`.
    pub value: Worst<(Owner, Owner)>,
    /// `|∇F₁ − ∇F₂| / max(|∇F₁|, |∇F₂|)` (an upper bound on the angle between them in radians
    /// for small values).
    pub gradient: Worst<(Owner, Owner)>,
}

/// Interpolation of the mesh's vertices and normals.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InterpolationReport {
    /// `|F(p_i)| / (|∇F(p_i)| · bounding-box diagonal)`, over every piece containing `p_i`.
    pub value: Worst<usize>,
    /// Angle between `∇F(p_i)` and `n_i` (radians).
    pub normal_angle: Worst<usize>,
}

fn angle(a: DVec3, b: DVec3) -> f64 {
    // atan2(|a×b|, a·b) is accurate for small and large angles alike.
    a.cross(b).length().atan2(a.dot(b))
}

fn key(p: DVec3) -> [u64; 3] {
    p.to_array().map(f64::to_bits)
}

impl ApatchSurface {
    /// All pieces of F.
    pub fn pieces(&self) -> Vec<Piece<'_>> {
        let mut out = Vec::new();
        for (f, ff) in self.faces().iter().enumerate() {
            match ff {
                FaceFunction::Planar => {}
                FaceFunction::Convex { side, cubic } => out.push(Piece {
                    owner: Owner::Face(f),
                    side: *side,
                    function: PieceFunction::Face(cubic),
                }),
                FaceFunction::Split(split) => {
                    for (s, side) in split.sides.iter().zip([Side::Positive, Side::Negative]) {
                        for a in 0..3 {
                            out.push(Piece {
                                owner: Owner::Face(f),
                                side,
                                function: PieceFunction::Split(s, a),
                            });
                        }
                    }
                }
            }
        }
        for (e, pair) in self.edges().iter().enumerate() {
            for (c, side) in pair.iter().zip([Side::Positive, Side::Negative]) {
                if let Some(c) = c {
                    out.push(Piece {
                        owner: Owner::Edge(e),
                        side,
                        function: PieceFunction::Edge(c),
                    });
                }
            }
        }
        out
    }

    /// Samples value and gradient of the two pieces on each side of every interior facet on
    /// the barycentric grid of level `level` of the facet (points on a mesh edge, where the
    /// rational blends are singular but vanish to second order, are skipped; level 6 gives at
    /// least 16 points per facet).
    pub fn continuity_report(&self, level: usize) -> ContinuityReport {
        let pieces = self.pieces();
        let mut by_facet: HashMap<[[u64; 3]; 3], Vec<usize>> = HashMap::new();
        for (i, p) in pieces.iter().enumerate() {
            let t = p.tetrahedron();
            for skip in 0..4 {
                let mut k: Vec<[u64; 3]> = (0..4)
                    .filter(|&v| v != skip)
                    .map(|v| key(t.vertex(v)))
                    .collect();
                k.sort();
                by_facet.entry([k[0], k[1], k[2]]).or_default().push(i);
            }
        }
        let mesh = self.hull().mesh();
        let is_mesh_vertex: std::collections::HashSet<[u64; 3]> =
            mesh.positions().iter().map(|p| key(*p)).collect();
        let mut report = ContinuityReport::default();
        for (facet, users) in &by_facet {
            if users.len() != 2 {
                continue;
            }
            report.facets += 1;
            let (a, b) = (&pieces[users[0]], &pieces[users[1]]);
            let verts: Vec<DVec3> = facet
                .iter()
                .map(|k| DVec3::from_array(k.map(f64::from_bits)))
                .collect();
            let diam = (0..3)
                .map(|i| verts[i].distance(verts[(i + 1) % 3]))
                .fold(0.0, f64::max);
            let on_mesh = facet
                .iter()
                .map(|k| is_mesh_vertex.contains(k))
                .collect::<Vec<_>>();
            for i in 0..=level {
                for j in 0..=(level - i) {
                    let w = [i, j, level - i - j].map(|x| x as f64 / level as f64);
                    // Skip points on the segment between two mesh vertices of the facet.
                    let on_edge =
                        (0..3).any(|z| w[z] == 0.0 && on_mesh[(z + 1) % 3] && on_mesh[(z + 2) % 3]);
                    if on_edge {
                        continue;
                    }
                    let x = verts[0] * w[0] + verts[1] * w[1] + verts[2] * w[2];
                    let (fa, ga) = a.value_gradient(x);
                    let (fb, gb) = b.value_gradient(x);
                    let g = ga.length().max(gb.length());
                    if g == 0.0 {
                        continue;
                    }
                    report.samples += 1;
                    let at = (a.owner, b.owner);
                    report.value.update((fa - fb).abs() / (g * diam), at);
                    report.gradient.update((ga - gb).length() / g, at);
                }
            }
        }
        report
    }

    /// F and ∇F at every mesh vertex from every piece containing it.
    pub fn interpolation_report(&self) -> InterpolationReport {
        let mesh = self.hull().mesh();
        let diag = mesh.bounding_box().diagonal().max(f64::MIN_POSITIVE);
        let index: HashMap<[u64; 3], usize> = mesh
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| (key(*p), i))
            .collect();
        let mut r = InterpolationReport::default();
        for piece in self.pieces() {
            let t = piece.tetrahedron();
            for v in 0..4 {
                let x = t.vertex(v);
                if let Some(&i) = index.get(&key(x)) {
                    let (f, g) = piece.value_gradient(x);
                    r.value
                        .update(f.abs() / (g.length() * diag).max(f64::MIN_POSITIVE), i);
                    r.normal_angle.update(angle(g, self.hull().normals()[i]), i);
                }
            }
        }
        r
    }

    /// At every vertex of the tessellation used by two or more patches, the largest angle
    /// between the normals `∇F` of the pieces (of those patches) that contain it.
    pub fn normal_agreement(&self, t: &Tessellation) -> Worst<usize> {
        let pieces = self.pieces();
        let nf = self.hull().mesh().face_count();
        let mut by_owner: HashMap<Owner, Vec<usize>> = HashMap::new();
        for (i, p) in pieces.iter().enumerate() {
            by_owner.entry(p.owner).or_default().push(i);
        }
        let mut patches_of: HashMap<u32, Vec<u32>> = HashMap::new();
        for (tri, &patch) in t.triangles.iter().zip(&t.triangle_patch) {
            for &v in tri {
                let e = patches_of.entry(v).or_default();
                if !e.contains(&patch) {
                    e.push(patch);
                }
            }
        }
        let mut worst = Worst::default();
        let mesh_vertices = self.hull().mesh().vertex_count() as u32;
        for (&v, patches) in &patches_of {
            if patches.len() < 2 || v < mesh_vertices {
                continue;
            }
            let x = t.positions[v as usize];
            let mut normals = Vec::new();
            for &patch in patches {
                let owner = if (patch as usize) < nf {
                    Owner::Face(patch as usize)
                } else {
                    Owner::Edge(patch as usize - nf)
                };
                for &i in by_owner.get(&owner).map(Vec::as_slice).unwrap_or(&[]) {
                    let tau = pieces[i].tetrahedron().barycentric(x);
                    // Contained up to rounding (1e-9 of the barycentric scale).
                    if tau.iter().all(|&c| c >= -1e-9) {
                        normals.push(pieces[i].value_gradient(x).1);
                    }
                }
            }
            for a in 0..normals.len() {
                for b in a + 1..normals.len() {
                    worst.update(angle(normals[a], normals[b]), v as usize);
                }
            }
        }
        worst
    }
}
