//! `<includes>` expansion, mirroring upstream's `fp_proc`:
//! * the procedure is searched in the including plan's directory, then in the search
//!   directories (upstream: `conf/flight_plans`);
//! * `<param>`s take the `<arg>` value, else their `default_value` (neither is fatal);
//! * waypoints, blocks, modules, variables, exceptions and sectors are appended after the main
//!   plan's; the header becomes `main + "\n" + procedure`;
//! * blocks are renamed `Name.block`; `deroute` targets become the `<with>` target or
//!   `Name.target`; `IndexOfBlock(x)` becomes `IndexOfBlock('Name.x')`;
//! * nearly every stage attribute is parsed, substituted and re-printed (raw C texts too), and
//!   `guided`, `survey_rectangle`, `oval`, `home`, `follow`, `path` are refused.

use std::path::{Path, PathBuf};

use crate::ast::{Attrs, IncludeInfo, NameValue, RawAttr, Text};
use crate::diag::ErrorKind;
use crate::expr::{ProcEnv, parse, print_upstream, subst_procedure};
use crate::span::{FileId, Span};

use super::ctx::Ctx;
use super::tree::{Elem, read_document};

/// The plan's lists after include expansion (main plan's elements first).
#[derive(Default)]
pub struct Merged {
    pub header: Option<(String, Span)>,
    pub waypoints: Vec<Elem>,
    pub sectors: Vec<Elem>,
    pub variables: Vec<Elem>,
    pub modules: Vec<Elem>,
    pub exceptions: Vec<Elem>,
    pub blocks: Vec<Elem>,
    pub forbidden: Vec<Elem>,
    pub includes: Vec<IncludeInfo>,
}

fn children_of(root: &Elem, tag: &str) -> Vec<Elem> {
    root.children
        .iter()
        .filter(|c| c.tag_is(tag))
        .flat_map(|c| c.children.iter().cloned())
        .collect()
}

/// The text of a `<header>` as upstream's reader leaves it: `None` when the element holds no
/// text at all (xml-light drops whitespace-only text; a DTD-validated `#PCDATA` element gets an
/// empty text instead).
fn header_text(h: &Elem, validated: bool) -> Option<String> {
    (!h.text.is_empty() || validated).then(|| h.text.clone())
}

/// Collects the main plan's lists and appends every included procedure.
pub fn expand(ctx: &mut Ctx, root: &Elem, validated: bool) -> Merged {
    let main_header = root.child("header");
    let mut m = Merged {
        header: main_header.and_then(|h| header_text(h, validated).map(|t| (t, h.span))),
        waypoints: children_of(root, "waypoints"),
        sectors: children_of(root, "sectors"),
        variables: children_of(root, "variables"),
        modules: children_of(root, "modules"),
        exceptions: children_of(root, "exceptions"),
        blocks: children_of(root, "blocks"),
        forbidden: children_of(root, "forbidden_deroutes"),
        includes: Vec::new(),
    };
    let includes = children_of(root, "includes");
    if let (Some(h), None, false) = (main_header, &m.header, includes.is_empty()) {
        empty_header(ctx, h.span, "the plan");
    }
    for inc in includes {
        if !inc.tag_is("include") {
            continue; // reported by the schema check
        }
        include_one(ctx, &inc, &mut m);
    }
    m
}

/// Upstream concatenates the plan's and the procedures' header texts and crashes
/// (`Invalid_argument "index out of bounds"`) on a `<header>` without any text.
fn empty_header(ctx: &mut Ctx, span: Span, whose: &str) {
    ctx.error_help(
        ErrorKind::MissingElement,
        format!("empty <header> in {whose}: upstream cannot merge it with an included procedure's"),
        span,
        "upstream's generator fails here with Invalid_argument(\"index out of bounds\"); remove the element or give it a text",
    );
}

fn text_of(a: &RawAttr) -> Text {
    Text { value: a.value.clone(), span: a.value_span }
}

fn find_procedure(search: &[PathBuf], name: &str) -> Option<PathBuf> {
    let p = Path::new(name);
    if p.is_absolute() {
        return p.is_file().then(|| p.to_path_buf());
    }
    search.iter().map(|d| d.join(name)).find(|c| c.is_file())
}

