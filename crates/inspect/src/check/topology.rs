//! The combinatorial measurements of the tessellation: closed 2-manifold, no duplicate
//! positions, Euler characteristic equal to the input's.

use super::{InputTopology, Location, Tessellated};
use std::collections::{HashMap, HashSet};

/// Defects of the tessellation's topology.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TopologyMeasure {
    /// Edges that break the manifold: used by more than two triangles or twice in the same
    /// direction, or (closed input only) used by one triangle.
    pub bad_edges: usize,
    /// The first such edge.
    pub first_bad_edge: Option<(u32, u32)>,
    /// Vertices at exactly the position of an earlier vertex (pairs of two interpolated input
    /// vertices excepted: those are coincident in the input).
    pub duplicate_positions: usize,
    /// The first such vertex.
    pub first_duplicate: Option<usize>,
    /// Vertices with a NaN or infinite coordinate.
    pub non_finite: usize,
    /// The first such vertex.
    pub first_non_finite: Option<usize>,
    /// The input's topology.
    pub input: InputTopology,
    /// `V − E + F` of the tessellation (vertices used by a triangle).
    pub euler_characteristic: i64,
}

/// Counts the tessellation's edge and vertex defects and its Euler characteristic.
pub fn topology(t: &Tessellated, input: InputTopology) -> TopologyMeasure {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for tri in &t.triangles {
        for k in 0..3 {
            *directed.entry((tri[k], tri[(k + 1) % 3])).or_default() += 1;
        }
    }
    let mut bad: Vec<(u32, u32)> = Vec::new();
    let mut undirected = 0usize;
    for (&(a, b), &n) in &directed {
        let back = directed.get(&(b, a)).copied().unwrap_or(0);
        if a < b || back == 0 {
            undirected += 1;
        }
        let ok = n == 1 && back <= 1 && (back == 1 || !input.closed);
        if !ok {
            bad.push((a.min(b), a.max(b)));
        }
    }
    bad.sort_unstable();
    bad.dedup();
    let mut seen: HashMap<[u64; 3], usize> = HashMap::new();
    let mut duplicates = Vec::new();
    for (i, p) in t.positions.iter().enumerate() {
        if let Some(j) = seen.insert(p.to_array().map(f64::to_bits), i) {
            // Two interpolated vertices at one position are the input's own coincident
            // vertices (kept apart by repair), not a crack the tessellation opened.
            let from_input = i < t.interpolated_vertices && j < t.interpolated_vertices;
            if !from_input {
                duplicates.push(i);
            }
        }
    }
    let non_finite: Vec<usize> = (0..t.positions.len())
        .filter(|&i| !t.positions[i].is_finite())
        .collect();
    let used: HashSet<u32> = t.triangles.iter().flatten().copied().collect();
    TopologyMeasure {
        bad_edges: bad.len(),
        first_bad_edge: bad.first().copied(),
        duplicate_positions: duplicates.len(),
        first_duplicate: duplicates.first().copied(),
        non_finite: non_finite.len(),
        first_non_finite: non_finite.first().copied(),
        input,
        euler_characteristic: used.len() as i64 - undirected as i64 + t.triangles.len() as i64,
    }
}

impl TopologyMeasure {
    /// Where the first bad edge is.
    pub fn bad_edge_location(&self) -> Option<Location> {
        self.first_bad_edge
            .map(|(a, b)| Location::TessellationEdge(a, b))
    }
}
