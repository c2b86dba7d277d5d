//! The state of the C side, found from the C texts themselves: every variable with static
//! storage that the generated header defines (plan variables, ABI statics, the `static int8_t`
//! counters of `for` loops inside `auto_nav`, anything a future emitter adds) and every global
//! the stub runtime declares (`extern` lines of `fp_stub.h`: block, stage, last block and stage,
//! `last_wp`, the timers).
//!
//! Nothing here is a fixed list of names: a small C tokenizer finds the declarations, and the
//! driver learns their addresses through one *registration* line inserted after each header
//! declaration (`VOUCH_REGISTER(id, name)`, a static record of the address and size placed in
//! a linker section; see `c/explore_driver.c`). The header's code is not changed otherwise.
//! Names matter only to classify a variable ([`Kind`]): which runtime global it is, and which
//! loop (block, variable) a counter belongs to.

use std::fmt::Write as _;

/// What a state variable is, for the comparisons and the state views of the validator.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Kind {
    /// `nav_block` of the runtime.
    Block,
    /// `nav_stage`.
    Stage,
    /// `last_block`.
    LastBlock,
    /// `last_stage`.
    LastStage,
    /// `last_wp` (written by `NextStageAndBreakFrom`).
    LastWp,
    /// The counter of a `for` loop (`_var_v`, or its bound `_var_v_to`), declared inside
    /// `auto_nav` in the code of block `block`.
    Counter { block: usize, var: String, bound: bool },
    /// Any other static variable (plan variables, ABI statics, the runtime's timers, ...).
    Other,
}

/// One variable with static storage.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CVar {
    /// Registration number (the order of the state bytes).
    pub id: usize,
    pub name: String,
    pub kind: Kind,
    /// Declared by the runtime (`fp_stub.h`) rather than by the header.
    pub runtime: bool,
}

/// The variables and the texts the driver is compiled from.
#[derive(Debug, Clone)]
pub struct Discovery {
    pub vars: Vec<CVar>,
    /// The header with one registration line after each of its static declarations.
    pub registered_header: String,
    /// Registration lines of the runtime's globals (a file the driver includes).
    pub runtime_registrations: String,
}

/// A token of C text: what the scan needs (identifiers, numbers, punctuation), with its line.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Tok<'a> {
    text: &'a str,
    ident: bool,
    line: usize,
}

/// Tokens of `text`, without comments, string and character literals, and preprocessor lines.
fn tokens(text: &str) -> Vec<Tok<'_>> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let (mut i, mut line, mut line_start) = (0, 0, true);
    while i < b.len() {
        let c = b[i];
        if c == b'\n' {
            line += 1;
            line_start = true;
            i += 1;
        } else if c.is_ascii_whitespace() {
            i += 1;
        } else if line_start && c == b'#' {
            // a directive, with backslash continuations
            while i < b.len() && b[i] != b'\n' {
                if b[i] == b'\\' && b.get(i + 1) == Some(&b'\n') {
                    line += 1;
                    i += 1;
                }
                i += 1;
            }
        } else if c == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if c == b'/' && b.get(i + 1) == Some(&b'*') {
            i += 2;
            while i < b.len() && !(b[i] == b'*' && b.get(i + 1) == Some(&b'/')) {
                line += usize::from(b[i] == b'\n');
                i += 1;
            }
            i += 2;
        } else if c == b'"' || c == b'\'' {
            line_start = false;
            i += 1;
            while i < b.len() && b[i] != c && b[i] != b'\n' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            out.push(Tok { text: if c == b'"' { "\"\"" } else { "''" }, ident: false, line });
            i += 1;
        } else if c.is_ascii_alphanumeric() || c == b'_' {
            line_start = false;
            let s = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_' || b[i] == b'.') {
                // numbers may hold dots (1.5); identifiers never do
                if b[i] == b'.' && !b[s].is_ascii_digit() {
                    break;
                }
                i += 1;
            }
            out.push(Tok { text: &text[s..i], ident: !c.is_ascii_digit(), line });
        } else {
            line_start = false;
            let len = text[i..].chars().next().map_or(1, char::len_utf8);
            out.push(Tok { text: &text[i..i + len], ident: false, line });
            i += len;
        }
    }
    out
}

