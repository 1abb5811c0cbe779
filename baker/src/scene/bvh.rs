//! Bounding volume hierarchy: built on the CPU with binned SAH (Wald 2007, "On fast
//! Construction of SAH-based Bounding Volume Hierarchies": 16 bins per axis, cost
//! 1 traversal + 1 intersection per triangle, leaves of ≤ 4), flattened into 32-byte
//! nodes that the CPU and the WGSL traversal read alike. Interior node: `count` = 0 and
//! children at `left_first`, `left_first + 1`; leaf: triangles `left_first..+count`.

use crate::scene::Scene;
use sbf::glam::Vec3;

/// A flattened node (`#[repr(C)]`, shared with WGSL).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Node {
    pub min: [f32; 3],
    pub left_first: u32,
    pub max: [f32; 3],
    pub count: u32,
}

/// A triangle as the tracer stores it: vertex 0, two edges, and where it came from.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Tri {
    pub corner: [f32; 3],
    pub material: u32,
    pub edge_u: [f32; 3],
    pub mesh: u32,
    pub edge_v: [f32; 3],
    /// Index of the triangle within its mesh.
    pub prim: u32,
}

impl Tri {
    pub fn v0(&self) -> Vec3 {
        Vec3::from(self.corner)
    }
    pub fn e1(&self) -> Vec3 {
        Vec3::from(self.edge_u)
    }
    pub fn e2(&self) -> Vec3 {
        Vec3::from(self.edge_v)
    }
    /// Unit geometric normal (winding e1 × e2).
    pub fn normal(&self) -> Vec3 {
        self.e1().cross(self.e2()).normalize()
    }
    pub fn area(&self) -> f32 {
        0.5 * self.e1().cross(self.e2()).length()
    }
    fn bounds(&self) -> (Vec3, Vec3) {
        let (a, b, c) = (self.v0(), self.v0() + self.e1(), self.v0() + self.e2());
        (a.min(b).min(c), a.max(b).max(c))
    }
}

/// A ray hit: distance, triangle (index into [`Bvh::tris`]) and barycentrics (u, v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub tri: u32,
    pub u: f32,
    pub v: f32,
}

/// The hierarchy and its triangles in leaf order.
#[derive(Debug, Clone)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    pub tris: Vec<Tri>,
}

const BINS: usize = 16;
const LEAF_MAX: usize = 4;

/// The deepest a built tree may be: the traversal stacks (CPU and WGSL) hold 64 entries
/// and a depth-first walk needs at most depth + 1.
pub const MAX_DEPTH: usize = 62;

#[derive(Clone, Copy)]
struct Aabb {
    lo: Vec3,
    hi: Vec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb { lo: Vec3::splat(f32::INFINITY), hi: Vec3::splat(f32::NEG_INFINITY) };
    fn grow(&mut self, lo: Vec3, hi: Vec3) {
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
    }
    fn area(&self) -> f32 {
        let d = (self.hi - self.lo).max(Vec3::ZERO);
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }
}

impl Bvh {
    /// Builds over every non-degenerate triangle of the scene (zero-area triangles are
    /// skipped: they cannot be hit and have no lightmap texels).
    pub fn build(scene: &Scene) -> Bvh {
        let mut tris = Vec::new();
        for (mi, m) in scene.meshes.iter().enumerate() {
            for (pi, t) in m.indices.iter().enumerate() {
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                if (b - a).cross(c - a).length() > 0.0 {
                    tris.push(Tri {
                        corner: a.into(),
                        material: m.material as u32,
                        edge_u: (b - a).into(),
                        mesh: mi as u32,
                        edge_v: (c - a).into(),
                        prim: pi as u32,
                    });
                }
            }
        }
        Self::from_tris(tris)
    }

    /// Builds over the given triangles (reordered into leaf order), at most
    /// [`MAX_DEPTH`] + 1 levels deep.
    pub fn from_tris(tris: Vec<Tri>) -> Bvh {
        Self::from_tris_bounded(tris, MAX_DEPTH)
    }

