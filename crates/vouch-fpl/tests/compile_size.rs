//! Size verification: the runtime keeps block and stage numbers in `uint8_t`, so plans with
//! more than 256 blocks (HOME included) or 256 stages in a block (end stage included) must be
//! rejected with a clear error, and the limits themselves accepted. Plans are generated here.

use vouch_fpl::passes::{CompileErrorKind, compile};

fn plan(blocks: &[String]) -> String {
    format!(
        "<flight_plan name=\"gen\" lat0=\"43.46\" lon0=\"1.27\" alt=\"200\" ground_alt=\"150\" \
         security_height=\"25\" max_dist_from_home=\"1000\">\n<waypoints><waypoint name=\"HOME\" x=\"0\" y=\"0\"/></waypoints>\n\
         <blocks>\n{}\n</blocks>\n</flight_plan>\n",
        blocks.join("\n")
    )
}

fn blocks(n: usize) -> Vec<String> {
    (0..n).map(|i| format!("<block name=\"b{i}\"><call_once fun=\"f({i})\"/></block>")).collect()
}

fn one_block(stages: usize) -> Vec<String> {
    let body: String = (0..stages).map(|i| format!("<call_once fun=\"g({i})\"/>")).collect();
    vec![format!("<block name=\"big\">{body}</block>")]
}

fn check(xml: &str) -> Result<usize, (CompileErrorKind, String)> {
    let p = vouch_fpl::front::parse_str("gen.xml", xml).expect("generated plan parses");
    compile(&p).map(|fps| fps.nb_block()).map_err(|e| (e.kind, e.message))
}

#[test]
fn exactly_256_blocks_are_accepted() {
    // 255 written blocks + the implicit HOME block.
    assert_eq!(check(&plan(&blocks(255))), Ok(256));
}

#[test]
fn more_than_256_blocks_are_rejected() {
    let (kind, msg) = check(&plan(&blocks(256))).expect_err("257 blocks must be rejected");
    assert_eq!(kind, CompileErrorKind::Size);
    assert!(msg.contains("257 blocks") && msg.contains("uint8_t"), "{msg}");
    let (_, msg) = check(&plan(&blocks(300))).expect_err("301 blocks must be rejected");
    assert!(msg.contains("301 blocks"), "{msg}");
}

#[test]
fn exactly_256_stages_are_accepted() {
    // 255 stages + the default stage = numbers 0..=255.
    assert!(check(&plan(&one_block(255))).is_ok());
}

#[test]
fn more_than_256_stages_are_rejected() {
    let (kind, msg) = check(&plan(&one_block(256))).expect_err("257 stages must be rejected");
    assert_eq!(kind, CompileErrorKind::Size);
    assert!(msg.contains("'big'") && msg.contains("257 stages"), "{msg}");
}

#[test]
fn loop_stages_count_toward_the_limit() {
    // A for loop uses init + test + body + loop-back: 2 + 252 + 1 = 255, + end stage = 256: ok.
    let body: String = (0..252).map(|i| format!("<call_once fun=\"h({i})\"/>")).collect();
    let ok = vec![format!(
        "<block name=\"loop\"><for var=\"i\" from=\"1\" to=\"3\">{body}</for></block>"
    )];
    assert!(check(&plan(&ok)).is_ok());
    let body: String = (0..253).map(|i| format!("<call_once fun=\"h({i})\"/>")).collect();
    let too_big = vec![format!(
        "<block name=\"loop\"><for var=\"i\" from=\"1\" to=\"3\">{body}</for></block>"
    )];
    let (kind, msg) =
        check(&plan(&too_big)).expect_err("257 stages with the loop must be rejected");
    assert_eq!(kind, CompileErrorKind::Size);
    assert!(msg.contains("257 stages"), "{msg}");
}

#[test]
fn the_cli_error_is_located_at_the_block() {
    let p = vouch_fpl::front::parse_str("gen.xml", &plan(&one_block(300))).expect("parses");
    let err = compile(&p).expect_err("too many stages");
    let rendered = err.to_diagnostics(&p.sources).listing();
    assert!(rendered.contains("gen.xml:4"), "error should point at the block line: {rendered}");
}
