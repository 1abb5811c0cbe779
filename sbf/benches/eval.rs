//! Single-direction evaluation cost of every basis (ns per direction).
//!
//!     cargo bench --workspace --bench eval
//!
//! Each iteration evaluates one basis at one of 1024 pre-generated unit directions
//! (cycled), writing into a reused slice: the per-texel cost of reconstruction
//! or of one progressive-encoder sample.

use criterion::{criterion_group, criterion_main, Criterion};
use sbf::basis::sh_fast::{eval_sh_l2, eval_sh_l4};
use sbf::glam::{DVec3, Vec3};
use sbf::sampling::{uniform_sphere, Pcg32};
use sbf::{AmbientCube, AmbientDiceBezier, AmbientDiceLinear, AmbientDiceSrbf, Asg, Basis, HBasis, SgBasis, ShBasis};
use std::hint::black_box;

fn directions() -> Vec<DVec3> {
    let mut rng = Pcg32::new(1, 1);
    (0..1024).map(|_| uniform_sphere(rng.next_2d())).collect()
}

fn bench_bases(c: &mut Criterion) {
    let dirs = directions();
    let dirs32: Vec<Vec3> = dirs.iter().map(|d| d.as_vec3()).collect();
    let mut g = c.benchmark_group("eval");
    let mut i = 0usize;
    g.bench_function("SH L2 f32 fast", |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(eval_sh_l2(black_box(dirs32[i])))
        })
    });
    g.bench_function("SH L4 f32 fast", |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(eval_sh_l4(black_box(dirs32[i])))
        })
    });
    let vogel = sbf::layout::vogel_sphere(12).unwrap();
    let bases: Vec<(&str, Box<dyn Basis>)> = vec![
        ("SH L2 f64 recurrence", Box::new(ShBasis::new(2).unwrap())),
        ("SH L4 f64 recurrence", Box::new(ShBasis::new(4).unwrap())),
        ("SH L8 f64 recurrence", Box::new(ShBasis::new(8).unwrap())),
        ("SG 12", Box::new(SgBasis::new(&vogel, 6.0, false).unwrap())),
        ("AD SRBF 12", Box::new(AmbientDiceSrbf::twelve())),
        ("AD SRBF 9", Box::new(AmbientDiceSrbf::nine_hemisphere())),
        ("AD Bezier 36", Box::new(AmbientDiceBezier::new())),
        ("AD linear 12", Box::new(AmbientDiceLinear::new())),
        ("H-basis 6", Box::new(HBasis::new(6).unwrap())),
        ("ambient cube", Box::new(AmbientCube)),
    ];
    for (name, basis) in &bases {
        let mut out = vec![0.0; basis.len()];
        g.bench_function(*name, |b| {
            b.iter(|| {
                i = (i + 1) & 1023;
                basis.eval_into(black_box(dirs[i]), &mut out);
                black_box(&out);
            })
        });
    }
    let asg = Asg::new(DVec3::Z, DVec3::X, 30.0, 3.0, 1.0).unwrap();
    g.bench_function("ASG", |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(asg.eval(black_box(dirs[i])))
        })
    });
    g.finish();
}

criterion_group!(benches, bench_bases);
criterion_main!(benches);
