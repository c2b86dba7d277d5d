//! Upstream-exact printing of expressions and OCaml's float text.

use super::Expr;

/// Prints `e` as upstream's generator does: binary operations fully parenthesised without
/// spaces (`(a>2)`), unary operators as `-(x)` / `!(x)`, calls `f(a,b)`, `a[e]`, `a.b`,
/// `(e)->f`, integers `%d`, floats C `%f`, `$v` as `_var_v`, other identifiers verbatim,
/// resolved `IndexOfBlock` as the block number.
pub fn print_upstream(e: &Expr) -> String {
    let mut s = String::new();
    write_expr(&mut s, e);
    s
}

fn write_expr(s: &mut String, e: &Expr) {
    match e {
        Expr::Int(v) => s.push_str(&v.to_string()),
        // Rust's `{:.6}` and glibc's `%f` both round the exact binary value correctly.
        Expr::Float(v) => s.push_str(&format!("{v:.6}")),
        Expr::Ident(i) => write_ident(s, i),
        Expr::Call(f, args) => {
            s.push_str(f);
            s.push('(');
            for (k, a) in args.iter().enumerate() {
                if k > 0 {
                    s.push(',');
                }
                write_expr(s, a);
            }
            s.push(')');
        }
        Expr::Index(i, e) => {
            s.push_str(i);
            s.push('[');
            write_expr(s, e);
            s.push(']');
        }
        Expr::Field(i, f) => {
            s.push_str(i);
            s.push('.');
            s.push_str(f);
        }
        Expr::Deref(e, f) => {
            s.push('(');
            write_expr(s, e);
            s.push_str(")->");
            s.push_str(f);
        }
        Expr::Binary(op, l, r) => {
            s.push('(');
            write_expr(s, l);
            s.push_str(op.c_text());
            write_expr(s, r);
            s.push(')');
        }
        Expr::Unary(op, e) => {
            s.push_str(op.c_text());
            s.push('(');
            write_expr(s, e);
            s.push(')');
        }
        Expr::BlockIndex { id, .. } => s.push_str(&id.0.to_string()),
    }
}

fn write_ident(s: &mut String, i: &str) {
    match i.strip_prefix('$') {
        Some(v) => {
            s.push_str("_var_");
            s.push_str(v);
        }
        None => s.push_str(i),
    }
}

/// OCaml's `string_of_float`: `%.12g`, plus a trailing `.` when the result looks like an
/// integer (`185.` for 185, `25.5` for 25.5, `1e+20` unchanged).
pub fn ocaml_float_text(v: f64) -> String {
    let g = format_g(v, 12);
    if g.contains(['.', 'e', 'n', 'i']) { g } else { g + "." }
}

/// C's `%.<prec>g`.
pub fn format_g(v: f64, prec: usize) -> String {
    if v.is_nan() {
        return if v.is_sign_negative() { "-nan".into() } else { "nan".into() };
    }
    if v.is_infinite() {
        return if v < 0.0 { "-inf".into() } else { "inf".into() };
    }
    let p = prec.max(1);
    if v == 0.0 {
        return if v.is_sign_negative() { "-0".into() } else { "0".into() };
    }
    // Exponent after rounding to p significant digits, as C decides the style.
    let e_form = format!("{:.*e}", p - 1, v);
    let (mant, exp) = e_form.split_once('e').unwrap_or((&e_form, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if exp < -4 || exp >= p as i32 {
        let mant = trim_zeros(mant);
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{mant}e{sign}{:02}", exp.abs())
    } else {
        let decimals = (p as i32 - 1 - exp).max(0) as usize;
        trim_zeros(&format!("{v:.decimals$}")).to_string()
    }
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.') } else { s }
}
