//! Structs shared between Rust and WGSL: their layout as naga reflects it from the
//! WGSL source, and a check that a `#[repr(C)]` Rust twin matches it member by member
//! (name, offset, size) and in total size. A mismatch is a bug that would otherwise
//! show up as garbage on the GPU, so tests run [`check`] on every shared struct.

use naga::proc::Layouter;

/// One member of a struct.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldLayout {
    pub name: String,
    pub offset: u32,
    pub size: u32,
}

/// A struct's members and total size in bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StructLayout {
    pub name: String,
    pub fields: Vec<FieldLayout>,
    pub size: u32,
}

fn parse(src: &str) -> Result<naga::Module, String> {
    naga::front::wgsl::parse_str(src).map_err(|e| e.emit_to_string(src))
}

/// The layout naga computes for struct `name` in WGSL `src`.
pub fn reflect(src: &str, name: &str) -> Result<StructLayout, String> {
    let module = parse(src)?;
    let mut layouter = Layouter::default();
    layouter.update(module.to_ctx()).map_err(|e| format!("layout of {name}: {e}"))?;
    for (_, ty) in module.types.iter() {
        if ty.name.as_deref() != Some(name) {
            continue;
        }
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            return Err(format!("'{name}' is not a struct"));
        };
        let fields = members
            .iter()
            .map(|m| FieldLayout { name: m.name.clone().unwrap_or_default(), offset: m.offset, size: layouter[m.ty].size })
            .collect();
        return Ok(StructLayout { name: name.to_string(), fields, size: *span });
    }
    Err(format!("no struct '{name}' in the WGSL source"))
}

/// The value of a `u32` constant `name` in WGSL `src` (after naga's constant evaluation).
pub fn constant_u32(src: &str, name: &str) -> Result<u32, String> {
    let module = parse(src)?;
    let (_, c) = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name)).ok_or_else(|| format!("no constant '{name}'"))?;
    match module.global_expressions[c.init] {
        naga::Expression::Literal(naga::Literal::U32(v)) => Ok(v),
        ref e => Err(format!("constant '{name}' is not a u32 literal: {e:?}")),
    }
}

/// A Rust struct with a WGSL twin.
pub trait GpuStruct: bytemuck::Pod {
    /// The WGSL struct's name.
    const WGSL_NAME: &'static str;
    /// The Rust layout of the members the WGSL struct declares (Rust-only padding
    /// members are left out; the total size covers them).
    fn layout() -> StructLayout;
}

/// Implements [`GpuStruct`] for a `#[repr(C)]` struct from the list of its members
/// that WGSL declares, in order.
#[macro_export]
macro_rules! gpu_struct {
    ($t:ty, $wgsl:expr, [$($f:ident),* $(,)?]) => {
        impl $crate::layout::GpuStruct for $t {
            const WGSL_NAME: &'static str = $wgsl;
            fn layout() -> $crate::layout::StructLayout {
                let z: $t = bytemuck::Zeroable::zeroed();
                $crate::layout::StructLayout {
                    name: $wgsl.to_string(),
                    fields: vec![$($crate::layout::FieldLayout {
                        name: stringify!($f).to_string(),
                        offset: std::mem::offset_of!($t, $f) as u32,
                        size: std::mem::size_of_val(&z.$f) as u32,
                    }),*],
                    size: std::mem::size_of::<$t>() as u32,
                }
            }
        }
    };
}

/// Checks that `T` matches its WGSL twin in `src`; the error lists every difference.
pub fn check<T: GpuStruct>(src: &str) -> Result<(), String> {
    let wgsl = reflect(src, T::WGSL_NAME)?;
    let rust = T::layout();
    let mut diffs = Vec::new();
    if wgsl.fields.len() != rust.fields.len() {
        diffs.push(format!("{} members in WGSL, {} in Rust", wgsl.fields.len(), rust.fields.len()));
    }
    for (w, r) in wgsl.fields.iter().zip(&rust.fields) {
        if w != r {
            diffs.push(format!("WGSL {} @{} ({} B) vs Rust {} @{} ({} B)", w.name, w.offset, w.size, r.name, r.offset, r.size));
        }
    }
    if wgsl.size != rust.size {
        diffs.push(format!("size {} B in WGSL vs {} B in Rust", wgsl.size, rust.size));
    }
    if diffs.is_empty() {
        Ok(())
    } else {
        Err(format!("{} layout mismatch: {}", T::WGSL_NAME, diffs.join("; ")))
    }
}
