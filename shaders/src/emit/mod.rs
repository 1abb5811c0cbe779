//! The structured emitter: the composed WGSL library, parsed, typed and validated by
//! naga's front end, written as a readable include file in HLSL, GLSL or MSL.
//!
//! One source (`wgsl/*.wgsl`, composed per configuration), one emitter of our own over
//! naga's IR, four languages. It keeps what a reader needs and a back end throws away:
//! every function, struct, member, parameter, `let` and `var` keeps its WGSL name (a local
//! that is a keyword somewhere gets a `_`), constants stay named, loops are written as
//! `for`/`while` loops, sub-expressions are written inline (not one temporary per
//! operation), each item keeps the comment above it, and there is no entry point. The
//! reasons for this choice over Slang and over naga's back ends are in ARCHITECTURE.md.
//!
//! - [`syntax`]: per-language tokens (types, literals, built-ins, reserved words).
//! - `function`: function bodies (statements, expressions, where locals are declared).
//! - `source`: what the WGSL text says beyond naga (comments, formulas, order, notes).
//! - this file: the item order, declarations, constants and the file header.

mod function;
pub mod names;
mod source;
pub mod syntax;

use source::{const_formulas, item_comments, item_offsets, module_notes};

use crate::lang::{Glsl, Lang};
use naga::valid::ModuleInfo;
use naga::{Handle, Type, TypeInner};
use std::cell::RefCell;
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// What to write besides the items.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// First line(s) of the header, e.g. the configuration and its features.
    pub title: String,
    /// The include guard's macro (default: from the title).
    pub guard: Option<String>,
    /// The public functions (listed in the header with their signatures).
    pub roots: Vec<String>,
    /// Items not to write (they come from an included file): names of functions,
    /// constants and structs.
    pub skip: BTreeSet<String>,
    /// Write no header, guard or prelude (the rest of a file that includes a library).
    pub bare: bool,
    /// The text of a library this output is included after: typedefs and helpers it
    /// already defines are not written again.
    pub included: Option<String>,
}

/// The names of a WGSL module's functions, constants and structs (the items a file that
/// includes its export must not define again: [`Options::skip`]).
pub fn item_names(source: &str) -> Result<BTreeSet<String>, String> {
    let (m, _) = crate::lang::validate(source)?;
    let mut s: BTreeSet<String> = m.functions.iter().filter_map(|(_, f)| f.name.clone()).collect();
    s.extend(m.constants.iter().filter_map(|(_, c)| c.name.clone()));
    s.extend(m.types.iter().filter_map(|(_, t)| t.name.clone()));
    Ok(s)
}

/// The shared state of one emission.
pub(crate) struct Ctx<'a> {
    pub m: &'a naga::Module,
    pub info: &'a ModuleInfo,
    pub lang: Lang,
    /// HLSL: `typedef`s of array types (name → line), written before the items.
    pub typedefs: RefCell<BTreeMap<String, String>>,
    /// HLSL: helpers used — texture queries (GetDimensions is a statement there) and the
    /// component-wise select (see `function::hlsl_helper`).
    pub helpers: RefCell<BTreeSet<String>>,
}

