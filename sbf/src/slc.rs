//! Stochastic light culling for many virtual point lights (VPLs): the random light range
//! by Russian roulette, its bounding volumes — a sphere for diffuse VPLs, a spheroid for
//! VPLs on GGX microsurfaces — and the space transforms that cull an ellipsoid with a
//! sphere–AABB test. Sources: \[TH17\] (Tokuyoshi & Harada, "Stochastic Light Culling for
//! VPLs on GGX Microsurfaces"), its supplement 000, and 001 (Fujieda, Tokuyoshi & Harada,
//! single scattering, supplement).
//!
//! Conventions: ω_i points from the VPL towards where its light came from (so the mirror
//! direction is ω_u = 2(ω_i·n)n − ω_i, eq. 13's u axis); n is the VPL's unit geometric
//! normal; ξ ∈ (0, 1] is the light's one uniform number (ξ → 0 gives an unbounded range);
//! δ > 0 is the user's variance control (the paper uses 1e-3).
//!
//! Every function exists twice with the same body: [`reference`](mod@reference) in f64 on `DVec3`/`DMat3`
//! (tests, offline tools) and [`runtime`] in f32 on `Vec3`/`Mat3` (the twin of the WGSL).
//! The f64 items are re-exported at this level.
//!
//! **The diffuse sphere's offset.** The isosurface of a Lambertian VPL is
//! l(d) = A·√(d·n), A = √(Φk/(πδξ)); its widest ring is at d·n = 1/√3, radius
//! A·(4/27)^{1/4}, at height A·(1/3)^{3/4} along n. The sphere centred there with that
//! radius contains the whole isosurface (the squared distance from the centre to the
//! surface, A²(c − 2h'c^{3/2} + h'²) with c = d·n and h' = (1/3)^{3/4}, peaks at
//! c = 1/√3 where it equals the radius²) and touches it along that ring: [FTH22-supp eq. 2]
//! is right. [TH17 §6] prints (1/3)^{1/4}: that sphere starts 0.14·A above the VPL and
//! misses the isosurface near it (the tests show both).

