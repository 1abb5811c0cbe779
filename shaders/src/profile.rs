//! What a lighting profile ([`sbf::profile::Profile`]) asks of the runtime library: the
//! composition features for its bases (Lambert irradiance always, GGX specular on the
//! profile's runtime paths when its BRDF set has it) and what is not available in shaders.

use sbf::profile::Profile;

/// The irradiance feature of a profile basis name.
pub fn irradiance_feature(basis: &str) -> Option<&'static str> {
    sbf::BasisId::from_name(basis)?.irradiance_feature()
}

/// The composition features the profile needs (sorted, unique): every basis's irradiance
/// and, with GGX, the specular runtime of every basis on every path the profile names
/// ([`sbf::profile::specular_runtime`], the table fitgen and the baker read too); and
/// notes on what it asks for that the shader library does not have.
pub fn features(p: &Profile) -> (Vec<&'static str>, Vec<String>) {
    let mut f: Vec<&'static str> =
        p.all_bases().iter().map(|b| b.irradiance_feature().expect("profile bases have a Lambert runtime")).collect();
    f.extend(p.specular_features());
    let notes = p
        .all_bases()
        .iter()
        .filter(|b| p.specular && b.is_sh())
        .map(|b| format!("{b}: no shader specular path (CPU: sbf::recon::sh::specular_zonal with the DFG table)"))
        .collect();
    f.sort_unstable();
    f.dedup();
    (f, notes)
}

/// The composition configuration of a profile, named after it.
pub fn config(p: &Profile) -> Result<crate::compose::Config, String> {
    let (f, _) = features(p);
    let mut c = crate::compose::Config::parse(&f.join(","))?;
    c.name = format!("profile '{}'", p.name);
    Ok(c)
}
