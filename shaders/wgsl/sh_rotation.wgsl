// sh_rotation.wgsl — rotation of real SH coefficients, bands ≤ 4, in f32, by the
// Ivanic–Ruedenberg recurrence (J. Phys. Chem. 100 (1996) 6342; corrections in
// J. Phys. Chem. A 102 (1998) 9099). Engines rotate probe coefficients into an object or
// tangent frame once per probe or object, not per pixel.
// CPU twin: sbf::basis::sh_rotation::ShRotation (f64, any order), same convention: the
// result holds the coefficients of g(v) = f(Rᵀ·v), the lighting turned by R.

// One band's matrix, row-major with stride 9 (band l ≤ 4 has (2l+1)² ≤ 81 entries):
// entry (m, n), m, n ∈ [−l, l], sits at (m + l)·9 + (n + l).
alias ShRotBand = array<f32, 81>;

// Band 1: R with rows and columns in the (y, z, x) order of m = −1, 0, 1.
fn sh_rot_band1(r: mat3x3<f32>) -> ShRotBand {
    var axis = array<i32, 3>(1, 2, 0);
    var rr = r;
    var b: ShRotBand;
    for (var i = 0; i < 3; i++) {
        for (var j = 0; j < 3; j++) {
            // rr[column][row]
            b[i * 9 + j] = rr[axis[j]][axis[i]];
        }
    }
    return b;
}

// The recurrence's P(i, a, b) for band l from band 1 (r1) and band l − 1 (prev).
fn sh_rot_p(i: i32, l: i32, a: i32, b: i32, r1: ptr<function, ShRotBand>, prev: ptr<function, ShRotBand>) -> f32 {
    let ri = (i + 1) * 9;
    let pa = (a + l - 1) * 9;
    if (b == l) {
        return (*r1)[ri + 2] * (*prev)[pa + 2 * l - 2] - (*r1)[ri] * (*prev)[pa];
    }
    if (b == -l) {
        return (*r1)[ri + 2] * (*prev)[pa] + (*r1)[ri] * (*prev)[pa + 2 * l - 2];
    }
    return (*r1)[ri + 1] * (*prev)[pa + b + l - 1];
}

// Band l (≥ 2) from band 1 and band l − 1: M_mn = u·U + v·V + w·W.
fn sh_rot_next_band(l: i32, r1: ptr<function, ShRotBand>, prev: ptr<function, ShRotBand>) -> ShRotBand {
    var out: ShRotBand;
    for (var m = -l; m <= l; m++) {
        let am = abs(m);
        let d0 = select(0.0, 1.0, m == 0);
        for (var n = -l; n <= l; n++) {
            var den = f32(2 * l * (2 * l - 1));
            if (abs(n) < l) {
                den = f32((l + n) * (l - n));
            }
            var x = 0.0;
            if (am < l) {
                x += sqrt(f32((l + m) * (l - m)) / den) * sh_rot_p(0, l, m, n, r1, prev);
            }
            let v = 0.5 * sqrt((1.0 + d0) * f32((l + am - 1) * (l + am)) / den) * (1.0 - 2.0 * d0);
            var vv = 0.0;
            if (m == 0) {
                vv = sh_rot_p(1, l, 1, n, r1, prev) + sh_rot_p(-1, l, -1, n, r1, prev);
            } else if (m > 0) {
                let d1 = select(0.0, 1.0, m == 1);
                vv = sh_rot_p(1, l, m - 1, n, r1, prev) * sqrt(1.0 + d1) - sh_rot_p(-1, l, -m + 1, n, r1, prev) * (1.0 - d1);
            } else {
                let d1 = select(0.0, 1.0, m == -1);
                vv = sh_rot_p(1, l, m + 1, n, r1, prev) * (1.0 - d1) + sh_rot_p(-1, l, -m - 1, n, r1, prev) * sqrt(1.0 + d1);
            }
            x += v * vv;
            if (m != 0 && am < l - 1) {
                let w = -0.5 * sqrt(f32((l - am - 1) * (l - am)) / den);
                var ww = 0.0;
                if (m > 0) {
                    ww = sh_rot_p(1, l, m + 1, n, r1, prev) + sh_rot_p(-1, l, -m - 1, n, r1, prev);
                } else {
                    ww = sh_rot_p(1, l, m - 1, n, r1, prev) - sh_rot_p(-1, l, -m + 1, n, r1, prev);
                }
                x += w * ww;
            }
            out[(m + l) * 9 + n + l] = x;
        }
    }
    return out;
}

// RGB coefficients of bands 0..=order (≤ 4, the rest of the array passes through
// untouched) rotated by r.
fn sh_rotate_bands(c: array<vec3<f32>, 25>, order: i32, r: mat3x3<f32>) -> array<vec3<f32>, 25> {
    var src = c;
    var out = c;
    var r1 = sh_rot_band1(r);
    var band = r1;
    for (var l = 1; l <= order; l++) {
        if (l > 1) {
            var prev = band;
            band = sh_rot_next_band(l, &r1, &prev);
        }
        let base = l * l;
        for (var m = 0; m <= 2 * l; m++) {
            var acc = vec3<f32>(0.0);
            for (var n = 0; n <= 2 * l; n++) {
                acc += band[m * 9 + n] * src[base + n];
            }
            out[base + m] = acc;
        }
    }
    return out;
}

// The 4 RGB SH L1 coefficients c of a signal f, rotated by the rotation matrix r: the
// coefficients of f(rᵀ ω) (column-major r, as mat3x3 multiplies column vectors).
fn sh_rotate_l1(c: array<vec3<f32>, 4>, r: mat3x3<f32>) -> array<vec3<f32>, 4> {
    var full: array<vec3<f32>, 25>;
    var src = c;
    for (var k = 0; k < 4; k++) {
        full[k] = src[k];
    }
    let o = sh_rotate_bands(full, 1, r);
    return array<vec3<f32>, 4>(o[0], o[1], o[2], o[3]);
}

// The 9 RGB SH L2 coefficients c of a signal f, rotated by the rotation matrix r (as
// `sh_rotate_l1`).
fn sh_rotate_l2(c: array<vec3<f32>, 9>, r: mat3x3<f32>) -> array<vec3<f32>, 9> {
    var full: array<vec3<f32>, 25>;
    var src = c;
    for (var k = 0; k < 9; k++) {
        full[k] = src[k];
    }
    var o = sh_rotate_bands(full, 2, r);
    var out: array<vec3<f32>, 9>;
    for (var k = 0; k < 9; k++) {
        out[k] = o[k];
    }
    return out;
}

// The 25 RGB SH L4 coefficients c of a signal f, rotated by the rotation matrix r (as
// `sh_rotate_l1`).
fn sh_rotate_l4(c: array<vec3<f32>, 25>, r: mat3x3<f32>) -> array<vec3<f32>, 25> {
    return sh_rotate_bands(c, 4, r);
}
