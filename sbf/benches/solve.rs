//! Solver costs: progressive update per sample (RGB) and batch LS / NNLS solves.
//!
//!     cargo bench --workspace --bench solve

use criterion::{criterion_group, criterion_main, Criterion};
use sbf::envmap::{LatLongImage, ProceduralSky};
use sbf::gram::{gram_matrix, GramOptions};
use sbf::sampling::{halton2, uniform_sphere};
use sbf::solve::*;
use sbf::{AmbientDiceBezier, AmbientDiceSrbf, Basis, Domain, SgBasis, ShBasis};
use std::hint::black_box;

fn bench_progressive(c: &mut Criterion) {
    let sky = ProceduralSky::default();
    let dirs: Vec<_> = (0..4096).map(|i| uniform_sphere(halton2(i))).collect();
    let vals: Vec<[f64; 3]> = dirs.iter().map(|d| sky.radiance(*d)).collect();
    let vogel = sbf::layout::vogel_sphere(12).unwrap();
    let bases: Vec<(&str, Box<dyn Basis>)> = vec![
        ("SH9", Box::new(ShBasis::new(2).unwrap())),
        ("SG12", Box::new(SgBasis::new(&vogel, 8.0, false).unwrap())),
        ("AD12", Box::new(AmbientDiceSrbf::twelve())),
    ];
    let mut g = c.benchmark_group("progressive");
    for (name, basis) in &bases {
        let n = basis.len();
        let mut i = 0usize;
        // Basis evaluation + update, f32 state (what a GPU texel does per sample).
        let mut enc32 = ProgressiveEncoder::<f32>::new(n, ProgressiveOptions::default());
        g.bench_function(format!("{name} eval+update f32"), |b| {
            b.iter(|| {
                i = (i + 1) & 4095;
                enc32.add_sample(basis.as_ref(), dirs[i], vals[i], 1.0).unwrap();
            })
        });
        // Update only (basis values precomputed), f64 state.
        let pre: Vec<Vec<f64>> = dirs.iter().map(|d| basis.eval(*d)).collect();
        let mut enc64 = ProgressiveEncoder::<f64>::new(n, ProgressiveOptions::default());
        g.bench_function(format!("{name} update f64"), |b| {
            b.iter(|| {
                i = (i + 1) & 4095;
                enc64.update(black_box(&pre[i]), vals[i], 1.0);
            })
        });
    }
    g.finish();
}

fn bench_batch(c: &mut Criterion) {
    let sky = ProceduralSky::default();
    let map = LatLongImage::from_fn(64, 32, |d| sky.radiance(d)).unwrap();
    let samples = map_samples(&map);
    let vogel = sbf::layout::vogel_sphere(12).unwrap();
    let bases: Vec<(&str, Box<dyn Basis>)> = vec![
        ("9 (AD9)", Box::new(AmbientDiceSrbf::nine_hemisphere())),
        ("12 (SG12)", Box::new(SgBasis::new(&vogel, 6.0, false).unwrap())),
        ("36 (AD Bezier)", Box::new(AmbientDiceBezier::new())),
    ];
    let mut g = c.benchmark_group("batch");
    for (name, basis) in &bases {
        let gm = gram_matrix(basis.as_ref(), Domain::Sphere, GramOptions { n_z: 64, force_quadrature: false }).unwrap().matrix;
        let m = moments(basis.as_ref(), &samples);
        g.bench_function(format!("LS RGB {name}"), |b| b.iter(|| black_box(solve_gram(&gm, &m, LsOptions::default()).unwrap())));
        let m0: Vec<f64> = m.column(0).iter().copied().collect();
        g.bench_function(format!("NNLS 1 channel {name}"), |b| b.iter(|| black_box(nnls_gram(&gm, &m0, NnlsOptions::default()).unwrap())));
    }
    g.finish();
}

criterion_group!(benches, bench_progressive, bench_batch);
criterion_main!(benches);
