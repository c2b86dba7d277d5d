//! Expression lexing, parsing and upstream-exact printing. Expected texts are the examples of
//! upstream's behaviour given in shared/fpl/GENERATOR_FACTS.md (section 9, 11, quirk 4).

use vouch_fpl::expr::{ExprErrorKind, format_g, ocaml_float_text, parse, print_upstream};

fn p(s: &str) -> String {
    print_upstream(&parse(s).unwrap_or_else(|e| panic!("{s:?} should parse: {e}")))
}

#[test]
fn binary_operations_are_fully_parenthesised_with_c_spelling() {
    assert_eq!(p("a @GT 2"), "(a>2)");
    assert_eq!(p("a @LT 2"), "(a<2)");
    assert_eq!(p("a @GEQ 2"), "(a>=2)");
    assert_eq!(p("a @LEQ 2"), "(a<=2)");
    assert_eq!(p("a == b"), "(a==b)");
    assert_eq!(p("a @OR b"), "(a||b)");
}

#[test]
fn and_or_share_one_left_associative_level() {
    assert_eq!(p("a || b @AND c"), "((a||b)&&c)");
    assert_eq!(p("a && b || c"), "((a&&b)||c)");
}

#[test]
fn comparison_level_is_shared_and_left_associative() {
    assert_eq!(p("a == b > c"), "((a==b)>c)");
    assert_eq!(p("a + b * c > d - e"), "((a+(b*c))>(d-e))");
    assert_eq!(p("a - b - c"), "((a-b)-c)");
    assert_eq!(p("a ** b * c"), "((a**b)*c)");
}

#[test]
fn unary_operators_print_with_parentheses_and_bind_as_upstream() {
    assert_eq!(p("-x"), "-(x)");
    assert_eq!(p("!x"), "!(x)");
    assert_eq!(p("- a * b"), "(-(a)*b)");
    assert_eq!(p("!a @AND b"), "(!(a)&&b)");
    assert_eq!(p("!-a"), "!(-(a))");
    assert_eq!(p("-DEFAULT_CIRCLE_RADIUS"), "-(DEFAULT_CIRCLE_RADIUS)");
}

#[test]
fn numbers_print_with_percent_d_and_percent_f() {
    assert_eq!(p("0.5"), "0.500000");
    assert_eq!(p("1."), "1.000000");
    assert_eq!(p("0.0000001"), "0.000000");
    assert_eq!(p("007"), "7");
    assert_eq!(p("bar( 1.50 )"), "bar(1.500000)");
}

#[test]
fn calls_fields_index_and_deref() {
    assert_eq!(p("foo(a,   b)"), "foo(a,b)");
    assert_eq!(p("f()"), "f()");
    assert_eq!(p("autopilot.kill_throttle"), "autopilot.kill_throttle");
    assert_eq!(p("wps[ 3 ]"), "wps[3]");
    assert_eq!(p("stateGetPositionEnu_f()->z"), "(stateGetPositionEnu_f())->z");
    assert_eq!(p("a @DEREF b"), "(a)->b");
    assert_eq!(p("-a->b"), "-((a)->b)");
}

#[test]
fn identifiers_dollar_and_quoted() {
    assert_eq!(p("$i + 1"), "(_var_i+1)");
    assert_eq!(p("IndexOfBlock('land here')"), "IndexOfBlock(land here)");
    assert_eq!(p("a /* comment */ + b"), "(a+b)");
}

#[test]
fn rejected_texts_match_upstream_lexer_and_grammar() {
    for (text, kind) in [
        ("a < b", ExprErrorKind::Lexing),
        // `!=` lexes as `!` then `=` (no rule for `!=`); the grammar then rejects it.
        ("a != b", ExprErrorKind::Parsing),
        ("a & b", ExprErrorKind::Lexing),
        ("\"s\"", ExprErrorKind::Lexing),
        ("a\r", ExprErrorKind::Lexing),
        ("1.5e3", ExprErrorKind::Parsing),
        ("x = 3", ExprErrorKind::Parsing),
        ("f(a); g(b)", ExprErrorKind::Parsing),
        ("a.b.c", ExprErrorKind::Parsing),
        ("(a", ExprErrorKind::Parsing),
        ("", ExprErrorKind::Parsing),
        ("99999999999999999999999", ExprErrorKind::Lexing),
    ] {
        let e = parse(text).expect_err(text);
        assert_eq!(e.kind, kind, "{text:?}: {e}");
        assert!(e.start <= text.len());
    }
    // The error points at the offending character.
    assert_eq!(parse("abc < d").unwrap_err().start, 4);
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let deep = "(".repeat(5000) + "a" + &")".repeat(5000);
    assert!(parse(&deep).is_err());
    let neg = "-".repeat(5000) + "a";
    assert!(parse(&neg).is_err());
    // Long left-associative chains and deref chains build deep trees without deep recursion
    // in the parser; they are bounded too.
    let chain = vec!["a"; 100_000].join("+");
    assert!(parse(&chain).is_err());
    let derefs = "a".to_string() + &"->b".repeat(100_000);
    assert!(parse(&derefs).is_err());
    // Realistic lengths stay accepted.
    assert!(parse(&vec!["a"; 50].join(" @AND ")).is_ok());
}

#[test]
fn ocaml_float_text_matches_string_of_float() {
    assert_eq!(ocaml_float_text(185.0), "185.");
    assert_eq!(ocaml_float_text(25.5), "25.5");
    assert_eq!(ocaml_float_text(-0.25), "-0.25");
    assert_eq!(ocaml_float_text(1e20), "1e+20");
    assert_eq!(ocaml_float_text(0.1 + 0.2), "0.3");
    assert_eq!(ocaml_float_text(1.0 / 3.0), "0.333333333333");
    assert_eq!(format_g(0.0001, 12), "0.0001");
    assert_eq!(format_g(0.00001, 12), "1e-05");
}
