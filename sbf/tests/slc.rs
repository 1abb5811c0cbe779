//! Stochastic light culling math ([TH17; TH17-supp; FTH22-supp]) against brute force and closed forms:
//! the bounds are bounds (≥ 10⁵ outgoing directions per configuration), the spheroid is
//! the paper's bounding surface, the diffuse sphere's offset, maximum Fresnel, G1_dist,
//! the stretching and test-space matrices, and unbiasedness of the culled estimate.

use sbf::glam::{DMat3, DVec3, Vec3};
use sbf::quadrature::{gauss_legendre, Domain, SphereQuadrature};
use sbf::sampling::{spherical_fibonacci, uniform_sphere, Pcg32};
use sbf::slc::{self, runtime};
use std::f64::consts::PI;

/// A unit vector at angle `theta` from +Z in the xz plane.
fn at(theta: f64) -> DVec3 {
    DVec3::new(theta.sin(), 0.0, theta.cos())
}

/// Outgoing directions: 10⁵ spherical-Fibonacci over the sphere, 10⁵ uniform in the
/// cap of half-angle min(10α, π/2) about ω_u (the lobe), and a ring at grazing.
fn directions(wu: DVec3, alpha: f64, rng: &mut Pcg32) -> Vec<DVec3> {
    let n = 100_000;
    let mut v: Vec<DVec3> = (0..n).map(|i| spherical_fibonacci(i, n)).collect();
    let (t, b) = (wu.any_orthonormal_vector(), wu.cross(wu.any_orthonormal_vector()));
    let cmax = (10.0 * alpha).min(PI / 2.0).cos();
    for _ in 0..n {
        let [a, c] = rng.next_2d();
        let z = 1.0 - a * (1.0 - cmax);
        let s = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * c;
        v.push(wu * z + t * (s * phi.cos()) + b * (s * phi.sin()));
    }
    for k in 0..2000 {
        let phi = 2.0 * PI * k as f64 / 2000.0;
        v.push(DVec3::new(phi.cos(), phi.sin(), 1e-4).normalize());
    }
    v
}

