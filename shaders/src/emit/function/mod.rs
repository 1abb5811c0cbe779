//! Function bodies: naga's statements and expressions written back as structured source.
//!
//! - **Expressions** are written inline into the statement that uses them (naga emits
//!   every sub-expression just before the statement that consumes it), with the fewest
//!   parentheses C's precedence needs; `let` bindings (naga's named expressions) become
//!   declarations with their WGSL names. A call whose result is used once and that takes
//!   no pointer is written inside its user; other calls get a named result.
//! - **Locals** (`var`) are declared in the innermost block that holds every use, at the
//!   first use: merged with it when that use is a full store (`float x = …;`), else with
//!   the WGSL initial value (zero when there is none), outside any loop when the value
//!   must survive iterations (WGSL initialises such a `var` once).
//! - **Loops**: a naga loop that starts with `if (!cond) { break; }` and whose continuing
//!   block is a single store is a `for (init; cond; update)` (the loop variable declared in
//!   it when nothing after the loop reads it) or a `while (cond)`; any other loop is a
//!   `for (;;)` with its continuing block written at the end and before each `continue`.
//!
//! This file holds the analysis (uses, scopes, locals, loops) and the writer's state;
//! `statements` writes statements, `expressions` expressions.

mod expressions;
mod statements;

use super::syntax::{self, Math};
use super::{Ctx, Item};
use crate::lang::Lang;
use naga::{BinaryOperator as B, Block, Expression as E, Handle, LocalVariable, Statement as S, TypeInner};
use std::collections::{BTreeSet, HashMap, HashSet};

type R<T> = Result<T, String>;

/// Precedence levels (higher binds tighter), as in C.
const ATOM: u8 = 15;
const UNARY: u8 = 14;
const MUL: u8 = 13;
const ADD: u8 = 12;
const SHIFT: u8 = 11;
const REL: u8 = 10;
const EQ: u8 = 9;
const BAND: u8 = 8;
const BXOR: u8 = 7;
const BOR: u8 = 6;
const LAND: u8 = 5;
const LOR: u8 = 4;
const TERN: u8 = 3;

/// The functions a block calls.
pub(super) fn calls(block: &Block, out: &mut BTreeSet<Item>) {
    for s in block.iter() {
        if let S::Call { function, .. } = s {
            out.insert(Item::Function(*function));
        }
        for b in children(s) {
            calls(b.0, out);
        }
    }
}

/// The blocks nested in a statement, each with whether it is a loop's body or continuing.
fn children(s: &S) -> Vec<(&Block, bool)> {
    match s {
        S::Block(b) => vec![(b, false)],
        S::If { accept, reject, .. } => vec![(accept, false), (reject, false)],
        S::Switch { cases, .. } => cases.iter().map(|c| (&c.body, false)).collect(),
        S::Loop { body, continuing, .. } => vec![(body, true), (continuing, true)],
        _ => Vec::new(),
    }
}

/// The expressions an expression reads directly.
fn operands(e: &E) -> Vec<Handle<E>> {
    let mut v = Vec::new();
    match *e {
        E::Compose { ref components, .. } => v.extend(components.iter().copied()),
        E::Access { base, index } => v.extend([base, index]),
        E::AccessIndex { base, .. } => v.push(base),
        E::Splat { value, .. } => v.push(value),
        E::Swizzle { vector, .. } => v.push(vector),
        E::Load { pointer } => v.push(pointer),
        E::ImageLoad { image, coordinate, array_index, sample, level } => {
            v.extend([image, coordinate]);
            v.extend(array_index.into_iter().chain(sample).chain(level));
        }
        E::ImageSample { image, sampler, coordinate, array_index, offset, level, depth_ref, .. } => {
            v.extend([image, sampler, coordinate]);
            v.extend(array_index.into_iter().chain(offset).chain(depth_ref));
            match level {
                naga::SampleLevel::Exact(l) | naga::SampleLevel::Bias(l) => v.push(l),
                naga::SampleLevel::Gradient { x, y } => v.extend([x, y]),
                naga::SampleLevel::Auto | naga::SampleLevel::Zero => {}
            }
        }
        E::ImageQuery { image, query } => {
            v.push(image);
            if let naga::ImageQuery::Size { level: Some(l) } = query {
                v.push(l);
            }
        }
        E::Unary { expr, .. } => v.push(expr),
        E::Binary { left, right, .. } => v.extend([left, right]),
        E::Select { condition, accept, reject } => v.extend([condition, accept, reject]),
        E::Relational { argument, .. } => v.push(argument),
        E::Math { arg, arg1, arg2, arg3, .. } => {
            v.push(arg);
            v.extend(arg1.into_iter().chain(arg2).chain(arg3));
        }
        E::As { expr, .. } => v.push(expr),
        E::ArrayLength(x) => v.push(x),
        _ => {}
    }
    v
}

