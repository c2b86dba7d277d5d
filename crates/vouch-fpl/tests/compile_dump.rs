//! `vouch fpl compile --dump`: the dump holds the expanded, numbered plan (procedures included,
//! paths expanded, HOME appended, `no` on blocks and stages) and the `<stages>` index. Its
//! `<flight_plan>` element, without the appended HOME block (the front end appends it again),
//! parses again with vouch's own front end into the same plan: same blocks, stages, waypoints,
//! exceptions, and the same compiled `auto_nav` and tables.

mod common;

use std::path::{Path, PathBuf};

use vouch_fpl::ast::{FlightPlan, Stage, StageKind};
use vouch_fpl::emit::{compile_plan, dump::dump, EmitOptions};
use vouch_fpl::front::{parse_file, parse_str};

fn count_stages(list: &[Stage]) -> usize {
    list.iter()
        .map(|s| match &s.kind {
            StageKind::While(w) => 1 + count_stages(&w.body),
            StageKind::For(f) => 1 + count_stages(&f.body),
            _ => 1,
        })
        .sum()
}

/// `<flight_plan …>…</flight_plan>` of the dump, without the last (appended HOME) block.
fn reparsable_plan(dump_text: &str, home_no: usize) -> Result<String, String> {
    let start = dump_text.find("<flight_plan").ok_or("no <flight_plan> in the dump")?;
    let end = dump_text.find("</flight_plan>").ok_or("no </flight_plan> in the dump")?
        + "</flight_plan>".len();
    let fp = &dump_text[start..end];
    let home = format!("<block name=\"HOME\" no=\"{home_no}\">");
    let h = fp.find(&home).ok_or_else(|| format!("no {home} in the dump"))?;
    let close = fp[h..].find("</block>").ok_or("HOME block not closed")? + h + "</block>".len();
    Ok(format!("{}{}", &fp[..h], &fp[close..]))
}

/// The compiled header from `#define FLIGHT_PLAN_NAME` on (the banner names the file, and the
/// `<header>` text loses its whitespace-only lines on the way, as upstream's reader does).
fn compiled_body(plan: &FlightPlan) -> Result<String, String> {
    let opts = EmitOptions { source_path: "plan.xml".into(), ..EmitOptions::default() };
    let h = compile_plan(plan, &opts).map_err(|e| format!("{e:?}"))?;
    let at = h.find("#define FLIGHT_PLAN_NAME").ok_or("no FLIGHT_PLAN_NAME")?;
    Ok(h[at..].to_string())
}

fn check(path: &Path) -> Result<(), String> {
    let plan = parse_file(path).map_err(|e| e.to_string())?;
    let text = dump(&plan);
    let n = plan.blocks.len();
    // The numbered parts upstream's GCS reads.
    for (i, b) in plan.blocks.iter().enumerate() {
        let tag = format!("no=\"{i}\"");
        if !text.contains(&format!("name=\"{}\"", b.name.value)) || !text.contains(&tag) {
            return Err(format!("block {i} ({}) not numbered in the dump", b.name.value));
        }
    }
    if !text.contains("<stages>") {
        return Err("no <stages> index".into());
    }
    let again = parse_str("dump.xml", &reparsable_plan(&text, n - 1)?)
        .map_err(|e| format!("re-parse: {e}"))?;
    if again.blocks.len() != n {
        return Err(format!("{} blocks after re-parse, {n} before", again.blocks.len()));
    }
    for (a, b) in plan.blocks.iter().zip(&again.blocks) {
        if a.name.value != b.name.value
            || count_stages(&a.stages) != count_stages(&b.stages)
            || a.exceptions.len() != b.exceptions.len()
        {
            return Err(format!("block {} differs after re-parse", a.name.value));
        }
    }
    if plan.waypoints.len() != again.waypoints.len()
        || plan.exceptions.len() != again.exceptions.len()
    {
        return Err("waypoints or global exceptions differ after re-parse".into());
    }
    if compiled_body(&plan)? != compiled_body(&again)? {
        return Err("the re-parsed dump compiles to a different header".into());
    }
    Ok(())
}

#[test]
fn demo_dump_reparses_into_the_same_plan() {
    let demo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fpl/demo.xml");
    check(&demo).unwrap_or_else(|e| panic!("demo: {e}"));
    let text = dump(&parse_file(&demo).expect("demo parses"));
    // Demo: "Wait GPS" is set (0) + while (test 1, loop-back 2), so the index names stage 1.
    assert!(
        text.contains("<stage block=\"0\" block_name=\"Wait GPS\" stage=\"1\"><while/></stage>"),
        "{text}"
    );
    assert!(text.contains("<while cond=\"!GpsFixValid()\" no=\"1\"/>"), "{text}");
}

#[test]
fn every_corpus_dump_reparses_into_the_same_plan() {
    let Some(dir) = common::corpus_dir() else { return };
    let plans: Vec<PathBuf> = common::corpus_plans(&dir);
    let failures: Vec<String> = plans
        .iter()
        .filter_map(|p| check(p).err().map(|e| format!("{}: {e}", p.display())))
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} dumps failed:\n{}",
        failures.len(),
        plans.len(),
        failures.join("\n")
    );
}
