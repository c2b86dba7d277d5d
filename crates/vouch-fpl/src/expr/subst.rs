//! Upstream's procedure parameter substitution (`fp_proc`): identifiers equal to a parameter
//! name are replaced by the argument *text* (not re-parsed; printed verbatim), and
//! `IndexOfBlock(x)` with a single identifier becomes `IndexOfBlock('Name.x')`.

use super::Expr;

/// The include being expanded: its name (block prefix) and parameter values.
pub struct ProcEnv<'a> {
    pub name: &'a str,
    pub params: &'a [(String, String)],
}

/// Applies the substitution, mirroring upstream: function names, indexed names, field names
/// and deref fields are left alone; `IndexOfBlock(ident)` is prefixed before any parameter
/// lookup.
pub fn subst_procedure(e: &Expr, env: &ProcEnv<'_>) -> Expr {
    match e {
        Expr::Ident(i) => match env.params.iter().find(|(n, _)| n == i) {
            Some((_, v)) => Expr::Ident(v.clone()),
            None => e.clone(),
        },
        Expr::Int(_) | Expr::Float(_) | Expr::Field(..) | Expr::BlockIndex { .. } => e.clone(),
        Expr::Call(f, args)
            if f == "IndexOfBlock" && matches!(args.as_slice(), [Expr::Ident(_)]) =>
        {
            let Some(Expr::Ident(s)) = args.first() else { return e.clone() };
            Expr::Call(f.clone(), vec![Expr::Ident(format!("'{}.{}'", env.name, s))])
        }
        Expr::Call(f, args) => {
            Expr::Call(f.clone(), args.iter().map(|a| subst_procedure(a, env)).collect())
        }
        Expr::Binary(op, l, r) => {
            Expr::Binary(*op, Box::new(subst_procedure(l, env)), Box::new(subst_procedure(r, env)))
        }
        Expr::Unary(op, x) => Expr::Unary(*op, Box::new(subst_procedure(x, env))),
        Expr::Index(i, x) => Expr::Index(i.clone(), Box::new(subst_procedure(x, env))),
        Expr::Deref(x, f) => Expr::Deref(Box::new(subst_procedure(x, env)), f.clone()),
    }
}