/// The expressions a statement reads itself (not in nested blocks).
fn statement_operands(s: &S, f: &naga::Function) -> Vec<Handle<E>> {
    match s {
        S::Emit(r) => r.clone().flat_map(|h| operands(&f.expressions[h])).collect(),
        S::Store { pointer, value } => vec![*pointer, *value],
        S::Call { arguments, .. } => arguments.clone(),
        S::If { condition, .. } => vec![*condition],
        S::Switch { selector, .. } => vec![*selector],
        S::Return { value } => value.iter().copied().collect(),
        S::Loop { break_if, .. } => break_if.iter().copied().collect(),
        _ => Vec::new(),
    }
}

/// Where a block sits: the block and statement that hold it, and whether it is inside a loop.
#[derive(Clone, Copy)]
struct Place {
    parent: Option<(*const Block, usize)>,
    in_loop: bool,
}

/// The parts of a loop that reads as `for`/`while`.
struct ForLoop<'a> {
    /// The loop's condition and whether it is negated.
    cond: (Handle<E>, bool),
    /// Index in the body of the first statement after the condition's `if`.
    rest: usize,
    /// The continuing block's single store (pointer, value).
    update: Option<(Handle<E>, Handle<E>)>,
    body: &'a Block,
}

/// The body writer of one function.
struct W<'c, 'a> {
    c: &'c Ctx<'a>,
    f: &'a naga::Function,
    fi: &'a naga::valid::FunctionInfo,
    args: Vec<String>,
    locals: HashMap<Handle<LocalVariable>, String>,
    /// Expressions with a name: `let`s, named call results, temporaries.
    names: HashMap<Handle<E>, String>,
    /// Calls written into their single user (result, text), in call order.
    deferred: Vec<(Handle<E>, String)>,
    taken: HashSet<String>,
    /// Names declared per open scope (released when the scope closes: sibling blocks may
    /// reuse a name, nested ones may not shadow).
    scopes: Vec<Vec<String>>,
    /// `a || b` / `a && b`: the `if` naga lowers a short-circuit into → (its bool local,
    /// `true` for ||), and the local's expression once written.
    short_circuit: HashMap<*const S, (Handle<LocalVariable>, bool)>,
    sugar: HashMap<Handle<LocalVariable>, (String, u8)>,
    /// (block, statement) → the locals declared just before (or merged with) it.
    plan: HashMap<(*const Block, usize), Vec<Handle<LocalVariable>>>,
    /// The last statement of its declaring block that uses a local.
    last_use: HashMap<Handle<LocalVariable>, usize>,
    /// Lines that must precede the statement being written (HLSL aggregates, flushed calls).
    pre: Vec<String>,
    /// Per enclosing loop: the continuing block to write before a `continue`.
    loops: Vec<Option<&'a Block>>,
    out: String,
    depth: usize,
}

/// `RET name(params)` of a function.
pub(super) fn signature(c: &Ctx, fh: Handle<naga::Function>) -> R<String> {
    W::new(c, &c.m.functions[fh], &c.info[fh]).signature()
}

/// A function's definition.
pub(super) fn write(c: &Ctx, fh: Handle<naga::Function>) -> R<String> {
    let f = &c.m.functions[fh];
    let mut w = W::new(c, f, &c.info[fh]);
    w.plan_locals();
    let sig = w.signature()?;
    w.depth = 1;
    w.block(&f.body)?;
    let prefix = if c.lang == Lang::Msl { "inline " } else { "" };
    Ok(format!("{prefix}{sig} {{\n{}}}\n", w.out))
}

