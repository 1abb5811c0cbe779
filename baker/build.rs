//! intel_tex_2 (BC6H encoding, `output::compress`) links the ISPC Texture Compressor's
//! prebuilt C++ ASTC object, which refers to the C++ runtime (`__gxx_personality_v0`):
//! link libstdc++ (g++'s, present wherever `cc` links Rust) on Linux.
fn main() {
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-link-lib=dylib=stdc++");
    }
}
