//! `vouch fpl diff` on pairs made from the Paparazzi corpus: every plan against a reformatted
//! copy and against a consistent waypoint rename (equivalent), and a catalogue of mutants of
//! `basic.xml` (different), each with its first divergence written by hand from upstream's
//! own header for that plan (`../shared/fpl/upstream/headers/basic.h`: the condition and code
//! texts, block and waypoint numbers), not from the code under test.

#[path = "support/reformat.rs"]
mod reformat;

use std::path::{Path, PathBuf};

use vouch_fpl::diff::{DiffOptions, DiffReport, PartingKind, Verdict, Version, diff};
use vouch_fpl::front::{Options, parse_file_with};

/// A copy of the corpus (so that copies of plans sit where their DTD and procedures are).
fn corpus_copy() -> Option<(tempfile::TempDir, Vec<String>)> {
    let root = vouch_testkit::shared("fpl/corpus", "INDEX.tsv")?;
    let dir = tempfile::tempdir().expect("tempdir");
    copy_tree(&root, dir.path());
    let index = std::fs::read_to_string(root.join("INDEX.tsv")).expect("index");
    let plans = index
        .lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            (f.get(1) == Some(&"flight_plan") && f.get(6) == Some(&"yes")).then(|| f[0].to_string())
        })
        .collect();
    Some((dir, plans))
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("mkdir");
    for e in std::fs::read_dir(from).expect("read_dir") {
        let e = e.expect("entry");
        let target = to.join(e.file_name());
        if e.file_type().expect("type").is_dir() {
            copy_tree(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), &target).expect("copy");
        }
    }
}

fn compare(old: &Path, new: &Path, jumps: bool) -> DiffReport {
    let opts = Options::default();
    let parse = |p: &Path| {
        parse_file_with(p, &opts)
            .unwrap_or_else(|e| panic!("{}: {}", p.display(), e.items[0].message))
    };
    let (a, b) = (parse(old), parse(new));
    let fa = vouch_fpl::passes::lower::lower(&a).expect("lowers");
    let fb = vouch_fpl::passes::lower::lower(&b).expect("lowers");
    let o = DiffOptions { operator_jumps: jumps, ..DiffOptions::default() };
    diff(Version { plan: &a, fp: &fa }, Version { plan: &b, fp: &fb }, &o).expect("runs")
}

fn sibling(p: &Path, suffix: &str) -> PathBuf {
    p.with_file_name(format!(
        "{}.{suffix}.xml",
        p.file_stem().and_then(|s| s.to_str()).unwrap_or("x")
    ))
}

#[test]
fn every_corpus_plan_equals_its_reformatted_copy() {
    let Some((dir, plans)) = corpus_copy() else { return };
    assert_eq!(plans.len(), 104);
    for rel in &plans {
        let path = dir.path().join(rel);
        let text = std::fs::read_to_string(&path).expect("read");
        let copy = sibling(&path, "reformatted");
        let re = reformat::reformat(&text);
        assert_ne!(re, text);
        std::fs::write(&copy, re).expect("write");
        let r = compare(&path, &copy, true);
        assert_eq!(r.verdict, Verdict::Equivalent, "{rel}: {}", vouch_fpl::diff::render(&r));
        assert!(r.structure.is_empty(), "{rel}: {}", vouch_fpl::diff::summary(&r.structure));
        assert!(r.state_pairs >= 1 && r.transitions >= 1);
    }
}