fn include_one(ctx: &mut Ctx, inc: &Elem, m: &mut Merged) {
    let (Some(name_a), Some(proc_a)) = (inc.attr("name").cloned(), inc.attr("procedure").cloned())
    else {
        ctx.error(
            ErrorKind::MissingAttribute,
            "<include> needs both 'name' and 'procedure'",
            inc.span,
        );
        return;
    };
    let name = name_a.value.clone();
    let Some((file, proc)) = load_procedure(ctx, &proc_a) else { return };

    let attr_pairs = |tag: &str, k: &str, v: &str| -> Vec<NameValue> {
        inc.children
            .iter()
            .filter(|c| c.tag_is(tag))
            .filter_map(|c| {
                Some(NameValue {
                    name: text_of(c.attr(k)?),
                    value: c.attr(v).map(text_of),
                    span: c.span,
                })
            })
            .collect()
    };
    let args = attr_pairs("arg", "name", "value");
    let withs = attr_pairs("with", "from", "to");

    let params = parameters(ctx, inc, &proc, &proc_a, &args);
    let reroutes: Vec<(String, String)> = withs
        .iter()
        .map(|w| {
            (w.name.value.clone(), w.value.as_ref().map(|t| t.value.clone()).unwrap_or_default())
        })
        .collect();
    let tr = Transformer { name: &name, params: &params, reroutes: &reroutes };

    let proc_header = proc.child("header");
    let header_text = match proc_header.map(|h| header_text(h, false)) {
        Some(Some(t)) => t,
        Some(None) => {
            empty_header(ctx, proc_header.map_or(inc.span, |h| h.span), "a procedure");
            String::new()
        }
        None => String::new(),
    };
    let (main_h, h_span) = m.header.take().unwrap_or((String::new(), inc.span));
    m.header = Some((format!("{main_h}\n{header_text}"), h_span));

    let mut tag_origin = |mut e: Elem| {
        e.origin = Some(name.clone());
        e
    };
    m.waypoints.extend(children_of(&proc, "waypoints").into_iter().map(&mut tag_origin));
    for b in children_of(&proc, "blocks") {
        if let Some(b) = tr.block(ctx, b) {
            m.blocks.push(tag_origin(b));
        }
    }
    m.modules.extend(children_of(&proc, "modules"));
    m.variables.extend(children_of(&proc, "variables"));
    for e in children_of(&proc, "exceptions") {
        if let Some(e) = tr.exception(ctx, e) {
            m.exceptions.push(tag_origin(e));
        }
    }
    m.sectors.extend(children_of(&proc, "sectors"));
    m.includes.push(IncludeInfo {
        name: text_of(&name_a),
        procedure: text_of(&proc_a),
        file,
        args,
        withs,
        span: inc.span,
    });
}

/// Finds, reads and parses the procedure file an include names (its nested includes are
/// checked for loops, not expanded, as upstream does).
fn load_procedure(ctx: &mut Ctx, proc_a: &RawAttr) -> Option<(FileId, Elem)> {
    let search = if ctx.opts.upstream_includes { upstream_search(ctx) } else { ctx.search.clone() };
    let found = find_procedure(&search, &proc_a.value);
    if !ctx.opts.upstream_includes {
        warn_other_choice(ctx, proc_a, found.as_deref());
    }
    let Some(path) = found else {
        let dirs: Vec<String> = search.iter().map(|d| d.display().to_string()).collect();
        ctx.error_help(
            ErrorKind::IncludeNotFound,
            format!("procedure file '{}' not found", proc_a.value),
            proc_a.value_span,
            format!("searched: {}", dirs.join(", ")),
        );
        return None;
    };
    if same_file(&path, &ctx.main_path) {
        ctx.error(
            ErrorKind::IncludeLoop,
            format!("'{}' includes the plan itself", proc_a.value),
            proc_a.value_span,
        );
        return None;
    }
    let text = match std::fs::read(&path) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) => {
            ctx.error(
                ErrorKind::IncludeNotFound,
                format!("cannot read '{}': {e}", path.display()),
                proc_a.value_span,
            );
            return None;
        }
    };
    let file = ctx.sources.add(path.display().to_string(), text);
    let doc = match read_document(file, &ctx.sources.files[file.0 as usize].text) {
        Ok(d) => d,
        Err(d) => {
            ctx.push(*d);
            return None;
        }
    };
    ctx.warnings.extend(doc.warnings);
    let proc = doc.root;
    check_nested_includes(ctx, &proc, &path);
    Some((file, proc))
}

