//! The analytic measurements: interpolation of vertices and normals, C1 across every interior
//! facet, normal agreement across patch boundaries (Theorem 4.1 of Xu–Huang–Bajaj 2001).

use super::{Element, Location, PatchSurface, Tessellated};
use crate::InspectError;
use algesurf_bb::Tetrahedron;
use glam::DVec3;
use rayon::prelude::*;
use std::collections::{HashMap, HashSet};

/// The worst case of a measured quantity and where it happened.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Worst {
    /// The worst value (0 when nothing was measured; NaN wins over any number).
    pub value: f64,
    /// Where (`None` when nothing was measured).
    pub at: Option<Location>,
}

impl Worst {
    /// Keeps `(v, at)` if it is worse (larger, or NaN) than the current worst.
    pub fn update(&mut self, v: f64, at: Location) {
        let worse = self.at.is_none() || v > self.value || (v.is_nan() && !self.value.is_nan());
        if worse {
            self.value = v;
            self.at = Some(at);
        }
    }

    /// The worse of two.
    pub fn merge(mut self, other: Worst) -> Worst {
        if let Some(at) = other.at {
            self.update(other.value, at);
        }
        self
    }
}

/// The angle between two vectors: atan2(|a×b|, a·b) is accurate for small and large angles.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Exact key of a point: pieces share vertices bit for bit (they are built from the same
/// positions and apexes), so no tolerance is involved in matching facets.
fn key(p: DVec3) -> [u64; 3] {
    p.to_array().map(f64::to_bits)
}

/// A facet: the keys of its three vertices, sorted.
type FacetKey = [[u64; 3]; 3];

/// Interpolation of the vertices and their normals.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InterpolationMeasure {
    /// `|F(p_i)| / (|∇F(p_i)| · bbox diagonal)`, over every piece containing `p_i`.
    pub value: Worst,
    /// Angle between `∇F(p_i)` and `n_i` (radians).
    pub normal_angle: Worst,
    /// (piece, vertex) evaluations.
    pub samples: usize,
}

/// F and ∇F at every interpolated point from every piece having it as a vertex. Only the
/// points that have a normal are measured (the targets' two lists must have one length;
/// [`crate::check::check`] refuses them otherwise).
pub fn interpolation<S: PatchSurface + ?Sized>(surface: &S) -> InterpolationMeasure {
    let (points, normals) = surface.interpolation_targets();
    let points = &points[..points.len().min(normals.len())];
    let (lo, hi) = points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let diag = if points.is_empty() {
        1.0
    } else {
        (hi - lo).length().max(f64::MIN_POSITIVE)
    };
    // Position → every interpolated vertex there. A mesh may keep coincident vertices
    // (repair does not weld vertices whose welding would make the mesh non-manifold), each
    // with its own normal; a piece at that position belongs to one of them, so its gradient
    // is compared with the nearest of their normals. (That cannot hide a defect: a wrong
    // gradient would have to match the normal of another vertex there exactly.)
    let mut index: HashMap<[u64; 3], Vec<usize>> = HashMap::new();
    for (i, p) in points.iter().enumerate() {
        index.entry(key(*p)).or_default().push(i);
    }
    (0..surface.piece_count())
        .into_par_iter()
        .map(|piece| {
            let mut r = InterpolationMeasure::default();
            for (k, x) in surface.piece_simplex(piece).into_iter().enumerate() {
                if let Some(ids) = index.get(&key(x)) {
                    // At the vertex itself: barycentric e_k, exact (see `continuity`).
                    let mut tau = [0.0; 4];
                    tau[k] = 1.0;
                    let (f, g) = surface.value_gradient_barycentric(piece, tau);
                    let (i, a) = ids
                        .iter()
                        .map(|&i| (i, angle(g, normals[i])))
                        .reduce(|a, b| if b.1 < a.1 { b } else { a })
                        .expect("at least one vertex per position");
                    let at = Location::Element(Element::Vertex(i));
                    r.samples += 1;
                    r.value
                        .update(f.abs() / (g.length() * diag).max(f64::MIN_POSITIVE), at);
                    r.normal_angle.update(a, at);
                }
            }
            r
        })
        .reduce(InterpolationMeasure::default, |a, b| InterpolationMeasure {
            value: a.value.merge(b.value),
            normal_angle: a.normal_angle.merge(b.normal_angle),
            samples: a.samples + b.samples,
        })
}

/// The measured mismatch across one interior facet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FacetMeasure {
    /// The two pieces sharing the facet.
    pub pieces: (usize, usize),
    /// Points sampled.
    pub samples: usize,
    /// Largest `|F₁ − F₂| / (|∇F| · facet diameter)`.
    pub value: f64,
    /// Largest `|∇F₁ − ∇F₂| / max(|∇F₁|, |∇F₂|)`.
    pub gradient: f64,
}