impl<'a> Ctx<'a> {
    fn inner(&self, ty: Handle<Type>) -> &'a TypeInner {
        &self.m.types[ty].inner
    }

    /// The element type and dimensions (outermost first) of a possibly nested array.
    fn array_dims(&self, inner: &'a TypeInner) -> Result<(&'a TypeInner, Vec<u32>), String> {
        let (mut t, mut dims) = (inner, Vec::new());
        while let TypeInner::Array { base, size, .. } = t {
            match size {
                naga::ArraySize::Constant(n) => dims.push(n.get()),
                _ => return Err("runtime-sized arrays are only allowed in the harness bindings".into()),
            }
            t = self.inner(*base);
        }
        Ok((t, dims))
    }

    /// The name of a non-array type.
    fn base_name(&self, inner: &TypeInner, handle: Option<Handle<Type>>) -> Result<String, String> {
        Ok(match *inner {
            TypeInner::Scalar(s) => syntax::scalar(self.lang, s)?.to_string(),
            TypeInner::Vector { size, scalar } => syntax::vector(self.lang, size, scalar)?,
            TypeInner::Matrix { columns, rows, scalar } => {
                if scalar.kind != naga::ScalarKind::Float || scalar.width != 4 {
                    return Err("only f32 matrices are exported".into());
                }
                syntax::matrix(self.lang, columns, rows)
            }
            TypeInner::Struct { .. } => {
                let h = handle.ok_or("a struct type without a handle")?;
                names::exported(names::ItemKind::Struct, self.m.types[h].name.as_deref().ok_or("an unnamed struct")?)
            }
            TypeInner::Image { dim, arrayed, class } => syntax::image(self.lang, dim, arrayed, class)?.to_string(),
            TypeInner::Sampler { comparison } => syntax::sampler(self.lang, comparison)?.to_string(),
            TypeInner::Pointer { base, .. } => self.type_name(base)?,
            ref other => return Err(format!("type {other:?} is not in the exported subset")),
        })
    }

    /// A type as it is written where a declarator cannot carry it (return types,
    /// constructors, casts): GLSL `float[9]`, HLSL a typedef `float_array9`, MSL
    /// `array<float, 9>`.
    pub fn type_name(&self, ty: Handle<Type>) -> Result<String, String> {
        self.inner_name(self.inner(ty), Some(ty))
    }

    /// [`Ctx::type_name`] of a type that may have no handle (a typifier's value).
    pub fn inner_name(&self, inner: &TypeInner, handle: Option<Handle<Type>>) -> Result<String, String> {
        if let TypeInner::Array { base, .. } = *inner {
            let (elem, dims) = self.array_dims(inner)?;
            let elem_h = self.innermost(base);
            let b = self.base_name(elem, elem_h)?;
            return Ok(match self.lang {
                Lang::Glsl(_) => format!("{b}{}", dims.iter().map(|n| format!("[{n}]")).collect::<String>()),
                Lang::Msl => dims.iter().rev().fold(b, |acc, n| format!("array<{acc}, {n}>")),
                Lang::Hlsl => {
                    let stem = if b.starts_with("Sbf") { b.clone() } else { format!("sbf_{b}") };
                    let name = format!("{stem}{}", dims.iter().map(|n| format!("_array{n}")).collect::<String>());
                    let line = format!("typedef {b} {name}{};", dims.iter().map(|n| format!("[{n}]")).collect::<String>());
                    self.typedefs.borrow_mut().insert(name.clone(), line);
                    name
                }
                Lang::Wgsl => unreachable!("WGSL is exported as written"),
            });
        }
        self.base_name(inner, handle)
    }

    /// The handle of the innermost element type of an array.
    fn innermost(&self, mut ty: Handle<Type>) -> Option<Handle<Type>> {
        while let TypeInner::Array { base, .. } = self.m.types[ty].inner {
            ty = base;
        }
        Some(ty)
    }

    /// `T name` with the array dimensions on the declarator (GLSL, HLSL) or in the type
    /// (MSL).
    pub fn decl(&self, inner: &TypeInner, handle: Option<Handle<Type>>, name: &str) -> Result<String, String> {
        if let (TypeInner::Array { base, .. }, Lang::Glsl(_) | Lang::Hlsl) = (inner, self.lang) {
            let (elem, dims) = self.array_dims(inner)?;
            let b = self.base_name(elem, self.innermost(*base))?;
            return Ok(format!("{b} {name}{}", dims.iter().map(|n| format!("[{n}]")).collect::<String>()));
        }
        Ok(format!("{} {name}", self.inner_name(inner, handle)?))
    }

    /// A zero of `ty`: GLSL constructors, HLSL `(T)0` (a declaration-only form for
    /// aggregates), MSL value-initialisation `T{}`.
    pub fn zero(&self, ty: Handle<Type>) -> Result<String, String> {
        let inner = self.inner(ty);
        Ok(match self.lang {
            Lang::Msl => match inner {
                TypeInner::Scalar(s) => syntax::literal(self.lang, zero_literal(*s)?)?,
                _ => format!("{}{{}}", self.type_name(ty)?),
            },
            // Scalars, vectors and matrices cast 0; an array or struct is a list of zeros
            // (nested as the type is), which only a declaration takes.
            Lang::Hlsl => match inner {
                TypeInner::Scalar(s) => syntax::literal(self.lang, zero_literal(*s)?)?,
                TypeInner::Array { base, size: naga::ArraySize::Constant(n), .. } => {
                    format!("{{ {} }}", vec![self.zero(*base)?; n.get() as usize].join(", "))
                }
                TypeInner::Struct { ref members, .. } => {
                    let zs: Vec<String> = members.iter().map(|m| self.zero(m.ty)).collect::<Result<_, _>>()?;
                    format!("{{ {} }}", zs.join(", "))
                }
                _ => format!("(({})0)", self.type_name(ty)?),
            },
            Lang::Glsl(_) => match *inner {
                TypeInner::Scalar(s) => syntax::literal(self.lang, zero_literal(s)?)?,
                TypeInner::Vector { scalar, .. } => {
                    format!("{}({})", self.type_name(ty)?, syntax::literal(self.lang, zero_literal(scalar)?)?)
                }
                TypeInner::Matrix { .. } => format!("{}(0.0)", self.type_name(ty)?),
                TypeInner::Array { base, size: naga::ArraySize::Constant(n), .. } => {
                    let z = self.zero(base)?;
                    format!("{}({})", self.type_name(ty)?, vec![z; n.get() as usize].join(", "))
                }
                TypeInner::Struct { ref members, .. } => {
                    let zs: Vec<String> = members.iter().map(|m| self.zero(m.ty)).collect::<Result<_, _>>()?;
                    format!("{}({})", self.type_name(ty)?, zs.join(", "))
                }
                ref other => return Err(format!("no zero value for {other:?}")),
            },
            Lang::Wgsl => unreachable!("WGSL is exported as written"),
        })
    }

    /// A constant's value (the validated module's evaluated global expression).
    fn global_expr(&self, h: Handle<naga::Expression>, ty: Option<Handle<Type>>) -> Result<String, String> {
        use naga::Expression as E;
        Ok(match self.m.global_expressions[h] {
            E::Literal(l) => syntax::literal(self.lang, l)?,
            E::Constant(c) => names::exported(names::ItemKind::Constant, self.m.constants[c].name.as_deref().ok_or("an unnamed constant")?),
            E::ZeroValue(t) => self.zero(t)?,
            E::Splat { value, .. } => {
                let ty = ty.ok_or("a splat without a type")?;
                let v = self.global_expr(value, None)?;
                match self.lang {
                    Lang::Hlsl => format!("(({}){v})", self.type_name(ty)?),
                    _ => format!("{}({v})", self.type_name(ty)?),
                }
            }
            E::Compose { ty, ref components } => {
                let sub = |c: &Handle<naga::Expression>| -> Result<Option<Handle<Type>>, String> {
                    Ok(match *self.inner(ty) {
                        TypeInner::Array { base, .. } => Some(base),
                        TypeInner::Struct { ref members, .. } => {
                            let k = components.iter().position(|x| x == c).unwrap_or(0);
                            members.get(k).map(|m| m.ty)
                        }
                        _ => None,
                    })
                };
                let parts: Vec<String> = components.iter().map(|c| self.global_expr(*c, sub(c)?)).collect::<Result<_, _>>()?;
                let aggregate = matches!(self.inner(ty), TypeInner::Array { .. } | TypeInner::Struct { .. });
                match (self.lang, aggregate) {
                    (Lang::Hlsl, true) => format!("{{ {} }}", parts.join(", ")),
                    (Lang::Msl, true) => format!("{}{{{}}}", self.type_name(ty)?, parts.join(", ")),
                    _ => format!("{}({})", self.type_name(ty)?, parts.join(", ")),
                }
            }
            ref other => return Err(format!("constant expression {other:?} is not in the exported subset")),
        })
    }
}

