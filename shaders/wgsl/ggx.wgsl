// ggx.wgsl — GGX (Trowbridge–Reitz) microfacet terms in tangent space (normal +Z).
// CPU twins: sbf::ggx::{d, lambda, g1, g2, schlick_weight}, same stable forms:
// D = α²/(π(α² cos²θ + sin²θ)²) with sin²θ = h_x² + h_y² (no cancellation at α → 1e-4);
// Λ = a/(2(1 + √(1 + a))), a = α² tan²θ; G1 = 2/(1 + √(1 + a)); height-correlated
// G2 = 1/(1 + Λ(v) + Λ(l)) (Heitz 2014, "Understanding the Masking-Shadowing Function").

// GGX normal distribution D(h) for a unit half vector h in the tangent frame (normal +Z)
// and GGX α (= perceptual roughness²), per steradian of h.
fn ggx_d(h: vec3<f32>, alpha: f32) -> f32 {
    if (h.z <= 0.0) {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = a2 * h.z * h.z + (h.x * h.x + h.y * h.y);
    return a2 / (PI * t * t);
}

// a = α² tan²θ for unit w with w_z > 0.
fn ggx_a_term(w: vec3<f32>, alpha: f32) -> f32 {
    return alpha * alpha * (w.x * w.x + w.y * w.y) / (w.z * w.z);
}

// Smith Λ(w); precondition w_z > 0.
fn ggx_lambda(w: vec3<f32>, alpha: f32) -> f32 {
    let a = ggx_a_term(w, alpha);
    return a / (2.0 * (1.0 + sqrt(1.0 + a)));
}

// Smith masking G1(w) for a unit direction w in the tangent frame (normal +Z) and GGX α;
// 0 below the surface.
fn ggx_g1(w: vec3<f32>, alpha: f32) -> f32 {
    if (w.z <= 0.0) {
        return 0.0;
    }
    return 2.0 / (1.0 + sqrt(1.0 + ggx_a_term(w, alpha)));
}

// Height-correlated masking-shadowing G2(v, l) for unit view v and light l in the tangent
// frame (normal +Z) and GGX α; 0 when either is below the surface.
fn ggx_g2(v: vec3<f32>, l: vec3<f32>, alpha: f32) -> f32 {
    if (v.z <= 0.0 || l.z <= 0.0) {
        return 0.0;
    }
    return 1.0 / (1.0 + ggx_lambda(v, alpha) + ggx_lambda(l, alpha));
}

// Schlick's Fresnel weight (1 − v·h)^5; F = f0·(1 − w) + f90·w.
fn schlick_weight(v_dot_h: f32) -> f32 {
    let x = clamp(1.0 - v_dot_h, 0.0, 1.0);
    let x2 = x * x;
    return x2 * x2 * x;
}

// Multiple-scattering energy compensation (Fdez-Agüera 2019, "A Multiple-Scattering
// Microfacet Model for Real-Time Image-based Lighting", JCGT 8(1); as Filament): the factor
// 1 + f0·(1/E − 1) that scales any single-scattering GGX specular response, E = dfg.x + dfg.y
// the DFG table's single-scattering albedo at (n·v, α) for f0 = f90 = 1; 1 where E ≤ 0.
fn ggx_energy_compensation(dfg: vec2<f32>, f0: f32) -> f32 {
    let e = dfg.x + dfg.y;
    if (e <= 0.0) {
        return 1.0;
    }
    return 1.0 + f0 * (1.0 / e - 1.0);
}
