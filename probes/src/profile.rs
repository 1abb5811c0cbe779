//! What a lighting profile ([`sbf::profile::Profile`]) asks of a comparison: the modes that
//! evaluate its bases the way the runtime does, and the specular roughness values inside
//! its range (none for a Lambert-only profile).

use sbf::profile::Profile;

/// The default specular roughness values of `probes compare`.
pub const DEFAULT_ALPHAS: [f64; 5] = [0.1, 0.2, 0.4, 0.6, 0.8];

/// The comparison mode of a profile basis as its runtime evaluates it (the registry's
/// [`sbf::registry::BasisInfo::probes_modes`]): lightmap bases in tangent space (the
/// Appendix C modes), probe bases on the sphere. SH L1 is its plain runtime
/// (shaders' `sh_l1_irradiance`), not Geomerics or ZH3 (run those with --modes).
pub fn basis_modes(basis: sbf::BasisId, probe: bool) -> &'static [&'static str] {
    match &basis.info().probes_modes[probe as usize] {
        Some(m) => std::slice::from_ref(m),
        None => &[],
    }
}

/// The modes of every basis the profile names, in order, without repeats.
pub fn modes(p: &Profile) -> Vec<String> {
    let mut v: Vec<String> = Vec::new();
    let all = p.lightmap_bases.iter().map(|b| (b, false)).chain(p.probe_bases.iter().map(|b| (b, true)));
    for (b, probe) in all {
        for m in basis_modes(*b, probe) {
            if !v.iter().any(|x| x == m) {
                v.push(m.to_string());
            }
        }
    }
    v
}

/// The specular roughness values: the defaults inside the profile's range, or its two
/// ends when fewer than two defaults fall inside; none without GGX.
pub fn alphas(p: &Profile) -> Vec<f64> {
    let Some((lo, hi)) = p.roughness else { return Vec::new() };
    let inside: Vec<f64> = DEFAULT_ALPHAS.iter().copied().filter(|a| (lo..=hi).contains(a)).collect();
    if inside.len() >= 2 {
        return inside;
    }
    let mut v = vec![lo.max(1e-4)];
    if hi > lo {
        v.push(hi);
    }
    v
}

/// The specular runtime paths the profile names, as probes' [`crate::specular::SpecularRuntime`]
/// (the profile's `runtime.specular`: `fit` → the fits, `tables` → the per-lobe tables).
pub fn specular_runtimes(p: &Profile) -> Vec<crate::specular::SpecularRuntime> {
    p.specular_paths
        .iter()
        .map(|x| match x {
            sbf::profile::SpecularPath::Fit => crate::specular::SpecularRuntime::Fit,
            sbf::profile::SpecularPath::Tables => crate::specular::SpecularRuntime::Table,
        })
        .collect()
}