/// Bounds are bounds: for α from 0.01 to 1, incidence from normal to 89.5°, Schlick and
/// dielectric Fresnel (η on both sides of the monotonic range 2 ± √3), random ξ, the
/// isosurface l_max(ω_o) = √(Φ f cos_o/(δξ)) of the exact GGX BRDF (height-correlated
/// G2) never leaves the spheroid (tolerance 1e-9: f64 rounding of a quadratic form).
/// Also reported: the largest normalised radius reached (how close the isosurface comes)
/// and the volume ratio spheroid / isosurface.
#[test]
fn ggx_spheroid_contains_the_isosurface() {
    let mut rng = Pcg32::new(17, 3);
    let (phi, delta) = (1.0, 1e-3);
    type Fresnel = (&'static str, Box<dyn Fn(f64) -> f64>, Box<dyn Fn(f64) -> f64>);
    let fresnels: Vec<Fresnel> = vec![
        ("Schlick F0 0.04", Box::new(|c: f64| 0.04 + 0.96 * (1.0 - c).powi(5)), Box::new(|ci: f64| slc::schlick_max(0.04, ci))),
        ("dielectric η 0.2", Box::new(|c: f64| slc::dielectric_fresnel(0.2, c)), Box::new(|ci: f64| slc::dielectric_max(0.2, ci))),
        ("dielectric η 1.5", Box::new(|c: f64| slc::dielectric_fresnel(1.5, c)), Box::new(|ci: f64| slc::dielectric_max(1.5, ci))),
        ("dielectric η 5", Box::new(|c: f64| slc::dielectric_fresnel(5.0, c)), Box::new(|ci: f64| slc::dielectric_max(5.0, ci))),
    ];
    let mut worst = 0.0f64;
    for alpha in [0.01, 0.05, 0.1, 0.3, 0.6, 1.0] {
        for deg in [0.0, 30.0, 60.0, 85.0, 89.5] {
            let wi = at(f64::to_radians(deg));
            for (name, fresnel, fmax) in &fresnels {
                let xi = 0.05 + 0.9 * rng.next_f64();
                let r = slc::spheroid_scale(phi, fmax(wi.z), slc::g1_dist(wi.z, alpha), wi.z, delta, xi);
                let e = slc::ggx_spheroid(DVec3::ZERO, wi, DVec3::Z, alpha, r);
                let mut reach = 0.0f64;
                for wo in directions(e.axes.col(0), alpha, &mut rng) {
                    let l = slc::random_range(slc::ggx_vpl_intensity(phi, wi, wo, alpha, fresnel.as_ref()), delta, xi);
                    let k = e.normalized(wo * l).length_squared();
                    reach = reach.max(k);
                    assert!(k <= 1.0 + 1e-9, "α {alpha} θi {deg}° {name}: isosurface at {wo} reaches {k} > 1");
                }
                worst = worst.max(reach);
                if deg == 30.0 && *name == "Schlick F0 0.04" {
                    println!("α {alpha:>4} θi 30° {name}: isosurface reaches {:.3} of the spheroid's normalised radius", reach.sqrt());
                }
            }
        }
    }
    println!("worst normalised radius² reached over all configurations: {worst:.4}");
}

/// The spheroid is the bounding surface s(ω_o) = r√(πD(cos θ/2)) ([TH17 eq. 12] = eq. 13–15,
/// Appendix A): points q + s(θ)·(cos θ ω_u + sin θ ω_v) lie on it (|normalised|² = 1 to
/// 1e-9), and its volume 4πr_u r²/3 equals ∫ s³/3 dω (2000-node Gauss–Legendre in
/// cos θ: quadrature error far below the 1e-6 bar for α ≥ 0.05). And the construction is
/// tight where the paper says: at normal incidence with F ≡ 1 (the only slack is
/// G2 = 1/(1 + Λ(ω_o)) ≤ G1_dist = 1), the isosurface's volume ∫ l³/3 dω is within
/// (1 + Λ at the lobe's edge)^{3/2} ≤ 1.2 of the spheroid's for α ≤ 0.3 (Λ ≈ α²tan²θ/4,
/// θ ≈ 6α at the edge: 9α⁴ ≤ 0.07); the factor is reported for every α.
#[test]
fn spheroid_is_the_papers_bounding_surface_and_tight() {
    let (x, w) = gauss_legendre(2000);
    for alpha in [0.05, 0.1, 0.3, 0.6, 1.0] {
        let r = 0.7;
        let wi = at(0.4);
        let e = slc::ggx_spheroid(DVec3::new(0.1, -0.2, 0.3), wi, DVec3::Z, alpha, r);
        let (wu, wv) = (e.axes.col(0), e.axes.col(1));
        let q = DVec3::new(0.1, -0.2, 0.3);
        for k in 0..=360 {
            let th = PI * k as f64 / 360.0;
            let s = slc::bound_surface(th, r, alpha);
            let p = q + (wu * th.cos() + wv * th.sin()) * s;
            let n2 = e.normalized(p).length_squared();
            assert!((n2 - 1.0).abs() < 1e-9, "α {alpha} θ {th}: {n2}");
        }
        let vol: f64 = x.iter().zip(&w).map(|(mu, wt)| wt * 2.0 * PI * slc::bound_surface(mu.acos(), r, alpha).powi(3) / 3.0).sum();
        assert!((vol / e.volume() - 1.0).abs() < 1e-6, "α {alpha}: ∫s³/3 = {vol} vs {}", e.volume());
        // Tightness at normal incidence, F ≡ 1: isosurface volume by a product rule in
        // (cos θ about n, φ) — the lobe is about n.
        let wi = DVec3::Z;
        let (phi, delta, xi) = (1.0, 1e-3, 0.5);
        let r = slc::spheroid_scale(phi, 1.0, slc::g1_dist(1.0, alpha), 1.0, delta, xi);
        let e = slc::ggx_spheroid(DVec3::ZERO, wi, DVec3::Z, alpha, r);
        let mut v_iso = 0.0;
        for (mu, wt) in x.iter().zip(&w) {
            let z = 0.5 * (mu + 1.0); // cos θ ∈ [0, 1]
            let wo = DVec3::new((1.0 - z * z).sqrt(), 0.0, z);
            let l = slc::random_range(slc::ggx_vpl_intensity(phi, wi, wo, alpha, &|_| 1.0), delta, xi);
            v_iso += 0.5 * wt * 2.0 * PI * l.powi(3) / 3.0;
        }
        let factor = e.volume() / v_iso;
        println!("α {alpha}: spheroid / isosurface volume at normal incidence with F ≡ 1: {factor:.4}");
        assert!(factor >= 1.0 - 1e-6, "α {alpha}: the spheroid is smaller than the isosurface ({factor})");
        if alpha <= 0.3 {
            assert!(factor <= 1.2, "α {alpha}: factor {factor}");
        }
    }
}

/// Diffuse VPL sphere: the Lambert isosurface l(d) = A√(max(d·n, 0)) lies inside the sphere
/// of [FTH22-supp eq. 2–3] and touches it (max normalised distance 1 within 1e-4 on 10⁵
/// directions); the sphere with [TH17 §6]'s offset (1/3)^{1/4} misses the isosurface near the
/// VPL (the VPL itself lies outside it) — 001 is right. The directional bound I_max(d)
/// ([FTH22-supp eq. 7]) turns into exactly the distance to the sphere along d, and bounds the
/// true intensity.
#[test]
fn diffuse_sphere_bounds_the_lambert_isosurface() {
    let mut rng = Pcg32::new(5, 5);
    let delta = 1e-3;
    for _ in 0..8 {
        let n = uniform_sphere(rng.next_2d());
        let q = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64());
        let (phi_k, xi) = (0.1 + 3.0 * rng.next_f64(), 0.05 + 0.9 * rng.next_f64());
        let sph = slc::diffuse_sphere(q, n, phi_k, delta, xi);
        let a = (phi_k / (PI * delta * xi)).sqrt();
        let mut reach = 0.0f64;
        let mut misses_002 = false;
        let c002 = q + n * ((1.0f64 / 3.0).powf(0.25) * a);
        for i in 0..100_000 {
            let d = spherical_fibonacci(i, 100_000);
            let l = a * d.dot(n).max(0.0).sqrt();
            let p = q + d * l;
            let k = (p - sph.center).length() / sph.radius;
            assert!(k <= 1.0 + 1e-9, "isosurface outside the sphere: {k}");
            reach = reach.max(k);
            misses_002 |= (p - c002).length() > sph.radius * (1.0 + 1e-9);
            // I_max(d) → range = distance from q to the sphere along d (ray exits).
            let oc = q - sph.center;
            let b = oc.dot(d);
            let t = -b + (b * b - oc.length_squared() + sph.radius * sph.radius).sqrt();
            let range = slc::random_range(slc::diffuse_intensity_bound(d.dot(n), phi_k), delta, xi);
            assert!((range - t).abs() <= 1e-9 * t, "I_max range {range} vs distance {t}");
            assert!(slc::diffuse_intensity_bound(d.dot(n), phi_k) >= phi_k * d.dot(n).max(0.0) / PI * (1.0 - 1e-12));
        }
        assert!(reach > 1.0 - 1e-4, "the sphere is not tight: {reach}");
        assert!(misses_002, "002's offset should leave part of the isosurface outside");
        assert!((q - c002).length() > sph.radius, "002's sphere should not contain the VPL");
    }
}

