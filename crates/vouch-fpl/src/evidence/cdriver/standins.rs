//! Opaque stand-ins for the types of plan variables that the validation build cannot see.
//!
//! A plan variable is declared `<type> <var> = <init>;` with any type the airframe's C knows:
//! often a structure or a `typedef` name from a module header the plan's `<header>` includes
//! (`struct EnuCoor_i`, `EnuCoor_f`). The instrumented header carries the `<header>` text as a
//! marker, and the stub runtime has no module headers, so those names are unknown to the
//! validation build. The variables' values are never computed with there (conditions, code and
//! initialisers are recorded texts: `FP_C`, `FP_X`, `FP_I`), so any complete type of that name
//! serves: each unknown `struct`/`union` tag gets a definition holding a few opaque bytes, each
//! unknown `enum` tag one enumerator, each unknown type name a `typedef` of such a structure.
//! The driver is compiled with these definitions first (`-include vouch_types.h`); the
//! variables stay C state (their bytes are compared like any other).

/// Bytes of an opaque stand-in: a stand-in's bytes never change (no code writes them), so
/// the size only costs state bytes.
const OPAQUE_BYTES: usize = 8;

/// Keywords that may appear in a declaration's specifiers without naming a type.
const QUALIFIERS: &[&str] =
    &["const", "volatile", "restrict", "static", "extern", "register", "inline", "_Atomic"];

/// Keywords that are type specifiers.
const BASIC: &[&str] = &[
    "void", "char", "short", "int", "long", "float", "double", "signed", "unsigned", "_Bool",
    "bool",
];

/// Type names the C library headers the stub includes declare (`stdint.h`, `stddef.h`).
fn library_type(name: &str) -> bool {
    let int = |n: &str| {
        let n = n.strip_prefix('u').unwrap_or(n);
        let n = n.strip_prefix("int").and_then(|n| n.strip_suffix("_t"));
        n.is_some_and(|w| {
            let w = w.strip_prefix("_least").or_else(|| w.strip_prefix("_fast")).unwrap_or(w);
            matches!(w, "8" | "16" | "32" | "64" | "ptr" | "max")
        })
    };
    int(name) || matches!(name, "size_t" | "ptrdiff_t" | "wchar_t" | "ssize_t")
}

fn identifiers(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(start) = rest.find(|c: char| c.is_ascii_alphabetic() || c == '_') {
        let s = &rest[start..];
        let len = s.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(s.len());
        // an identifier directly after a digit is part of a number (`1e5`, `0x1f`)
        let after_digit = rest[..start].ends_with(|c: char| c.is_ascii_digit());
        if !after_digit {
            out.push(&s[..len]);
        }
        rest = &s[len..];
    }
    out
}

/// What a declaration's specifiers name: tags (`struct X` as ("struct", "X")) and a typedef
/// name, if any. Stops at the declarator: the first `*`, `(`, `[` or the name after a type.
fn specifiers(decl: &str) -> (Vec<(&str, &str)>, Option<&str>) {
    let head = decl.split(['*', '(', '[', '=']).next().unwrap_or("");
    let words = identifiers(head);
    let (mut tags, mut typedef, mut typed) = (Vec::new(), None, false);
    let mut i = 0;
    while i < words.len() {
        let w = words[i];
        if matches!(w, "struct" | "union" | "enum") {
            if let Some(tag) = words.get(i + 1) {
                tags.push((w, *tag));
            }
            typed = true;
            i += 2;
            continue;
        }
        if BASIC.contains(&w) {
            typed = true;
        } else if !QUALIFIERS.contains(&w) {
            if typed {
                break;
            }
            typedef = Some(w);
            typed = true;
        }
        i += 1;
    }
    (tags, typedef)
}

