//! Shared edges: how neighbouring patches agree on the vertices of the edge between them.
//!
//! **No cracks.** Neighbouring patches must place the same vertices on the edge they share.
//! Every patch edge belongs to one of the patch's two directions (the edges `v = 0, 1` run along
//! `u` and use `m_u`). Edges with identical control points (in either order) tie their
//! directions together, across all patches and whatever the topology, and each tied set takes
//! the largest count of its members ([`tie_shared_edges`]). Edge vertices are then evaluated
//! from the edge's own cubic in a canonical orientation ([`canonical`]; de Casteljau, so a
//! collapsed edge at a pole stays exactly one point), which makes both sides bit-identical:
//! the mesh is watertight without welding, and [`super::TriMesh::welded`] can merge the copies
//! exactly.

use glam::DVec3;
use std::collections::HashMap;

use super::tessellate::PatchPoints;

/// The four boundary edges of a patch as cubics, with the direction whose count they use:
/// `(v = 0, along u)`, `(v = 1, along u)`, `(u = 0, along v)`, `(u = 1, along v)`.
pub(super) fn edges(p: &PatchPoints) -> [([DVec3; 4], usize); 4] {
    [
        ([p[0], p[4], p[8], p[12]], 0),
        ([p[3], p[7], p[11], p[15]], 0),
        ([p[0], p[1], p[2], p[3]], 1),
        ([p[12], p[13], p[14], p[15]], 1),
    ]
}

/// The edge in canonical orientation (the lexicographically smaller of the two orders of its
/// control points' bits) and whether that is the reverse of the given order.
pub(super) fn canonical(edge: &[DVec3; 4]) -> ([DVec3; 4], bool) {
    let key = |e: &[DVec3; 4]| e.map(|p| [p.x, p.y, p.z].map(f64::to_bits));
    let rev = [edge[3], edge[2], edge[1], edge[0]];
    if key(&rev) < key(edge) {
        (rev, true)
    } else {
        (*edge, false)
    }
}

/// Segment counts per patch after tying shared edges together (union–find over the `2 n`
/// patch directions; collapsed edges tie nothing, a point has no vertices to disagree on).
pub(super) fn tie_shared_edges(
    patches: &[PatchPoints],
    own: &[([u32; 2], [f64; 2])],
) -> (Vec<[u32; 2]>, Vec<usize>) {
    let mut parent: Vec<usize> = (0..2 * patches.len()).collect();
    fn find(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let mut owner: HashMap<[[u64; 3]; 4], usize> = HashMap::with_capacity(2 * patches.len());
    for (index, p) in patches.iter().enumerate() {
        for (edge, dir) in edges(p) {
            if edge.iter().all(|q| *q == edge[0]) {
                continue;
            }
            let (c, _) = canonical(&edge);
            let key = c.map(|p| [p.x, p.y, p.z].map(f64::to_bits));
            let node = 2 * index + dir;
            match owner.get(&key) {
                Some(&other) => {
                    let (ra, rb) = (find(&mut parent, node), find(&mut parent, other));
                    parent[ra] = rb;
                }
                None => {
                    owner.insert(key, node);
                }
            }
        }
    }
    let mut class_max = vec![0u32; parent.len()];
    for node in 0..parent.len() {
        let root = find(&mut parent, node);
        class_max[root] = class_max[root].max(own[node / 2].0[node % 2]);
    }
    let classes: Vec<usize> = (0..parent.len()).map(|x| find(&mut parent, x)).collect();
    let counts = (0..patches.len())
        .map(|i| [class_max[classes[2 * i]], class_max[classes[2 * i + 1]]])
        .collect();
    (counts, classes)
}