/// Maximum Fresnel ([TH17-supp eq. 1–6]) is the maximum over the outgoing hemisphere (2·10⁵
/// directions; brute force ≤ F_max, and F_max − brute ≤ 0.02·F_max: the grid's grazing
/// directions come within ~0.005 rad of θ_h^max), for Schlick and for dielectrics inside
/// and outside the monotonic range (η = 0.2, 5: quasiconvex, where F(1) can win).
#[test]
fn maximum_fresnel_is_the_maximum() {
    let dirs: Vec<DVec3> = (0..400_000).map(|i| spherical_fibonacci(i, 400_000)).filter(|d| d.z > 0.0).collect();
    for cos_i in [1.0f64, 0.7, 0.3, 0.05] {
        let wi = DVec3::new((1.0 - cos_i * cos_i).sqrt(), 0.0, cos_i);
        type Case = (String, Box<dyn Fn(f64) -> f64>, f64);
        let mut cases: Vec<Case> = Vec::new();
        for f0 in [0.04, 0.5] {
            cases.push((format!("Schlick {f0}"), Box::new(move |c: f64| f0 + (1.0 - f0) * (1.0 - c).powi(5)), slc::schlick_max(f0, cos_i)));
        }
        for eta in [0.2, 0.5, 1.5, 3.0, 5.0] {
            cases.push((format!("η {eta}"), Box::new(move |c: f64| slc::dielectric_fresnel(eta, c)), slc::dielectric_max(eta, cos_i)));
        }
        for (name, f, fmax) in cases {
            let brute = dirs.iter().map(|wo| f(wi.dot((wi + *wo).normalize()))).fold(0.0f64, f64::max);
            assert!(brute <= fmax * (1.0 + 1e-12), "{name} cos_i {cos_i}: brute {brute} > F_max {fmax}");
            assert!(fmax - brute <= 0.02 * fmax, "{name} cos_i {cos_i}: F_max {fmax} vs brute {brute}");
        }
    }
    // The dielectric formula against the textbook values: η = 1.5 at normal incidence 0.04.
    assert!((slc::dielectric_fresnel(1.5, 1.0) - 0.04).abs() < 1e-12);
    assert_eq!(slc::dielectric_fresnel(0.5, 0.1), 1.0, "total internal reflection");
}

