//! What differs between the four languages at the level of single tokens: type names,
//! declarators, literals, built-in function names and reserved words.
//!
//! Matrices: WGSL, GLSL and MSL index a matrix by column (`m[i]` is column i, `m * v`
//! multiplies a column vector). HLSL's `floatCxR` written with the WGSL columns as its rows
//! holds Mᵀ; with that storage `m[i]` is still WGSL's column i and `M * v` becomes
//! `mul(v, M)` (vᵀMᵀ = (Mv)ᵀ), `v * M` becomes `mul(M, v)` and `A * B` becomes `mul(B, A)`
//! ((AB)ᵀ = BᵀAᵀ). This is the convention of naga's HLSL back end and of DXC's SPIR-V
//! output for WGSL-origin shaders.

use crate::lang::{Glsl, Lang};
use naga::{ImageClass, ImageDimension, Literal, MathFunction, Scalar, ScalarKind, TypeInner, VectorSize};

/// The name of a scalar type.
pub fn scalar(lang: Lang, s: Scalar) -> Result<&'static str, String> {
    let _ = lang;
    Ok(match (s.kind, s.width) {
        (ScalarKind::Float, 4) => "float",
        (ScalarKind::Sint, 4) => "int",
        (ScalarKind::Uint, 4) => "uint",
        (ScalarKind::Bool, _) => "bool",
        _ => return Err(format!("scalar type {s:?} has no portable spelling (f32, i32, u32, bool only)")),
    })
}

fn size(n: VectorSize) -> u8 {
    n as u8
}

/// The name of a vector type.
pub fn vector(lang: Lang, n: VectorSize, s: Scalar) -> Result<String, String> {
    let base = scalar(lang, s)?;
    Ok(match lang {
        Lang::Glsl(_) => {
            let p = match s.kind {
                ScalarKind::Float => "",
                ScalarKind::Sint => "i",
                ScalarKind::Uint => "u",
                ScalarKind::Bool => "b",
                ScalarKind::AbstractInt | ScalarKind::AbstractFloat => return Err("abstract vector type".into()),
            };
            format!("{p}vec{}", size(n))
        }
        Lang::Wgsl => format!("vec{}<{}>", size(n), wgsl_scalar(s)),
        Lang::Hlsl | Lang::Msl => format!("{base}{}", size(n)),
    })
}

fn wgsl_scalar(s: Scalar) -> &'static str {
    match s.kind {
        ScalarKind::Float => "f32",
        ScalarKind::Sint => "i32",
        ScalarKind::Uint => "u32",
        _ => "bool",
    }
}

/// The name of a `columns`×`rows` float matrix (see the module note for HLSL).
pub fn matrix(lang: Lang, columns: VectorSize, rows: VectorSize) -> String {
    let (c, r) = (size(columns), size(rows));
    match lang {
        Lang::Glsl(_) if c == r => format!("mat{c}"),
        Lang::Glsl(_) => format!("mat{c}x{r}"),
        Lang::Wgsl => format!("mat{c}x{r}<f32>"),
        Lang::Hlsl | Lang::Msl => format!("float{c}x{r}"),
    }
}

/// The name of a sampled float texture parameter type.
pub fn image(lang: Lang, dim: ImageDimension, arrayed: bool, class: ImageClass) -> Result<&'static str, String> {
    let volume = dim == ImageDimension::D3 && !arrayed;
    if !(dim == ImageDimension::D2 || volume) || !matches!(class, ImageClass::Sampled { kind: ScalarKind::Float, multi: false }) {
        return Err(format!("texture {dim:?} {class:?}: only 2D float textures (and arrays) and 3D float textures are exported"));
    }
    if volume {
        return Ok(match lang {
            Lang::Glsl(Glsl::Vulkan) => "texture3D",
            Lang::Glsl(Glsl::Gl) => "sampler3D",
            Lang::Glsl(Glsl::Es) => "highp sampler3D",
            Lang::Hlsl => "Texture3D<float2>",
            Lang::Msl => "texture3d<float>",
            Lang::Wgsl => "texture_3d<f32>",
        });
    }
    Ok(match (lang, arrayed) {
        (Lang::Glsl(Glsl::Vulkan), false) => "texture2D",
        (Lang::Glsl(Glsl::Vulkan), true) => "texture2DArray",
        (Lang::Glsl(Glsl::Gl), false) => "sampler2D",
        (Lang::Glsl(Glsl::Gl), true) => "sampler2DArray",
        (Lang::Glsl(Glsl::Es), false) => "highp sampler2D",
        (Lang::Glsl(Glsl::Es), true) => "highp sampler2DArray",
        (Lang::Hlsl, false) => "Texture2D<float2>",
        (Lang::Hlsl, true) => "Texture2DArray<float2>",
        (Lang::Msl, false) => "texture2d<float>",
        (Lang::Msl, true) => "texture2d_array<float>",
        (Lang::Wgsl, false) => "texture_2d<f32>",
        (Lang::Wgsl, true) => "texture_2d_array<f32>",
    })
}