/// A declaration found by the scan: its declared names and the line of its `;`.
#[derive(Debug)]
struct Decl<'a> {
    names: Vec<&'a str>,
    end_line: usize,
    /// Inside a function (its name), and the `Block(n)` case it follows, if any.
    function: Option<&'a str>,
    block: Option<usize>,
    external: bool,
}

/// Index just after the bracket group opening at `i` (`(`, `[` or `{`).
fn skip_group(t: &[Tok<'_>], i: usize) -> usize {
    let (open, close) = match t[i].text {
        "(" => ("(", ")"),
        "[" => ("[", "]"),
        _ => ("{", "}"),
    };
    let mut depth = 0;
    let mut j = i;
    while j < t.len() {
        if t[j].text == open {
            depth += 1;
        } else if t[j].text == close {
            depth -= 1;
            if depth == 0 {
                return j + 1;
            }
        }
        j += 1;
    }
    t.len()
}

/// The names a declaration statement (without its `;`) declares; `None` for statements that
/// declare no object (prototypes, typedefs).
fn declared_names<'a>(stmt: &[Tok<'a>]) -> Option<Vec<&'a str>> {
    if stmt.first().is_some_and(|t| t.text == "typedef") {
        return None;
    }
    // declarators are separated by top-level commas; an initializer ends at the next one
    let mut names = Vec::new();
    let mut last_ident: Option<&'a str> = None;
    let mut in_init = false;
    // the current declarator's name was in parentheses (`(*cb)(void)`, `(*rows)[4]`): the
    // groups after it are its parameter lists or dimensions
    let mut parenthesised = false;
    let mut i = 0;
    while i < stmt.len() {
        let t = &stmt[i];
        match t.text {
            "__attribute__" => {
                i += 1;
                if stmt.get(i).is_some_and(|t| t.text == "(") {
                    i = skip_group(stmt, i);
                }
                continue;
            }
            "(" if !in_init && !parenthesised => {
                if stmt.get(i + 1).is_none_or(|t| t.text != "*") {
                    return None; // a function declarator
                }
                let end = skip_group(stmt, i);
                last_ident = stmt[i + 1..end.saturating_sub(1)]
                    .iter()
                    .filter(|t| t.ident && !matches!(t.text, "const" | "volatile" | "restrict"))
                    .map(|t| t.text)
                    .next();
                parenthesised = true;
                i = end;
                continue;
            }
            "(" | "[" | "{" => {
                i = skip_group(stmt, i);
                continue;
            }
            "=" => {
                names.extend(last_ident.take());
                in_init = true;
            }
            "," => {
                names.extend(last_ident.take());
                in_init = false;
                parenthesised = false;
            }
            _ if t.ident && !in_init && !parenthesised => last_ident = Some(t.text),
            _ => {}
        }
        i += 1;
    }
    names.extend(last_ident);
    (!names.is_empty()).then_some(names)
}

/// Index of the token ending the statement that starts at `i` (its `;`, brace groups skipped).
fn statement_end(t: &[Tok<'_>], mut i: usize) -> usize {
    while i < t.len() && t[i].text != ";" {
        i = if matches!(t[i].text, "(" | "[" | "{") { skip_group(t, i) } else { i + 1 };
    }
    i.min(t.len().saturating_sub(1))
}

/// Every declaration with static storage: file-scope definitions and declarations, and
/// `static` declarations inside function bodies.
fn declarations<'a>(t: &[Tok<'a>]) -> Vec<Decl<'a>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < t.len() {
        // a top-level item: tokens up to `;`, or a function definition
        let start = i;
        let mut j = i;
        let mut body = None;
        while j < t.len() && t[j].text != ";" {
            if t[j].text == "{" {
                if j > start && t[j - 1].text == ")" {
                    body = Some(j);
                    break;
                }
                j = skip_group(t, j);
                continue;
            }
            j = if matches!(t[j].text, "(" | "[") { skip_group(t, j) } else { j + 1 };
        }
        if let Some(open) = body {
            let end = skip_group(t, open);
            let name = function_name(&t[start..open]);
            function_statics(&t[open..end], name, &mut out);
            i = end;
            continue;
        }
        let stmt = &t[start..j.min(t.len())];
        if let Some(names) = declared_names(stmt) {
            out.push(Decl {
                names,
                end_line: t.get(j).map_or(0, |x| x.line),
                function: None,
                block: None,
                external: stmt.iter().any(|x| x.text == "extern"),
            });
        }
        i = j + 1;
    }
    out
}