/// G1_dist ([TH17 eq. 8]) equals its definition |cos_i|/∫D(m·n)max(ω_i·m, 0)dm (512 × 1024
/// Gauss product over the hemisphere; error < 1e-6 for α ≥ 0.1) and sbf's Smith G1.
#[test]
fn g1_dist_matches_its_definition() {
    let q = SphereQuadrature::gauss_product(Domain::UpperHemisphere, 512, 1024);
    for alpha in [0.1, 0.3, 0.7, 1.0] {
        for cos_i in [1.0f64, 0.8, 0.4, 0.1] {
            let wi = DVec3::new((1.0 - cos_i * cos_i).sqrt(), 0.0, cos_i);
            let proj: f64 = q.directions.iter().zip(&q.weights).map(|(m, w)| w * sbf::ggx::d(*m, alpha) * wi.dot(*m).max(0.0)).sum();
            let def = cos_i / proj;
            let g = slc::g1_dist(cos_i, alpha);
            assert!((g - def).abs() < 1e-6, "α {alpha} cos {cos_i}: {g} vs definition {def}");
            assert!((g - sbf::ggx::g1(wi, alpha)).abs() < 1e-12);
        }
    }
}

/// S ([TH17 eq. 16]) maps the spheroid onto a unit sphere; B (eq. 17) is a rotation (both of
/// its branches) that keeps depth planes perpendicular to z: (B·S)⁻ᵀẑ ∥ ẑ. The f32
/// runtime twins agree with the f64 reference to f32 rounding × conditioning.
#[test]
fn stretching_and_test_space_rotation() {
    let mut rng = Pcg32::new(8, 1);
    let mut branches = [false; 2];
    for k in 0..200 {
        let n = uniform_sphere(rng.next_2d());
        let mut wi = uniform_sphere(rng.next_2d());
        if wi.dot(n) < 0.0 {
            wi = -wi;
        }
        let alpha = 0.02 + 0.98 * rng.next_f64();
        let r = 0.1 + 5.0 * rng.next_f64();
        let q = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64());
        let e = slc::ggx_spheroid(q, wi, n, alpha, r);
        let s = e.stretching();
        for _ in 0..20 {
            let u = uniform_sphere(rng.next_2d());
            let p = e.center + e.axes * (e.radii * u);
            assert!(((s * (p - e.center)).length() - 1.0).abs() < 1e-9);
        }
        // In view space the rotation is arbitrary: rotate by a random orthonormal view.
        let view = DMat3::from_quat(sbf::glam::DQuat::from_axis_angle(uniform_sphere(rng.next_2d()), 6.0 * rng.next_f64()));
        let sv = view * s * view.transpose();
        let b = slc::test_space_rotation(sv);
        branches[((sv * DVec3::X).length_squared() > (sv * DVec3::Y).length_squared()) as usize] = true;
        assert!((b.transpose() * b - DMat3::IDENTITY).to_cols_array().iter().all(|x| x.abs() < 1e-12), "B not orthonormal");
        assert!((b.determinant() - 1.0).abs() < 1e-12, "B not a rotation");
        let m = b * sv;
        let nz = (m.inverse().transpose() * DVec3::Z).normalize();
        assert!(nz.z.abs() > 1.0 - 1e-12, "depth planes tilt: {nz}");
        // f32 twin.
        let e32 = runtime::ggx_spheroid(q.as_vec3(), wi.as_vec3(), n.as_vec3(), alpha as f32, r as f32);
        let scale = e.radii.x.max(q.length());
        assert!((e32.center.as_dvec3() - e.center).length() < 1e-5 * scale, "case {k}: centre");
        assert!((e32.radii.as_dvec3() - e.radii).length() < 1e-5 * e.radii.x, "case {k}: radii");
        let b32 = runtime::test_space_rotation(sv.as_mat3());
        assert!((b32.as_dmat3() - b).to_cols_array().iter().all(|x| x.abs() < 1e-4), "case {k}: B f32");
    }
    assert!(branches[0] && branches[1], "both branches of eq. 17 exercised");
    let d32 = runtime::diffuse_sphere(Vec3::ZERO, Vec3::Z, 2.0, 1e-3, 0.5);
    let d64 = slc::diffuse_sphere(DVec3::ZERO, DVec3::Z, 2.0, 1e-3, 0.5);
    assert!(((d32.radius as f64) - d64.radius).abs() < 1e-6 * d64.radius);
}