/// The name of a (non-comparison) sampler parameter type.
pub fn sampler(lang: Lang, comparison: bool) -> Result<&'static str, String> {
    if comparison {
        return Err("comparison samplers are not exported".into());
    }
    Ok(match lang {
        Lang::Glsl(_) => "sampler",
        Lang::Hlsl => "SamplerState",
        Lang::Msl => "sampler",
        Lang::Wgsl => "sampler",
    })
}

/// A literal. Floats are written with the shortest digits that read back to the same f32
/// (Rust's `Debug`), with a `.` or an exponent; MSL takes the `f` suffix (an unsuffixed
/// literal is a double in C++).
pub fn literal(lang: Lang, l: Literal) -> Result<String, String> {
    Ok(match l {
        Literal::F32(x) => {
            if !x.is_finite() {
                return Err(format!("literal {x} is not finite"));
            }
            let mut s = format!("{x:?}");
            if !s.contains(['.', 'e']) {
                s.push_str(".0");
            }
            if lang == Lang::Msl {
                s.push('f');
            }
            s
        }
        Literal::I32(i) => format!("{i}"),
        Literal::U32(u) => format!("{u}u"),
        Literal::Bool(b) => format!("{b}"),
        other => return Err(format!("literal {other:?} has no portable spelling")),
    })
}

