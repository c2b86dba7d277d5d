//! What the diff observes of a C text: its meaning up to layout, not its spelling.
//!
//! Two texts are the same observation when they are the same C up to what cannot change what
//! the aircraft does:
//! * blanks, and the parentheses and number spellings that upstream's re-printing of procedure
//!   texts changes (`f(a,   b)` is `f(a,b)`, `-x` is `-(x)`, `0.0` is `0.000000`): a text that
//!   parses as a Paparazzi expression is compared as its syntax tree, integers and floats by
//!   value (an integer never equals a float: `x/2` and `x/2.0` differ in C);
//! * waypoint *names*: `WP_name` is the C macro of the waypoint's number, so it is compared as
//!   that number (as the preprocessor would replace it); a waypoint renamed consistently keeps its number and is the same observation.
//!   Block names never reach the C (blocks are numbers there), so they are not observed either.
//!
//! Any other text is compared token by token (blanks dropped, numbers by value, `WP_name` by
//! number).

use std::collections::HashMap;
use std::sync::Arc;

use crate::ast::FlightPlan;
use crate::expr::{Expr, parse};

/// The canonical form of the texts of one plan (cached: the walk meets the same texts often).
#[derive(Debug, Default)]
pub struct Canon {
    /// `WP_name` → the waypoint's number (upstream's `WP_` define).
    waypoints: HashMap<String, usize>,
    cache: HashMap<String, Arc<str>>,
}

impl Canon {
    /// The canonical form for `plan`'s texts. Only names upstream defines as `WP_name`
    /// (letters, digits, `_`) are mapped; with duplicate names the first wins, like the C.
    pub fn of(plan: &FlightPlan) -> Canon {
        let mut waypoints = HashMap::new();
        for (i, w) in plan.waypoints.iter().enumerate() {
            let name = &w.name.value;
            if name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                waypoints.entry(format!("WP_{name}")).or_insert(i + 1);
            }
        }
        waypoints.insert("WP_dummy".into(), 0);
        Canon { waypoints, cache: HashMap::new() }
    }

    /// The canonical form of `text`.
    pub fn text(&mut self, text: &str) -> Arc<str> {
        if let Some(c) = self.cache.get(text) {
            return c.clone();
        }
        let c: Arc<str> = self.compute(text).into();
        self.cache.insert(text.to_string(), c.clone());
        c
    }

    fn compute(&self, text: &str) -> String {
        match parse(text) {
            Ok(mut e) => {
                e.walk_mut(&mut |x| self.map_expr(x));
                format!("{e:?}")
            }
            Err(_) => self.tokens(text),
        }
    }

    fn map_expr(&self, e: &mut Expr) {
        match e {
            Expr::Ident(i) => {
                if let Some(n) = self.waypoints.get(i.as_str()) {
                    *e = Expr::Int(*n as i64);
                }
            }
            Expr::BlockIndex { id, .. } => *e = Expr::Int(id.0 as i64),
            _ => {}
        }
    }

    /// Token by token: identifiers, numbers by value, strings and other characters as they are.
    fn tokens(&self, text: &str) -> String {
        let mut out = String::with_capacity(text.len());
        let mut chars = text.char_indices().peekable();
        while let Some((i, c)) = chars.next() {
            if c.is_whitespace() {
                continue;
            }
            let mut end = i + c.len_utf8();
            if c.is_ascii_alphabetic() || c == '_' || c == '$' {
                while let Some(&(j, d)) = chars.peek() {
                    if !(d.is_ascii_alphanumeric() || d == '_') {
                        break;
                    }
                    end = j + d.len_utf8();
                    chars.next();
                }
                let word = &text[i..end];
                match self.waypoints.get(word) {
                    Some(n) => out.push_str(&format!("i{n}")),
                    None => out.push_str(word),
                }
            } else if c.is_ascii_digit()
                || (c == '.' && chars.peek().is_some_and(|x| x.1.is_ascii_digit()))
            {
                while let Some(&(j, d)) = chars.peek() {
                    if !(d.is_ascii_alphanumeric() || d == '.') {
                        break;
                    }
                    end = j + d.len_utf8();
                    chars.next();
                }
                out.push_str(&number(&text[i..end]));
            } else if c == '"' || c == '\'' {
                let mut escaped = false;
                for (j, d) in chars.by_ref() {
                    end = j + d.len_utf8();
                    if !escaped && d == c {
                        break;
                    }
                    escaped = !escaped && d == '\\';
                }
                out.push_str(&text[i..end]);
            } else {
                out.push(c);
            }
            out.push(' ');
        }
        out
    }
}

/// A C number by value where that is plain (`1.50` and `1.500000` are one float; `2` an
/// integer); anything with a suffix or another base is kept as written.
fn number(word: &str) -> String {
    if word.bytes().all(|b| b.is_ascii_digit()) {
        return match word.trim_start_matches('0') {
            "" => "i0".into(),
            digits => format!("i{digits}"),
        };
    }
    let plain = word.bytes().all(|b| b.is_ascii_digit() || b == b'.');
    match word.parse::<f64>() {
        Ok(v) if plain => format!("f{v:?}"),
        _ => word.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn canon() -> Canon {
        let plan = crate::front::parse_str(
            "t.xml",
            r#"<flight_plan name="t" lat0="43.5" lon0="1.4" alt="250" ground_alt="150"
            security_height="30" max_dist_from_home="1000">
          <waypoints><waypoint name="HOME" x="0" y="0"/><waypoint name="A" x="1" y="0"/></waypoints>
          <blocks><block name="B"><call_once fun="f()"/></block></blocks></flight_plan>"#,
        )
        .expect("parses");
        Canon::of(&plan)
    }

    #[test]
    fn layout_is_not_observed() {
        let mut c = canon();
        assert_eq!(c.text("f(a,   b)"), c.text("f(a,b)"));
        assert_eq!(c.text("g(-x)"), c.text("g(-(x))"));
        assert_eq!(c.text("h(0.0)"), c.text("h(0.000000)"));
        assert_eq!(c.text("NavSetWaypointHere(WP_A)"), c.text("NavSetWaypointHere(2)"));
        // not an expression: token by token
        assert_eq!(c.text("x = 1.50 ; y=WP_A"), c.text("x=1.500000; y = 2"));
    }

    #[test]
    fn meaning_is_observed() {
        let mut c = canon();
        assert_ne!(c.text("f(a,b)"), c.text("f(b,a)"));
        assert_ne!(c.text("x/2"), c.text("x/2.0"));
        assert_ne!(c.text("NavGotoWaypoint(WP_A)"), c.text("NavGotoWaypoint(WP_HOME)"));
        assert_ne!(c.text("x = 1; y = 2"), c.text("x = 1; y = 3"));
        assert_ne!(c.text("s(\"a b\")"), c.text("s(\"ab\")"));
    }
}