/// An HLSL helper's definition: texture queries (statements there), and `select_<T>` for
/// a component-wise choice between vectors of type T — `select()` under DXC's HLSL 2021
/// rules, where a vector condition in `?:` is an error, and in Slang, which deprecates it;
/// `?:` for FXC (SM 5) and older DXC, which have no `select()`.
pub(super) fn hlsl_helper(name: &str) -> String {
    if let Some(ty) = name.strip_prefix("select_") {
        let n = ty.trim_start_matches(|c: char| c.is_ascii_alphabetic());
        return format!(
            "{ty} sbf_select(bool{n} c, {ty} a, {ty} b) {{\n#if (defined(__HLSL_VERSION) && __HLSL_VERSION >= 2021) || defined(__SLANG__)\n    return select(c, a, b);\n#else\n    return c ? a : b;\n#endif\n}}\n"
        );
    }
    match name {
        "size" => "uint2 sbf_texture_size(Texture2D<float2> t) {\n    uint w, h;\n    t.GetDimensions(w, h);\n    return uint2(w, h);\n}\n",
        "size_array" => "uint2 sbf_texture_size(Texture2DArray<float2> t) {\n    uint w, h, n;\n    t.GetDimensions(w, h, n);\n    return uint2(w, h);\n}\n",
        "size_3d" => "uint3 sbf_texture_size(Texture3D<float2> t) {\n    uint w, h, d;\n    t.GetDimensions(w, h, d);\n    return uint3(w, h, d);\n}\n",
        _ => "uint sbf_texture_layers(Texture2DArray<float2> t) {\n    uint w, h, n;\n    t.GetDimensions(w, h, n);\n    return n;\n}\n",
    }
    .to_string()
}

impl<'c, 'a> W<'c, 'a> {
    fn new(c: &'c Ctx<'a>, f: &'a naga::Function, fi: &'a naga::valid::FunctionInfo) -> W<'c, 'a> {
        // Module-scope names are never shadowed.
        let mut taken: HashSet<String> = HashSet::new();
        taken.extend(c.m.functions.iter().filter_map(|(_, f)| f.name.clone()));
        taken.extend(c.m.constants.iter().filter_map(|(_, k)| k.name.clone()));
        taken.extend(c.m.types.iter().filter_map(|(_, t)| t.name.clone()));
        taken.extend(c.m.global_variables.iter().filter_map(|(_, g)| g.name.clone()));
        let mut w = W {
            c,
            f,
            fi,
            args: Vec::new(),
            locals: HashMap::new(),
            names: HashMap::new(),
            deferred: Vec::new(),
            taken,
            scopes: vec![Vec::new()],
            short_circuit: HashMap::new(),
            sugar: HashMap::new(),
            plan: HashMap::new(),
            last_use: HashMap::new(),
            pre: Vec::new(),
            loops: Vec::new(),
            out: String::new(),
            depth: 0,
        };
        for a in &f.arguments {
            let n = w.unique(a.name.as_deref().unwrap_or("arg"));
            w.args.push(n);
        }
        w
    }

    fn unique(&mut self, base: &str) -> String {
        let base = if syntax::reserved(base) { format!("{base}_") } else { base.to_string() };
        let mut n = base.clone();
        let mut k = 1;
        while self.taken.contains(&n) {
            n = format!("{base}_{k}");
            k += 1;
        }
        self.taken.insert(n.clone());
        self.scopes.last_mut().expect("a scope").push(n.clone());
        n
    }

    fn open_scope(&mut self) {
        self.scopes.push(Vec::new());
    }

    fn close_scope(&mut self) {
        for n in self.scopes.pop().expect("an open scope") {
            self.taken.remove(&n);
        }
    }

    /// A local's name, given when it is declared.
    fn local_name(&mut self, v: Handle<LocalVariable>) -> String {
        if let Some(n) = self.locals.get(&v) {
            return n.clone();
        }
        let n = self.f.local_variables[v].name.clone().unwrap_or_else(|| "tmp".into());
        let n = self.unique(&n);
        self.locals.insert(v, n.clone());
        n
    }

