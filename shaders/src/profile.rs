//! What a lighting profile ([`sbf::profile::Profile`]) asks of the runtime library: the
//! composition features for its bases (Lambert irradiance always, GGX specular when the
//! profile's BRDF set has it) and what is not available in WGSL.

use sbf::profile::Profile;

/// (irradiance feature, specular feature) of a profile basis name; SH has no WGSL
/// specular path (its zonal specular lives in `sbf::recon::sh` on the CPU).
pub fn basis_features(basis: &str) -> Option<(&'static str, Option<&'static str>)> {
    Some(match basis {
        "sh1" => ("sh-l1-irradiance", None),
        "sh2" => ("sh-l2-irradiance", None),
        "sg9" | "sg12" => ("sg-irradiance", Some("sg-specular")),
        "ad9" => ("ad9-irradiance", Some("ad9-specular")),
        "ad12" => ("ad12-irradiance", Some("ad12-specular")),
        _ => return None,
    })
}

/// The composition features the profile needs (sorted, unique) and notes on what it asks
/// for that the WGSL library does not have.
pub fn features(p: &Profile) -> (Vec<&'static str>, Vec<String>) {
    let (mut f, mut notes) = (Vec::new(), Vec::new());
    for b in p.all_bases() {
        let (irr, spec) = basis_features(b).expect("profile bases are validated");
        f.push(irr);
        if p.specular {
            match spec {
                Some(s) => f.push(s),
                None => notes.push(format!("{b}: no WGSL specular path (CPU: sbf::recon::sh::specular_zonal)")),
            }
        }
    }
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
