//! Expressions written inline with the fewest parentheses C's precedence needs.

use super::*;

impl<'c, 'a> W<'c, 'a> {
    pub(super) fn top(&mut self, h: Handle<E>) -> R<String> {
        Ok(self.expr(h)?.0)
    }

    /// `h` written where an operand of precedence `min` is expected.
    pub(super) fn sub(&mut self, h: Handle<E>, min: u8) -> R<String> {
        let (t, p) = self.expr(h)?;
        Ok(if p < min { format!("({t})") } else { t })
    }

    pub(super) fn expr(&mut self, h: Handle<E>) -> R<(String, u8)> {
        if let Some(n) = self.names.get(&h) {
            return Ok((n.clone(), ATOM));
        }
        if let Some(i) = self.deferred.iter().position(|(k, _)| *k == h) {
            return Ok((self.deferred.remove(i).1, ATOM));
        }
        self.expr_value(h)
    }

    /// An aggregate HLSL can only build in a declaration: a temporary before the line.
    pub(super) fn hlsl_temporary(&mut self, h: Handle<E>, init: String) -> R<(String, u8)> {
        let n = self.unique("tmp");
        let d = self.decl_of(h, &n)?;
        self.pre.push(format!("{d} = {init};"));
        self.names.insert(h, n.clone());
        Ok((n, ATOM))
    }

    pub(super) fn expr_value(&mut self, h: Handle<E>) -> R<(String, u8)> {
        let c = self.c;
        let lang = c.lang;
        Ok(match self.f.expressions[h] {
            E::Literal(l) => {
                let t = syntax::literal(lang, l)?;
                let p = if t.starts_with('-') { UNARY } else { ATOM };
                (t, p)
            }
            E::Constant(k) => (
                crate::emit::names::exported(
                    crate::emit::names::ItemKind::Constant,
                    c.m.constants[k].name.as_deref().ok_or("an unnamed constant")?,
                ),
                ATOM,
            ),
            E::ZeroValue(ty) => {
                if lang == Lang::Hlsl && syntax::hlsl_aggregate(&c.m.types[ty].inner) {
                    let z = c.zero(ty)?;
                    return self.hlsl_temporary(h, z);
                }
                (c.zero(ty)?, ATOM)
            }
            E::Compose { ty, ref components } => {
                let parts: Vec<String> = components.iter().map(|x| self.top(*x)).collect::<R<_>>()?;
                let aggregate = syntax::hlsl_aggregate(&c.m.types[ty].inner);
                match (lang, aggregate) {
                    (Lang::Hlsl, true) => return self.hlsl_temporary(h, format!("{{ {} }}", parts.join(", "))),
                    (Lang::Msl, true) => (format!("{}{{{}}}", c.type_name(ty)?, parts.join(", ")), ATOM),
                    _ => (format!("{}({})", c.type_name(ty)?, parts.join(", ")), ATOM),
                }
            }
            E::Access { base, index } => {
                let b = self.sub(base, ATOM)?;
                let i = self.top(index)?;
                (format!("{b}[{i}]"), ATOM)
            }
            E::AccessIndex { base, index } => {
                let b = self.sub(base, ATOM)?;
                match self.value_ty(base) {
                    TypeInner::Struct { ref members, .. } => {
                        (format!("{b}.{}", members[index as usize].name.clone().ok_or("an unnamed member")?), ATOM)
                    }
                    TypeInner::Vector { .. } => (format!("{b}.{}", ["x", "y", "z", "w"][index as usize]), ATOM),
                    _ => (format!("{b}[{index}]"), ATOM),
                }
            }
            E::Splat { value, .. } => {
                let ty = c.inner_name(self.ty(h), None)?;
                match lang {
                    Lang::Hlsl => (format!("(({ty}){})", self.sub(value, UNARY)?), ATOM),
                    _ => (format!("{ty}({})", self.top(value)?), ATOM),
                }
            }
            E::Swizzle { size, vector, pattern } => self.swizzle(size, vector, pattern)?,
            E::FunctionArgument(i) => (self.args[i as usize].clone(), ATOM),
            E::GlobalVariable(g) => (c.m.global_variables[g].name.clone().ok_or("an unnamed global")?, ATOM),
            E::LocalVariable(v) => (self.locals.get(&v).cloned().ok_or("a local used before its declaration")?, ATOM),
            E::Load { pointer } => match self.f.expressions[pointer] {
                E::LocalVariable(v) if self.sugar.contains_key(&v) => self.sugar[&v].clone(),
                _ => self.expr(pointer)?,
            },
            E::ImageLoad { image, coordinate, array_index, sample: None, level } => {
                self.image_load(image, coordinate, array_index, level)?
            }

            // Filtered sampling at an explicit mip level (the subset the library uses:
            // no gather, offset, array layer or depth comparison).
            E::ImageSample {
                image,
                sampler,
                gather: None,
                coordinate,
                array_index: None,
                offset: None,
                level,
                depth_ref: None,
                clamp_to_edge: false,
            } => self.image_sample(image, sampler, coordinate, level)?,
            E::ImageQuery { image, query } => self.image_query(image, query)?,

            E::Unary { op, expr } => self.unary(op, expr)?,
            E::Binary { op, left, right } => self.binary(op, left, right)?,
            E::Select { condition, accept, reject } => self.select(condition, accept, reject)?,

            E::Relational { fun, argument } => {
                let name = match fun {
                    naga::RelationalFunction::All => "all",
                    naga::RelationalFunction::Any => "any",
                    naga::RelationalFunction::IsNan => "isnan",
                    naga::RelationalFunction::IsInf => "isinf",
                };
                (format!("{name}({})", self.top(argument)?), ATOM)
            }
            E::Math { fun, arg, arg1, arg2, arg3 } => {
                let mut args = vec![self.top(arg)?];
                for a in [arg1, arg2, arg3].into_iter().flatten() {
                    args.push(self.top(a)?);
                }
                match syntax::math(lang, fun)? {
                    Math::Call(name) => (format!("{name}({})", args.join(", ")), ATOM),
                    Math::ClampUnit => (format!("clamp({}, 0.0, 1.0)", args[0]), ATOM),
                }
            }
            E::As { expr, kind, convert } => self.cast(h, expr, kind, convert)?,

            E::CallResult(_) => return Err("a call result used before its call".into()),
            ref other => return Err(format!("expression {other:?} is not in the exported subset")),
        })
    }

