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

use super::syntax::{self, Math};
use super::{Ctx, Item};
use crate::export::Lang;
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

    // ---- statements ----

    fn block(&mut self, b: &'a Block) -> R<()> {
        self.statements(b, 0)
    }

    fn statements(&mut self, b: &'a Block, start: usize) -> R<()> {
        self.open_scope();
        let r = self.statements_in_scope(b, start);
        self.close_scope();
        r
    }

    fn statements_in_scope(&mut self, b: &'a Block, start: usize) -> R<()> {
        let p = b as *const Block;
        let mut i = start;
        while i < b.len() {
            let mut decls = self.plan.get(&(p, i)).cloned().unwrap_or_default();
            let is_store_to = |w: &Self, v: Handle<LocalVariable>, s: &S| matches!(*s, S::Store { pointer, .. } if w.f.expressions[pointer] == E::LocalVariable(v));
            // The store-merged local last, so plain declarations come before it.
            decls.sort_by_key(|v| is_store_to(self, *v, &b[i]));
            let mut consumed = 0;
            for (k, &v) in decls.iter().enumerate() {
                let last = k + 1 == decls.len();
                if is_store_to(self, v, &b[i]) {
                    let S::Store { value, .. } = b[i] else { unreachable!() };
                    if last && self.last_use[&v] <= i + 1 && !self.plan.contains_key(&(p, i + 1)) {
                        if let Some(S::Loop { body, continuing, break_if }) = b.get(i + 1) {
                            if let Some(fl) = self.for_loop(body, continuing, *break_if).filter(|fl| self.updates(fl, v)) {
                                // `for (T v = value; …)`: v lives in the loop's scope.
                                self.open_scope();
                                let init = format!("{} = {}", self.local_decl(v)?, self.decl_init(value)?);
                                let r = self.write_for(fl, Some(init));
                                self.close_scope();
                                r?;
                                consumed = 2;
                                continue;
                            }
                        }
                    }
                    let init = format!("{} = {}", self.local_decl(v)?, self.decl_init(value)?);
                    self.line(&format!("{init};"));
                    consumed = 1;
                } else {
                    if last && self.last_use[&v] <= i {
                        if let S::Loop { body, continuing, break_if } = &b[i] {
                            if let Some(fl) = self.for_loop(body, continuing, *break_if).filter(|fl| self.updates(fl, v)) {
                                self.open_scope();
                                let r = self.local_init(v).and_then(|init| self.write_for(fl, Some(init)));
                                self.close_scope();
                                r?;
                                consumed = 1;
                                continue;
                            }
                        }
                    }
                    let init = self.local_init(v)?;
                    self.line(&format!("{init};"));
                }
            }
            if consumed == 0 {
                self.statement(&b[i])?;
                i += 1;
            } else {
                i += consumed;
            }
        }
        // Calls whose results nothing in this block used (their value is dropped).
        for (_, call) in std::mem::take(&mut self.deferred) {
            self.raw(&format!("{call};"));
        }
        Ok(())
    }

    fn updates(&self, fl: &ForLoop, v: Handle<LocalVariable>) -> bool {
        matches!(fl.update, Some((p, _)) if self.f.expressions[p] == E::LocalVariable(v))
    }

    fn statement(&mut self, s: &'a S) -> R<()> {
        match s {
            S::Emit(r) => {
                for h in r.clone() {
                    let Some(name) = self.f.named_expressions.get(&h).cloned() else { continue };
                    if matches!(self.ty(h), TypeInner::Pointer { .. } | TypeInner::ValuePointer { .. }) {
                        // `let p = &x.y;` names a place: written where it is used.
                        let (t, _) = self.expr_value(h)?;
                        self.names.insert(h, t);
                        continue;
                    }
                    let init = self.decl_init(h)?;
                    let n = self.unique(&name);
                    let d = self.decl_of(h, &n)?;
                    self.line(&format!("{d} = {init};"));
                    self.names.insert(h, n);
                }
            }
            S::Block(b) => {
                self.line("{");
                self.depth += 1;
                self.block(b)?;
                self.depth -= 1;
                self.raw("}");
            }
            S::If { condition, accept, reject } => match self.short_circuit.get(&(s as *const S)).copied() {
                Some((v, or)) => {
                    // naga's lowering of `a || b` (`if (!a) { t = b; } else { t = true; }`)
                    // and `a && b` (`if (a) { t = b; } else { t = false; }`), written back.
                    let Some(S::Store { value, .. }) = accept.last() else { unreachable!() };
                    let (op, p) = if or { ("||", LOR) } else { ("&&", LAND) };
                    let a = match (or, &self.f.expressions[*condition]) {
                        (true, E::Unary { op: naga::UnaryOperator::LogicalNot, expr }) => self.logical_operand(*expr, p, false)?,
                        (true, _) => format!("!{}", self.sub(*condition, UNARY)?),
                        (false, _) => self.logical_operand(*condition, p, false)?,
                    };
                    let b = self.logical_operand(*value, p, true)?;
                    self.sugar.insert(v, (format!("{a} {op} {b}"), p));
                }
                None => self.write_if(*condition, accept, reject, false)?,
            },
            S::Switch { selector, cases } => {
                let sel = self.top(*selector)?;
                self.line(&format!("switch ({sel}) {{"));
                for case in cases {
                    let label = match case.value {
                        naga::SwitchValue::I32(n) => format!("case {n}:"),
                        naga::SwitchValue::U32(n) => format!("case {n}u:"),
                        naga::SwitchValue::Default => "default:".into(),
                    };
                    if case.body.is_empty() && case.fall_through {
                        self.raw(&label);
                        continue;
                    }
                    self.raw(&format!("{label} {{"));
                    self.depth += 1;
                    self.block(&case.body)?;
                    let jumps = matches!(case.body.last(), Some(S::Return { .. } | S::Break | S::Continue | S::Kill));
                    if !case.fall_through && !jumps {
                        self.raw("break;");
                    }
                    self.depth -= 1;
                    self.raw("}");
                }
                self.raw("}");
            }
            S::Loop { body, continuing, break_if } => match self.for_loop(body, continuing, *break_if) {
                Some(fl) => self.write_for(fl, None)?,
                None => {
                    self.line("for (;;) {");
                    self.depth += 1;
                    self.loops.push((!continuing.is_empty() || break_if.is_some()).then_some(continuing));
                    self.block(body)?;
                    self.write_continuing(continuing, *break_if)?;
                    self.loops.pop();
                    self.depth -= 1;
                    self.raw("}");
                }
            },
            S::Break => self.line("break;"),
            S::Continue => {
                if let Some(Some(cont)) = self.loops.last().copied() {
                    let S::Loop { break_if, .. } = self.find_loop(cont) else { unreachable!() };
                    self.write_continuing(cont, *break_if)?;
                }
                self.line("continue;");
            }
            S::Return { value } => match value {
                Some(v) => {
                    let t = self.top(*v)?;
                    self.line(&format!("return {t};"));
                }
                None => self.line("return;"),
            },
            S::Kill => self.line(if self.c.lang == Lang::Msl { "discard_fragment();" } else { "discard;" }),
            S::Store { pointer, value } => {
                let t = self.store(*pointer, *value)?;
                self.line(&format!("{t};"));
            }
            S::Call { function, arguments, result } => {
                let callee = &self.c.m.functions[*function];
                let name = callee.name.clone().ok_or("a call to an unnamed function")?;
                let mut args = Vec::new();
                for (a, p) in arguments.iter().zip(&callee.arguments) {
                    if !(self.c.lang.combined_samplers() && is_sampler(&self.c.m.types[p.ty].inner)) {
                        args.push(self.top(*a)?);
                    }
                }
                let call = format!("{}({})", super::names::exported(super::names::ItemKind::Function, &name), args.join(", "));
                let takes_pointer = callee.arguments.iter().any(|a| matches!(self.c.m.types[a.ty].inner, TypeInner::Pointer { .. }));
                match result {
                    None => self.line(&format!("{call};")),
                    Some(r) => {
                        let named = self.f.named_expressions.get(r).cloned();
                        if named.is_none() && !takes_pointer && self.fi[*r].ref_count == 1 {
                            self.deferred.push((*r, call));
                        } else {
                            let n = self.unique(&named.unwrap_or_else(|| format!("{name}_result")));
                            let d = self.decl_of(*r, &n)?;
                            self.line(&format!("{d} = {call};"));
                            self.names.insert(*r, n);
                        }
                    }
                }
            }
            other => return Err(format!("statement {other:?} is not in the exported subset")),
        }
        Ok(())
    }

    /// The `Loop` statement whose continuing block is `cont` (for a `continue`).
    fn find_loop(&self, cont: &'a Block) -> &'a S {
        fn find(b: &Block, cont: *const Block) -> Option<&S> {
            for s in b.iter() {
                if let S::Loop { continuing, .. } = s {
                    if std::ptr::eq(continuing, cont) {
                        return Some(s);
                    }
                }
                for (c, _) in children(s) {
                    if let Some(x) = find(c, cont) {
                        return Some(x);
                    }
                }
            }
            None
        }
        find(&self.f.body, cont).expect("a continuing block belongs to a loop")
    }

    fn write_continuing(&mut self, cont: &'a Block, break_if: Option<Handle<E>>) -> R<()> {
        if cont.is_empty() && break_if.is_none() {
            return Ok(());
        }
        self.line("{");
        self.depth += 1;
        self.block(cont)?;
        if let Some(b) = break_if {
            let t = self.top(b)?;
            self.line(&format!("if ({t}) {{"));
            self.raw("    break;");
            self.raw("}");
        }
        self.depth -= 1;
        self.raw("}");
        Ok(())
    }

    fn write_if(&mut self, condition: Handle<E>, accept: &'a Block, reject: &'a Block, else_if: bool) -> R<()> {
        let cond = self.top(condition)?;
        if else_if {
            self.raw(&format!("}} else if ({cond}) {{"));
        } else {
            self.line(&format!("if ({cond}) {{"));
        }
        self.depth += 1;
        self.block(accept)?;
        self.depth -= 1;
        if !reject.is_empty() {
            // `else if` when the else block is only the condition's expressions and an `if`
            // (HLSL may need lines before a condition, so it keeps the nesting).
            let p = reject as *const Block;
            let k = reject
                .iter()
                .take_while(|s| matches!(s, S::Emit(r) if r.clone().all(|h| !self.f.named_expressions.contains_key(&h))))
                .count();
            let no_decls = (0..reject.len()).all(|i| !self.plan.contains_key(&(p, i)));
            if k + 1 == reject.len() && no_decls && self.c.lang != Lang::Hlsl && self.deferred.is_empty() {
                if let S::If { condition, accept, reject } = &reject[k] {
                    return self.write_if(*condition, accept, reject, true);
                }
            }
            self.raw("} else {");
            self.depth += 1;
            self.block(reject)?;
            self.depth -= 1;
        }
        self.raw("}");
        Ok(())
    }

    fn for_loop(&self, body: &'a Block, continuing: &'a Block, break_if: Option<Handle<E>>) -> Option<ForLoop<'a>> {
        if break_if.is_some() {
            return None;
        }
        let unnamed = |s: &S| matches!(s, S::Emit(r) if r.clone().all(|h| !self.f.named_expressions.contains_key(&h)));
        let k = body.iter().take_while(|s| unnamed(s)).count();
        let cond = match body.get(k)? {
            S::If { condition, accept, reject } if accept.is_empty() && matches!(&reject[..], [S::Break]) => (*condition, false),
            S::If { condition, accept, reject } if reject.is_empty() && matches!(&accept[..], [S::Break]) => (*condition, true),
            _ => return None,
        };
        let update = match &continuing[..] {
            [] => None,
            [lead @ .., S::Store { pointer, value }] if lead.iter().all(unnamed) => Some((*pointer, *value)),
            _ => return None,
        };
        Some(ForLoop { cond, rest: k + 1, update, body })
    }

    fn write_for(&mut self, fl: ForLoop<'a>, init: Option<String>) -> R<()> {
        let (c, negate) = fl.cond;
        let cond = if negate { format!("!{}", self.sub(c, UNARY)?) } else { self.top(c)? };
        let update = fl.update.map(|(p, v)| self.store(p, v)).transpose()?;
        match (&init, &update) {
            (None, None) => self.line(&format!("while ({cond}) {{")),
            _ => self.line(&format!("for ({}; {cond}; {}) {{", init.unwrap_or_default(), update.unwrap_or_default())),
        }
        self.depth += 1;
        self.loops.push(None);
        match &fl.body[fl.rest..] {
            [S::Block(b)] => self.block(b)?,
            _ => self.statements(fl.body, fl.rest)?,
        }
        self.loops.pop();
        self.depth -= 1;
        self.raw("}");
        Ok(())
    }

    /// `p = v`, `p += x` or `p++`.
    fn store(&mut self, pointer: Handle<E>, value: Handle<E>) -> R<String> {
        let lhs = self.top(pointer)?;
        if let E::Binary { op, left, right } = self.f.expressions[value] {
            let same = matches!(self.f.expressions[left], E::Load { pointer: p } if p == pointer);
            let matrix = matches!(self.ty(left), TypeInner::Matrix { .. }) || matches!(self.ty(right), TypeInner::Matrix { .. });
            let float_mod = op == B::Modulo
                && !matches!(self.value_ty(left), TypeInner::Scalar(s) | TypeInner::Vector { scalar: s, .. } if s.kind != naga::ScalarKind::Float);
            if same && !matrix && !float_mod && !self.names.contains_key(&value) {
                let one = matches!(self.f.expressions[right], E::Literal(naga::Literal::I32(1) | naga::Literal::U32(1)));
                if op == B::Add && one {
                    return Ok(format!("{lhs}++"));
                }
                if let Some(sym) = match op {
                    B::Add => Some("+="),
                    B::Subtract => Some("-="),
                    B::Multiply => Some("*="),
                    B::Divide => Some("/="),
                    _ => None,
                } {
                    let rhs = self.top(right)?;
                    return Ok(format!("{lhs} {sym} {rhs}"));
                }
            }
        }
        let rhs = self.top(value)?;
        Ok(format!("{lhs} = {rhs}"))
    }

    /// The value written after `T name = `: HLSL builds an array or struct from a list.
    fn decl_init(&mut self, h: Handle<E>) -> R<String> {
        if self.c.lang == Lang::Hlsl && !self.names.contains_key(&h) {
            if let E::Compose { ty, ref components } = self.f.expressions[h] {
                if syntax::hlsl_aggregate(&self.c.m.types[ty].inner) {
                    let parts: Vec<String> = components.iter().map(|c| self.top(*c)).collect::<R<_>>()?;
                    return Ok(format!("{{ {} }}", parts.join(", ")));
                }
            }
        }
        self.top(h)
    }

    // ---- expressions ----

    fn top(&mut self, h: Handle<E>) -> R<String> {
        Ok(self.expr(h)?.0)
    }

    /// `h` written where an operand of precedence `min` is expected.
    fn sub(&mut self, h: Handle<E>, min: u8) -> R<String> {
        let (t, p) = self.expr(h)?;
        Ok(if p < min { format!("({t})") } else { t })
    }

    fn expr(&mut self, h: Handle<E>) -> R<(String, u8)> {
        if let Some(n) = self.names.get(&h) {
            return Ok((n.clone(), ATOM));
        }
        if let Some(i) = self.deferred.iter().position(|(k, _)| *k == h) {
            return Ok((self.deferred.remove(i).1, ATOM));
        }
        self.expr_value(h)
    }

    /// An aggregate HLSL can only build in a declaration: a temporary before the line.
    fn hlsl_temporary(&mut self, h: Handle<E>, init: String) -> R<(String, u8)> {
        let n = self.unique("tmp");
        let d = self.decl_of(h, &n)?;
        self.pre.push(format!("{d} = {init};"));
        self.names.insert(h, n.clone());
        Ok((n, ATOM))
    }

    fn expr_value(&mut self, h: Handle<E>) -> R<(String, u8)> {
        let c = self.c;
        let lang = c.lang;
        Ok(match self.f.expressions[h] {
            E::Literal(l) => {
                let t = syntax::literal(lang, l)?;
                let p = if t.starts_with('-') { UNARY } else { ATOM };
                (t, p)
            }
            E::Constant(k) => (
                super::names::exported(super::names::ItemKind::Constant, c.m.constants[k].name.as_deref().ok_or("an unnamed constant")?),
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
            E::Swizzle { size, vector, pattern } => {
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
            }
            E::FunctionArgument(i) => (self.args[i as usize].clone(), ATOM),
            E::GlobalVariable(g) => (c.m.global_variables[g].name.clone().ok_or("an unnamed global")?, ATOM),
            E::LocalVariable(v) => (self.locals.get(&v).cloned().ok_or("a local used before its declaration")?, ATOM),
            E::Load { pointer } => match self.f.expressions[pointer] {
                E::LocalVariable(v) if self.sugar.contains_key(&v) => self.sugar[&v].clone(),
                _ => self.expr(pointer)?,
            },
            E::ImageLoad { image, coordinate, array_index, sample: None, level } => {
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
            } => {
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
            }
            E::ImageQuery { image, query } => {
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
            }
            E::Unary { op, expr } => {
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
            }
            E::Binary { op, left, right } => self.binary(op, left, right)?,
            E::Select { condition, accept, reject } => {
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
            }
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
            E::As { expr, kind, convert } => {
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
            }
            E::CallResult(_) => return Err("a call result used before its call".into()),
            ref other => return Err(format!("expression {other:?} is not in the exported subset")),
        })
    }

    fn binary(&mut self, op: B, left: Handle<E>, right: Handle<E>) -> R<(String, u8)> {
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

/// Whether a parameter type is a sampler (dropped in the OpenGL dialects, whose textures are
/// combined samplers).
fn is_sampler(inner: &TypeInner) -> bool {
    matches!(inner, TypeInner::Sampler { .. })
}