    fn signature(&self) -> R<String> {
        let c = self.c;
        let name = super::names::exported(super::names::ItemKind::Function, self.f.name.as_deref().ok_or("an unnamed function")?);
        let ret = match &self.f.result {
            Some(r) => c.type_name(r.ty)?,
            None => "void".into(),
        };
        let mut params = Vec::new();
        for (a, n) in self.f.arguments.iter().zip(&self.args) {
            if c.lang.combined_samplers() && is_sampler(&c.m.types[a.ty].inner) {
                continue; // the texture parameter is the combined sampler
            }
            params.push(match c.m.types[a.ty].inner {
                TypeInner::Pointer { base, space: naga::AddressSpace::Function } => match c.lang {
                    Lang::Msl => format!("thread {}& {n}", c.type_name(base)?),
                    _ => format!("inout {}", c.decl(&c.m.types[base].inner, Some(base), n)?),
                },
                TypeInner::Pointer { .. } => return Err(format!("parameter {n}: only function-space pointers are exported")),
                ref inner => c.decl(inner, Some(a.ty), n)?,
            });
        }
        Ok(format!("{ret} {name}({})", params.join(", ")))
    }

    // ---- where locals are declared ----

    fn plan_locals(&mut self) {
        let mut places: HashMap<*const Block, Place> = HashMap::new();
        let mut blocks: HashMap<*const Block, &'a Block> = HashMap::new();
        let mut refs: HashMap<Handle<LocalVariable>, Vec<(*const Block, usize)>> = HashMap::new();
        fn walk<'a>(
            f: &'a naga::Function,
            b: &'a Block,
            place: Place,
            places: &mut HashMap<*const Block, Place>,
            blocks: &mut HashMap<*const Block, &'a Block>,
            refs: &mut HashMap<Handle<LocalVariable>, Vec<(*const Block, usize)>>,
        ) {
            let p = b as *const Block;
            places.insert(p, place);
            blocks.insert(p, b);
            for (i, s) in b.iter().enumerate() {
                for h in statement_operands(s, f) {
                    if let E::LocalVariable(v) = f.expressions[h] {
                        refs.entry(v).or_default().push((p, i));
                    }
                }
                for (child, is_loop) in children(s) {
                    let pl = Place { parent: Some((p, i)), in_loop: place.in_loop || is_loop };
                    walk(f, child, pl, places, blocks, refs);
                }
            }
        }
        walk(self.f, &self.f.body, Place { parent: None, in_loop: false }, &mut places, &mut blocks, &mut refs);