    /// A swizzle (`v.xy`).
    fn swizzle(&mut self, size: naga::VectorSize, vector: Handle<E>, pattern: [naga::SwizzleComponent; 4]) -> R<(String, u8)> {
        let lang = self.c.lang;
        Ok({
            let mut v = self.sub(vector, ATOM)?;
            let s: String = pattern[..size as usize].iter().map(|k| ['x', 'y', 'z', 'w'][*k as usize]).collect();
            // An HLSL table read widened to WGSL's (r, g, 0, 1) and swizzled within r, g
            // reads the float2 itself.
            if lang == Lang::Hlsl
                && !s.contains(['z', 'w'])
                && matches!(self.f.expressions[vector], E::ImageLoad { .. } | E::ImageSample { .. })
            {
                if let Some(inner) = v.strip_prefix("float4(").and_then(|x| x.strip_suffix(", 0.0, 1.0)")) {
                    v = inner.to_string();
                }
            }
            (format!("{v}.{s}"), ATOM)
        })
    }

    /// A unary operator; GLSL negates a bool vector with `not()`.
    fn unary(&mut self, op: naga::UnaryOperator, expr: Handle<E>) -> R<(String, u8)> {
        let lang = self.c.lang;
        Ok({
            let bool_vector = matches!(self.ty(expr), TypeInner::Vector { scalar, .. } if scalar.kind == naga::ScalarKind::Bool);
            match op {
                naga::UnaryOperator::LogicalNot if lang.is_glsl() && bool_vector => (format!("not({})", self.top(expr)?), ATOM),
                _ => {
                    let sym = match op {
                        naga::UnaryOperator::Negate => "-",
                        naga::UnaryOperator::LogicalNot => "!",
                        naga::UnaryOperator::BitwiseNot => "~",
                    };
                    let mut x = self.sub(expr, UNARY)?;
                    if x.starts_with('-') {
                        x = format!("({x})");
                    }
                    (format!("{sym}{x}"), UNARY)
                }
            }
        })
    }