    /// [`Self::from_tris`] with another depth bound (≥ ⌈log2(n/4)⌉ + 1 for n triangles):
    /// SAH splits until a subtree could run past it, object-median splits from there.
    pub fn from_tris_bounded(mut tris: Vec<Tri>, max_depth: usize) -> Bvh {
        let bounds: Vec<(Vec3, Vec3)> = tris.iter().map(|t| t.bounds()).collect();
        let centroids: Vec<Vec3> = bounds.iter().map(|(l, h)| 0.5 * (*l + *h)).collect();
        let mut order: Vec<usize> = (0..tris.len()).collect();
        let mut nodes = vec![Node { min: [0.0; 3], left_first: 0, max: [0.0; 3], count: 0 }];
        // (node index, first, count, depth)
        let mut stack = vec![(0usize, 0usize, tris.len(), 0usize)];
        while let Some((ni, first, count, depth)) = stack.pop() {
            let mut bb = Aabb::EMPTY;
            let mut cb = Aabb::EMPTY;
            for &k in &order[first..first + count] {
                bb.grow(bounds[k].0, bounds[k].1);
                cb.grow(centroids[k], centroids[k]);
            }
            nodes[ni].min = bb.lo.into();
            nodes[ni].max = bb.hi.into();
            // Depth bound: where SAH splits could run past MAX_DEPTH (pathological size
            // distributions make them peel one triangle per level), split at the object
            // median instead, which halves the count: ⌈log2(count/LEAF_MAX)⌉ more levels.
            let levels_needed = (count.div_ceil(LEAF_MAX) as f64).log2().ceil() as usize;
            let median = count > LEAF_MAX && depth + levels_needed + 1 >= max_depth;
            let split =
                if count > LEAF_MAX && !median { best_split(&order[first..first + count], &bounds, &centroids, cb, bb) } else { None };
            let left_count = if median {
                let ext = cb.hi - cb.lo;
                let axis = if ext.x >= ext.y && ext.x >= ext.z {
                    0
                } else if ext.y >= ext.z {
                    1
                } else {
                    2
                };
                order[first..first + count].sort_by(|a, b| centroids[*a][axis].total_cmp(&centroids[*b][axis]).then(a.cmp(b)));
                count / 2
            } else {
                let Some((axis, pos)) = split else {
                    nodes[ni].left_first = first as u32;
                    nodes[ni].count = count as u32;
                    continue;
                };
                // Partition by the split plane.
                let slice = &mut order[first..first + count];
                let mut i = 0;
                for j in 0..slice.len() {
                    if centroids[slice[j]][axis] < pos {
                        slice.swap(i, j);
                        i += 1;
                    }
                }
                if i == 0 || i == count {
                    count / 2
                } else {
                    i
                }
            };
            let l = nodes.len();
            nodes.push(Node { min: [0.0; 3], left_first: 0, max: [0.0; 3], count: 0 });
            nodes.push(Node { min: [0.0; 3], left_first: 0, max: [0.0; 3], count: 0 });
            nodes[ni].left_first = l as u32;
            nodes[ni].count = 0;
            stack.push((l + 1, first + left_count, count - left_count, depth + 1));
            stack.push((l, first, left_count, depth + 1));
        }
        let reordered: Vec<Tri> = order.iter().map(|&k| tris[k]).collect();
        tris = reordered;
        Bvh { nodes, tris }
    }