fn zero_literal(s: naga::Scalar) -> Result<naga::Literal, String> {
    Ok(match s.kind {
        naga::ScalarKind::Float => naga::Literal::F32(0.0),
        naga::ScalarKind::Sint => naga::Literal::I32(0),
        naga::ScalarKind::Uint => naga::Literal::U32(0),
        naga::ScalarKind::Bool => naga::Literal::Bool(false),
        _ => return Err("abstract scalar".into()),
    })
}

/// A top-level item of the module, in emission order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Item {
    Struct(Handle<Type>),
    Constant(Handle<naga::Constant>),
    Function(Handle<naga::Function>),
}

impl Ctx<'_> {
    /// The name an item is written under ([`names::exported`]).
    fn exported_name(&self, it: Item) -> String {
        let kind = match it {
            Item::Struct(_) => names::ItemKind::Struct,
            Item::Constant(_) => names::ItemKind::Constant,
            Item::Function(_) => names::ItemKind::Function,
        };
        names::exported(kind, &self.item_name(it))
    }

    fn item_name(&self, it: Item) -> String {
        match it {
            Item::Struct(t) => self.m.types[t].name.clone().unwrap_or_default(),
            Item::Constant(c) => self.m.constants[c].name.clone().unwrap_or_default(),
            Item::Function(f) => self.m.functions[f].name.clone().unwrap_or_default(),
        }
    }

    /// The structs a type contains (itself included).
    fn structs_in(&self, ty: Handle<Type>, out: &mut BTreeSet<Item>) {
        match self.m.types[ty].inner {
            TypeInner::Struct { ref members, .. } => {
                out.insert(Item::Struct(ty));
                for m in members {
                    self.structs_in(m.ty, out);
                }
            }
            TypeInner::Array { base, .. } | TypeInner::Pointer { base, .. } => self.structs_in(base, out),
            _ => {}
        }
    }

    /// The items an item needs declared before it.
    fn deps(&self, it: Item) -> BTreeSet<Item> {
        let mut out = BTreeSet::new();
        match it {
            Item::Struct(t) => {
                if let TypeInner::Struct { ref members, .. } = self.m.types[t].inner {
                    for m in members {
                        self.structs_in(m.ty, &mut out);
                    }
                }
            }
            Item::Constant(c) => self.structs_in(self.m.constants[c].ty, &mut out),
            Item::Function(fh) => {
                let f = &self.m.functions[fh];
                for a in &f.arguments {
                    self.structs_in(a.ty, &mut out);
                }
                if let Some(r) = &f.result {
                    self.structs_in(r.ty, &mut out);
                }
                for (_, v) in f.local_variables.iter() {
                    self.structs_in(v.ty, &mut out);
                }
                let fi = &self.info[fh];
                for (h, e) in f.expressions.iter() {
                    match *e {
                        naga::Expression::Constant(c) => {
                            out.insert(Item::Constant(c));
                        }
                        naga::Expression::CallResult(g) => {
                            out.insert(Item::Function(g));
                        }
                        _ => {}
                    }
                    if let naga::proc::TypeResolution::Handle(t) = fi[h].ty {
                        self.structs_in(t, &mut out);
                    }
                }
                function::calls(&f.body, &mut out);
            }
        }
        out.remove(&it);
        out
    }
}

