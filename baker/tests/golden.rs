//! The bake's outputs pinned by content: small bakes of the built-in scene and of the
//! mixed-lighting glTF with SH L2 + AD 9 lightmaps (SH L2 + AD 12 probes) on the CPU path,
//! every written file hashed (SHA-256) and compared with the hashes the same command gave
//! before the crate's layout was redesigned. The CPU path is deterministic for any thread
//! count (ordered reductions, counter-based random numbers), so the oracle is exact: any
//! change to a sample's order, a random number's use, an encoder update, the denoiser, the
//! seam stitcher, dilation, EXR encoding or bake.json's numbers changes a hash.
//!
//! bake.json is compared without the fields that measure this run (wall times, the device
//! and its thread count) or name the engine (the GPU pipeline: both give the same bake):
//! they are removed and the rest is hashed in canonical form (keys sorted, numbers written
//! round-trip exact).
//!
//! When a change is *meant* to alter the outputs, run this test, check the printed table
//! against the reason for the change, and paste it in place of the pinned one.
//! (2026-12-03: bake.json re-pinned — its `runtime.left_out_bytes` grew with the library's
//! new `ggx_energy_compensation`, which these bakes leave out; every other file unchanged.
//! Re-pinned again the same day: bake.json states each SG/AD basis's lobe axes (and SG's
//! sharpness); every other file unchanged. 2026-12-04: bake.json re-pinned — its
//! `runtime.left_out_bytes` grew with the library's new `engine` and `lightmap` modules, which
//! these bakes leave out: with the two modules removed from `shaders::modules::all` the old
//! pins pass; every other file unchanged. 2026-12-05: bake.json re-pinned — its
//! `runtime.left_out_bytes` grew with the library's `lobe_ggx_filtered_*` (the tables through
//! the texture unit's filter), which these bakes leave out; every other file unchanged.
//! 2026-12-06: re-pinned for the solvers' change — SH by the running projection (sh2_*.exr,
//! the probes' SH L2 in probes.json) and the default `nnls-rescaled` (ad9_*.exr scaled per
//! texel to the texel's E/π), bake.json with them and each basis' irradiance ratio;
//! irradiance.exr, its standard error, normals, the probes' AD 12 and the preview unchanged.
//! Later the same day: bake.json re-pinned — `runtime.left_out_bytes` grew with SG's split-sum
//! specular (`sg_split_sum_*`, `sg_hill_cos`), which these bakes leave out: with sg.wgsl as it
//! was before, the old pins pass; every other file unchanged. Later the same day: bake.json
//! and runtime.wgsl re-pinned — the runtime holds the probes' bases too (these bakes' AD 12
//! probes add `ad12-irradiance` and `ad12-specular`), the library's items carry the `sbf_`,
//! `Sbf`, `SBF_` prefix in the written runtime.wgsl, and `left_out_bytes` moved with the
//! library (SG's lobe loops, the largest-f32 constant, comments); every other file unchanged.
//! Then: the bake writes its tables as KTX 2.0 too (`dfg.ktx2`, `ad_specular_2d.ktx2`, new
//! pins) and bake.json lists them (`runtime.textures`); every other file unchanged.
//! 2026-12-07: bake.json re-pinned — `runtime.left_out_bytes` moved with engine.wgsl's
//! comments (which Godot and Bakery decode each function is), which these bakes leave out;
//! every other file unchanged. Later the same day: again, engine.wgsl gained Bakery's default
//! non-linear MonoSH and Godot 4.0–4.3's decodes (left out here); every other file unchanged.
//! Then the glTF bake re-pinned: seam stitching holds texels where the free solve took E/π
//! below zero (this bake had 32 such texels) and rescales the AD lobes by the stitched E/π
//! (`baker::post::seams`): irradiance, the SH and AD lobes, the preview and bake.json
//! (`seams.held_texels`, `metric_after`) changed; the built-in scene has no seams and kept
//! every pin.) Then the citations rewritten to docs/references.md's keys: runtime.wgsl's and
//! ad_specular_2d.ktx2's comments and layout text, and with them bake.json's byte counts and
//! hashes, re-pinned in all three bakes; every EXR, probes.json and the preview unchanged.
//! 2026-12-07: the bake spec split from the run options — bake.json gained `spec` and the
//! bakes write spec.json (both compared with the scene's and environment's folders cut, so
//! a clone elsewhere hashes the same); bake.json re-pinned, spec.json pinned, every other
//! file unchanged.

mod common;