/// The parameter environment of one include: argument, else default value, else an error.
fn parameters(
    ctx: &mut Ctx,
    inc: &Elem,
    proc: &Elem,
    proc_a: &RawAttr,
    args: &[NameValue],
) -> Vec<(String, String)> {
    let mut params: Vec<(String, String)> = Vec::new();
    for p in proc.children.iter().filter(|c| c.tag_is("param")) {
        let Some(pn) = p.attr_value("name") else {
            ctx.error(ErrorKind::MissingAttribute, "<param> without 'name'", p.span);
            continue;
        };
        let arg = args
            .iter()
            .find(|a| a.name.value == pn)
            .and_then(|a| a.value.as_ref())
            .map(|t| t.value.clone());
        match arg.or_else(|| p.attr_value("default_value").map(str::to_string)) {
            Some(v) => params.push((pn.to_string(), v)),
            None => ctx.error(
                ErrorKind::MissingParam,
                format!("value required for parameter '{pn}' of procedure '{}'", proc_a.value),
                inc.span,
            ),
        }
    }
    params
}

/// Upstream's search path (`fp_proc.ml`: `find_file [dir; Env.flight_plans_path]`).
fn upstream_search(ctx: &Ctx) -> Vec<PathBuf> {
    let mut dirs = vec![ctx.main_path.parent().map(Path::to_path_buf).unwrap_or_default()];
    dirs.extend(ctx.opts.upstream_flight_plans.clone());
    dirs
}

/// Where upstream's search order finds another file than vouch's: a warning naming both.
fn warn_other_choice(ctx: &mut Ctx, proc_a: &RawAttr, ours: Option<&Path>) {
    let Some(ours) = ours else { return };
    let Some(theirs) = find_procedure(&upstream_search(ctx), &proc_a.value) else { return };
    if same_file(ours, &theirs) {
        return;
    }
    let same_text =
        std::fs::read(ours).ok().is_some_and(|a| std::fs::read(&theirs).ok() == Some(a));
    let d = crate::diag::Diagnostic::warning(
        format!(
            "procedure '{}': vouch includes {}, upstream's generator would include {}{}",
            proc_a.value,
            ours.display(),
            theirs.display(),
            if same_text { " (same text)" } else { "" }
        ),
        Some(proc_a.value_span),
    )
    .with_help(
        "upstream searches the plan's directory, then $PAPARAZZI_HOME/conf/flight_plans; \
         --upstream-compat includes what upstream does, --include-dir chooses the directory",
    );
    ctx.push(d);
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Upstream does not expand includes found inside a procedure. One that points back to the
/// procedure itself or to the main plan would be a loop: that is reported as an error; others
/// are ignored with a warning, as upstream ignores them.
fn check_nested_includes(ctx: &mut Ctx, proc: &Elem, proc_path: &Path) {
    for inc in children_of(proc, "includes") {
        let Some(p) = inc.attr("procedure") else { continue };
        let mut dirs = vec![proc_path.parent().map(Path::to_path_buf).unwrap_or_default()];
        dirs.extend(ctx.search.iter().cloned());
        let target = find_procedure(&dirs, &p.value);
        let looping = target
            .as_deref()
            .is_some_and(|t| same_file(t, proc_path) || same_file(t, &ctx.main_path));
        if looping {
            ctx.error(
                ErrorKind::IncludeLoop,
                format!("include loop: '{}' is already being included", p.value),
                p.value_span,
            );
        } else {
            ctx.warn("includes inside a procedure are ignored (as upstream does)", inc.span);
        }
    }
}

struct Transformer<'a> {
    name: &'a str,
    params: &'a [(String, String)],
    reroutes: &'a [(String, String)],
}