/// Writes the library in `lang`. `source` is the composed WGSL (already validated into
/// `module`/`info`); its comments are carried over.
pub fn library(source: &str, module: &naga::Module, info: &ModuleInfo, lang: Lang, opts: &Options) -> Result<String, String> {
    if lang == Lang::Wgsl {
        return Err("WGSL is exported as written".into());
    }
    let ctx = Ctx { m: module, info, lang, typedefs: RefCell::default(), helpers: RefCell::default() };
    let comments = item_comments(source);
    let formulas = const_formulas(source);
    let offsets = item_offsets(source);

    // Items, ordered as in the source where their dependencies allow (C-family languages
    // declare before use; WGSL does not need to).
    let mut items: Vec<Item> = Vec::new();
    for (h, t) in module.types.iter() {
        if matches!(t.inner, TypeInner::Struct { .. }) {
            items.push(Item::Struct(h));
        }
    }
    items.extend(module.constants.iter().map(|(h, _)| Item::Constant(h)));
    items.extend(module.functions.iter().map(|(h, _)| Item::Function(h)));
    items.retain(|it| !opts.skip.contains(&ctx.item_name(*it)));
    let key = |it: &Item| offsets.get(&ctx.item_name(*it)).copied().unwrap_or(usize::MAX);
    items.sort_by_key(|it| (key(it), *it));
    let deps: HashMap<Item, BTreeSet<Item>> =
        items.iter().map(|it| (*it, ctx.deps(*it).into_iter().filter(|d| items.contains(d)).collect())).collect();
    let mut order = Vec::new();
    let mut done = BTreeSet::new();
    while order.len() < items.len() {
        let next = items.iter().find(|it| !done.contains(*it) && deps[*it].iter().all(|d| done.contains(d)));
        let Some(&next) = next else {
            return Err("the module's items depend on each other in a cycle".into());
        };
        done.insert(next);
        order.push(next);
    }

    // Module-scope names stay as documented; one that a language reserves is an error.
    for it in &order {
        let n = ctx.item_name(*it);
        if syntax::reserved(&n) {
            return Err(format!("'{n}' is reserved in one of the exported languages: rename it in the WGSL source"));
        }
    }

    let mut body = String::new();
    for it in &order {
        let name = ctx.item_name(*it);
        let exported = ctx.exported_name(*it);
        let mut text = String::new();
        if let Some(c) = comments.get(&name) {
            for l in c {
                text.push_str(l);
                text.push('\n');
            }
        }
        match *it {
            Item::Struct(t) => text.push_str(&write_struct(&ctx, t)?),
            Item::Constant(c) => {
                let k = &module.constants[c];
                let value = ctx.global_expr(k.init, Some(k.ty))?;
                let d = ctx.decl(ctx.inner(k.ty), Some(k.ty), &exported)?;
                let formula = formulas.get(&name).map(|f| format!(" // {f}")).unwrap_or_default();
                text.push_str(&match lang {
                    Lang::Glsl(_) => format!("const {d} = {value};{formula}\n"),
                    Lang::Hlsl => format!("static const {d} = {value};{formula}\n"),
                    Lang::Msl => format!("constant {d} = {value};{formula}\n"),
                    Lang::Wgsl => unreachable!(),
                });
            }
            Item::Function(f) => text.push_str(&function::write(&ctx, f).map_err(|e| format!("{name}: {e}"))?),
        }
        // A library's items are guarded one by one (two configurations in one shader define
        // a shared item once); the rest of a file that includes a library is not.
        body.push_str(&if opts.bare { text } else { names::guarded(&exported, &text) });
        body.push('\n');
    }

    let mut out = String::new();
    let guard = opts.guard.clone().unwrap_or_else(|| {
        let word: String = opts.title.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_uppercase() } else { '_' }).collect();
        let mut g = String::new();
        for c in word.trim_matches('_').chars() {
            if !(c == '_' && g.ends_with('_')) {
                g.push(c);
            }
        }
        format!("SBF_{g}_INCLUDED")
    });
    if !opts.bare {
        out.push_str(&header(&ctx, opts, &order)?);
        out.push_str(&module_notes(source));
        out.push_str(&format!("#ifndef {guard}\n#define {guard}\n\n"));
        match lang {
            Lang::Glsl(Glsl::Vulkan) => out.push_str("#extension GL_EXT_samplerless_texture_functions : require\n\n"),
            Lang::Msl => out.push_str("#include <metal_stdlib>\nusing namespace metal;\n\n"),
            _ => {}
        }
    }
    let typedefs = ctx.typedefs.borrow();
    let defined = |text: &str| opts.included.as_ref().is_some_and(|inc| inc.contains(text));
    let typedefs: Vec<&String> = typedefs.values().filter(|l| !defined(l)).collect();
    for line in &typedefs {
        let name = line.trim_end_matches(';').rsplit(' ').next().unwrap_or_default().split('[').next().unwrap_or_default();
        out.push_str(&if opts.bare { format!("{line}\n") } else { names::guarded(name, &format!("{line}\n")) });
    }
    if !typedefs.is_empty() {
        out.push('\n');
    }
    for h in ctx.helpers.borrow().iter() {
        let text = function::hlsl_helper(h);
        if !defined(&text) {
            out.push_str(&if opts.bare { text } else { names::guarded(&format!("{h}_helper"), &text) });
            out.push('\n');
        }
    }
    out.push_str(&body);
    if !opts.bare {
        out.push_str(&format!("#endif // {guard}\n"));
    }
    Ok(out)
}