/// C1 across the interior facets.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContinuityMeasure {
    /// One entry per interior facet (pair of pieces sharing a face).
    pub facets: Vec<FacetMeasure>,
    /// Worst value mismatch.
    pub value: Worst,
    /// Worst gradient mismatch.
    pub gradient: Worst,
}

impl ContinuityMeasure {
    /// Points sampled in all.
    pub fn samples(&self) -> usize {
        self.facets.iter().map(|f| f.samples).sum()
    }

    /// Fewest points sampled on one facet (0 when there are no facets).
    pub fn min_facet_samples(&self) -> usize {
        self.facets.iter().map(|f| f.samples).min().unwrap_or(0)
    }
}

/// Samples value and gradient of the two pieces on either side of every interior facet on
/// the barycentric grid of `level`. Points on the segment between two interpolated vertices
/// are skipped: there the rational blends of (4.1)/(4.7) are 0/0 (they vanish to second
/// order, so F is C1 there by continuity, but a sample would measure rounding of 0/0).
///
/// Each piece is evaluated at the sample's barycentric coordinates in its own tetrahedron
/// ([`PatchSurface::value_gradient_barycentric`]), which are exact: the facet's grid weights
/// on the facet's vertices, 0 on the opposite one. C1 is a statement about the two pieces'
/// limits *on* the facet; a Cartesian sample point is rounded off the facet by ~ε·|x|, and
/// there the two pieces' gradients differ by their Hessian jump times that offset (F is only
/// C1). On fandisk's thin edge tetrahedra (height 2e-5 at |x| ≈ 15, Hessian ~|∇F|·edge/height²)
/// that term alone was 1.5e-8 of |∇F| while the gradients on the facet agree to 1e-13.
pub fn continuity<S: PatchSurface + ?Sized>(surface: &S, level: usize) -> ContinuityMeasure {
    // Every piece's four facets with the piece, sorted: the pieces of a facet are then next
    // to each other, in increasing order. (A hash map from facet to a vector of pieces, built
    // on one core, was 1.6 s of the bunny's `algesurf check`: 1.9 M facets of 485 k pieces.)
    let mut facet_pieces: Vec<(FacetKey, u32)> = (0..surface.piece_count())
        .into_par_iter()
        .flat_map_iter(|piece| {
            let t = surface.piece_simplex(piece).map(key);
            (0..4).map(move |skip| {
                let mut k = [t[(skip + 1) % 4], t[(skip + 2) % 4], t[(skip + 3) % 4]];
                k.sort();
                (k, piece as u32)
            })
        })
        .collect();
    facet_pieces.par_sort_unstable();
    let is_vertex: HashSet<[u64; 3]> = surface
        .interpolation_targets()
        .0
        .iter()
        .map(|p| key(*p))
        .collect();
    // Facets of exactly two pieces.
    let mut shared: Vec<(FacetKey, (usize, usize))> = facet_pieces
        .chunk_by(|a, b| a.0 == b.0)
        .filter_map(|run| match run {
            [(facet, a), (_, b)] => Some((*facet, (*a as usize, *b as usize))),
            _ => None,
        })
        .collect();
    drop(facet_pieces);
    // Deterministic order (and deterministic `Worst` locations on ties).
    shared.par_sort_unstable_by_key(|&(facet, pieces)| (pieces, facet));
    let facets: Vec<FacetMeasure> = shared
        .par_iter()
        .map(|&(facet, (a, b))| {
            let v = facet.map(|k| DVec3::from_array(k.map(f64::from_bits)));
            let diam = (0..3)
                .map(|i| v[i].distance(v[(i + 1) % 3]))
                .fold(0.0, f64::max);
            let on_mesh = facet.map(|k| is_vertex.contains(&k));
            // Where each facet vertex sits in each piece's tetrahedron (bit-exact keys, as
            // the facets were matched).
            let local = |piece: usize| {
                let t = surface.piece_simplex(piece).map(key);
                facet.map(|k| t.iter().position(|x| *x == k).expect("a facet vertex"))
            };
            let (a_index, b_index) = (local(a), local(b));
            let mut m = FacetMeasure {
                pieces: (a, b),
                samples: 0,
                value: 0.0,
                gradient: 0.0,
            };
            for i in 0..=level {
                for j in 0..=(level - i) {
                    let w = [i, j, level - i - j].map(|x| x as f64 / level as f64);
                    let on_edge =
                        (0..3).any(|z| w[z] == 0.0 && on_mesh[(z + 1) % 3] && on_mesh[(z + 2) % 3]);
                    if on_edge {
                        continue;
                    }
                    let (fa, ga) = surface.value_gradient_barycentric(a, on_facet(&a_index, w));
                    let (fb, gb) = surface.value_gradient_barycentric(b, on_facet(&b_index, w));
                    let g = ga.length().max(gb.length());
                    m.samples += 1;
                    // A vanishing gradient on a facet is itself a defect (F is regular
                    // near its zero set); dividing by 0 gives NaN/inf, which fails.
                    m.value = nan_max(m.value, (fa - fb).abs() / (g * diam));
                    m.gradient = nan_max(m.gradient, (ga - gb).length() / g);
                }
            }
            m
        })
        .collect();
    let mut out = ContinuityMeasure::default();
    for f in &facets {
        let at = Location::Facet(
            surface.piece_element(f.pieces.0),
            surface.piece_element(f.pieces.1),
        );
        out.value.update(f.value, at);
        out.gradient.update(f.gradient, at);
    }
    out.facets = facets;
    out
}