impl Transformer<'_> {
    fn env(&self) -> ProcEnv<'_> {
        ProcEnv { name: self.name, params: self.params }
    }

    /// Parses, substitutes and re-prints every attribute not in `keep`.
    fn values(&self, ctx: &mut Ctx, attrs: &mut Attrs, keep: &[&str]) -> bool {
        let mut ok = true;
        for a in attrs.0.iter_mut() {
            if keep.contains(&a.name.as_str()) {
                continue;
            }
            match parse(&a.value) {
                Ok(e) => a.value = print_upstream(&subst_procedure(&e, &self.env())),
                Err(err) => {
                    ok = false;
                    ctx.error_help(
                        ErrorKind::BadExpression,
                        format!("in procedure '{}': attribute '{}': cannot parse '{}': {err}", self.name, a.name, a.value),
                        a.value_span,
                        "inside procedures upstream parses and re-prints nearly every attribute, raw C texts included",
                    );
                }
            }
        }
        ok
    }

    /// `deroute`/`block` target: `<with>` target or `Name.target`.
    fn reroute(&self, attrs: &mut Attrs, key: &str) {
        for a in attrs.0.iter_mut().filter(|a| a.name == key) {
            a.value = match self.reroutes.iter().find(|(f, _)| *f == a.value) {
                Some((_, to)) => to.clone(),
                None => format!("{}.{}", self.name, a.value),
            };
        }
    }

    fn exception(&self, ctx: &mut Ctx, mut e: Elem) -> Option<Elem> {
        self.reroute(&mut e.attrs, "deroute");
        self.values(ctx, &mut e.attrs, &[]).then_some(e)
    }

    fn block(&self, ctx: &mut Ctx, mut b: Elem) -> Option<Elem> {
        let name = b.attr_value("name").map(str::to_string);
        match name {
            // Upstream's `subst_attrib`: the renamed attribute moves to the end.
            Some(n) => b.subst_attr("name", format!("{}.{n}", self.name)),
            None => {
                ctx.error(ErrorKind::MissingAttribute, "<block> without 'name'", b.span);
                return None;
            }
        }
        let stages = std::mem::take(&mut b.children);
        b.children = stages.into_iter().filter_map(|s| self.stage(ctx, s)).collect();
        Some(b)
    }

    fn stage(&self, ctx: &mut Ctx, mut s: Elem) -> Option<Elem> {
        let tag = s.tag.to_ascii_lowercase();
        let leaf = ["exception", "heading", "go", "xyz", "circle", "deroute", "stay"];
        if leaf.contains(&tag.as_str()) && !s.children.is_empty() {
            ctx.error_help(
                ErrorKind::ProcedureStage,
                format!("<{}> in procedure '{}' has child elements", s.tag, self.name),
                s.span,
                "upstream's procedure expansion asserts that this stage is empty (Assertion failed)",
            );
            return None;
        }
        let keep: &[&str] = match tag.as_str() {
            "exception" => return self.exception(ctx, s),
            "while" | "for" => {
                let ok = self.values(ctx, &mut s.attrs, &[]);
                let body = std::mem::take(&mut s.children);
                s.children = body.into_iter().filter_map(|c| self.stage(ctx, c)).collect();
                return ok.then_some(s);
            }
            "deroute" => {
                self.reroute(&mut s.attrs, "block");
                return Some(s);
            }
            "heading" | "attitude" => &["vmode"],
            "go" => &["wp", "from", "hmode", "vmode"],
            "xyz" => &[],
            "circle" => &["wp", "hmode", "vmode"],
            "eight" => &["center", "turn_around", "radius"],
            "stay" => &["wp", "vmode"],
            "call" | "call_once" | "set" => &["var"],
            "return" => &["reset_stage"],
            _ => {
                ctx.error(
                    ErrorKind::ProcedureStage,
                    format!("stage '<{}>' is not supported inside a procedure (upstream: Unexpected tag)", s.tag),
                    s.span,
                );
                return None;
            }
        };
        self.values(ctx, &mut s.attrs, keep).then_some(s)
    }
}