/// Unbiased: 300 point lights with random intensities and distances; the mean over K
/// independent ξ vectors of Σ culled_estimate equals the exact Σ I/l² within 4σ (σ from
/// the K estimates; one ξ per light per draw, as the method requires), while the classic
/// deterministic range cut (drop lights beyond the range of ξ = ½, no reweighting) is
/// biased by more than 10σ.
#[test]
fn culled_estimate_is_unbiased_and_a_range_cut_is_not() {
    let mut rng = Pcg32::new(21, 4);
    let delta = 1e-3;
    let lights: Vec<(f64, f64)> = (0..300).map(|_| (0.01 + rng.next_f64(), 0.5 + 8.0 * rng.next_f64())).collect();
    let exact: f64 = lights.iter().map(|(i, l)| i / (l * l)).sum();
    let k = 4000;
    let (mut sum, mut sum2, mut cut) = (0.0, 0.0, 0.0);
    for _ in 0..k {
        let est: f64 = lights
            .iter()
            .map(|(i, l)| {
                let xi = 1.0 - rng.next_f64(); // (0, 1]
                let p = slc::acceptance_probability(*i, delta, *l);
                slc::culled_estimate(i / (l * l), p, xi)
            })
            .sum();
        sum += est;
        sum2 += est * est;
    }
    for (i, l) in &lights {
        if *l <= slc::random_range(*i, delta, 0.5) {
            cut += i / (l * l);
        }
    }
    let mean = sum / k as f64;
    let sigma = ((sum2 / k as f64 - mean * mean) / (k as f64 - 1.0)).sqrt();
    println!("exact {exact:.5}, culled mean {mean:.5} ± {sigma:.1e}, deterministic cut {cut:.5} ({:.1}σ off)", (cut - exact) / sigma);
    assert!((mean - exact).abs() <= 4.0 * sigma, "culled mean {mean} vs exact {exact} ± {sigma}");
    assert!((cut - exact).abs() > 10.0 * sigma, "the range cut should be visibly biased");
    // A light inside its range is always accepted (p = 1) and counted at full weight.
    assert_eq!(slc::culled_estimate(2.0, slc::acceptance_probability(1.0, delta, 1.0), 0.999), 2.0);
}