/// Barycentric coordinates in a piece of the facet point with weights `w` on the facet's
/// vertices, which sit at `index` in the piece: exact, with 0 on the opposite vertex.
fn on_facet(index: &[usize; 3], w: [f64; 3]) -> [f64; 4] {
    let mut tau = [0.0; 4];
    for z in 0..3 {
        tau[index[z]] = w[z];
    }
    tau
}

/// `max` that keeps NaN (a failed measurement must not be hidden by `f64::max`).
fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// Normal agreement across patch boundaries.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NormalAgreement {
    /// Largest angle (radians) between the normals of two pieces of different patches at a
    /// boundary vertex of the tessellation.
    pub angle: Worst,
    /// Boundary vertices measured.
    pub vertices: usize,
}

/// At every tessellation vertex used by two or more patches (the interpolated mesh vertices
/// excepted, see [`Tessellated::interpolated_vertices`]), the largest angle between the
/// normals `∇F` of the pieces of those patches whose tetrahedra contain it (pieces of one
/// patch are compared too: on a split face they meet there as well).
///
/// # Errors
/// [`InspectError::Measurement`] when a piece's tetrahedron is degenerate, a triangle of `t`
/// names a vertex it does not have, or a patch lists a piece that does not exist.
pub fn normal_agreement<S: PatchSurface + ?Sized>(
    surface: &S,
    t: &Tessellated,
) -> Result<NormalAgreement, InspectError> {
    if let Some((k, v)) = t.triangles.iter().enumerate().find_map(|(k, tri)| {
        tri.iter()
            .find(|&&v| v as usize >= t.positions.len())
            .map(|&v| (k, v))
    }) {
        return Err(InspectError::Measurement(format!(
            "tessellation triangle {k} names vertex {v}, but the tessellation has {} vertices",
            t.positions.len()
        )));
    }
    // In parallel, then the first degenerate one in order (the same error as a loop).
    let tets: Vec<Result<Tetrahedron, _>> = (0..surface.piece_count())
        .into_par_iter()
        .map(|i| Tetrahedron::new(surface.piece_simplex(i)))
        .collect();
    let tets: Vec<Tetrahedron> = tets
        .into_iter()
        .enumerate()
        .map(|(i, t)| {
            t.map_err(|e| {
                InspectError::Measurement(format!(
                    "the tetrahedron of {} is degenerate: {e}",
                    surface.piece_element(i)
                ))
            })
        })
        .collect::<Result<_, _>>()?;
    // The patches at each vertex in the order of their first triangle there: the vertex's
    // triangles by sorting (vertex, triangle) pairs, then each run's distinct patches. Hash
    // maps from vertex to a vector of patches, and from patch to pieces, filled on one core,
    // were 0.85 s of the bunny's `algesurf check` (3.6 M triangles).
    let mut corners: Vec<(u32, u32)> = t
        .triangles
        .par_iter()
        .enumerate()
        .flat_map_iter(|(k, tri)| tri.iter().map(move |&v| (v, k as u32)))
        .collect();
    corners.par_sort_unstable();
    let mut boundary: Vec<(u32, Vec<u32>)> = corners
        .par_chunk_by(|a, b| a.0 == b.0)
        .filter(|run| run[0].0 as usize >= t.interpolated_vertices)
        .filter_map(|run| {
            let mut patches: Vec<u32> = Vec::new();
            // A triangle without a patch id (a shorter list) has none to compare, as before.
            for &(_, k) in run {
                let Some(&patch) = t.triangle_patch.get(k as usize) else {
                    continue;
                };
                if !patches.contains(&patch) {
                    patches.push(patch);
                }
            }
            (patches.len() >= 2).then(|| (run[0].0, patches))
        })
        .collect();
    drop(corners);
    boundary.sort_unstable_by_key(|(v, _)| *v);
    // The pieces of every patch at a boundary vertex, by patch id.
    let mut wanted: Vec<u32> = boundary
        .iter()
        .flat_map(|(_, p)| p.iter().copied())
        .collect();
    wanted.par_sort_unstable();
    wanted.dedup();
    let pieces: Vec<Vec<usize>> = wanted
        .par_iter()
        .map(|&p| surface.patch_pieces(p))
        .collect();
    // The surface's own lists, checked before they index its pieces.
    for (&patch, list) in wanted.iter().zip(&pieces) {
        if let Some(&bad) = list.iter().find(|&&i| i >= tets.len()) {
            return Err(InspectError::Measurement(format!(
                "patch {patch} lists piece {bad}, but the surface has {} pieces",
                tets.len()
            )));
        }
    }
    let pieces_of = |patch: u32| -> &[usize] {
        let i = wanted
            .binary_search(&patch)
            .expect("the pieces of every boundary patch are listed");
        &pieces[i]
    };
    let angle_worst = boundary
        .par_iter()
        .map(|(v, patches)| {
            let x = t.positions[*v as usize];
            let mut normals: Vec<(u32, DVec3)> = Vec::new();
            for &patch in patches {
                for &i in pieces_of(patch) {
                    if let Some(tau) = contained(&tets[i], x) {
                        normals.push((patch, surface.value_gradient_barycentric(i, tau).1));
                    }
                }
            }
            let mut w = Worst::default();
            for a in 0..normals.len() {
                for b in a + 1..normals.len() {
                    let at = Location::Boundary {
                        vertex: *v as usize,
                        patches: (
                            surface.patch_element(normals[a].0),
                            surface.patch_element(normals[b].0),
                        ),
                    };
                    w.update(angle(normals[a].1, normals[b].1), at);
                }
            }
            w
        })
        .reduce(Worst::default, Worst::merge);
    Ok(NormalAgreement {
        angle: angle_worst,
        vertices: boundary.len(),
    })
}