        let chain = |mut b: *const Block| {
            let mut v = vec![b];
            while let Some((p, _)) = places[&b].parent {
                v.push(p);
                b = p;
            }
            v
        };
        // Index of the statement of block `d` that holds a use at (b, i).
        let index_in = |(mut b, mut i): (*const Block, usize), d: *const Block| {
            while b != d {
                (b, i) = places[&b].parent.expect("d is an ancestor");
            }
            i
        };
        self.find_short_circuits(&self.f.body, &refs);
        let sugared: HashSet<Handle<LocalVariable>> = self.short_circuit.values().map(|(v, _)| *v).collect();
        let mut vars: Vec<_> = refs.into_iter().filter(|(v, _)| !sugared.contains(v)).collect();
        vars.sort_by_key(|(v, _)| *v);
        for (v, uses) in vars {
            let mut lca = chain(uses[0].0);
            for u in &uses[1..] {
                let other: HashSet<*const Block> = chain(u.0).into_iter().collect();
                lca.retain(|b| other.contains(b));
            }
            let d0 = lca[0];
            let first = uses.iter().map(|u| index_in(*u, d0)).min().expect("a use");
            let merged = matches!(blocks[&d0][first], S::Store { pointer, .. } if self.f.expressions[pointer] == E::LocalVariable(v));
            let mut d = d0;
            if !merged {
                while places[&d].in_loop {
                    d = places[&d].parent.expect("a loop block has a parent").0;
                }
            }
            let first = uses.iter().map(|u| index_in(*u, d)).min().expect("a use");
            let last = uses.iter().map(|u| index_in(*u, d)).max().expect("a use");
            self.plan.entry((d, first)).or_default().push(v);
            self.last_use.insert(v, last);
        }
    }

    /// An operand of `||` (p = LOR) or `&&` (p = LAND): the other of the two is
    /// parenthesised.
    fn logical_operand(&mut self, h: Handle<E>, p: u8, right: bool) -> R<String> {
        let (t, q) = self.expr(h)?;
        let paren = q < p || (right && q == p) || (matches!(q, LAND | LOR) && q != p);
        Ok(if paren { format!("({t})") } else { t })
    }

    /// The `if` statements that are naga's lowering of a short-circuit operator, with
    /// their bool local: an unnamed local stored in both branches (the `else` branch
    /// storing the constant) and read once after.
    fn find_short_circuits(&mut self, b: &'a Block, uses: &HashMap<Handle<LocalVariable>, Vec<(*const Block, usize)>>) {
        for s in b.iter() {
            if let S::If { accept, reject, .. } = s {
                let store_to = |st: Option<&S>| match st {
                    Some(S::Store { pointer, value }) => match self.f.expressions[*pointer] {
                        E::LocalVariable(v) if self.f.local_variables[v].name.is_none() => Some((v, *value)),
                        _ => None,
                    },
                    _ => None,
                };
                let leading_emits = accept[..accept.len().saturating_sub(1)]
                    .iter()
                    .all(|st| matches!(st, S::Emit(r) if r.clone().all(|h| !self.f.named_expressions.contains_key(&h))));
                if let (Some((v, _)), Some((v2, k)), true, 1) =
                    (store_to(accept.last()), store_to(reject.first()), leading_emits, reject.len())
                {
                    if let (true, E::Literal(naga::Literal::Bool(or))) = (v == v2, &self.f.expressions[k]) {
                        if uses.get(&v).is_some_and(|u| u.len() == 3) {
                            self.short_circuit.insert(s as *const S, (v, *or));
                        }
                    }
                }
            }
            for (c, _) in children(s) {
                self.find_short_circuits(c, uses);
            }
        }
    }

    fn local_decl(&mut self, v: Handle<LocalVariable>) -> R<String> {
        let lv = &self.f.local_variables[v];
        let n = self.local_name(v);
        self.c.decl(&self.c.m.types[lv.ty].inner, Some(lv.ty), &n)
    }

    /// `T v = initial value` of a local not merged with a store.
    fn local_init(&mut self, v: Handle<LocalVariable>) -> R<String> {
        let lv = &self.f.local_variables[v];
        let init = match lv.init {
            Some(h) => self.top(h)?,
            None => self.c.zero(lv.ty)?,
        };
        Ok(format!("{} = {init}", self.local_decl(v)?))
    }

    // ---- output ----

    fn line(&mut self, text: &str) {
        // Calls deferred but not used by this line ran before it: give them a name.
        let flushed = std::mem::take(&mut self.deferred);
        for (h, call) in flushed {
            let callee = match self.f.expressions[h] {
                E::CallResult(g) => self.c.m.functions[g].name.clone().unwrap_or_default(),
                _ => "value".into(),
            };
            let n = self.unique(&format!("{callee}_result"));
            let d = self.decl_of(h, &n).unwrap_or_else(|e| format!("/* {e} */ {n}"));
            self.pre.push(format!("{d} = {call};"));
            self.names.insert(h, n);
        }
        for p in std::mem::take(&mut self.pre) {
            self.raw(&p);
        }
        self.raw(text);
    }

    fn raw(&mut self, text: &str) {
        for _ in 0..self.depth {
            self.out.push_str("    ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    /// `T name` for the type of expression `h`.
    fn decl_of(&self, h: Handle<E>, name: &str) -> R<String> {
        match self.fi[h].ty {
            naga::proc::TypeResolution::Handle(t) => self.c.decl(&self.c.m.types[t].inner, Some(t), name),
            naga::proc::TypeResolution::Value(ref inner) => self.c.decl(inner, None, name),
        }
    }

    fn ty(&self, h: Handle<E>) -> &TypeInner {
        self.fi[h].ty.inner_with(&self.c.m.types)
    }

    /// The type a pointer or value expression refers to.
    fn value_ty(&self, h: Handle<E>) -> TypeInner {
        match *self.ty(h) {
            TypeInner::Pointer { base, .. } => self.c.m.types[base].inner.clone(),
            TypeInner::ValuePointer { size: Some(size), scalar, .. } => TypeInner::Vector { size, scalar },
            TypeInner::ValuePointer { size: None, scalar, .. } => TypeInner::Scalar(scalar),
            ref t => t.clone(),
        }
    }
}

/// Whether a parameter type is a sampler (dropped in the OpenGL dialects, whose textures are
/// combined samplers).
fn is_sampler(inner: &TypeInner) -> bool {
    matches!(inner, TypeInner::Sampler { .. })
}