/// The tile test never culls an ellipsoid that meets the tile's frustum part: random
/// spheroids in view space and random tiles; 2 000 random points inside each frustum part
/// (pixel position and depth uniform); whenever one lies inside the ellipsoid the test must
/// keep the light. Reports how often the test keeps a light no sampled point touches.
#[test]
fn tile_test_is_conservative() {
    let mut rng = Pcg32::new(31, 7);
    let (w, h, tx, ty) = (256.0, 128.0, 0.7, 0.35);
    let (mut kept, mut touched, mut cases) = (0, 0, 0);
    for _ in 0..400 {
        let q = DVec3::new(4.0 * rng.next_f64() - 2.0, 2.0 * rng.next_f64() - 1.0, -1.0 - 8.0 * rng.next_f64());
        let n = uniform_sphere(rng.next_2d());
        let mut wi = uniform_sphere(rng.next_2d());
        if wi.dot(n) < 0.0 {
            wi = -wi;
        }
        let alpha = 0.05 + 0.95 * rng.next_f64();
        let e = slc::ggx_spheroid(q, wi, n, alpha, 0.2 + 1.5 * rng.next_f64());
        let (m, mc) = slc::cull_transform(&e, DMat3::IDENTITY, DVec3::ZERO);
        let (x0, y0) = ((rng.next_f64() * 15.0).floor() * 16.0, (rng.next_f64() * 7.0).floor() * 16.0);
        let z0 = 0.5 + 6.0 * rng.next_f64();
        let z1 = z0 + 4.0 * rng.next_f64();
        let corners = slc::tile_corners(x0, y0, x0 + 16.0, y0 + 16.0, w, h, tx, ty, z0, z1);
        let hit = slc::ellipsoid_hits_corners(m, mc, &corners);
        let mut inside = false;
        for _ in 0..2000 {
            let [a, b] = rng.next_2d();
            let z = z0 + (z1 - z0) * rng.next_f64();
            let p = slc::tile_corners(x0 + 16.0 * a, y0 + 16.0 * b, 0.0, 0.0, w, h, tx, ty, z, z)[0];
            inside |= e.contains(p, -1e-9);
        }
        assert!(hit || !inside, "a light meeting the tile was culled");
        kept += hit as usize;
        touched += inside as usize;
        cases += 1;
    }
    println!("{cases} tile/ellipsoid cases: kept {kept}, of which a sampled point touches {touched}");
    assert!(touched > 20, "the cases should include real intersections");
}

