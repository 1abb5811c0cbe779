//! The basis registry's rows against the bases themselves: each fact a row states is
//! measured on the constructed basis (its size, its domain, the sign of its functions on a
//! dense sphere grid, its lobe axes) or follows from another row by the registry's own
//! rules (names unique and round-tripping, GPU slot kinds 0..n for exactly the lightmap
//! bases, probes on the sphere). Mutations tried: AD 12's `domain` set to the hemisphere,
//! SG 9's `non_negative` to false, SH L2's `lobes` to 8, two equal `gpu_kind`s, a probe
//! basis on the hemisphere — each fails.

use sbf::registry::{BasisId, Holds, BASES};
use sbf::{glam::DVec3, Domain};
use std::collections::BTreeSet;

/// Directions on a Fibonacci sphere (n points; no pole or axis singled out).
fn sphere(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * (golden * i as f64).cos(), r * (golden * i as f64).sin(), z)
        })
        .collect()
}

#[test]
fn every_row_builds_and_states_its_basis() {
    for (k, row) in BASES.iter().enumerate() {
        let id = row.id;
        assert_eq!(BasisId::ALL[k], id, "row {k} out of BasisId order");
        assert_eq!(id.info(), row, "{id}: info()");
        let b = id.basis();
        assert_eq!(b.len(), row.lobes, "{id}: lobes");
        // The domain: the basis object's own, or (SG, whose functions are defined on the
        // whole sphere) that of its lobes' layout — every axis above the horizon.
        let axes = id.axes();
        let layout_upper = !axes.is_empty() && axes.iter().all(|a| a.z > 0.0);
        let measured = if b.domain() == Domain::UpperHemisphere || layout_upper { Domain::UpperHemisphere } else { Domain::Sphere };
        assert_eq!(measured, row.domain, "{id}: domain");
        // The sign of the functions, measured over the domain (2 000 directions: a
        // function with a negative lobe is negative on a region far larger than the grid's
        // spacing).
        let dirs: Vec<DVec3> = sphere(2000).into_iter().filter(|d| row.domain == Domain::Sphere || d.z > 0.0).collect();
        let min = dirs.iter().flat_map(|d| b.eval(*d)).fold(f64::INFINITY, f64::min);
        assert_eq!(min >= -1e-12, row.non_negative, "{id}: non_negative, while the smallest value is {min}");
        // SG and AD lobes: one unit axis per coefficient, each its lobe's maximum.
        if matches!(id, BasisId::Sg9 | BasisId::Sg12 | BasisId::Ad9 | BasisId::Ad12) {
            assert_eq!(axes.len(), row.lobes, "{id}: axes");
            for (i, a) in axes.iter().enumerate() {
                assert!((a.length() - 1.0).abs() < 1e-12, "{id}: axis {i} not unit");
                let at = b.eval(*a)[i];
                assert!(dirs.iter().all(|d| b.eval(*d)[i] <= at + 1e-12), "{id}: lobe {i} peaks off its axis");
            }
        } else {
            assert!(axes.is_empty(), "{id}: axes of a basis without lobes");
        }
    }
}

#[test]
fn names_kinds_and_roles_are_consistent() {
    let names: BTreeSet<&str> = BASES.iter().map(|b| b.name).collect();
    assert_eq!(names.len(), BASES.len(), "names must be unique");
    for b in &BASES {
        assert_eq!(BasisId::from_name(b.name), Some(b.id));
        assert_eq!(b.id.to_string(), b.name);
        // A basis the tools bake holds radiance, has a Lambert runtime in the shader
        // library and a GPU slot; a probe covers the sphere.
        if b.lightmap || b.probe {
            assert_eq!(b.holds, Holds::Radiance, "{}", b.name);
            assert!(b.irradiance_feature.is_some(), "{}: a baked basis needs a Lambert runtime", b.name);
            assert!(b.gpu_kind.is_some(), "{}: a baked basis needs a GPU slot kind", b.name);
        }
        if b.probe {
            assert_eq!(b.domain, Domain::Sphere, "{}: a probe basis must cover the sphere", b.name);
            assert!(b.probes_modes[1].is_some(), "{}: a probe basis needs its sphere mode in probes", b.name);
        }
        if b.lightmap {
            assert!(b.probes_modes[0].is_some(), "{}: a lightmap basis needs its tangent-space mode in probes", b.name);
        }
        assert_eq!(b.holds == Holds::Irradiance, b.specular == [(None, None), (None, None)], "{}: specular needs radiance", b.name);
    }
    assert_eq!(BasisId::from_name("sh3"), None);
    // GPU slot kinds: 0..n, one per baked basis, in registry order.
    let kinds: Vec<u32> = BASES.iter().filter_map(|b| b.gpu_kind).collect();
    assert_eq!(kinds, (0..kinds.len() as u32).collect::<Vec<_>>());
    assert_eq!(BasisId::lightmap().count(), kinds.len(), "every lightmap basis has a slot kind, and only they");
}
