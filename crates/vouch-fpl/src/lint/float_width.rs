//! W009: a comparison whose result can depend on the width of floating point. C reads `10.3`
//! as a `double`; the autopilot's Cortex-M4F/M7 FPU computes in single precision, and a build
//! with `-fsingle-precision-constant` (or a firmware that stores the value in a `float`) makes
//! the constant `10.300000190734863` instead of `10.300000000000001`. A condition such as
//! `GetPosAlt() > ground_alt + 10.3` then changes its result for the positions in between:
//! the plan's meaning depends on how it is compiled. Constants that single precision holds
//! exactly (`0.5`, `100`, `1e3`) are not reported, nor are numbers outside comparisons.

use super::{Rule, Warning};
use crate::ast::{Attrs, FlightPlan, Stage, StageKind};
use crate::expr::{TokenKind, lex};
use crate::span::{SourceMap, Span, line_col};

/// Integers from 2^24 on are not all representable in single precision.
const FLOAT_EXACT_INT: i64 = 1 << 24;

/// A numeric literal whose value changes when it is held in single precision: its value as a
/// double and as a float.
fn width_dependent(kind: &TokenKind) -> Option<(f64, f64)> {
    let v = match kind {
        TokenKind::Float(v) => *v,
        TokenKind::Int(i) if i.unsigned_abs() > FLOAT_EXACT_INT as u64 => *i as f64,
        _ => return None,
    };
    let single = f64::from(v as f32);
    (v.is_finite() && single != v).then_some((v, single))
}

fn is_comparison(tokens: &[crate::expr::Token]) -> bool {
    tokens.iter().enumerate().any(|(i, t)| match t.kind {
        TokenKind::Gt | TokenKind::Lt | TokenKind::Ge | TokenKind::Le | TokenKind::EqEq => true,
        TokenKind::Not => tokens.get(i + 1).is_some_and(|n| n.kind == TokenKind::Assign),
        _ => false,
    })
}

/// `text` with control characters escaped (`\u{1b}`): attribute values reach the terminal.
fn printable(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { c.escape_unicode().to_string() } else { c.to_string() })
        .collect()
}

/// The warnings of one attribute value: each width-dependent literal of a comparison, located
/// at the literal in the XML.
fn check_value(sources: &SourceMap, name: &str, value: &str, at: Span, out: &mut Vec<Warning>) {
    let Ok(tokens) = lex(value) else { return };
    if !is_comparison(&tokens) {
        return;
    }
    let raw = sources.snippet(at);
    let file_text = sources.text(at.file);
    let mut from = 0;
    for t in &tokens {
        let Some((double, single)) = width_dependent(&t.kind) else { continue };
        let literal = &value[t.start..t.end];
        // the literal's digits are spelled the same in the raw XML (entities never hold digits)
        let span = match raw.get(from..).and_then(|r| r.find(literal)) {
            Some(i) => {
                let start = at.start as usize + from + i;
                from += i + literal.len();
                let (line, col) = line_col(file_text, start);
                let end = (start + literal.len()) as u32;
                Span { file: at.file, start: start as u32, end, line, col }
            }
            None => at,
        };
        out.push(Warning::new(
            Rule::FloatWidth,
            format!(
                "constant {literal} in the comparison {name}=\"{}\" is {double:?} in double precision but {single:?} in single precision: the comparison can go the other way when the autopilot computes in float (Cortex-M4F/M7 FPU, -fsingle-precision-constant, a float variable)",
                printable(value)
            ),
            span,
        ));
    }
}

fn check_attrs(sources: &SourceMap, attrs: &Attrs, out: &mut Vec<Warning>) {
    for a in &attrs.0 {
        check_value(sources, &a.name, &a.value, a.value_span, out);
    }
}

fn check_stages(sources: &SourceMap, stages: &[Stage], out: &mut Vec<Warning>) {
    for s in stages {
        check_attrs(sources, &s.attrs, out);
        match &s.kind {
            StageKind::While(w) => check_stages(sources, &w.body, out),
            StageKind::For(l) => check_stages(sources, &l.body, out),
            _ => {}
        }
    }
}

/// W009 over the whole plan: global and block exceptions, every stage attribute.
pub fn float_width(plan: &FlightPlan, out: &mut Vec<Warning>) {
    for e in &plan.exceptions {
        check_attrs(&plan.sources, &e.attrs, out);
    }
    for b in &plan.blocks {
        for e in &b.exceptions {
            check_attrs(&plan.sources, &e.attrs, out);
        }
        check_stages(&plan.sources, &b.stages, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_precision_changes_only_inexact_constants() {
        let (d, f) = width_dependent(&TokenKind::Float(10.3)).expect("10.3 is inexact in float");
        assert_eq!(d, 10.3);
        assert_eq!(f, 10.300000190734863);
        for exact in [0.5, 100.0, 1e3, 0.25, -2.0] {
            assert!(width_dependent(&TokenKind::Float(exact)).is_none(), "{exact}");
        }
        assert!(width_dependent(&TokenKind::Int(16_777_216)).is_none());
        assert!(width_dependent(&TokenKind::Int(16_777_217)).is_some());
    }

    #[test]
    fn control_characters_of_the_value_are_escaped() {
        assert_eq!(printable("a\u{1b}]0;x\u{7}b"), "a\\u{1b}]0;x\\u{7}b");
    }
}
