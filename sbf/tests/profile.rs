//! Lighting profiles: the example profiles in `profiles/` parse; every kind of bad input is
//! an error naming the key at fault.
use sbf::profile::Profile;

fn examples() -> Vec<(String, Profile)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../profiles");
    let mut v: Vec<(String, Profile)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), Profile::load(&p).unwrap()))
        .collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    v
}

#[test]
fn example_profiles_parse() {
    let ex = examples();
    assert!(ex.len() >= 3, "{} example profiles", ex.len());
    let get = |n: &str| &ex.iter().find(|(f, _)| f == n).unwrap_or_else(|| panic!("{n}")).1;
    let mobile = get("mobile-sh-l1.toml");
    assert_eq!((mobile.lightmap_bases.clone(), mobile.specular, mobile.language.as_str()), (vec![sbf::BasisId::Sh1], false, "glsl"));
    let ad9 = get("ad9-diffuse-specular.toml");
    assert_eq!((ad9.specular, ad9.roughness), (true, Some((0.1, 0.8))));
    assert_eq!(ad9.all_bases(), vec![sbf::BasisId::Ad9, sbf::BasisId::Sh2]);
    let all = get("everything.toml");
    assert_eq!(all.lightmap_bases.len(), 6);
}

const GOOD: &str = "name = \"t\"\n[lightmap]\nbases = [\"sh2\"]\n[brdf]\nmodels = [\"lambert\", \"ggx\"]\nroughness = [0.1, 0.5]\n[runtime]\nprecision = \"f32\"\nlanguage = \"wgsl\"\nspecular = [\"fit\"]\n";

#[test]
fn bad_profiles_name_the_key() {
    assert!(Profile::parse(GOOD).is_ok());
    let cases: [(&str, &str, &str); 10] = [
        ("bases = [\"sh2\"]", "bases = [\"sh3\"]", "lightmap.bases"),
        ("bases = [\"sh2\"]", "bases = []", "lightmap.bases"),
        ("bases = [\"sh2\"]", "bases = [\"sh2\", \"sh2\"]", "lightmap.bases"),
        ("roughness = [0.1, 0.5]\n", "", "brdf.roughness"),
        ("roughness = [0.1, 0.5]", "roughness = [0.5, 0.1]", "brdf.roughness"),
        ("models = [\"lambert\", \"ggx\"]", "models = [\"ggx\"]", "brdf.models"),
        ("models = [\"lambert\", \"ggx\"]", "models = [\"lambert\", \"phong\"]", "brdf.models"),
        ("precision = \"f32\"", "precision = \"f16\"", "runtime.precision"),
        ("language = \"wgsl\"", "language = \"spirv\"", "runtime.language"),
        ("name = \"t\"", "name = \" \"", "name"),
    ];
    for (from, to, key) in cases {
        let text = GOOD.replacen(from, to, 1);
        let e = Profile::parse(&text).unwrap_err();
        assert_eq!(e.key, key, "{to}: {e}");
        assert!(e.to_string().contains(key), "{e}");
    }
    // The specular runtime path: required with GGX, refused without, named values only.
    let e = Profile::parse(&GOOD.replacen("specular = [\"fit\"]\n", "", 1)).unwrap_err();
    assert_eq!(e.key, "runtime.specular", "{e}");
    let e = Profile::parse(&GOOD.replacen("[\"fit\"]", "[\"lut\"]", 1)).unwrap_err();
    assert_eq!(e.key, "runtime.specular", "{e}");
    let lambert = GOOD.replacen("models = [\"lambert\", \"ggx\"]", "models = [\"lambert\"]", 1).replacen("roughness = [0.1, 0.5]\n", "", 1);
    assert_eq!(Profile::parse(&lambert).unwrap_err().key, "runtime.specular");
    let p = Profile::parse(&lambert.replacen("specular = [\"fit\"]\n", "", 1)).unwrap();
    assert!(p.specular_paths.is_empty() && p.specular_features().is_empty());
    // Each path names its own features and tables (sbf::profile::specular_runtime).
    let tables = |paths: &str, bases: &str| {
        let p = Profile::parse(&GOOD.replacen("[\"fit\"]", paths, 1).replacen("bases = [\"sh2\"]", bases, 1)).unwrap();
        (p.specular_features(), p.tables())
    };
    assert_eq!(tables("[\"fit\"]", "bases = [\"ad9\"]"), (vec!["ad9-specular"], vec!["fits", "fits-wgsl", "ad-specular-2d"]));
    assert_eq!(tables("[\"tables\"]", "bases = [\"ad9\"]"), (vec!["lobe-ggx-filtered"], vec!["fits", "fits-wgsl", "lobe-ggx-ad"]));
    assert_eq!(
        tables("[\"fit\", \"tables\"]", "bases = [\"sg9\", \"sh1\"]"),
        (vec!["lobe-ggx-filtered", "sg-specular", "sh-specular"], vec!["fits", "fits-wgsl", "dfg", "lobe-ggx-sg6"])
    );
    // Multiple scattering: "compensated" adds the energy-compensation feature and the DFG
    // table it reads; "single" is the default; an unknown value or one without GGX is refused.
    let ms = |v: &str| GOOD.replacen("roughness = [0.1, 0.5]\n", &format!("roughness = [0.1, 0.5]\nmultiple_scattering = \"{v}\"\n"), 1);
    let p = Profile::parse(&ms("compensated").replacen("bases = [\"sh2\"]", "bases = [\"ad9\"]", 1)).unwrap();
    assert!(p.multiple_scattering);
    assert_eq!(
        (p.specular_features(), p.tables()),
        (vec!["ad9-specular", "ggx-energy-compensation"], vec!["fits", "fits-wgsl", "ad-specular-2d", "dfg"])
    );
    assert!(p.summary().contains("multiple scattering compensated"), "{}", p.summary());
    assert!(!Profile::parse(&ms("single")).unwrap().multiple_scattering && !Profile::parse(GOOD).unwrap().multiple_scattering);
    assert_eq!(Profile::parse(&ms("kulla-conty")).unwrap_err().key, "brdf.multiple_scattering");
    let no_ggx = ms("compensated").replacen("models = [\"lambert\", \"ggx\"]", "models = [\"lambert\"]", 1).replacen(
        "roughness = [0.1, 0.5]\n",
        "",
        1,
    );
    assert_eq!(Profile::parse(&no_ggx.replacen("specular = [\"fit\"]\n", "", 1)).unwrap_err().key, "brdf.multiple_scattering");
    // Where: the value's line and column (1-based, characters).
    let e = Profile::parse(&GOOD.replacen("bases = [\"sh2\"]", "bases = [\"sh3\"]", 1)).unwrap_err();
    assert_eq!(e.at, Some((3, 9)), "{e}");
    assert!(e.to_string().contains("line 3, column 9"), "{e}");
    let e = Profile::parse(&GOOD.replacen("language = \"wgsl\"", "language = \"spirv\"", 1)).unwrap_err();
    assert_eq!(e.at, Some((9, 12)), "{e}");
    let e = Profile::parse("name = \"x\"\n[lightmap\n").unwrap_err();
    assert_eq!(e.at.map(|(l, _)| l), Some(2), "a syntax error on line 2: {e}");
    // Unknown and missing keys: toml names them.
    let e = Profile::parse(&GOOD.replacen("[runtime]", "[runtime]\nspeed = 3", 1)).unwrap_err();
    assert!(e.to_string().contains("speed"), "{e}");
    let e = Profile::parse(&GOOD.replacen("language = \"wgsl\"\n", "", 1)).unwrap_err();
    assert!(e.to_string().contains("language"), "{e}");
    let e = Profile::parse("not toml [").unwrap_err();
    assert!(e.key.is_empty(), "{e}");
    // Lambert-only with a roughness range is refused (it would be ignored silently).
    let e = Profile::parse(&GOOD.replacen("models = [\"lambert\", \"ggx\"]", "models = [\"lambert\"]", 1)).unwrap_err();
    assert_eq!(e.key, "brdf.roughness");
}

