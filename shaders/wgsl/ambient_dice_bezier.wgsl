// ambient_dice_bezier.wgsl — Ambient Dice hybrid cubic Bézier (Iwanicki & Sloan 2017;
// sbf::basis::ambient_dice_bezier documents the derivation): per icosahedron vertex the
// value f and derivatives (Du, Dv) along its tangent frame, 36 coefficients per channel,
// laid out [f_0, Du_0, Dv_0, f_1, …]. On the face holding d, with gnomonic barycentrics
// b_k, the value is the cubic Bézier triangle Σ b_k³ f_k + Σ 3 b_i² b_j c_{i→j} +
// 6 b₀b₁b₂ c₁₁₁, edge points from the vertex data and the interior point split
// Gregory-style; the YCoCg form takes luma from it and chroma piecewise-linearly.
// Tables (face centres, barycentric normals, derivative factors, a0..a2) are generated
// from sbf below this header. CPU twins: sbf::Icosahedron::locate,
// sbf::AmbientDiceBezier::weights, sbf::AmbientDiceYCoCg::eval_rgb.

// The face holding unit d (nearest face centre) and its unnormalised barycentrics.
struct AdFace {
    face: u32,
    b: vec3<f32>,
}

fn ad_ico_locate(d: vec3<f32>) -> AdFace {
    var best = 0u;
    var best_dot = -2.0;
    for (var f = 0u; f < 20u; f++) {
        let s = dot(AD_ICO_CENTRES[f], d);
        if (s > best_dot) {
            best_dot = s;
            best = f;
        }
    }
    return AdFace(best, d * AD_ICO_BARY[best]);
}

// The 9 non-zero Bézier weights at d: the face's vertices and per corner the weights of
// (f, Du, Dv).
struct AdBezierWeights {
    vertices: vec3<u32>,
    w: array<vec3<f32>, 3>,
}

// The icosahedron triangle that unit direction d falls in and its Bézier basis weights
// (value and two tangent derivatives per vertex), for `ad_bezier_eval`/`ad_ycocg_eval`.
fn ad_bezier_weights(d: vec3<f32>) -> AdBezierWeights {
    let loc = ad_ico_locate(d);
    let b = loc.b;
    // Corner points b_k³; edge points ew[k] = (3 b_k² b_{k+1}, 3 b_k² b_{k+2}).
    var cw = b * b * b;
    var ew: array<vec2<f32>, 3>;
    for (var k = 0u; k < 3u; k++) {
        ew[k] = 3.0 * b[k] * b[k] * vec2<f32>(b[(k + 1u) % 3u], b[(k + 2u) % 3u]);
    }
    // Interior point: c₁₁₁ = Σ w_k c₁₁₁⁽ᵏ⁾ with w_k = b_i b_j / D over the edge opposite k.
    // At a vertex D = 0 and the interior Bernstein weight is 0 as well.
    let dd = b.y * b.z + b.x * b.z + b.x * b.y;
    if (dd > 0.0) {
        let c111 = 6.0 * b.x * b.y * b.z;
        for (var k = 0u; k < 3u; k++) {
            let i = (k + 1u) % 3u;
            let j = (k + 2u) % 3u;
            let wk = c111 * b[i] * b[j] / dd;
            cw[i] += AD_BEZIER_A.x * wk;
            cw[j] += AD_BEZIER_A.x * wk;
            // a1 on c_{i→j} (slot 0 of i) and c_{j→i} (slot 1 of j); a2 on c_{i→k}
            // (slot 1 of i) and c_{j→k} (slot 0 of j).
            ew[i].x += AD_BEZIER_A.y * wk;
            ew[j].y += AD_BEZIER_A.y * wk;
            ew[i].y += AD_BEZIER_A.z * wk;
            ew[j].x += AD_BEZIER_A.z * wk;
        }
    }
    let deriv = AD_BEZIER_DERIV[loc.face];
    var w: array<vec3<f32>, 3>;
    for (var k = 0u; k < 3u; k++) {
        let e = ew[k];
        let g = deriv[k];
        w[k] = vec3<f32>(cw[k] + AD_ICO_EDGE_COS * (e.x + e.y), e.x * g.x + e.y * g.z, e.x * g.y + e.y * g.w);
    }
    return AdBezierWeights(AD_ICO_FACES[loc.face], w);
}

// RGB value at unit d of 36 RGB coefficients.
fn ad_bezier_eval(c: array<vec3<f32>, 36>, d: vec3<f32>) -> vec3<f32> {
    let bw = ad_bezier_weights(d);
    var v = vec3<f32>(0.0);
    for (var k = 0u; k < 3u; k++) {
        let o = 3u * bw.vertices[k];
        let w = bw.w[k];
        v += c[o] * w.x + c[o + 1u] * w.y + c[o + 2u] * w.z;
    }
    return v;
}

// RGB at unit d from YCoCg coefficients: Y by the Bézier patch (36), Co and Cg
// piecewise-linear on the same face (12 each, weights b_k / Σb), then YCoCg → RGB.
fn ad_ycocg_eval(y: array<f32, 36>, co: array<f32, 12>, cg: array<f32, 12>, d: vec3<f32>) -> vec3<f32> {
    let bw = ad_bezier_weights(d);
    let loc = ad_ico_locate(d);
    let lw = loc.b / (loc.b.x + loc.b.y + loc.b.z);
    var luma = 0.0;
    var chroma = vec2<f32>(0.0);
    for (var k = 0u; k < 3u; k++) {
        let o = 3u * bw.vertices[k];
        let w = bw.w[k];
        luma += y[o] * w.x + y[o + 1u] * w.y + y[o + 2u] * w.z;
        let vk = AD_ICO_FACES[loc.face][k];
        chroma += lw[k] * vec2<f32>(co[vk], cg[vk]);
    }
    let t = luma - chroma.y;
    return vec3<f32>(t + chroma.x, luma + chroma.y, t - chroma.x);
}