/// The identifier before the parameter list of a function definition's head.
fn function_name<'a>(head: &[Tok<'a>]) -> Option<&'a str> {
    let open = head.iter().position(|x| x.text == "(")?;
    head[..open].iter().rev().find(|x| x.ident).map(|x| x.text)
}

/// `static` declarations inside one function body (`body` starts at its `{`).
fn function_statics<'a>(body: &[Tok<'a>], function: Option<&'a str>, out: &mut Vec<Decl<'a>>) {
    let mut block = None;
    let mut i = 0;
    while i < body.len() {
        let w = &body[i..];
        if w.len() >= 4 && w[0].text == "Block" && w[1].text == "(" && w[3].text == ")" {
            block = w[2].text.parse().ok();
        }
        if body[i].text == "static" {
            let end = statement_end(body, i);
            if let Some(names) = declared_names(&body[i..end]) {
                out.push(Decl {
                    names,
                    end_line: body[end].line,
                    function,
                    block,
                    external: false,
                });
            }
            i = end;
        }
        i += 1;
    }
}

const RUNTIME_KINDS: [(&str, Kind); 5] = [
    ("nav_block", Kind::Block),
    ("nav_stage", Kind::Stage),
    ("last_block", Kind::LastBlock),
    ("last_stage", Kind::LastStage),
    ("last_wp", Kind::LastWp),
];

fn kind_of(name: &str, d: &Decl<'_>) -> Kind {
    if d.function.is_none() {
        return RUNTIME_KINDS
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(Kind::Other, |(_, k)| k.clone());
    }
    match (d.function, d.block, name.strip_prefix("_var_")) {
        (Some("auto_nav"), Some(block), Some(_)) => match name.strip_suffix("_to") {
            Some(var) => Kind::Counter { block, var: var.to_string(), bound: true },
            None => Kind::Counter { block, var: name.to_string(), bound: false },
        },
        _ => Kind::Other,
    }
}