/// The statements of C text, split at `;` outside braces (a `typedef struct { … } T;` is one).
fn statements(text: &str) -> Vec<&str> {
    let (mut out, mut depth, mut start) = (Vec::new(), 0usize, 0);
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth = depth.saturating_sub(1),
            ';' if depth == 0 => {
                out.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out
}

/// The names `texts` (C headers) define: structure, union and enum tags with a body, and
/// `typedef` names.
fn defined(texts: &[&str]) -> (Vec<String>, Vec<String>) {
    let (mut tags, mut names) = (Vec::new(), Vec::new());
    for text in texts {
        for stmt in statements(text) {
            let words = identifiers(stmt);
            for (i, w) in words.iter().enumerate() {
                if matches!(*w, "struct" | "union" | "enum")
                    && let Some(tag) = words.get(i + 1)
                    && stmt.contains('{')
                {
                    tags.push(format!("{w} {tag}"));
                }
            }
            if words.contains(&"typedef")
                && let Some(last) = words.last()
            {
                names.push((*last).to_string());
            }
        }
    }
    (tags, names)
}

/// The stand-in definitions for the plan variables of `header` (an instrumented header: its
/// `extern <type> <var>;` lines) whose types neither C nor `known` (the texts of the stub
/// runtime's headers) define.
pub fn standins(header: &str, known: &[&str]) -> String {
    let (known_tags, known_names) = defined(known);
    let mut tags: Vec<String> = Vec::new();
    let mut names: Vec<String> = Vec::new();
    for line in header.lines() {
        let Some(decl) = line.strip_prefix("extern ").and_then(|l| l.trim_end().strip_suffix(';'))
        else {
            continue;
        };
        let (t, n) = specifiers(decl);
        for (kind, tag) in t {
            let full = format!("{kind} {tag}");
            if !known_tags.contains(&full) && !tags.contains(&full) {
                tags.push(full);
            }
        }
        if let Some(n) = n.filter(|n| !library_type(n) && !known_names.iter().any(|k| k == n))
            && !names.iter().any(|k| k == n)
        {
            names.push(n.to_string());
        }
    }
    let mut out = String::from("/* opaque stand-ins for the types of plan variables */\n");
    for t in &tags {
        if let Some(tag) = t.strip_prefix("enum ") {
            out.push_str(&format!("enum {tag} {{ vouch_opaque_enum_{tag} }};\n"));
        } else {
            out.push_str(&format!("{t} {{ unsigned char vouch_opaque[{OPAQUE_BYTES}]; }};\n"));
        }
    }
    for n in &names {
        out.push_str(&format!(
            "typedef struct {{ unsigned char vouch_opaque[{OPAQUE_BYTES}]; }} {n};\n"
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_tags_and_type_names_get_stand_ins() {
        let header = "extern struct EnuCoor_i wps[3];\nextern EnuCoor_f cfg;\n\
            extern const struct Foo *const p;\nextern enum Mode m;\nextern union U u;\n\
            extern uint8_t buf[4];\nextern unsigned n;\nextern volatile int32_t c;\n\
            extern void (*cb)(void);\nextern struct stub_point q;\nextern abi_event ev;\n\
            extern const char * names[];\nextern my_t *(*table[2])(my_t);\n";
        let known = "struct stub_point { float x; };\ntypedef struct { int u; } abi_event;\n";
        let s = standins(header, &[known]);
        for want in [
            "struct EnuCoor_i { unsigned char vouch_opaque[8]; };",
            "struct Foo { unsigned char vouch_opaque[8]; };",
            "union U { unsigned char vouch_opaque[8]; };",
            "enum Mode { vouch_opaque_enum_Mode };",
            "typedef struct { unsigned char vouch_opaque[8]; } EnuCoor_f;",
            "typedef struct { unsigned char vouch_opaque[8]; } my_t;",
        ] {
            assert!(s.contains(want), "{want} in\n{s}");
        }
        for not in ["stub_point", "abi_event", "uint8_t", "int32_t", " n;", "cb", "names"] {
            assert!(!s.contains(not), "{not} in\n{s}");
        }
    }
}
