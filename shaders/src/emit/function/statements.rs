//! Statements written back as structured source: blocks and scopes, `if`, loops (as `for`,
//! `while` or `for (;;)` with their continuing blocks), stores and declarations.

use super::*;

impl<'c, 'a> W<'c, 'a> {
    pub(super) fn block(&mut self, b: &'a Block) -> R<()> {
        self.statements(b, 0)
    }

    pub(super) fn statements(&mut self, b: &'a Block, start: usize) -> R<()> {
        self.open_scope();
        let r = self.statements_in_scope(b, start);
        self.close_scope();
        r
    }

    pub(super) fn statements_in_scope(&mut self, b: &'a Block, start: usize) -> R<()> {
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

    pub(super) fn updates(&self, fl: &ForLoop, v: Handle<LocalVariable>) -> bool {
        matches!(fl.update, Some((p, _)) if self.f.expressions[p] == E::LocalVariable(v))
    }

    /// A `switch` with its cases; a case that neither falls through nor jumps ends in `break`.
    fn write_switch(&mut self, selector: Handle<E>, cases: &'a [naga::SwitchCase]) -> R<()> {
        let sel = self.top(selector)?;
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
        Ok(())
    }

    /// A call; a result used once and unnamed is written inline where it is used.
    fn write_call(&mut self, function: Handle<naga::Function>, arguments: &[Handle<E>], result: Option<Handle<E>>) -> R<()> {
        let callee = &self.c.m.functions[function];
        let name = callee.name.clone().ok_or("a call to an unnamed function")?;
        let mut args = Vec::new();
        for (a, p) in arguments.iter().zip(&callee.arguments) {
            if !(self.c.lang.combined_samplers() && is_sampler(&self.c.m.types[p.ty].inner)) {
                args.push(self.top(*a)?);
            }
        }
        let call = format!("{}({})", crate::emit::names::exported(crate::emit::names::ItemKind::Function, &name), args.join(", "));
        let takes_pointer = callee.arguments.iter().any(|a| matches!(self.c.m.types[a.ty].inner, TypeInner::Pointer { .. }));
        match result {
            None => self.line(&format!("{call};")),
            Some(r) => {
                let named = self.f.named_expressions.get(&r).cloned();
                if named.is_none() && !takes_pointer && self.fi[r].ref_count == 1 {
                    self.deferred.push((r, call));
                } else {
                    let n = self.unique(&named.unwrap_or_else(|| format!("{name}_result")));
                    let d = self.decl_of(r, &n)?;
                    self.line(&format!("{d} = {call};"));
                    self.names.insert(r, n);
                }
            }
        }
        Ok(())
    }

    pub(super) fn statement(&mut self, s: &'a S) -> R<()> {
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
            S::Switch { selector, cases } => self.write_switch(*selector, cases)?,
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
            S::Call { function, arguments, result } => self.write_call(*function, arguments, *result)?,
            other => return Err(format!("statement {other:?} is not in the exported subset")),
        }
        Ok(())
    }

    /// The `Loop` statement whose continuing block is `cont` (for a `continue`).
    pub(super) fn find_loop(&self, cont: &'a Block) -> &'a S {
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

    pub(super) fn write_continuing(&mut self, cont: &'a Block, break_if: Option<Handle<E>>) -> R<()> {
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

    pub(super) fn write_if(&mut self, condition: Handle<E>, accept: &'a Block, reject: &'a Block, else_if: bool) -> R<()> {
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

    pub(super) fn for_loop(&self, body: &'a Block, continuing: &'a Block, break_if: Option<Handle<E>>) -> Option<ForLoop<'a>> {
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

    pub(super) fn write_for(&mut self, fl: ForLoop<'a>, init: Option<String>) -> R<()> {
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
    pub(super) fn store(&mut self, pointer: Handle<E>, value: Handle<E>) -> R<String> {
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
    pub(super) fn decl_init(&mut self, h: Handle<E>) -> R<String> {
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
}