    /// `textureLoad`: a texel fetch of a two-channel table, in each language's form.
    fn image_load(
        &mut self,
        image: Handle<E>,
        coordinate: Handle<E>,
        array_index: Option<Handle<E>>,
        level: Option<Handle<E>>,
    ) -> R<(String, u8)> {
        let c = self.c;
        let lang = c.lang;
        Ok({
            let t = self.sub(image, ATOM)?;
            let xy = self.top(coordinate)?;
            let lod = match level {
                Some(l) => self.top(l)?,
                None => "0".into(),
            };
            let layer = array_index.map(|a| self.top(a)).transpose()?;
            let t = match (lang, layer) {
                (Lang::Glsl(_), None) => format!("texelFetch({t}, ivec2({xy}), int({lod}))"),
                (Lang::Glsl(_), Some(a)) => format!("texelFetch({t}, ivec3(ivec2({xy}), int({a})), int({lod}))"),
                // The tables are two-channel (Texture2D<float2>): WGSL reads (r, g, 0, 1).
                (Lang::Hlsl, None) => format!("float4({t}.Load(int3(int2({xy}), int({lod}))), 0.0, 1.0)"),
                (Lang::Hlsl, Some(a)) => format!("float4({t}.Load(int4(int2({xy}), int({a}), int({lod}))), 0.0, 1.0)"),
                (Lang::Msl, None) => format!("{t}.read(uint2({xy}), uint({lod}))"),
                (Lang::Msl, Some(a)) => format!("{t}.read(uint2({xy}), uint({a}), uint({lod}))"),
                (Lang::Wgsl, _) => unreachable!(),
            };
            (t, ATOM)
        })
    }

    /// `textureSampleLevel`: filtered sampling at an explicit mip level.
    fn image_sample(&mut self, image: Handle<E>, sampler: Handle<E>, coordinate: Handle<E>, level: naga::SampleLevel) -> R<(String, u8)> {
        let lang = self.c.lang;
        Ok({
            let dim = match self.value_ty(image) {
                TypeInner::Image { dim, .. } => dim,
                _ => return Err("a sample from a non-texture".into()),
            };
            let lod = match level {
                naga::SampleLevel::Zero => "0.0".to_string(),
                naga::SampleLevel::Exact(l) => self.top(l)?,
                other => return Err(format!("texture sample at level {other:?}: only explicit levels are exported")),
            };
            let (t, xyz) = (self.sub(image, ATOM)?, self.top(coordinate)?);
            // A combined sampler is the texture itself; the sampler expression is not written.
            let smp = if lang.combined_samplers() { String::new() } else { self.top(sampler)? };
            let t = match lang {
                _ if lang.combined_samplers() => format!("textureLod({t}, {xyz}, {lod})"),
                Lang::Glsl(_) => {
                    let combined = match dim {
                        naga::ImageDimension::D2 => "sampler2D",
                        naga::ImageDimension::D3 => "sampler3D",
                        other => return Err(format!("texture sample of a {other:?} texture is not in the exported subset")),
                    };
                    format!("textureLod({combined}({t}, {smp}), {xyz}, {lod})")
                }
                Lang::Hlsl => format!("float4({t}.SampleLevel({smp}, {xyz}, {lod}), 0.0, 1.0)"),
                Lang::Msl => format!("{t}.sample({smp}, {xyz}, level({lod}))"),
                Lang::Wgsl => unreachable!(),
            };
            (t, ATOM)
        })
    }