/// One uniform-random-number Russian roulette per light, bounds and transforms, generic
/// over the float type.
macro_rules! slc_impl {
    ($f:ident, $v:ident, $m:ident, $pi:expr) => {
        use glam::{$m, $v};

        /// Acceptance probability p = min(I/(δl²), 1) ([TH17 eq. 2]) of a light of radiant
        /// intensity `intensity` towards a point at distance `l`.
        pub fn acceptance_probability(intensity: $f, delta: $f, l: $f) -> $f {
            if l <= 0.0 {
                return 1.0;
            }
            (intensity / (delta * l * l)).min(1.0)
        }

        /// The random range l_max = √(I/(δξ)) ([TH17 eq. 5]): with one ξ per light, a point
        /// farther than this in the light's direction rejects it.
        pub fn random_range(intensity: $f, delta: $f, xi: $f) -> $f {
            if xi <= 0.0 {
                return <$f>::INFINITY;
            }
            (intensity.max(0.0) / (delta * xi)).sqrt()
        }

        /// The culled estimate of radiance `radiance` with acceptance probability `p`
        /// and the light's ξ ([TH17 eq. 3]): L/p if p > ξ, else 0. Its mean over ξ is L.
        pub fn culled_estimate(radiance: $f, p: $f, xi: $f) -> $f {
            if p > xi {
                radiance / p
            } else {
                0.0
            }
        }

        /// cos θ_h^max for an incoming cosine ([TH17-supp eq. 2]): the largest angle between ω_i
        /// and a half vector of any ω_o in the upper hemisphere, θ_h^max = ½·acos(cos_i) +
        /// π/4, as √((1 − √(1 − cos_i²))/2) — evaluated as |cos_i|/√(2(1 + s)), s =
        /// √(1 − cos_i²), since 1 − s = cos_i²/(1 + s): the printed form cancels at
        /// grazing incidence (relative error 2⁻²⁴/cos_i² in f32).
        pub fn cos_theta_h_max(cos_i: $f) -> $f {
            let s = (1.0 - cos_i * cos_i).max(0.0).sqrt();
            cos_i.abs() / (2.0 * (1.0 + s)).sqrt()
        }

        /// Maximum Schlick Fresnel factor over the outgoing hemisphere ([TH17-supp eq. 1–2]):
        /// Schlick's F grows with θ_h, so F(cos θ_h^max).
        pub fn schlick_max(f0: $f, cos_i: $f) -> $f {
            let c = cos_theta_h_max(cos_i);
            let m = 1.0 - c;
            f0 + (1.0 - f0) * (m * m) * (m * m) * m
        }

        /// Unpolarised dielectric Fresnel factor ([TH17-supp eq. 3–5]) for relative index `eta` at
        /// cos θ_h; 1 under total internal reflection.
        pub fn dielectric_fresnel(eta: $f, cos_h: $f) -> $f {
            let c = cos_h.clamp(0.0, 1.0);
            let g2 = eta * eta - (1.0 - c * c);
            if g2 <= 0.0 {
                return 1.0;
            }
            let g = g2.sqrt();
            let perp = (c - g) / (c + g);
            let e2c = eta * eta * c;
            let par = (g - e2c) / (g + e2c);
            0.5 * (perp * perp + par * par)
        }

        /// Maximum dielectric Fresnel factor over the outgoing hemisphere ([TH17-supp eq. 6]):
        /// F is monotonic in θ_h for 2 − √3 ≤ η ≤ 2 + √3 and quasiconvex otherwise, so its
        /// maximum over θ_h ∈ [0, θ_h^max] is at an end: max(F(1), F(cos θ_h^max)).
        pub fn dielectric_max(eta: $f, cos_i: $f) -> $f {
            dielectric_fresnel(eta, 1.0).max(dielectric_fresnel(eta, cos_theta_h_max(cos_i)))
        }

        /// G1_dist(ω_i) = 2|cos_i|/(|cos_i| + √((1 − α²)cos_i² + α²)) ([TH17 eq. 8]): the
        /// Smith masking of the GGX distribution, an upper bound of any Smith G2(ω_i, ·).
        pub fn g1_dist(cos_i: $f, alpha: $f) -> $f {
            let c = cos_i.abs();
            let den = c + ((1.0 - alpha * alpha) * c * c + alpha * alpha).sqrt();
            if den > 0.0 {
                2.0 * c / den
            } else {
                0.0
            }
        }

        /// GGX NDF as a function of cos θ_m ([TH17 eq. 7]), 0 for cos θ_m ≤ 0.
        pub fn ggx_ndf(cos_m: $f, alpha: $f) -> $f {
            if cos_m <= 0.0 {
                return 0.0;
            }
            let a2 = alpha * alpha;
            let t = a2 * cos_m * cos_m + (1.0 - cos_m * cos_m).max(0.0);
            a2 / ($pi * t * t)
        }

        /// The spheroid's scale r = √(Φ·F_max·G1_dist/(4πδξ·|cos_i|)) ([TH17 eq. 12]).
        pub fn spheroid_scale(phi: $f, f_max: $f, g1: $f, cos_i: $f, delta: $f, xi: $f) -> $f {
            if xi <= 0.0 {
                return <$f>::INFINITY;
            }
            (phi * f_max * g1 / (4.0 * $pi * delta * xi * cos_i.abs())).sqrt()
        }

        /// The bounding surface s = r·√(π·D(cos(θ/2))) ([TH17 eq. 12]) at angle θ from ω_u.
        pub fn bound_surface(theta: $f, r: $f, alpha: $f) -> $f {
            r * ($pi * ggx_ndf((0.5 * theta).cos(), alpha)).sqrt()
        }

        /// An ellipsoid: centre, unit axes (the columns of R) and semi-axes.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct Ellipsoid {
            /// Its centre.
            pub center: $v,
            /// R = [ω_u, ω_w × ω_u, ω_w] for the GGX spheroid ([TH17 eq. 14]).
            pub axes: $m,
            /// Semi-axes along the columns of `axes`.
            pub radii: $v,
        }

        impl Ellipsoid {
            /// (p − c) in the axes' frame divided by the semi-axes: length ≤ 1 inside.
            pub fn normalized(&self, p: $v) -> $v {
                self.axes.transpose() * (p - self.center) / self.radii
            }
            /// Whether `p` lies inside (or on) the ellipsoid.
            pub fn contains(&self, p: $v, tolerance: $f) -> bool {
                self.normalized(p).length_squared() <= 1.0 + tolerance
            }
            /// The stretching matrix S = R·diag(1/r_u, 1/r_v, 1/r_w)·Rᵀ ([TH17 eq. 16]): maps
            /// the ellipsoid about its centre onto a unit sphere.
            pub fn stretching(&self) -> $m {
                self.axes * $m::from_diagonal(self.radii.recip()) * self.axes.transpose()
            }
            /// Volume 4π·r_u·r_v·r_w/3.
            pub fn volume(&self) -> $f {
                4.0 / 3.0 * $pi * self.radii.x * self.radii.y * self.radii.z
            }
        }

        /// The bounding spheroid of a GGX VPL at `q` ([TH17 eq. 13–15]): semi-axes
        /// ((1 + α²)/(2α)·r, r, r) along ω_u and two perpendicular axes, centre
        /// q + (1 − α²)/(2α)·r·ω_u, where r is [`spheroid_scale`]. `wi` and `n` are unit
        /// with wi·n > 0; α ∈ (0, 1]. At normal incidence (ω_u = n) the axes perpendicular
        /// to ω_u are any orthonormal pair (the spheroid is symmetric about ω_u).
        pub fn ggx_spheroid(q: $v, wi: $v, n: $v, alpha: $f, r: $f) -> Ellipsoid {
            let wu = (n * (2.0 * wi.dot(n)) - wi).normalize();
            let c = wu.cross(n);
            let ww = if c.length_squared() > 1e-12 { c.normalize() } else { wu.any_orthonormal_vector() };
            let wv = ww.cross(wu);
            let ru = (1.0 + alpha * alpha) / (2.0 * alpha) * r;
            Ellipsoid {
                center: q + wu * ((1.0 - alpha * alpha) / (2.0 * alpha) * r),
                axes: $m::from_cols(wu, wv, ww),
                radii: $v::new(ru, r, r),
            }
        }

        /// A sphere.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct Sphere {
            /// Its centre.
            pub center: $v,
            /// Its radius.
            pub radius: $f,
        }

        /// The bounding sphere of a diffuse VPL at `q` with unit normal `n` and reflected
        /// flux Φk ([FTH22-supp eq. 2–3], [TH17 §6] with \[FTH22-supp\]'s offset; see the module documentation):
        /// A = √(Φk/(πδξ)), centre q + (1/3)^{3/4}·A·n, radius (4/27)^{1/4}·A.
        pub fn diffuse_sphere(q: $v, n: $v, phi_k: $f, delta: $f, xi: $f) -> Sphere {
            let a = random_range(phi_k / $pi, delta, xi);
            Sphere { center: q + n * ((1.0 / 3.0 as $f).powf(0.75) * a), radius: (4.0 / 27.0 as $f).powf(0.25) * a }
        }

        /// The directional bound I_max(d) = Φ((d·n) + √((d·n)² + 1))²/(3√3·π) of a diffuse
        /// VPL's intensity Φ·max(d·n, 0)/π ([FTH22-supp eq. 7]): the intensity whose random range
        /// is the distance from the VPL to its bounding sphere along d.
        pub fn diffuse_intensity_bound(d_dot_n: $f, phi: $f) -> $f {
            let t = d_dot_n + (d_dot_n * d_dot_n + 1.0).sqrt();
            phi * t * t / (3.0 * (3.0 as $f).sqrt() * $pi)
        }

        /// The bounding sphere of a point light of radiant intensity I (isotropic): the
        /// random range √(I/(δξ)) about the light — its isosurface itself.
        pub fn point_sphere(q: $v, intensity: $f, delta: $f, xi: $f) -> Sphere {
            Sphere { center: q, radius: random_range(intensity, delta, xi) }
        }

        /// The chord [t0, t1] (t0 ≤ t1) of the ray o + t·d (unit d) through sphere `s`, or
        /// None when it misses. Stable roots (math.md): q = −(b + sign(b)·√disc), roots q
        /// and c/q, with b = d·(o − centre), c = |o − centre|² − r².
        pub fn ray_sphere(o: $v, d: $v, s: &Sphere) -> Option<($f, $f)> {
            let oc = o - s.center;
            let b = d.dot(oc);
            let c = oc.length_squared() - s.radius * s.radius;
            let disc = b * b - c;
            if disc.is_nan() || disc < 0.0 {
                return None;
            }
            let q = -(b + disc.sqrt().copysign(b));
            if q == 0.0 {
                return Some((0.0, 0.0));
            }
            let (t0, t1) = (q, c / q);
            Some((t0.min(t1), t0.max(t1)))
        }

        /// Equiangular distance sampling (Kulla & Fajardo 2012; [FTH22-supp §2.1] inside the inner
        /// sphere) on [a, b] along a ray whose closest point to the light is at t_c, at
        /// distance h > 0: pdf ∝ 1/(h² + (t − t_c)²). Returns (t, pdf) for uniform u ∈ [0, 1).
        /// The angles θ = atan((t − t_c)/h) stay finite for h → 0 (callers clamp h > 0).
        pub fn equiangular_sample(tc: $f, h: $f, a: $f, b: $f, u: $f) -> ($f, $f) {
            let (ta, tb) = ((a - tc).atan2(h), (b - tc).atan2(h));
            let t = (tc + h * (ta + u * (tb - ta)).tan()).clamp(a, b);
            (t, equiangular_pdf(tc, h, a, b, t))
        }

        /// The pdf of [`equiangular_sample`] at t ∈ [a, b]: h/((θ_b − θ_a)(h² + (t − t_c)²)).
        pub fn equiangular_pdf(tc: $f, h: $f, a: $f, b: $f, t: $f) -> $f {
            let (ta, tb) = ((a - tc).atan2(h), (b - tc).atan2(h));
            h / ((tb - ta) * (h * h + (t - tc) * (t - tc)))
        }

        /// What tiled culling stores per light ([TH17 §5.2]): M = B·S and M·c for the
        /// ellipsoid `e` moved to view space by rotation `view` and translation `origin`
        /// (x_view = view·x + origin). A tile's frustum transformed by M meets the unit
        /// sphere about M·c exactly when the frustum meets the ellipsoid.
        pub fn cull_transform(e: &Ellipsoid, view: $m, origin: $v) -> ($m, $v) {
            let axes = view * e.axes;
            let s = axes * $m::from_diagonal(e.radii.recip()) * axes.transpose();
            let m = test_space_rotation(s) * s;
            (m, m * (view * e.center + origin))
        }

        /// The 8 view-space corners of the part of a screen tile's frustum between view
        /// distances `z0` and `z1` (> 0, along −z): pixel rectangle [x0, x1) × [y0, y1) of a
        /// `width` × `height` image, a symmetric perspective with tan(half field of view)
        /// `tan_x`, `tan_y` (NDC x = 2px/W − 1, y = 1 − 2py/H, direction (x·tan_x, y·tan_y, −1)).
        #[allow(clippy::too_many_arguments)]
        pub fn tile_corners(x0: $f, y0: $f, x1: $f, y1: $f, width: $f, height: $f, tan_x: $f, tan_y: $f, z0: $f, z1: $f) -> [$v; 8] {
            let dir = |px: $f, py: $f| $v::new((2.0 * px / width - 1.0) * tan_x, (1.0 - 2.0 * py / height) * tan_y, -1.0);
            let d = [dir(x0, y0), dir(x1, y0), dir(x0, y1), dir(x1, y1)];
            [d[0] * z0, d[1] * z0, d[2] * z0, d[3] * z0, d[0] * z1, d[1] * z1, d[2] * z1, d[3] * z1]
        }

        /// Whether the unit sphere about `center` meets the box [lo, hi] (the squared
        /// distance from the centre to the box is at most 1).
        pub fn unit_sphere_hits_aabb(center: $v, lo: $v, hi: $v) -> bool {
            let d = center - center.clamp(lo, hi);
            d.length_squared() <= 1.0
        }

        /// The conservative ellipsoid–frustum test of tiled culling ([TH17 §5], Modified
        /// HalfZ's sphere–AABB form): the frustum part's corners transformed by M = B·S
        /// (from [`cull_transform`]), their AABB, and the unit sphere about M·c. Never
        /// culls an ellipsoid that meets the frustum part (the AABB of the transformed
        /// corners contains the transformed convex frustum part).
        pub fn ellipsoid_hits_corners(m: $m, mc: $v, corners: &[$v; 8]) -> bool {
            let mut lo = $v::splat(<$f>::INFINITY);
            let mut hi = $v::splat(<$f>::NEG_INFINITY);
            for c in corners {
                let p = m * *c;
                lo = lo.min(p);
                hi = hi.max(p);
            }
            unit_sphere_hits_aabb(mc, lo, hi)
        }

        /// The test-space rotation B ([TH17 eq. 17]) for a stretching matrix S: with
        /// b_x = S·x̂, b_y = S·ŷ, b_z = b_x × b_y, its rows are an orthonormal frame whose
        /// third row is b_z/|b_z|, so that B·S keeps view-space depth planes (z = const)
        /// perpendicular to z; the first row follows the longer of b_x, b_y.
        pub fn test_space_rotation(s: $m) -> $m {
            let bx = s * $v::X;
            let by = s * $v::Y;
            let z = bx.cross(by).normalize();
            let (x, y) = if bx.length_squared() > by.length_squared() {
                let x = bx.normalize();
                (x, z.cross(x))
            } else {
                let y = by.normalize();
                (y.cross(z), y)
            };
            $m::from_cols(x, y, z).transpose()
        }
    };
}

/// f64 reference (tests, offline tools).
pub mod reference {
    slc_impl!(f64, DVec3, DMat3, std::f64::consts::PI);
}

/// f32 runtime twins (the WGSL's CPU side).
pub mod runtime {
    slc_impl!(f32, Vec3, Mat3, std::f32::consts::PI);
}

pub use reference::*;

/// The exact radiant intensity a GGX VPL reflects towards ω_o (tangent frame, normal +Z):
/// Φ·f(ω_i, ω_o)·max(ω_o·n, 0) with f the Cook–Torrance GGX BRDF (height-correlated
/// Smith G2, Fresnel `fresnel(cos θ_h)`) — the quantity whose random range the spheroid
/// bounds ([TH17 eq. 4–6]). For tests and reference integrators.
pub fn ggx_vpl_intensity(phi: f64, wi: glam::DVec3, wo: glam::DVec3, alpha: f64, fresnel: &dyn Fn(f64) -> f64) -> f64 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let h = (wi + wo).normalize();
    let f = fresnel(wi.dot(h)) * crate::ggx::g2(wi, wo, alpha) * crate::ggx::d(h, alpha) / (4.0 * wi.z * wo.z);
    phi * f * wo.z
}