    /// Closest hit along o + t·d for t in (tmin, tmax).
    pub fn intersect(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<Hit> {
        self.traverse(o, d, tmin, tmax, false, &|_, _, _| true)
    }

    /// Whether anything lies along o + t·d for t in (tmin, tmax).
    pub fn occluded(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> bool {
        self.traverse(o, d, tmin, tmax, true, &|_, _, _| true).is_some()
    }

    /// [`Self::intersect`] counting only the hits `solid(tri, u, v)` accepts (alpha masks).
    pub fn intersect_solid(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, solid: &dyn Fn(u32, f32, f32) -> bool) -> Option<Hit> {
        self.traverse(o, d, tmin, tmax, false, solid)
    }

    /// [`Self::occluded`] counting only the hits `solid(tri, u, v)` accepts (alpha masks).
    pub fn occluded_solid(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, solid: &dyn Fn(u32, f32, f32) -> bool) -> bool {
        self.traverse(o, d, tmin, tmax, true, solid).is_some()
    }

    fn traverse(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, any: bool, solid: &dyn Fn(u32, f32, f32) -> bool) -> Option<Hit> {
        if self.tris.is_empty() {
            return None;
        }
        let inv = d.recip();
        let mut best: Option<Hit> = None;
        let mut t_best = tmax;
        let mut stack = [0u32; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let n = &self.nodes[stack[sp] as usize];
            if n.count > 0 {
                for k in n.left_first..n.left_first + n.count {
                    if let Some((t, u, v)) = intersect_tri(&self.tris[k as usize], o, d, tmin, t_best).filter(|h| solid(k, h.1, h.2)) {
                        t_best = t;
                        best = Some(Hit { t, tri: k, u, v });
                        if any {
                            return best;
                        }
                    }
                }
                continue;
            }
            let (a, b) = (n.left_first, n.left_first + 1);
            let ta = slab(&self.nodes[a as usize], o, inv, tmin, t_best);
            let tb = slab(&self.nodes[b as usize], o, inv, tmin, t_best);
            // Push the farther child first so the nearer is visited next.
            match (ta, tb) {
                (Some(x), Some(y)) => {
                    let (near, far) = if x <= y { (a, b) } else { (b, a) };
                    stack[sp] = far;
                    stack[sp + 1] = near;
                    sp += 2;
                }
                (Some(_), None) => {
                    stack[sp] = a;
                    sp += 1;
                }
                (None, Some(_)) => {
                    stack[sp] = b;
                    sp += 1;
                }
                (None, None) => {}
            }
        }
        best
    }

    /// Depth of the tree (the traversal stack holds 64 entries).
    pub fn depth(&self) -> usize {
        fn rec(nodes: &[Node], i: usize) -> usize {
            let n = &nodes[i];
            if n.count > 0 {
                1
            } else {
                1 + rec(nodes, n.left_first as usize).max(rec(nodes, n.left_first as usize + 1))
            }
        }
        if self.nodes.is_empty() {
            0
        } else {
            rec(&self.nodes, 0)
        }
    }
}

/// SAH-best (axis, position) over `BINS` bins per axis, or None when a leaf is cheaper.
fn best_split(items: &[usize], bounds: &[(Vec3, Vec3)], centroids: &[Vec3], cb: Aabb, bb: Aabb) -> Option<(usize, f32)> {
    let mut best: Option<(f32, usize, f32)> = None;
    for axis in 0..3 {
        let (lo, hi) = (cb.lo[axis], cb.hi[axis]);
        if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
            continue;
        }
        let scale = BINS as f32 / (hi - lo);
        let mut bins = [(Aabb::EMPTY, 0usize); BINS];
        for &k in items {
            let b = (((centroids[k][axis] - lo) * scale) as usize).min(BINS - 1);
            bins[b].0.grow(bounds[k].0, bounds[k].1);
            bins[b].1 += 1;
        }
        // Sweep: left areas/counts for planes 1..BINS.
        let mut left = [(0.0f32, 0usize); BINS];
        let mut acc = Aabb::EMPTY;
        let mut n = 0;
        for i in 0..BINS - 1 {
            acc.grow(bins[i].0.lo, bins[i].0.hi);
            n += bins[i].1;
            left[i + 1] = (acc.area(), n);
        }
        let mut acc = Aabb::EMPTY;
        let mut n = 0;
        for i in (1..BINS).rev() {
            acc.grow(bins[i].0.lo, bins[i].0.hi);
            n += bins[i].1;
            let (la, ln) = left[i];
            if ln == 0 || n == 0 {
                continue;
            }
            let cost = la * ln as f32 + acc.area() * n as f32;
            if best.is_none_or(|b| cost < b.0) {
                best = Some((cost, axis, lo + i as f32 / scale));
            }
        }
    }
    let (cost, axis, pos) = best?;
    // SAH: 1 (traversal) + cost/area vs count intersections for a leaf.
    let split_cost = 1.0 + cost / bb.area().max(f32::MIN_POSITIVE);
    (split_cost < items.len() as f32 || items.len() > 4 * LEAF_MAX).then_some((axis, pos))
}

/// Ray–box slab test; the entry distance when the box is hit within (tmin, tmax).
#[inline]
fn slab(n: &Node, o: Vec3, inv: Vec3, tmin: f32, tmax: f32) -> Option<f32> {
    let t0 = (Vec3::from(n.min) - o) * inv;
    let t1 = (Vec3::from(n.max) - o) * inv;
    let near = t0.min(t1).max_element().max(tmin);
    let far = t0.max(t1).min_element().min(tmax);
    (near <= far).then_some(near)
}

/// Möller–Trumbore ray–triangle test (Möller & Trumbore 1997), two-sided; returns
/// (t, u, v) for t in (tmin, tmax).
#[inline]
pub fn intersect_tri(tri: &Tri, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<(f32, f32, f32)> {
    let (e1, e2) = (tri.e1(), tri.e2());
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - tri.v0();
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > tmin && t < tmax).then_some((t, u, v))
}