/// Ellipsoid culling beats sphere culling on glossy VPLs ([TH17 §7, Fig. 9]–10): a fixed
/// scene — a camera looking down −z at a floor y = −1, 256 glossy VPLs on a wall z = −7
/// facing the camera, lit from (0.3, 0.5, 0.8) so their mirror lobes fall on the floor —
/// culled per 16 × 16 tile with two HalfZ depth ranges by (a) the GGX spheroid, (b) the
/// sphere enclosing it (centre c, radius r_u), (c) TH16's sphere about the VPL with radius
/// r/α. False discovery rate = culled-in (tile, VPL) pairs where no pixel of the tile
/// accepts the VPL (exact GGX intensity, p = min(I/(δl²), 1) > ξ) / culled-in pairs.
/// Reported: FDR and false-positive counts of the three; asserted: the spheroid, which
/// lies inside its enclosing sphere, keeps a subset of the sphere's pairs (fewer false
/// positives), and fewer than TH16's sphere. (Per tile the FDR drops by about a third while
/// the false-positive count drops by 77–86%; the per-pixel FDR drop of ≥ 80% is asserted
/// on glossy caustics in baker/tests/slc.rs `spheroids_cut_false_discoveries`.)
#[test]
fn ellipsoid_culling_cuts_false_discoveries() {
    let (w, h, tx, ty) = (256usize, 128usize, 0.9f64, 0.45f64);
    let (delta, phi) = (1e-3, 0.05);
    let wi = DVec3::new(0.3, 0.5, 0.8).normalize();
    // G-buffer: the floor y = −1 where the pixel's ray goes down, else background.
    let point = |px: f64, py: f64| -> Option<DVec3> {
        let d = slc::tile_corners(px, py, 0.0, 0.0, w as f64, h as f64, tx, ty, 1.0, 1.0)[0];
        (d.y < -1e-3).then(|| d * (-1.0 / d.y))
    };
    for alpha in [0.1, 0.3] {
        let mut rng = Pcg32::new(99, 1);
        let vpls: Vec<(DVec3, f64)> = (0..256)
            .map(|_| (DVec3::new(8.0 * rng.next_f64() - 4.0, -1.0 + 2.5 * rng.next_f64(), -7.0), 0.05 + 0.95 * rng.next_f64()))
            .collect();
        let fresnel = |c: f64| 0.04 + 0.96 * (1.0 - c).powi(5);
        let (mut kept, mut false_pos) = ([0usize; 3], [0usize; 3]);
        for ty_ in 0..h / 16 {
            for tx_ in 0..w / 16 {
                let pts: Vec<DVec3> =
                    (0..256).filter_map(|k| point((tx_ * 16 + k % 16) as f64 + 0.5, (ty_ * 16 + k / 16) as f64 + 0.5)).collect();
                if pts.is_empty() {
                    continue;
                }
                let (zmin, zmax) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(-p.z), b.max(-p.z)));
                let mid = 0.5 * (zmin + zmax);
                let halves: Vec<[DVec3; 8]> = [(zmin, mid), (mid, zmax)]
                    .iter()
                    .map(|(a, b)| {
                        let (x0, y0) = ((tx_ * 16) as f64, (ty_ * 16) as f64);
                        slc::tile_corners(x0, y0, x0 + 16.0, y0 + 16.0, w as f64, h as f64, tx, ty, *a, *b)
                    })
                    .collect();
                for (q, xi) in &vpls {
                    let r = slc::spheroid_scale(phi, slc::schlick_max(0.04, wi.z), slc::g1_dist(wi.z, alpha), wi.z, delta, *xi);
                    let e = slc::ggx_spheroid(*q, wi, DVec3::Z, alpha, r);
                    let enclosing = slc::Ellipsoid { center: e.center, axes: DMat3::IDENTITY, radii: DVec3::splat(e.radii.x) };
                    let th16 = slc::Ellipsoid { center: *q, axes: DMat3::IDENTITY, radii: DVec3::splat(r / alpha) };
                    let tests: Vec<bool> = [e, enclosing, th16]
                        .iter()
                        .map(|v| {
                            let (m, mc) = slc::cull_transform(v, DMat3::IDENTITY, DVec3::ZERO);
                            halves.iter().any(|c| slc::ellipsoid_hits_corners(m, mc, c))
                        })
                        .collect();
                    if !tests.iter().any(|t| *t) {
                        continue;
                    }
                    // Exact: does any pixel of the tile accept the VPL? (VPL frame: n = +Z.)
                    let accepted = pts.iter().any(|x| {
                        let to = *x - *q;
                        let l = to.length();
                        let intensity = slc::ggx_vpl_intensity(phi, wi, to / l, alpha, &fresnel);
                        slc::acceptance_probability(intensity, delta, l) > *xi
                    });
                    for k in 0..3 {
                        if tests[k] {
                            kept[k] += 1;
                            false_pos[k] += !accepted as usize;
                        }
                    }
                }
            }
        }
        let fdr: Vec<f64> = (0..3).map(|k| false_pos[k] as f64 / kept[k].max(1) as f64).collect();
        println!(
            "α {alpha}: culled-in (tile, VPL) pairs spheroid {} / enclosing sphere {} / TH16 sphere {}; FDR {:.3} / {:.3} / {:.3} (−{:.1}%, −{:.1}%); false positives {} / {} / {} (−{:.1}%, −{:.1}%)",
            kept[0],
            kept[1],
            kept[2],
            fdr[0],
            fdr[1],
            fdr[2],
            100.0 * (1.0 - fdr[0] / fdr[1]),
            100.0 * (1.0 - fdr[0] / fdr[2]),
            false_pos[0],
            false_pos[1],
            false_pos[2],
            100.0 * (1.0 - false_pos[0] as f64 / false_pos[1] as f64),
            100.0 * (1.0 - false_pos[0] as f64 / false_pos[2] as f64)
        );
        assert!(kept[0] > 0, "the scene must have culled-in pairs");
        assert!(
            kept[0] <= kept[1] && false_pos[0] <= false_pos[1],
            "α {alpha}: the spheroid must keep a subset of its enclosing sphere's pairs"
        );
        assert!(false_pos[0] < false_pos[2], "α {alpha}: more false positives than TH16's sphere");
    }
}
