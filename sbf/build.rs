//! The `bc` feature's encoder (`intel_tex_2`, [`bc`](src/bc.rs)) links the ISPC Texture
//! Compressor's prebuilt C++ ASTC object, which refers to the C++ runtime
//! (`__gxx_personality_v0`): link libstdc++ (g++'s, present wherever `cc` links Rust) on Linux.
fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_BC").is_some() && std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-link-lib=dylib=stdc++");
    }
}