/// `to_toml` writes text that parses back to the same profile, for every shape the parser
/// accepts (no probes, Lambert only, both specular paths, compensated, an α with no short
/// decimal): the bake spec records a profile this way, so a merge or resume must read back
/// exactly the profile the bake used. Oracle: `Profile::parse` of the written text.
/// Mutation tried: dropping the `multiple_scattering` line fails the third case.
#[test]
fn to_toml_round_trips() {
    let cases = [
        "name = \"lambert only\"\n[lightmap]\nbases = [\"sh2\"]\n[brdf]\nmodels = [\"lambert\"]\n[runtime]\nprecision = \"f32\"\nlanguage = \"glsl-es\"\n",
        "name = \"a \\\"quoted\\\" name\"\n[lightmap]\nbases = [\"ad9\", \"sg12\"]\n[probes]\nbases = [\"sh2\", \"ad12\"]\n[brdf]\nmodels = [\"lambert\", \"ggx\"]\nroughness = [0.1, 0.8]\n[runtime]\nprecision = \"f32\"\nlanguage = \"hlsl\"\nspecular = [\"fit\", \"tables\"]\n",
        "name = \"ms\"\n[lightmap]\nbases = [\"sg9\"]\n[brdf]\nmodels = [\"lambert\", \"ggx\"]\nroughness = [0.30000000000000004, 1.0]\nmultiple_scattering = \"compensated\"\n[runtime]\nprecision = \"f32\"\nlanguage = \"wgsl\"\nspecular = [\"tables\"]\n",
    ];
    for text in cases {
        let p = Profile::parse(text).unwrap();
        let written = p.to_toml();
        assert_eq!(Profile::parse(&written).unwrap_or_else(|e| panic!("{written}\n{e}")), p, "{written}");
    }
}