fn write_struct(ctx: &Ctx, t: Handle<Type>) -> Result<String, String> {
    let name = names::exported(names::ItemKind::Struct, ctx.m.types[t].name.as_deref().ok_or("an unnamed struct")?);
    let TypeInner::Struct { ref members, .. } = ctx.m.types[t].inner else { unreachable!() };
    let mut s = format!("struct {name} {{\n");
    for m in members {
        let mn = m.name.clone().ok_or("an unnamed struct member")?;
        if syntax::reserved(&mn) {
            return Err(format!("struct {name}: member '{mn}' is reserved in one of the exported languages"));
        }
        s.push_str(&format!("    {};\n", ctx.decl(ctx.inner(m.ty), Some(m.ty), &mn)?));
    }
    s.push_str("};\n");
    Ok(s)
}

/// The file header: what this is, how to include it, its functions and textures.
fn header(ctx: &Ctx, opts: &Options, order: &[Item]) -> Result<String, String> {
    let lang = ctx.lang;
    let mut h = String::new();
    let (langname, include) = match lang {
        Lang::Glsl(Glsl::Vulkan) => ("GLSL 4.50 for Vulkan (SPIR-V through glslang or shaderc)", "after `#version 450`, `#include \"this file\"` (GL_GOOGLE_include_directive) or\n// paste it in. It enables GL_EXT_samplerless_texture_functions (texelFetch on texture2D), which\n// OpenGL lacks: OpenGL engines include the `.gl.glsl` or `.es.glsl` file instead"),
        Lang::Glsl(Glsl::Gl) => ("GLSL 3.30–4.60 core for OpenGL (no extension; tested as 4.50 core)", "after `#version 330 core` or later (and the engine's own declarations), paste this file\n// in or include it with the engine's include mechanism. Textures are combined samplers\n// (`sampler2D`, `sampler2DArray`, `sampler3D`): a function that takes a texture and a sampler in\n// the other languages takes the combined sampler alone, its filter set on the texture object"),
        Lang::Glsl(Glsl::Es) => ("GLSL ES 3.00 for OpenGL ES 3.0 and WebGL 2 (no extension)", "after `#version 300 es` and `precision highp float;` (the functions need highp:\n// f32 coefficients and table coordinates), paste this file in. Textures are combined `highp`\n// samplers: a function that takes a texture and a sampler in the other languages takes the\n// combined sampler alone, its filter set on the texture object"),
        Lang::Hlsl => ("HLSL (Shader Model 5+; DXC, FXC or glslang)", "`#include \"this file\"` in any stage"),
        Lang::Msl => ("Metal Shading Language 2.0+", "`#include \"this file\"`; it includes <metal_stdlib> and opens `namespace metal`"),
        Lang::Wgsl => unreachable!(),
    };
    h.push_str(&format!("// sbf runtime library — {}\n", opts.title));
    h.push_str(&format!("// Language: {langname}.\n"));
    h.push_str(&format!(
        "// Generated by `shaders export` (sbf {}) from shaders/wgsl/*.wgsl and luts/ (one source for\n// WGSL, HLSL, GLSL and MSL); do not edit: change the WGSL and export again.\n",
        env!("CARGO_PKG_VERSION")
    ));
    h.push_str(&format!("// Use: {include}.\n"));
    h.push_str("// Conventions: right-handed, +Y up; tangent-space normal +Z; directions unit length;\n// irradiance is E/π; RGB coefficients are 3-vectors. No entry point, no bindings: textures\n// are parameters, bound however the engine likes.\n");
    h.push_str("// Names: every function is sbf_*, every struct Sbf*, every constant SBF_* (the comments below\n// name items as the WGSL sources do, without the prefix). Each item is guarded by\n// #ifndef SBF_DEFINED_<name>: several exported configurations can be included in one shader, or\n// export the union of their features: `shaders export --config a,b --lang L`.\n");
    let mut sigs = Vec::new();
    let mut textures = Vec::new();
    for it in order {
        let Item::Function(fh) = *it else { continue };
        let f = &ctx.m.functions[fh];
        let name = f.name.clone().unwrap_or_default();
        if !opts.roots.contains(&name) {
            continue;
        }
        sigs.push(format!("//   {}", function::signature(ctx, fh)?));
        for a in &f.arguments {
            if let TypeInner::Image { arrayed, dim, .. } = ctx.m.types[a.ty].inner {
                let an = a.name.clone().unwrap_or_default();
                let wgsl_name = name.clone();
                let name = names::exported(names::ItemKind::Function, &name);
                textures.push(if dim == naga::ImageDimension::D3 {
                    format!(
                        "//   {name}({an}): 3D, rg16float, sampled at mip 0 through {}\n//     (linear min/mag filter, clamp to edge). {}",
                        if lang.combined_samplers() { "its combined sampler" } else { "the sampler parameter" },
                        texture_note(&wgsl_name, &an)
                    )
                } else {
                    format!(
                        "//   {name}({an}): {}, rg32float, read with texelFetch/Load/read at mip 0 (no filtering;\n//     bilinear by hand). {}",
                        if arrayed { "2D array" } else { "2D" },
                        texture_note(&wgsl_name, &an)
                    )
                });
            }
        }
    }
    if !sigs.is_empty() {
        h.push_str(if lang.combined_samplers() {
            "// Functions (the same names and parameters in every language, less the sampler parameters;\n// each is documented below):\n"
        } else {
            "// Functions (the same names and parameters in every language; each is documented below):\n"
        });
        for s in sigs {
            h.push_str(&s);
            h.push('\n');
        }
    }
    if !textures.is_empty() {
        h.push_str("// Textures these functions read:\n");
        for t in textures {
            h.push_str(&t);
            h.push('\n');
        }
    }
    h.push('\n');
    Ok(h)
}

/// Which table a root function's texture parameter holds.
fn texture_note(function: &str, parameter: &str) -> &'static str {
    if parameter == "dfg" {
        return "The split-sum table luts/dfg.sbflut: u = n·v, v = GGX α (roughness², not the\n//     perceptual roughness Filament's DFG is indexed by); channels (f0 scale, f90 scale).";
    }
    match function {
        "ad9_specular" | "ad12_specular" => {
            "The AD specular table luts/ad_specular_2d.sbflut (Listing 8.2; u = n·v, v = α; see ad_specular_scale)."
        }
        "lobe_ggx_pixel" | "lobe_ggx_lobe" => {
            "The per-lobe GGX table luts/lobe_ggx_sg6.sbflut or lobe_ggx_ad.sbflut (x = ψ, y = γ,\n//     layer = n·v node × 12 + √α node)."
        }
        "lobe_ggx_filtered_pixel" | "lobe_ggx_filtered_lobe" => {
            "The per-lobe GGX table luts/lobe_ggx_sg6.sbflut or lobe_ggx_ad.sbflut as f16 (x = √α node\n//     × 24 + ψ node, y = γ node, z = n·v node)."
        }
        _ => "See the function's comment.",
    }
}