/// Renames waypoint `from` to `to` everywhere a plan names it: the waypoint and sector corner
/// `name`, every waypoint attribute of the stages, `<path wpts>`, and `WP_from` in C texts.
fn rename_waypoint(text: &str, from: &str, to: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find('<') {
        out.push_str(&rest[..start]);
        let end = rest[start..].find('>').map_or(rest.len(), |e| start + e + 1);
        out.push_str(&rename_in_tag(&rest[start..end], from, to));
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

fn rename_in_tag(tag: &str, from: &str, to: &str) -> String {
    let lower = tag.to_ascii_lowercase();
    let is_wp = lower.starts_with("<waypoint ") || lower.starts_with("<corner ");
    let mut names = vec!["wp", "from", "center", "turn_around", "p1", "p2", "wp1", "wp2"];
    if is_wp {
        names.push("name");
    }
    let mut t = tag.to_string();
    for n in names {
        for q in ['"', '\''] {
            for sp in ["", " "] {
                let pat = format!(" {n}{sp}={sp}{q}{from}{q}");
                t = t.replace(&pat, &format!(" {n}{sp}={sp}{q}{to}{q}"));
                let upper = format!(" {}{sp}={sp}{q}{from}{q}", n.to_ascii_uppercase());
                t = t.replace(&upper, &format!(" {}{sp}={sp}{q}{to}{q}", n.to_ascii_uppercase()));
            }
        }
    }
    // <path wpts="A, B C">: names separated by blanks and commas.
    if let Some(i) = lower.find("wpts=") {
        let q = t[i + 5..].chars().next().unwrap_or('"');
        if let Some(len) = t[i + 6..].find(q) {
            let list = &t[i + 6..i + 6 + len];
            let renamed: String = list
                .split_inclusive([' ', ',', '\t'])
                .map(|w| {
                    let name = w.trim_end_matches([' ', ',', '\t']);
                    if name == from { format!("{to}{}", &w[name.len()..]) } else { w.to_string() }
                })
                .collect();
            t = format!("{}{renamed}{}", &t[..i + 6], &t[i + 6 + len..]);
        }
    }
    replace_word(&t, &format!("WP_{from}"), &format!("WP_{to}"))
}

fn replace_word(text: &str, word: &str, by: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(word) {
        let before_ok =
            !rest[..i].chars().next_back().is_some_and(|c| c.is_ascii_alphanumeric() || c == '_');
        let after = &rest[i + word.len()..];
        let after_ok = !after.chars().next().is_some_and(|c| c.is_ascii_alphanumeric() || c == '_');
        out.push_str(&rest[..i]);
        out.push_str(if before_ok && after_ok { by } else { word });
        rest = after;
    }
    out.push_str(rest);
    out
}

#[test]
fn a_consistent_waypoint_rename_is_equivalent() {
    let Some((dir, plans)) = corpus_copy() else { return };
    let mut renamed = 0;
    for rel in &plans {
        let path = dir.path().join(rel);
        let plan = parse_file_with(&path, &Options::default()).expect("parses");
        // The first waypoint written in the main plan with a C-macro name, not HOME.
        let Some(w) = plan.waypoints.iter().find(|w| {
            w.origin == vouch_fpl::ast::WaypointOrigin::Plan
                && w.name.value != "HOME"
                && w.name.value.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        }) else {
            continue;
        };
        let from = w.name.value.clone();
        // Procedures are shared files: a plan whose procedures name the waypoint is skipped.
        let in_procedures = plan.sources.files.iter().skip(1).any(|f| f.text.contains(&from));
        if in_procedures {
            continue;
        }
        let to = format!("{from}_renamed");
        let text = std::fs::read_to_string(&path).expect("read");
        let copy = sibling(&path, "renamed");
        std::fs::write(&copy, rename_waypoint(&text, &from, &to)).expect("write");
        let r = compare(&path, &copy, true);
        assert_eq!(
            r.verdict,
            Verdict::Equivalent,
            "{rel} ({from}): {}",
            vouch_fpl::diff::render(&r)
        );
        let summary = vouch_fpl::diff::summary(&r.structure);
        assert!(summary.contains(&format!("'{from}' renamed '{to}'")), "{rel}: {summary}");
        renamed += 1;
    }
    assert!(renamed > 90, "{renamed} plans renamed");
}

/// One mutant of `basic.xml`: the edit, and the first divergence derived by hand.
struct Mutant {
    what: &'static str,
    old: &'static str,
    new: &'static str,
    /// The distinguishing run: `jump B` / `call [answers]`.
    run: &'static [&'static str],
    kind: PartingKind,
    old_seen: &'static str,
    new_seen: &'static str,
}

const MUTANTS: &[Mutant] = &[
    Mutant {
        what: "set value (block 0 stage 0)",
        old: r#"<set value="1" var="autopilot.kill_throttle"/>
      <while"#,
        new: r#"<set value="2" var="autopilot.kill_throttle"/>
      <while"#,
        run: &["call [0]"],
        kind: PartingKind::Event,
        old_seen: "X autopilot.kill_throttle = 1",
        new_seen: "X autopilot.kill_throttle = 2",
    },
    Mutant {
        what: "while condition inverted (block 0)",
        old: r#"<while cond="!GpsFixValid()"/>"#,
        new: r#"<while cond="GpsFixValid()"/>"#,
        run: &["call [0]"],
        kind: PartingKind::Event,
        old_seen: "C 0 !(GpsFixValid())",
        new_seen: "C 0 GpsFixValid()",
    },
    Mutant {
        what: "call_once becomes a looping call (block 1)",
        old: r#"<call_once fun="NavSetGroundReferenceHere()"/>"#,
        new: r#"<call fun="NavSetGroundReferenceHere()"/>"#,
        run: &["call [0]", "call [0]"],
        kind: PartingKind::Event,
        old_seen: "X NavSetGroundReferenceHere()",
        new_seen: "C 0 NavSetGroundReferenceHere()",
    },
    Mutant {
        what: "attitude roll (block 2)",
        old: r#"<attitude roll="0" throttle="0" vmode="throttle"/>"#,
        new: r#"<attitude roll="10" throttle="0" vmode="throttle"/>"#,
        run: &["jump 2", "call []"],
        kind: PartingKind::Event,
        old_seen: "X NavAttitude(RadOfDeg(0))",
        new_seen: "X NavAttitude(RadOfDeg(10))",
    },
    Mutant {
        what: "throttle (block 2)",
        old: r#"<attitude roll="0" throttle="0" vmode="throttle"/>"#,
        new: r#"<attitude roll="0" throttle="0.5" vmode="throttle"/>"#,
        run: &["jump 2", "call []"],
        kind: PartingKind::Event,
        old_seen: "X NavVerticalThrottleMode(9600*(0))",
        new_seen: "X NavVerticalThrottleMode(9600*(0.500000))",
    },
    Mutant {
        what: "exception condition (block 3)",
        old: "GetPosAlt() @GT GetAltRef()+25",
        new: "GetPosAlt() @GT GetAltRef()+35",
        run: &["jump 3", "call [0, 0]"],
        kind: PartingKind::Event,
        old_seen: "C 0 (GetPosAlt()>(GetAltRef()+25))",
        new_seen: "C 0 (GetPosAlt()>(GetAltRef()+35))",
    },
    Mutant {
        what: "exception target (block 3: Standby → MOB)",
        old: r#"GetAltRef()+25" deroute="Standby""#,
        new: r#"GetAltRef()+25" deroute="MOB""#,
        run: &["jump 3", "call [1]"],
        kind: PartingKind::State,
        old_seen: "block 4 stage 0",
        new_seen: "block 7 stage 0",
    },
    Mutant {
        what: "stage removed (block 3 stage 1)",
        old: r#"      <set value="0" var="autopilot.flight_time"/>
"#,
        new: "",
        run: &["jump 3", "call [0, 0]"],
        kind: PartingKind::Event,
        old_seen: "X autopilot.flight_time = 0",
        new_seen: "C 0 NavApproachingFrom(11,1,CARROT)",
    },
    Mutant {
        what: "two stages swapped (block 3 stages 0 and 1)",
        old: r#"<set value="0" var="autopilot.kill_throttle"/>
      <set value="0" var="autopilot.flight_time"/>"#,
        new: r#"<set value="0" var="autopilot.flight_time"/>
      <set value="0" var="autopilot.kill_throttle"/>"#,
        run: &["jump 3", "call [0, 0]"],
        kind: PartingKind::Event,
        old_seen: "X autopilot.kill_throttle = 0",
        new_seen: "X autopilot.flight_time = 0",
    },
    Mutant {
        what: "go target waypoint (block 3: CLIMB → STDBY)",
        old: r#"wp="CLIMB" pitch="15""#,
        new: r#"wp="STDBY" pitch="15""#,
        run: &["jump 3", "call [0, 0]"],
        kind: PartingKind::Event,
        old_seen: "C 0 NavApproachingFrom(11,1,CARROT)",
        new_seen: "C 0 NavApproachingFrom(2,1,CARROT)",
    },
    Mutant {
        what: "circle radius (block 4)",
        old: r#"<circle radius="nav_radius" wp="STDBY"/>"#,
        new: r#"<circle radius="nav_radius*2" wp="STDBY"/>"#,
        run: &["jump 4", "call []"],
        kind: PartingKind::Event,
        old_seen: "X NavCircleWaypoint(2, nav_radius)",
        new_seen: "X NavCircleWaypoint(2, (nav_radius*2))",
    },
    Mutant {
        what: "stage altitude (block 4)",
        old: r#"<circle radius="nav_radius" wp="STDBY"/>"#,
        new: r#"<circle alt="250" radius="nav_radius" wp="STDBY"/>"#,
        run: &["jump 4", "call []"],
        kind: PartingKind::Event,
        old_seen: "X NavVerticalAltitudeMode(WaypointAlt(2), 0.)",
        new_seen: "X NavVerticalAltitudeMode(250, 0.)",
    },
    Mutant {
        what: "two blocks swapped (5 and 6)",
        old: r#"    <block key="F8" name="Figure 8 around wp 1" strip_button="Figure 8 (wp 1-2)" strip_icon="eight.png" group="base_pattern">
      <eight center="1" radius="nav_radius" turn_around="2"/>
    </block>
    <block name="Oval 1-2" strip_button="Oval (wp 1-2)" strip_icon="oval.png" group="base_pattern">
      <oval p1="1" p2="2" radius="nav_radius"/>
    </block>"#,
        new: r#"    <block name="Oval 1-2" strip_button="Oval (wp 1-2)" strip_icon="oval.png" group="base_pattern">
      <oval p1="1" p2="2" radius="nav_radius"/>
    </block>
    <block key="F8" name="Figure 8 around wp 1" strip_button="Figure 8 (wp 1-2)" strip_icon="eight.png" group="base_pattern">
      <eight center="1" radius="nav_radius" turn_around="2"/>
    </block>"#,
        run: &["jump 5", "call []"],
        kind: PartingKind::Event,
        old_seen: "X nav_eight_init()",
        new_seen: "X nav_oval_init()",
    },
    Mutant {
        what: "survey grid (block 8)",
        old: r#"grid="150""#,
        new: r#"grid="200""#,
        run: &["jump 8", "call []"],
        kind: PartingKind::Event,
        old_seen: "X NavSurveyRectangleInit(6, 7, 150, NS)",
        new_seen: "X NavSurveyRectangleInit(6, 7, 200, NS)",
    },
    Mutant {
        what: "deroute target at the end of a path (block 9 stage 4: Standby → MOB)",
        old: r#"<deroute block="Standby"/>"#,
        new: r#"<deroute block="MOB"/>"#,
        run: &["jump 9", "call [1]", "call [1]", "call [1]", "call [1]", "call []"],
        kind: PartingKind::State,
        old_seen: "block 4 stage 0",
        new_seen: "block 7 stage 0",
    },
    Mutant {
        what: "deroute target (block 10: land → final)",
        old: r#"<set value="DEFAULT_CIRCLE_RADIUS" var="nav_radius"/>
      <deroute block="land"/>"#,
        new: r#"<set value="DEFAULT_CIRCLE_RADIUS" var="nav_radius"/>
      <deroute block="final"/>"#,
        run: &["jump 10", "call []"],
        kind: PartingKind::State,
        old_seen: "block 12 stage 0",
        new_seen: "block 13 stage 0",
    },
    Mutant {
        what: "until condition (block 12 stage 1)",
        old: r#"until="NavCircleCount() @GT 0.5""#,
        new: r#"until="NavCircleCount() @GT 1.5""#,
        run: &["jump 12", "call [0]"],
        kind: PartingKind::Event,
        old_seen: "C 0 (NavCircleCount()>0.500000)",
        new_seen: "C 0 (NavCircleCount()>1.500000)",
    },
];

fn describe_run(r: &DiffReport) -> Vec<String> {
    let d = r.divergence.as_ref().expect("a divergence");
    d.steps
        .iter()
        .map(|s| match s.jump {
            Some(b) => format!("jump {b}"),
            None => format!("call {:?}", s.answers),
        })
        .collect()
}

#[test]
fn every_mutant_of_basic_is_different_with_its_first_divergence() {
    let Some((dir, _)) = corpus_copy() else { return };
    let base = dir.path().join("basic.xml");
    let text = std::fs::read_to_string(&base).expect("read");
    for (i, m) in MUTANTS.iter().enumerate() {
        assert_eq!(text.matches(m.old).count(), 1, "{}: the edit must apply once", m.what);
        let path = dir.path().join(format!("basic_mutant_{i}.xml"));
        std::fs::write(&path, text.replacen(m.old, m.new, 1)).expect("write");
        let r = compare(&base, &path, true);
        assert_eq!(r.verdict, Verdict::Different, "{}", m.what);
        assert_eq!(describe_run(&r), m.run, "{}: {}", m.what, vouch_fpl::diff::render(&r));
        let d = r.divergence.as_ref().expect("divergence");
        assert_eq!(d.kind, m.kind, "{}", m.what);
        assert_eq!(d.old.text.as_deref(), Some(m.old_seen), "{}", m.what);
        assert_eq!(d.new.text.as_deref(), Some(m.new_seen), "{}", m.what);
        // Located on both files, in the block that differs.
        let (lo, ln) =
            (d.old.location.as_ref().expect("old"), d.new.location.as_ref().expect("new"));
        assert!(
            lo.file.ends_with("basic.xml") && ln.file.ends_with(&format!("basic_mutant_{i}.xml"))
        );
        // Without operator jumps the plans still differ (a natural run, or none reaches it).
        let natural = compare(&base, &path, false);
        assert_ne!(natural.verdict, Verdict::Undecided, "{}", m.what);
    }
}

#[test]
fn mutants_are_replayable_on_the_interpreter() {
    let Some((dir, _)) = corpus_copy() else { return };
    let base = dir.path().join("basic.xml");
    let text = std::fs::read_to_string(&base).expect("read");
    let m = &MUTANTS[14];
    let path = dir.path().join("basic_replay.xml");
    std::fs::write(&path, text.replacen(m.old, m.new, 1)).expect("write");
    let r = compare(&base, &path, true);
    let d = r.divergence.expect("divergence");
    // `vouch fpl sim` replays the same run: the answers and jumps it prints.
    for (p, block) in [(&base, 4), (&path, 7)] {
        let plan = parse_file_with(p, &Options::default()).expect("parses");
        let fp = vouch_fpl::passes::lower::lower(&plan).expect("lowers");
        let mut o = vouch_fpl::semantics::oracle::Scripted::new(d.answers.clone());
        let run = vouch_fpl::semantics::sim::simulate_with_jumps(&fp, &mut o, d.calls, &d.jumps)
            .expect("runs");
        assert_eq!(run.steps.last().expect("steps").after.block, block);
    }
    assert_eq!(vouch_fpl::diff::replay_args(&d), " --answers '1 1 1 1' --jump 1:9 --steps 5");
}

/// The crafted pair in `tests/diff_plans/` (written for this repository).
fn crafted(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/diff_plans").join(name)
}

#[test]
fn a_procedure_inlined_by_hand_is_equivalent() {
    let r = compare(&crafted("with_procedure.xml"), &crafted("inlined.xml"), true);
    assert_eq!(r.verdict, Verdict::Equivalent, "{}", vouch_fpl::diff::render(&r));
    let summary = vouch_fpl::diff::summary(&r.structure);
    // Matched by content: the procedure's blocks under their new names.
    assert!(summary.contains("block 'L.approach' renamed 'Approach'"), "{summary}");
    assert!(summary.contains("block 'L.final' renamed 'Final'"), "{summary}");
    assert!(!summary.contains("waypoint"), "{summary}");
    // Upstream merges an empty header for the include; not behaviour, but reported.
    assert!(r.structure.header_changed);
}

#[test]
fn a_change_in_the_inlined_copy_is_found() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = std::fs::read_to_string(crafted("inlined.xml")).expect("read");
    let changed = dir.path().join("inlined_changed.xml");
    std::fs::write(&changed, text.replacen("@GT 0.50", "@GT 0.60", 1)).expect("write");
    let r = compare(&crafted("with_procedure.xml"), &changed, true);
    assert_eq!(r.verdict, Verdict::Different);
    // Jump to block 3 (the procedure's first block), one call: the baseleg code, the circle's
    // four lines, then the until condition (upstream prints %f floats).
    assert_eq!(describe_run(&r), ["jump 3", "call [0, 0, 0]"]);
    let d = r.divergence.expect("divergence");
    assert_eq!(d.old.text.as_deref(), Some("C 0 (NavCircleCount()>0.500000)"));
    assert_eq!(d.new.text.as_deref(), Some("C 0 (NavCircleCount()>0.600000)"));
    // Located in the procedure file on one side and in the plan on the other.
    assert!(d.old.location.expect("old").file.ends_with("landing_proc.xml"));
    assert!(d.new.location.expect("new").file.ends_with("inlined_changed.xml"));
}