/// Safety factor on the rounding bound of [`contained`]: the vertex is a convex combination
/// of tetrahedron vertices (~4 roundings), then `x − v_0` and a dot product with the dual
/// vector (~4 more); 16 covers them with room to spare and is still rounding level.
const CONTAINMENT_ROUNDING: f64 = 16.0;

/// The barycentric coordinates in `tet` of the tessellation vertex `x` when `x` lies in `tet`
/// up to rounding, with the coordinates that are 0 up to rounding set to exactly 0 (and the
/// rest renormalised); `None` when it lies outside by more than rounding.
///
/// The rounding of a computed coordinate: `x` carries ~ε·M (M the size of the coordinates),
/// and the barycentric map's dual vectors carry a relative error ~ε·κ (κ = diameter ·
/// max |∇τ_i|, see `Simplex::new`), so `|δτ_i| ≲ ε·(M + κ·diameter)·|∇τ_i|`. A fixed
/// tolerance in τ (it was 1e-9) ignores that scale: it is far too wide on well-shaped
/// tetrahedra — it took in a piece on the far side of a split face's plane, 4e-11 away, whose
/// extrapolated gradient differs by the Hessian jump across that plane (2.9e-8 on fandisk) —
/// and only ten times the rounding on thin ones (rounding moves τ by ~1e-10 at height 2e-5 and
/// |x| ≈ 15, and by more on thinner ones). Snapping the coordinates
/// that vanish up to rounding puts a vertex the tessellation placed on a facet back on it,
/// where C1 says the pieces' gradients agree; it moves the point by rounding only, so a real
/// jump of ∇F across the facet is seen in full.
fn contained(tet: &Tetrahedron, x: DVec3) -> Option<[f64; 4]> {
    let v = tet.vertices();
    let g = tet.barycentric_gradients();
    let size = v.iter().fold(x.length(), |m, p| m.max(p.length()));
    let mut diam: f64 = 0.0;
    for a in 0..4 {
        for b in a + 1..4 {
            diam = diam.max(v[a].distance(v[b]));
        }
    }
    let kappa = diam * g.iter().map(|d| d.length()).fold(0.0, f64::max);
    let reach = CONTAINMENT_ROUNDING * f64::EPSILON * (size + kappa * diam);
    let mut tau = tet.barycentric(x);
    for i in 0..4 {
        let tol = reach * g[i].length();
        if tau[i] < -tol {
            return None;
        }
        if tau[i].abs() <= tol {
            tau[i] = 0.0;
        }
    }
    let sum: f64 = tau.iter().sum();
    (sum > 0.0).then(|| tau.map(|t| t / sum))
}
