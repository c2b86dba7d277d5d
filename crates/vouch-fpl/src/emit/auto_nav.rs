//! `nav_on_enter_block`, `nav_on_exit_block`, the optional `forbidden_deroute` check and
//! `auto_nav` itself, printed from the size-verified plan (GENERATOR_FACTS.md §6-§8).

use crate::ast::FlightPlan;
use crate::passes::extend::{ExtBlock, ExtException, ExtKind, ExtStage};
use crate::passes::fp::{Code, NavStage};
use crate::passes::size::{BlockNo, Fps, StageNo};

use super::Writer;

pub(super) fn functions(w: &mut Writer, _plan: &FlightPlan, fps: &Fps) {
    let p = fps.plan();
    w.raw("");
    hook(
        w,
        "nav_on_enter_block",
        p.blocks.iter().filter_map(|b| b.on_enter.as_ref().map(|c| (b, c))),
    );
    hook(
        w,
        "nav_on_exit_block",
        p.blocks.iter().filter_map(|b| b.on_exit.as_ref().map(|c| (b, c))),
    );
    let checked = !p.forbidden.is_empty();
    if checked {
        forbidden(w, fps);
    }
    w.raw("static inline void auto_nav(void) {");
    w.right();
    for e in &p.exceptions {
        exception(w, e, checked);
    }
    w.line("switch (nav_block) {");
    w.right();
    for b in &p.blocks {
        block(w, b, checked);
    }
    w.line("default: break;");
    w.left();
    w.line("}");
    w.left();
    w.raw("}");
}

fn hook<'a>(
    w: &mut Writer,
    name: &str,
    cases: impl Iterator<Item = (&'a ExtBlock<StageNo, BlockNo>, &'a Code)>,
) {
    w.raw(&format!("void {name}(uint8_t block_id) {{"));
    w.right();
    w.line("switch (block_id) {");
    w.right();
    for (b, c) in cases {
        w.line(&format!("case {}: // {}", b.no, b.name));
        w.right();
        let s = w.stmt(c);
        w.line(&s);
        w.line("break;");
        w.left();
    }
    w.line("default:");
    w.line("  break;");
    w.left();
    w.line("}");
    w.left();
    w.raw("}");
    w.raw("");
}

/// VFPG extension (not upstream): emitted only for plans with forbidden deroutes.
fn forbidden(w: &mut Writer, fps: &Fps) {
    w.raw("/* vouch: forbidden deroutes (VFPG extension, not part of upstream Paparazzi) */");
    w.raw("static inline bool forbidden_deroute(uint8_t from, uint8_t to) {");
    w.right();
    for f in &fps.plan().forbidden {
        match &f.only_when {
            None => {
                w.line(&format!("if (from == {} && to == {}) {{ return true; }}", f.from, f.to))
            }
            Some(c) => {
                let c = w.cond(c);
                w.line(&format!(
                    "if (from == {} && to == {} && ({c})) {{ return true; }}",
                    f.from, f.to
                ));
            }
        }
    }
    w.line("return false;");
    w.left();
    w.raw("}");
    w.raw("");
}

/// `GotoBlock(t)`, guarded by the forbidden-deroute check when the plan has any.
fn goto_block(target: &str, checked: bool) -> String {
    if checked {
        format!("if (!forbidden_deroute(nav_block, {target})) {{ GotoBlock({target}); }}")
    } else {
        format!("GotoBlock({target});")
    }
}

fn exception(w: &mut Writer, e: &ExtException<BlockNo>, checked: bool) {
    let t = e.target;
    let c = w.cond(&e.cond);
    let g = goto_block(&t.to_string(), checked);
    match &e.exec {
        Some(x) => {
            let x = w.stmt(x);
            w.line(&format!("if ((nav_block != {t}) && {c}) {{{x} {g} return; }}"));
        }
        None => w.line(&format!("if ((nav_block != {t}) && {c}) {{ {g} return; }}")),
    }
}

fn block(w: &mut Writer, b: &ExtBlock<StageNo, BlockNo>, checked: bool) {
    w.line(&format!("Block({}) // {}", b.no, b.name));
    if let Some(c) = &b.pre_call {
        let s = w.stmt(c);
        w.line(&s);
    }
    for e in &b.exceptions {
        exception(w, e, checked);
    }
    w.line("switch(nav_stage) {");
    w.right();
    let base = w.margin;
    for s in &b.stages {
        w.margin = base + 2 * s.depth;
        stage(w, s, checked);
    }
    w.margin = base;
    w.line("/* Falls through. */");
    w.line("default:");
    w.line(&format!("Stage({})", b.default_stage));
    w.right();
    if checked {
        w.line("if (!forbidden_deroute(nav_block, (int)nav_block < (int)NB_BLOCK - 1 ? nav_block + 1 : nav_block)) { NextBlock(); }");
    } else {
        w.line("NextBlock();");
    }
    w.line("break;");
    w.left();
    w.left();
    w.line("}");
    if let Some(c) = &b.post_call {
        let s = w.stmt(c);
        w.line(&s);
    }
    w.line("break;");
    w.raw("");
}