use common::outputs::{hashes, scenes_dir};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("baker-golden-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn bake(out: &Path, scene: &str, extra: &[&str]) {
    let mut args = vec![
        "--scene",
        scene,
        "--bases",
        "sh2,ad9",
        "--probe-bases",
        "sh2,ad12",
        "--probes",
        "2,2,2",
        "--preview-width",
        "48",
        "--checkpoint-every",
        "0",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    if !args.contains(&"--device") {
        args.extend(["--device", "cpu"]);
    }
    let o = Command::new(env!("CARGO_BIN_EXE_baker")).args(&args).output().unwrap();
    assert!(o.status.success(), "baker {args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

fn check(what: &str, dir: &Path, pinned: &[(&str, &str)]) {
    let got = hashes(dir);
    let table: String = got.iter().map(|(f, h)| format!("        (\"{f}\", \"{h}\"),\n")).collect();
    println!("{what}: {} files\n{table}", got.len());
    let names: Vec<&str> = got.iter().map(|(f, _)| f.as_str()).collect();
    let pinned_names: Vec<&str> = pinned.iter().map(|(f, _)| *f).collect();
    assert_eq!(names, pinned_names, "{what}: the bake wrote other files than the pinned bake");
    let differ: Vec<&str> = got.iter().zip(pinned).filter(|((_, h), (_, p))| h != p).map(|((f, _), _)| f.as_str()).collect();
    assert!(differ.is_empty(), "{what}: {} of {} files differ from the pinned bake: {differ:?}", differ.len(), got.len());
}

/// The built-in scene: 16 passes at 6 texels per unit, denoised and seam-stitched
/// (the command's defaults for short bakes), 2×2×2 probes.
#[test]
fn builtin_scene_outputs_match_the_pinned_bake() {
    let d = tmp("cornell");
    bake(&d, "cornell", &["--passes", "16", "--texels-per-unit", "6"]);
    check("cornell", &d, CORNELL);
}

/// The mixed-lighting glTF (authored lightmap UVs, ≈ 41 k triangles): 4 passes at
/// 8 texels per unit, its materials' factors (`--material-maps factors`: the pins predate
/// texture maps; the maps' sampling is checked against closed forms in textures.rs).
#[test]
fn gltf_scene_outputs_match_the_pinned_bake() {
    let Some(scenes) = scenes_dir() else { return };
    let gltf = scenes.join("bevy_MixedLightingExample/MixedLightingExample.gltf");
    let d = tmp("mixed");
    bake(&d, gltf.to_str().unwrap(), &["--passes", "4", "--texels-per-unit", "8", "--material-maps", "factors"]);
    check("mixed-lighting glTF", &d, MIXED);
}

/// The adapter the GPU hashes were pinned on (CI's lavapipe): its name, backend and driver.
/// Another driver compiles the kernels to other machine code (fused multiply-adds,
/// reassociated sums), so its bits differ — llvmpipe through GL shares lavapipe's name but
/// not its compiler — and there the pinned hashes do not apply: only the two pipelines'
/// agreement is checked.
const PINNED_ADAPTER: (&str, wgpu::Backend, &str) = ("llvmpipe (LLVM 15.0.6, 256 bits)", wgpu::Backend::Vulkan, "Mesa 22.3.6");

/// Whether the hashes pinned on [`PINNED_ADAPTER`] apply to `gpu`.
fn pinned_on(gpu: &shaders::gpu::Gpu) -> bool {
    let (name, backend, driver) = PINNED_ADAPTER;
    gpu.adapter.starts_with(&format!("{name} (")) && gpu.backend == backend && gpu.adapter.contains(driver)
}

/// The built-in scene on the GPU, megakernel and wavefront pipelines: both write the same
/// bits, pinned on lavapipe (the images, probes.json; bake.json names the pipeline).
#[test]
fn builtin_scene_gpu_outputs_match_the_pinned_bake() {
    let Some(gpu) = common::gpu() else { return };
    let (adapter, pinned) = (gpu.adapter.clone(), pinned_on(&gpu));
    drop(gpu);
    let mut pipelines = Vec::new();
    for pipeline in ["megakernel", "wavefront"] {
        let d = tmp(&format!("gpu-{pipeline}"));
        bake(&d, "cornell", &["--passes", "16", "--texels-per-unit", "6", "--device", "gpu", "--pipeline", pipeline]);
        if pinned {
            check(&format!("cornell GPU {pipeline}"), &d, CORNELL_GPU);
        } else {
            println!("adapter '{adapter}': hashes pinned on {PINNED_ADAPTER:?} do not apply");
        }
        pipelines.push(hashes(&d));
    }
    assert_eq!(pipelines[0], pipelines[1], "the megakernel and wavefront pipelines wrote different outputs");
}

const CORNELL_GPU: &[(&str, &str)] = &[
    ("ad9_00.exr", "4c5dbaece4149a1b6552b028f0e1a32f031eba0cb6f72f05eecb88708ad20209"),
    ("ad9_01.exr", "e1543b85d98803db9dbc6f7f7eecaba2f7e85395aacb0ca5f7b9015771251335"),
    ("ad9_02.exr", "1069cee5c3b467ed3d496602b601afbad3fb10da3756f080500ca896a781b173"),
    ("ad9_03.exr", "be6e706576834007476fbf0cbdde6fad10dde1415851e3a286e5fe3c486e4b39"),
    ("ad9_04.exr", "4fc8e6e93830a5a6cbc17b7191e081dd78e7313d6a717e5e1e983f2315d94507"),
    ("ad9_05.exr", "c43359da176e8ea293d855e87c8eb982f7316afa1ecea0fc6c21c528b5e75b96"),
    ("ad9_06.exr", "b48d7a45537ed88562fe36d21d645e72d446fbf179503b0fbcef5176e7a4ff96"),
    ("ad9_07.exr", "150006bae59d2d815a2d35c97b9cfc76607a57fdb05e8205519f85989281c64a"),
    ("ad9_08.exr", "e099693b3cf4d9d2805163aee5447caa7afcd73de0bf634ae0db1797c6a04acf"),
    ("ad_specular_2d.ktx2", "f904bc28724a7d1b3d1e9b01cd597deb0d2d7f243560a4ffa4e1c286a47fc2b1"),
    ("ad_specular_2d.sbflut", "3fdb6ee9bd96902d00a8e0aa2a2c9018382eff4bdd6b348c9a37aceb3e0421cc"),
    ("bake.json", "e04373706c1376df45c75f724e70acbd19c9d61d283d0dcd558152ba7aba627c"),
    ("dfg.ktx2", "4c33e6ab9f10bb2d199111b1352c19c1ae2cfafaf2c6566c6ac2a1ef1bcaa215"),
    ("dfg.sbflut", "0e232d60751dd7e8d9f5e230c68d4ce6d76f31c24d3f2749085a244c8454c708"),
    ("irradiance.exr", "b26fa86441984fe3b283f0c4665be88f381e42864feb4be1fa6f1be96969f8fb"),
    ("irradiance_se.exr", "fb592dec755370a546311ea7377a5e42c7048524d447e9454b9ac92e9bb4ff45"),
    ("normals.exr", "7bde30ddc1346d358f123d68242105b0ba0517e8ca774e8344b464e12a48d3b8"),
    ("preview.png", "b226f0af6e9fbdb967d6e18c493eb2ec5a09315b32ba7224417b4232acc511e2"),
    ("probes.json", "dfa490a3193586ca8dce179e3bdbb5e794454e146cb2582c91c4f1ea1ea108d9"),
    ("runtime.wgsl", "36f15e5299410e4d9e47e287b890c41ad81d072fcc83922d633bc79657882a49"),
    ("sh2_00.exr", "2b732dd4e6773d6f5a031275549fee9dc4f2a089bb392484ae011adab76f9126"),
    ("sh2_01.exr", "a7b234c031b8bebceb6196a0f75450a4badec6b0b869415d7d495e0ea6c53a45"),
    ("sh2_02.exr", "404826114100430147243fcd5b6412892b14d8bf57b6b99c7e3e2d2427bf6865"),
    ("sh2_03.exr", "bf3b0de9cd425bc5117c32c5018cecafe0c5e0cf087c5b9036662527fa367c95"),
    ("sh2_04.exr", "4c7510db29ac5dd25266de4a27ad43c235ce42de261fb48c2fbbc91556cb6fbf"),
    ("sh2_05.exr", "4d40bdcf0c6c057d30003bb29d50eca79f63fe8058d969f22d2d5131a2267bd7"),
    ("sh2_06.exr", "834a7a61689f587f912ff248394a7c5ca144da28d234771eec315532da6c4092"),
    ("sh2_07.exr", "d14d7b23c9cb71f4b5e2f8c19ae7e930e664762bd4add51cbaaf99c91cc9b81e"),
    ("sh2_08.exr", "3fa61b984fb0d3486967080c2bdaa7a01389310e3cd88cf5eced25e78e671cbd"),
    ("spec.json", "e4724379777e882805dbc674bace11570f2280b0c01e80ab36985e4d7f4a9a06"),
];

const CORNELL: &[(&str, &str)] = &[
    ("ad9_00.exr", "34ee3b586b233783af05b4b3ca372ca931532b5818d244c2552f020533815ed8"),
    ("ad9_01.exr", "c4562dc4930267eab94b965e6b2d913c00fa4d3ae48c6f62c3cfe5a396b16a91"),
    ("ad9_02.exr", "2dbfdf6ba5ba6de461a454163fe9f241835632c8c60ec9d569f343ace8631fd4"),
    ("ad9_03.exr", "7abc13f9d6d1181299b1f4855e3d5a24707b42dbb1e3e81889a8b39b936a6db8"),
    ("ad9_04.exr", "de6eca3f204405171e13a01637f3324fba0ada4e61d56c134644e049704a903d"),
    ("ad9_05.exr", "6c4b318bd371ff60a0097b091270b8aa5e5f05ab8501ca52c5407834d75b84d4"),
    ("ad9_06.exr", "55964a92acec02ca62284259f2cc694b6f526c48a15bd4ea8ebc3147d31be4af"),
    ("ad9_07.exr", "aa859731f5ab77bdd6c622821681c70160fc53f47d7789b8e1342f81aab8c825"),
    ("ad9_08.exr", "a63b6f509b37b123d1a816e27cbafc36715d7f6f57cd34614472798edee5eed7"),
    ("ad_specular_2d.ktx2", "f904bc28724a7d1b3d1e9b01cd597deb0d2d7f243560a4ffa4e1c286a47fc2b1"),
    ("ad_specular_2d.sbflut", "3fdb6ee9bd96902d00a8e0aa2a2c9018382eff4bdd6b348c9a37aceb3e0421cc"),
    ("bake.json", "54469fa90fb4f535647f1f13992a6085f3d77f2c1c9aef2bf53e25aea7849f31"),
    ("dfg.ktx2", "4c33e6ab9f10bb2d199111b1352c19c1ae2cfafaf2c6566c6ac2a1ef1bcaa215"),
    ("dfg.sbflut", "0e232d60751dd7e8d9f5e230c68d4ce6d76f31c24d3f2749085a244c8454c708"),
    ("irradiance.exr", "37a26e85c41950390002d8b45df4bf4bed891de03155be977680767957f36a7a"),
    ("irradiance_se.exr", "a65e775db56ce9fa43feb66b9ff192eb0d8613170847c5d581c277bd639f524e"),
    ("normals.exr", "7bde30ddc1346d358f123d68242105b0ba0517e8ca774e8344b464e12a48d3b8"),
    ("preview.png", "b226f0af6e9fbdb967d6e18c493eb2ec5a09315b32ba7224417b4232acc511e2"),
    ("probes.json", "f6b99b10a69815392a874c5c18ea6ceec3f38dee83d95b2063130b796c75f62c"),
    ("runtime.wgsl", "36f15e5299410e4d9e47e287b890c41ad81d072fcc83922d633bc79657882a49"),
    ("sh2_00.exr", "56e4828c0d9110ccbd5270d5a9367a13b033ac5dcccfdcb6205f9fa417753297"),
    ("sh2_01.exr", "642f1db757985f632ed23d808f942aa4fbc6a8ea558b94fbcf02efb0a37f66d6"),
    ("sh2_02.exr", "8981f7cd5514b7ac375b872db3b8829517e447100d84afa496f2fd5a111b76d0"),
    ("sh2_03.exr", "5ac46b2c08f8631a7a22ed6673af7e1a95fc2077bb6845838c95528f7512d29a"),
    ("sh2_04.exr", "125ff2cec49dd0fab02298e833c595ac5a8ca9f1dedd2a05e0fb8b49965fb9b4"),
    ("sh2_05.exr", "414a45782232e594a2f5c783fb224e33c43acb92d9d93fcffec867b569e4965e"),
    ("sh2_06.exr", "3fce0a948dc8d6999b6e4ddc7d0fae7125b9e2845d59a269ba9e4f30c8945fc2"),
    ("sh2_07.exr", "af2b38958be698a35f050199d508ad15d731ad979a76097589b6b0a3746f4e32"),
    ("sh2_08.exr", "9cf27b90635c597fad8614437d1e3f5601d094af8c5a8ff6f5c9f4d94e62f347"),
    ("spec.json", "e4724379777e882805dbc674bace11570f2280b0c01e80ab36985e4d7f4a9a06"),
];
const MIXED: &[(&str, &str)] = &[
    ("ad9_00.exr", "3dcdda5e1cdfa641614e4e22c3c953024838ead57e4ebdb644a3eb147c96f933"),
    ("ad9_01.exr", "43cdc388442149a64e51aa6101bef434fac7cd9e86a34c331bba68f0be6b8a0f"),
    ("ad9_02.exr", "3a3acd54bc1d6f52cf1902397315d987bca220964b3b109b0bb3a4201f0d13ca"),
    ("ad9_03.exr", "1c84bc9eba5243b0fda9bfa27c249f034020923026a08089fa1fbbbc60adac85"),
    ("ad9_04.exr", "00bb6016d3670e188a5f977d78b0582882693356d7a8bd7d18d90752ff643a1a"),
    ("ad9_05.exr", "afbc416ef4569835355d7f180517c9931784f03ed0a15f9e288f626c94b06698"),
    ("ad9_06.exr", "deab256dd5570937ad8018d00adbf8ba8c9baab7534ab383a8414b1e037531a9"),
    ("ad9_07.exr", "6a7b38dbfd1df5d014fafb29070e67977bb435b542b715a548be4d151e84dc4c"),
    ("ad9_08.exr", "63e7eca03c6b2d21c19e44abfd4a4c4fa912b4b988d1694ddc5f47fc59d58c41"),
    ("ad_specular_2d.ktx2", "f904bc28724a7d1b3d1e9b01cd597deb0d2d7f243560a4ffa4e1c286a47fc2b1"),
    ("ad_specular_2d.sbflut", "3fdb6ee9bd96902d00a8e0aa2a2c9018382eff4bdd6b348c9a37aceb3e0421cc"),
    ("bake.json", "a73b759c678613f563dbcee8decdd0df8df51dc93d92beae951c2776cdc6bc83"),
    ("dfg.ktx2", "4c33e6ab9f10bb2d199111b1352c19c1ae2cfafaf2c6566c6ac2a1ef1bcaa215"),
    ("dfg.sbflut", "0e232d60751dd7e8d9f5e230c68d4ce6d76f31c24d3f2749085a244c8454c708"),
    ("irradiance.exr", "abe850d1f3d2551c92da34fbc84bb868b32b972fbc67a65bf34280c1821374a6"),
    ("irradiance_se.exr", "91522e2a63b6c12c44af8b8469c911eb5985b35b455c69b0e9b1cab803757254"),
    ("normals.exr", "95c89f300d220c890e322c7a64c985345ff34c5dc2c3dc1dda61516de35c24b4"),
    ("preview.png", "703ca9a52760a03d6c6b5872e48e93bbc0466d179d6772778b9af8a9de3bd7c2"),
    ("probes.json", "d1ab5ef56a042a6212ea0d5366866ddc7465f553f76a9a0564fe29599ada3643"),
    ("runtime.wgsl", "36f15e5299410e4d9e47e287b890c41ad81d072fcc83922d633bc79657882a49"),
    ("sh2_00.exr", "b5d448c8d0fe359340928bee782090ad7eb137fcf027a78cf6b6165cbf8d1c31"),
    ("sh2_01.exr", "9f82833c5bb462126a5da1115acc30dd49a9a4ee438919e14d59cf979e85ad36"),
    ("sh2_02.exr", "1672a498c4b2d8d013cc0ca8332fb9d839d0628e9c8ccf83304a34f028e4ba7a"),
    ("sh2_03.exr", "4af1f415b5fe4e8bac41cb2d8bfb1582245d15c2c2bb3595d7cadc52cc2038a1"),
    ("sh2_04.exr", "0eb03cd3ecfcbe2a231f0a9c80055061511967367a02800128720fc5143e489d"),
    ("sh2_05.exr", "19de66754d4a2ccd6d30a30b217548d4adf1cdaea40542ffc053021ec1decc19"),
    ("sh2_06.exr", "18b3e045d9103c99dacb265263707d562d4968240ffc6173ef2c2c2bd7cffcff"),
    ("sh2_07.exr", "c4babc0f91745366ce61f23636157a2d73730d3297d96c991445c7f46e450940"),
    ("sh2_08.exr", "3aab5dceff0564a5d3269ec071400beaa975db16fd7b0d52842b698930147583"),
    ("spec.json", "d6b959826e57e6006c6671abb7372e5a109a49ac53c5328e64195087bf8f4438"),
];
