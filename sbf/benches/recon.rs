//! Reconstruction cost per direction (the "run time" half of error against run
//! time): irradiance and specular, f32 runtime API, RGB.
//!
//!     cargo bench --workspace --bench recon

use criterion::{criterion_group, criterion_main, Criterion};
use sbf::glam::Vec3;
use sbf::recon::{lut, runtime as rt};
use sbf::sampling::{halton2, uniform_hemisphere};
use sbf::AmbientDiceSrbf;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let normals: Vec<Vec3> = (0..1024).map(|i| uniform_hemisphere(halton2(i)).as_vec3()).collect();
    let coeffs: Vec<Vec3> = (0..25).map(|i| Vec3::splat(0.1 + 0.01 * i as f32)).collect();
    let ad12: Vec<Vec3> = AmbientDiceSrbf::twelve().lobes().iter().map(|l| l.as_vec3()).collect();
    let ad9: Vec<Vec3> = AmbientDiceSrbf::nine_hemisphere().lobes().iter().map(|l| l.as_vec3()).collect();
    let sg9: Vec<Vec3> = sbf::layout::vogel_hemisphere(9).unwrap().iter().map(|l| l.as_vec3()).collect();
    let sg12: Vec<Vec3> = sbf::layout::vogel_hemisphere(12).unwrap().iter().map(|l| l.as_vec3()).collect();
    let table = lut::ad_specular_lut(32, 32, 256).unwrap();
    let mut g = c.benchmark_group("recon");
    let mut i = 0usize;
    let mut next = || {
        i = (i + 1) & 1023;
        black_box(normals[i])
    };
    let l1: [Vec3; 4] = coeffs[..4].try_into().unwrap();
    let l2: [Vec3; 9] = coeffs[..9].try_into().unwrap();
    let l4: [Vec3; 25] = coeffs[..25].try_into().unwrap();
    g.bench_function("irradiance SH L1", |b| b.iter(|| rt::sh_l1_irradiance(&l1, next())));
    g.bench_function("irradiance SH L1 Geomerics", |b| b.iter(|| rt::sh_l1_geomerics_irradiance(&l1, next())));
    g.bench_function("irradiance SH L2", |b| b.iter(|| rt::sh_l2_irradiance(&l2, next())));
    g.bench_function("irradiance SH L4", |b| b.iter(|| rt::sh_l4_irradiance(&l4, next())));
    g.bench_function("irradiance SG9 Hill", |b| b.iter(|| rt::sg_irradiance(&sg9, 6.0, &coeffs[..9], next())));
    g.bench_function("irradiance SG12 Hill", |b| b.iter(|| rt::sg_irradiance(&sg12, 6.0, &coeffs[..12], next())));
    g.bench_function("irradiance AD9 poly", |b| b.iter(|| rt::ad_irradiance(&ad9, &coeffs[..9], next())));
    g.bench_function("irradiance AD12 poly", |b| b.iter(|| rt::ad_irradiance(&ad12, &coeffs[..12], next())));
    g.bench_function("specular SG9 ASG", |b| b.iter(|| rt::sg_specular_asg(&sg9, 6.0, &coeffs[..9], Vec3::Z, next(), 0.3, 0.04, 1.0)));
    g.bench_function("specular SG12 ASG", |b| b.iter(|| rt::sg_specular_asg(&sg12, 6.0, &coeffs[..12], Vec3::Z, next(), 0.3, 0.04, 1.0)));
    g.bench_function("specular AD9 fit+LUT", |b| b.iter(|| rt::ad_specular(&ad9, &coeffs[..9], Vec3::Z, next(), 0.3, 0.04, 1.0, &table)));
    g.bench_function("specular AD12 fit+LUT", |b| {
        b.iter(|| rt::ad_specular(&ad12, &coeffs[..12], Vec3::Z, next(), 0.3, 0.04, 1.0, &table))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