fn body(w: &mut Writer, lines: &[Code]) {
    for c in lines {
        let s = w.stmt(c);
        w.line(&s);
    }
}

fn stage(w: &mut Writer, s: &ExtStage<StageNo, BlockNo>, checked: bool) {
    let k = s.no;
    match &s.kind {
        ExtKind::WhileTest { cond, label, end_label } => {
            w.line(&format!("Label({label})"));
            w.line(&format!("Stage({k})"));
            let c = w.cond(cond);
            w.line(&format!("  if (! ({c})) Goto({end_label}) else NextStageAndBreak();"));
        }
        ExtKind::EndWhile { label, end_label } | ExtKind::EndFor { label, end_label } => {
            w.line(&format!("Stage({k})"));
            w.line(&format!("  Goto({label})"));
            w.line(&format!("Label({end_label})"));
        }
        ExtKind::ForInit { var, from, to } => {
            w.line(&format!("static int8_t {var};"));
            w.line(&format!("static int8_t {var}_to;"));
            w.line(&format!("Stage({k})"));
            let (f, t) = (w.value(from), w.value(to));
            w.line(&format!("  {var} = {f} - 1;"));
            w.line(&format!("  {var}_to = {t};"));
            w.line("  INTENTIONAL_FALLTHRU");
        }
        ExtKind::ForTest { var, label, end_label } => {
            w.line(&format!("Label({label})"));
            w.line(&format!("Stage({k})"));
            w.line(&format!(
                "  if (++{var} > {var}_to) Goto({end_label}) else NextStageAndBreak();"
            ));
        }
        ExtKind::Set { code } => {
            w.line(&format!("Stage({k})"));
            let s = w.stmt(code);
            w.line(&format!("  {s}"));
            w.line("  NextStage();");
        }
        ExtKind::Call { fun, loop_: true, brk, until } => {
            w.line(&format!("Stage({k})"));
            w.right();
            let c = w.cond(fun);
            w.line(&format!("if (! ({c})) {{"));
            w.line(if *brk { "  NextStageAndBreak();" } else { "  NextStage();" });
            w.line("} else {");
            if let Some(u) = until {
                let u = w.cond(u);
                w.line(&format!("  if ({u}) NextStageAndBreak();"));
            }
            w.line("  break;");
            w.line("}");
            w.left();
        }
        ExtKind::Call { fun, loop_: false, brk, .. } => {
            w.line(&format!("Stage({k})"));
            let s = w.stmt(&Code::stmt(fun.clone()));
            w.line(&format!("  {s}"));
            w.line(if *brk { "  NextStageAndBreak();" } else { "  NextStage();" });
        }
        ExtKind::Deroute { target } => {
            w.line(&format!("Stage({k})"));
            w.line(&format!("  {}", goto_block(&target.to_string(), checked)));
            w.line("  break;");
        }
        ExtKind::Return { reset } => {
            w.line(&format!("Stage({k})"));
            w.line(&format!("  Return({});", reset.text));
            w.line("  break;");
        }
        ExtKind::NavInit { lines } => {
            w.line(&format!("Stage({k})"));
            w.right();
            body(w, lines);
            w.line("NextStageAndBreak();");
            w.left();
        }
        ExtKind::Nav(n) => {
            w.line(&format!("Stage({k})"));
            w.right();
            nav(w, n);
            w.left();
        }
    }
}

fn nav(w: &mut Writer, n: &NavStage) {
    if let Some(c) = &n.pre_call {
        let s = w.stmt(c);
        w.line(&s);
    }
    body(w, &n.before);
    match &n.approach {
        Some((cond, wp)) => {
            let printed = w.compat.compat.pick(cond, n.approach_upstream.as_ref().unwrap_or(cond));
            let c = w.cond(printed);
            w.line(&format!("if ({c}) {{"));
            w.right();
            if let Some(p) = &n.post_call {
                let s = w.stmt(p);
                w.line(&s);
            }
            w.line(&format!("NextStageAndBreakFrom({wp});"));
            w.left();
            w.line("} else {");
            w.right();
            body(w, &n.lines);
            w.left();
            w.line("}");
        }
        None => body(w, &n.lines),
    }
    if let Some(u) = &n.until {
        let c = w.cond(u);
        w.line(&format!("if ({c}) {{"));
        w.right();
        if let Some(p) = &n.post_call {
            let s = w.stmt(p);
            w.line(&s);
        }
        w.line("NextStageAndBreak()");
        w.left();
        w.line("}");
    }
    if let Some(p) = &n.post_call {
        let s = w.stmt(p);
        w.line(&s);
    }
    w.line("break;");
}