/// The built-in for a math function, with how its arguments are passed.
#[derive(Debug)]
pub enum Math {
    /// `name(args…)` in the WGSL order.
    Call(&'static str),
    /// `saturate(x)` in GLSL: `clamp(x, 0.0, 1.0)`.
    ClampUnit,
}

/// The built-in that computes `fun` in `lang`.
pub fn math(lang: Lang, fun: MathFunction) -> Result<Math, String> {
    use MathFunction as M;
    let (g, h, m) = match fun {
        M::Abs => ("abs", "abs", "abs"),
        M::Min => ("min", "min", "min"),
        M::Max => ("max", "max", "max"),
        M::Clamp => ("clamp", "clamp", "clamp"),
        M::Saturate => return Ok(if lang.is_glsl() { Math::ClampUnit } else { Math::Call("saturate") }),
        M::Cos => ("cos", "cos", "cos"),
        M::Cosh => ("cosh", "cosh", "cosh"),
        M::Sin => ("sin", "sin", "sin"),
        M::Sinh => ("sinh", "sinh", "sinh"),
        M::Tan => ("tan", "tan", "tan"),
        M::Tanh => ("tanh", "tanh", "tanh"),
        M::Acos => ("acos", "acos", "acos"),
        M::Asin => ("asin", "asin", "asin"),
        M::Atan => ("atan", "atan", "atan"),
        M::Atan2 => ("atan", "atan2", "atan2"),
        M::Radians => ("radians", "radians", "radians"),
        M::Degrees => ("degrees", "degrees", "degrees"),
        M::Ceil => ("ceil", "ceil", "ceil"),
        M::Floor => ("floor", "floor", "floor"),
        // WGSL rounds halves to even.
        M::Round => ("roundEven", "round", "rint"),
        M::Fract => ("fract", "frac", "fract"),
        M::Trunc => ("trunc", "trunc", "trunc"),
        M::Ldexp => ("ldexp", "ldexp", "ldexp"),
        M::Exp => ("exp", "exp", "exp"),
        M::Exp2 => ("exp2", "exp2", "exp2"),
        M::Log => ("log", "log", "log"),
        M::Log2 => ("log2", "log2", "log2"),
        M::Pow => ("pow", "pow", "pow"),
        M::Dot => ("dot", "dot", "dot"),
        M::Cross => ("cross", "cross", "cross"),
        M::Distance => ("distance", "distance", "distance"),
        M::Length => ("length", "length", "length"),
        M::Normalize => ("normalize", "normalize", "normalize"),
        M::FaceForward => ("faceforward", "faceforward", "faceforward"),
        M::Reflect => ("reflect", "reflect", "reflect"),
        M::Refract => ("refract", "refract", "refract"),
        M::Sign => ("sign", "sign", "sign"),
        M::Fma => ("fma", "mad", "fma"),
        M::Mix => ("mix", "lerp", "mix"),
        M::Step => ("step", "step", "step"),
        M::SmoothStep => ("smoothstep", "smoothstep", "smoothstep"),
        M::Sqrt => ("sqrt", "sqrt", "sqrt"),
        M::InverseSqrt => ("inversesqrt", "rsqrt", "rsqrt"),
        M::Transpose => ("transpose", "transpose", "transpose"),
        M::Determinant => ("determinant", "determinant", "determinant"),
        M::CountOneBits => ("bitCount", "countbits", "popcount"),
        M::ReverseBits => ("bitfieldReverse", "reversebits", "reverse_bits"),
        other => return Err(format!("{other:?} is not in the exported subset (add it to emit::syntax::math)")),
    };
    Ok(Math::Call(match lang {
        Lang::Glsl(_) => g,
        Lang::Hlsl => h,
        Lang::Msl => m,
        Lang::Wgsl => return Err("WGSL is exported as written".into()),
    }))
}

/// Words no exported name may take in any of the languages (keywords, type names, and the
/// built-ins a name would hide). Module-scope names that collide are an error (the
/// documented names stay the same in every language); local names get a `_` appended.
pub const RESERVED: &[&str] = &[
    // C family and GLSL/HLSL/MSL keywords
    "asm",
    "auto",
    "break",
    "case",
    "char",
    "class",
    "const",
    "constant",
    "continue",
    "default",
    "delete",
    "do",
    "double",
    "else",
    "enum",
    "explicit",
    "extern",
    "false",
    "float",
    "for",
    "friend",
    "goto",
    "if",
    "inline",
    "int",
    "long",
    "namespace",
    "new",
    "operator",
    "private",
    "protected",
    "public",
    "register",
    "return",
    "short",
    "signed",
    "sizeof",
    "static",
    "struct",
    "switch",
    "template",
    "this",
    "true",
    "typedef",
    "typename",
    "union",
    "unsigned",
    "using",
    "virtual",
    "void",
    "volatile",
    "while",
    "bool",
    "uint",
    "half",
    "in",
    "out",
    "inout",
    "uniform",
    "buffer",
    "shared",
    "attribute",
    "varying",
    "layout",
    "centroid",
    "flat",
    "smooth",
    "noperspective",
    "patch",
    "sample",
    "precision",
    "lowp",
    "mediump",
    "highp",
    "invariant",
    "precise",
    "discard",
    "subroutine",
    "coherent",
    "readonly",
    "writeonly",
    "restrict",
    "resource",
    "input",
    "output",
    "matrix",
    "vector",
    "string",
    "packed",
    "row_major",
    "column_major",
    "cbuffer",
    "tbuffer",
    "groupshared",
    "nointerpolation",
    "linear",
    "export",
    "technique",
    "pass",
    "compile",
    "snorm",
    "unorm",
    "line",
    "point",
    "triangle",
    "lineadj",
    "triangleadj",
    "thread",
    "device",
    "threadgroup",
    "kernel",
    "vertex",
    "fragment",
    "main",
    "texture",
    "sampler",
    "array",
    "metal",
    "static_cast",
    "reinterpret_cast",
    "const_cast",
    "dynamic_cast",
    "mutable",
    "noexcept",
    "nullptr",
    "alignas",
    "alignof",
    "decltype",
    "constexpr",
    "and",
    "or",
    "not",
    "xor",
    "common",
    "active",
    "filter",
    "superp",
    "fixed",
    "sizeof",
    "cast",
    "interface",
    "partition",
    "goto",
    // built-ins a local of that name would hide
    "select",
    "mix",
    "lerp",
    "frac",
    "fract",
    "saturate",
    "fma",
    "mad",
    "rsqrt",
    "inversesqrt",
    "atan2",
    "dot",
    "cross",
    "normalize",
    "length",
    "distance",
    "reflect",
    "refract",
    "abs",
    "min",
    "max",
    "clamp",
    "sign",
    "floor",
    "ceil",
    "round",
    "trunc",
    "exp",
    "exp2",
    "log",
    "log2",
    "pow",
    "sqrt",
    "sin",
    "cos",
    "tan",
    "asin",
    "acos",
    "atan",
    "sinh",
    "cosh",
    "tanh",
    "step",
    "smoothstep",
    "any",
    "all",
    "isnan",
    "isinf",
    "transpose",
    "determinant",
    "mul",
    "equal",
    "notEqual",
    "lessThan",
    "greaterThan",
    "modf",
    "fmod",
    "mod",
];

/// Whether `name` is a type name in some language (vecN, floatN, matN, …).
pub fn is_type_like(name: &str) -> bool {
    let stems = ["vec", "ivec", "uvec", "bvec", "dvec", "mat", "dmat", "float", "int", "uint", "bool", "half", "double"];
    stems.iter().any(|s| name.strip_prefix(s).is_some_and(|rest| !rest.is_empty() && rest.chars().all(|c| c.is_ascii_digit() || c == 'x')))
}

/// Whether `name` may not be used as is.
pub fn reserved(name: &str) -> bool {
    RESERVED.contains(&name) || is_type_like(name) || name.starts_with("gl_") || name.starts_with("__")
}

/// Whether a type is a composite that HLSL can only build in a declaration (`= { … }`).
pub fn hlsl_aggregate(inner: &TypeInner) -> bool {
    matches!(inner, TypeInner::Array { .. } | TypeInner::Struct { .. })
}