    /// `textureDimensions` and `textureNumLayers`, through helpers where HLSL needs them.
    fn image_query(&mut self, image: Handle<E>, query: naga::ImageQuery) -> R<(String, u8)> {
        let c = self.c;
        let lang = c.lang;
        Ok({
            let arrayed = matches!(self.value_ty(image), TypeInner::Image { arrayed: true, .. });
            let volume = matches!(self.value_ty(image), TypeInner::Image { dim: naga::ImageDimension::D3, .. });
            let t = self.sub(image, ATOM)?;
            let s = match (query, lang) {
                (naga::ImageQuery::Size { level: None }, Lang::Glsl(_)) if volume => format!("uvec3(textureSize({t}, 0))"),
                (naga::ImageQuery::Size { level: None }, Lang::Hlsl) if volume => {
                    c.helpers.borrow_mut().insert("size_3d".into());
                    format!("sbf_texture_size({t})")
                }
                (naga::ImageQuery::Size { level: None }, Lang::Msl) if volume => {
                    format!("uint3({t}.get_width(), {t}.get_height(), {t}.get_depth())")
                }
                (naga::ImageQuery::Size { level: None }, Lang::Glsl(_)) => format!("uvec2(textureSize({t}, 0).xy)"),
                (naga::ImageQuery::Size { level: None }, Lang::Hlsl) => {
                    c.helpers.borrow_mut().insert(if arrayed { "size_array" } else { "size" }.into());
                    format!("sbf_texture_size({t})")
                }
                (naga::ImageQuery::Size { level: None }, Lang::Msl) => format!("uint2({t}.get_width(), {t}.get_height())"),
                (naga::ImageQuery::NumLayers, Lang::Glsl(_)) => format!("uint(textureSize({t}, 0).z)"),
                (naga::ImageQuery::NumLayers, Lang::Hlsl) => {
                    c.helpers.borrow_mut().insert("layers".into());
                    format!("sbf_texture_layers({t})")
                }
                (naga::ImageQuery::NumLayers, Lang::Msl) => format!("{t}.get_array_size()"),
                (q, _) => return Err(format!("texture query {q:?} is not in the exported subset")),
            };
            (s, ATOM)
        })
    }

    /// `select`: a vector condition as each language selects per component, a scalar one as `?:`.
    fn select(&mut self, condition: Handle<E>, accept: Handle<E>, reject: Handle<E>) -> R<(String, u8)> {
        let c = self.c;
        let lang = c.lang;
        Ok({
            let vector = matches!(self.ty(condition), TypeInner::Vector { .. });
            match (lang, vector) {
                (Lang::Glsl(_), true) => (format!("mix({}, {}, {})", self.top(reject)?, self.top(accept)?, self.top(condition)?), ATOM),
                (Lang::Msl, true) => (format!("select({}, {}, {})", self.top(reject)?, self.top(accept)?, self.top(condition)?), ATOM),
                (Lang::Hlsl, true) => {
                    let ty = c.inner_name(&self.value_ty(accept), None)?;
                    c.helpers.borrow_mut().insert(format!("select_{ty}"));
                    (format!("sbf_select({}, {}, {})", self.top(condition)?, self.top(accept)?, self.top(reject)?), ATOM)
                }
                _ => {
                    let cnd = self.sub(condition, LOR)?;
                    let a = self.sub(accept, LOR)?;
                    let r = self.sub(reject, LOR)?;
                    (format!("{cnd} ? {a} : {r}"), TERN)
                }
            }
        })
    }

    /// A conversion (`f32(x)`) or a bitcast (`bitcast<u32>(x)`).
    fn cast(&mut self, h: Handle<E>, expr: Handle<E>, kind: naga::ScalarKind, convert: Option<u8>) -> R<(String, u8)> {
        let c = self.c;
        let lang = c.lang;
        Ok({
            let target = c.inner_name(self.ty(h), None)?;
            let x = self.top(expr)?;
            match convert {
                Some(_) => (format!("{target}({x})"), ATOM),
                None => {
                    let from = match self.ty(expr) {
                        TypeInner::Scalar(s) | TypeInner::Vector { scalar: s, .. } => s.kind,
                        _ => return Err("bitcast of a non-numeric value".into()),
                    };
                    use naga::ScalarKind::{Float, Sint, Uint};
                    let f = match (lang, from, kind) {
                        (Lang::Msl, _, _) => format!("as_type<{target}>"),
                        (Lang::Glsl(_), Float, Uint) => "floatBitsToUint".into(),
                        (Lang::Glsl(_), Float, Sint) => "floatBitsToInt".into(),
                        (Lang::Glsl(_), Uint, Float) => "uintBitsToFloat".into(),
                        (Lang::Glsl(_), Sint, Float) => "intBitsToFloat".into(),
                        (Lang::Hlsl, _, Uint) => "asuint".into(),
                        (Lang::Hlsl, _, Sint) => "asint".into(),
                        (Lang::Hlsl, _, Float) => "asfloat".into(),
                        _ => target,
                    };
                    (format!("{f}({x})"), ATOM)
                }
            }
        })
    }