/// Finds the state variables of `header` (a generated `flight_plan.h`) and of the runtime whose
/// declarations are `runtime_h` (`fp_stub.h`), and writes the registration lines.
pub fn discover(header: &str, runtime_h: &str) -> Discovery {
    let mut vars = Vec::new();
    let mut runtime_registrations = String::new();
    for d in declarations(&tokens(runtime_h)).iter().filter(|d| d.external) {
        for name in &d.names {
            let id = vars.len();
            let _ = writeln!(runtime_registrations, "VOUCH_REGISTER({id}, {name})");
            vars.push(CVar { id, name: name.to_string(), kind: kind_of(name, d), runtime: true });
        }
    }
    let mut after_line: Vec<Vec<String>> = vec![Vec::new(); header.lines().count() + 1];
    for d in declarations(&tokens(header)).iter().filter(|d| !d.external) {
        for name in &d.names {
            let id = vars.len();
            let kind = kind_of(name, d);
            // the runtime's names are the runtime's, even if the header declares them again
            let kind = if d.function.is_none() && kind != Kind::Other { Kind::Other } else { kind };
            if let Some(slot) = after_line.get_mut(d.end_line) {
                slot.push(format!("VOUCH_REGISTER({id}, {name})"));
            }
            vars.push(CVar { id, name: name.to_string(), kind, runtime: false });
        }
    }
    let mut registered_header = String::with_capacity(header.len() + 64 * vars.len());
    for (n, line) in header.lines().enumerate() {
        registered_header.push_str(line);
        registered_header.push('\n');
        for r in &after_line[n] {
            registered_header.push_str(r);
            registered_header.push('\n');
        }
    }
    Discovery { vars, registered_header, runtime_registrations }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RUNTIME: &str = "/* c */\n#ifndef X\nextern uint8_t nav_block, nav_stage, last_block, last_stage, last_wp;\nextern uint16_t stage_time, block_time;\nvoid nav_init_stage(void);\n#define Block(x) case x: set_nav_block(x);\n";

    const HEADER: &str = r#"#define FOO "a;b"
extern float v;
static inline bool InsideA(float _x, float _y) {
  uint8_t i, j;
  const uint8_t wps_id[] = { 1, 2 };
  return i > j;
}
#ifdef NAV_C
float v = FP_I("0.");
int a = 1, b[3] = { 1, 2, 3 };
static abi_event FP_x_ev;
static inline void auto_nav(void) {
  switch (nav_block) {
    Block(0) // "static" in a comment
    switch(nav_stage) {
      Stage(0)
        FP_X("static int fake;");
        break;
      static int8_t _var_i;
      static int8_t _var_i_to;
      Stage(1)
        _var_i = FP_V("1") - 1;
    }
    Block(3)
    switch(nav_stage) {
        static int8_t _var_k; static int8_t _var_k_to;
    }
  }
}
#endif
"#;

    #[test]
    fn finds_every_static_with_its_kind() {
        let d = discover(HEADER, RUNTIME);
        let names: Vec<(&str, &Kind, bool)> =
            d.vars.iter().map(|v| (v.name.as_str(), &v.kind, v.runtime)).collect();
        let counter = |block, var: &str, bound| Kind::Counter { block, var: var.into(), bound };
        assert_eq!(
            names,
            vec![
                ("nav_block", &Kind::Block, true),
                ("nav_stage", &Kind::Stage, true),
                ("last_block", &Kind::LastBlock, true),
                ("last_stage", &Kind::LastStage, true),
                ("last_wp", &Kind::LastWp, true),
                ("stage_time", &Kind::Other, true),
                ("block_time", &Kind::Other, true),
                ("v", &Kind::Other, false),
                ("a", &Kind::Other, false),
                ("b", &Kind::Other, false),
                ("FP_x_ev", &Kind::Other, false),
                ("_var_i", &counter(0, "_var_i", false), false),
                ("_var_i_to", &counter(0, "_var_i", true), false),
                ("_var_k", &counter(3, "_var_k", false), false),
                ("_var_k_to", &counter(3, "_var_k", true), false),
            ]
        );
        assert!(d.runtime_registrations.starts_with("VOUCH_REGISTER(0, nav_block)\n"));
    }

    #[test]
    fn every_declaration_form_of_plan_variables() {
        // the forms `<type> <var> = <init>;` takes with the types and names plans use
        let header = "#ifdef NAV_C\nuint8_t buf[4] = FP_I(\"{0}\");\nfloat m[2][3] = FP_I(\"{{0}}\");\nfloat *p = FP_I(\"0\");\nvoid (*cb)(void) = FP_I(\"0\");\nint (*rows)[4] = FP_I(\"0\");\nconst int k = FP_I(\"3\"), *q = FP_I(\"0\");\nvolatile bool flag = FP_I(\"false\");\nstruct point { float x, y; } pt = FP_I(\"{0}\");\nint f(int a);\nint (g)(int);\n#endif\n";
        let d = discover(header, RUNTIME);
        let names: Vec<&str> =
            d.vars.iter().filter(|v| !v.runtime).map(|v| v.name.as_str()).collect();
        assert_eq!(names, ["buf", "m", "p", "cb", "rows", "k", "q", "flag", "pt"]);
        assert!(
            d.registered_header
                .contains("void (*cb)(void) = FP_I(\"0\");\nVOUCH_REGISTER(10, cb)\n")
        );
    }

    #[test]
    fn registrations_follow_their_declarations() {
        let d = discover(HEADER, RUNTIME);
        let h = &d.registered_header;
        assert!(h.contains("float v = FP_I(\"0.\");\nVOUCH_REGISTER(7, v)\n"));
        assert!(h.contains("static int8_t _var_i;\nVOUCH_REGISTER(11, _var_i)\n"));
        assert!(h.contains(
            "static int8_t _var_k; static int8_t _var_k_to;\nVOUCH_REGISTER(13, _var_k)\nVOUCH_REGISTER(14, _var_k_to)\n"
        ));
        // the original text is kept line for line
        let stripped: String = h
            .lines()
            .filter(|l| !l.starts_with("VOUCH_REGISTER"))
            .map(|l| format!("{l}\n"))
            .collect();
        assert_eq!(stripped, HEADER);
    }
}
