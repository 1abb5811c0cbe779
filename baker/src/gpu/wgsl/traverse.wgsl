// traverse.wgsl — closest-hit and any-hit traversal of the CPU-built BVH (no hardware
// ray queries; CPU twin baker::scene::bvh::Bvh::intersect/occluded), and the ray counters.

#define_import_path baker::traverse

#import baker::bindings::{CUT_TRAVERSALS, Hit, NO_HIT, Node, P, T_FAR, Tri, counters, nodes, tris}
#ifdef TEXTURES
#import baker::maps::is_hole
#endif

fn slab(n: Node, o: vec3<f32>, inv: vec3<f32>, tmax: f32) -> f32 {
    let t0 = (n.min - o) * inv;
    let t1 = (n.max - o) * inv;
    let lo = min(t0, t1);
    let hi = max(t0, t1);
    let near = max(max(lo.x, lo.y), max(lo.z, 0.0));
    let far = min(min(hi.x, hi.y), min(hi.z, tmax));
    return select(T_FAR, near, near <= far);
}

// Möller–Trumbore, two-sided; t in (0, tmax) or T_FAR (CPU twin: bvh::intersect_tri).
fn intersect_tri(tri: Tri, o: vec3<f32>, d: vec3<f32>, tmax: f32) -> f32 {
    let p = cross(d, tri.edge_v);
    let det = dot(tri.edge_u, p);
    if (abs(det) < 1e-12) {
        return T_FAR;
    }
    let inv = 1.0 / det;
    let s = o - tri.corner;
    let u = dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) {
        return T_FAR;
    }
    let q = cross(s, tri.edge_u);
    let v = dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) {
        return T_FAR;
    }
    let t = dot(tri.edge_v, q) * inv;
    return select(T_FAR, t, t > 0.0 && t < tmax);
}

// Closest hit (any = false) or any hit (any = true) within (0, tmax).
fn traverse(o: vec3<f32>, d: vec3<f32>, tmax: f32, any: bool) -> Hit {
    var best = Hit(tmax, NO_HIT);
    // Guard 1/d against zero components (the CPU's IEEE ∞ gives the same slabs).
    let dd = select(d, vec3<f32>(1e-30), abs(d) < vec3<f32>(1e-30));
    let inv = 1.0 / dd;
    var stack: array<u32, 64>;
    var sp = 1u;
    stack[0] = 0u;
    while (sp > 0u) {
        sp -= 1u;
        let n = nodes[stack[sp]];
        if (n.count > 0u) {
            for (var k = n.left_first; k < n.left_first + n.count; k++) {
                let t = intersect_tri(tris[k], o, d, best.t);
#ifdef TEXTURES
                if (t < best.t && is_hole(k, tris[k], o + d * t)) {
                    continue;
                }
#endif
                if (t < best.t) {
                    best = Hit(t, k);
                    if (any) {
                        return best;
                    }
                }
            }
            continue;
        }
        let a = n.left_first;
        let b = a + 1u;
        let ta = slab(nodes[a], o, inv, best.t);
        let tb = slab(nodes[b], o, inv, best.t);
        let hit_a = ta < T_FAR;
        let hit_b = tb < T_FAR;
        if (hit_a && hit_b) {
            let near_a = ta <= tb;
            stack[sp] = select(a, b, near_a);
            stack[sp + 1u] = select(b, a, near_a);
            sp += 2u;
        } else if (hit_a) {
            stack[sp] = a;
            sp += 1u;
        } else if (hit_b) {
            stack[sp] = b;
            sp += 1u;
        }
    }
    if (sp > 0u) {
        // Nodes left: the driver ended the loop early (llvmpipe/lavapipe end every loop of
        // an invocation after 65 535 iterations in all); the host refuses the results.
        atomicAdd(&counters[CUT_TRAVERSALS], 1u);
    }
    return best;
}

fn count_ray(k: u32) {
    if (P.count_rays == 1u) {
        atomicAdd(&counters[k], 1u);
    }
}