    pub(super) fn binary(&mut self, op: B, left: Handle<E>, right: Handle<E>) -> R<(String, u8)> {
        let lang = self.c.lang;
        let (lt, rt) = (self.value_ty(left), self.value_ty(right));
        let is_matrix = |t: &TypeInner| matches!(t, TypeInner::Matrix { .. });
        let is_vector = |t: &TypeInner| matches!(t, TypeInner::Vector { .. });
        let float =
            |t: &TypeInner| matches!(t, TypeInner::Scalar(s) | TypeInner::Vector { scalar: s, .. } if s.kind == naga::ScalarKind::Float);
        if lang == Lang::Hlsl
            && op == B::Multiply
            && (is_matrix(&lt) || is_matrix(&rt))
            && !matches!(lt, TypeInner::Scalar(_))
            && !matches!(rt, TypeInner::Scalar(_))
        {
            // See syntax's module note: HLSL holds Mᵀ.
            let (l, r) = (self.top(left)?, self.top(right)?);
            return Ok((format!("mul({r}, {l})"), ATOM));
        }
        if op == B::Modulo && float(&lt) {
            let (l, r) = (self.top(left)?, self.top(right)?);
            return Ok(match lang {
                // WGSL's float % truncates (like fmod); GLSL's mod floors.
                Lang::Glsl(_) => (format!("({l}) - ({r}) * trunc(({l}) / ({r}))"), ADD),
                _ => (format!("fmod({l}, {r})"), ATOM),
            });
        }
        if lang.is_glsl() && is_vector(&lt) {
            let f = match op {
                B::Less => Some("lessThan"),
                B::LessEqual => Some("lessThanEqual"),
                B::Greater => Some("greaterThan"),
                B::GreaterEqual => Some("greaterThanEqual"),
                B::Equal => Some("equal"),
                B::NotEqual => Some("notEqual"),
                B::LogicalAnd | B::LogicalOr => return Err("&& and || on boolean vectors have no GLSL spelling".into()),
                _ => None,
            };
            if let Some(f) = f {
                let (l, r) = (self.top(left)?, self.top(right)?);
                return Ok((format!("{f}({l}, {r})"), ATOM));
            }
        }
        let (sym, p) = match op {
            B::Add => ("+", ADD),
            B::Subtract => ("-", ADD),
            B::Multiply => ("*", MUL),
            B::Divide => ("/", MUL),
            B::Modulo => ("%", MUL),
            B::Equal => ("==", EQ),
            B::NotEqual => ("!=", EQ),
            B::Less => ("<", REL),
            B::LessEqual => ("<=", REL),
            B::Greater => (">", REL),
            B::GreaterEqual => (">=", REL),
            B::And => ("&", BAND),
            B::ExclusiveOr => ("^", BXOR),
            B::InclusiveOr => ("|", BOR),
            B::LogicalAnd => ("&&", LAND),
            B::LogicalOr => ("||", LOR),
            B::ShiftLeft => ("<<", SHIFT),
            B::ShiftRight => (">>", SHIFT),
        };
        // Operands keep WGSL's grouping exactly (a + (b + c) is not (a + b) + c in floating
        // point): a right operand of the same precedence is parenthesised. Bitwise and shift
        // operands that are themselves binary, and && inside || (or the reverse), are
        // parenthesised even where C's precedence would not need it (WGSL requires it and
        // compilers warn).
        let operand = |w: &mut Self, h: Handle<E>, right: bool| -> R<String> {
            let (t, q) = w.expr(h)?;
            let child_op = match w.f.expressions[h] {
                E::Binary { op: o, .. } if !w.names.contains_key(&h) => Some(o),
                _ => None,
            };
            let binary_child = (TERN..=MUL).contains(&q);
            let paren = q < p
                || (right && q == p)
                || (matches!(p, SHIFT | BAND | BXOR | BOR) && binary_child && (child_op != Some(op) || right))
                || (matches!(p, LAND | LOR) && matches!(q, LAND | LOR) && child_op != Some(op));
            Ok(if paren { format!("({t})") } else { t })
        };
        let l = operand(self, left, false)?;
        let r = operand(self, right, true)?;
        Ok((format!("{l} {sym} {r}"), p))
    }
}
