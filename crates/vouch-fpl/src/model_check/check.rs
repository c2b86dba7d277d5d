//! Checking properties on the state graph, with counterexample paths: a finite path for safety
//! properties, a lasso (a path, then a cycle repeated forever) for liveness.
//!
//! Every state has at least one transition (a call always ends somewhere), so an infinite run
//! avoiding a set exists exactly when a cycle inside that set is reachable inside it; cycles
//! are found with strongly connected components (Kosaraju, iterative).

use std::collections::VecDeque;

use serde::Serialize;

use super::Graph;
use super::property::{Property, PropertyError, Temporal};

#[derive(Debug, Clone, Serialize)]
pub struct Step {
    /// Call number from the start.
    pub call: usize,
    /// Answers of this call (oracle convention: condition = odd, value = n / 2).
    pub answers: Vec<i64>,
    /// State after the call.
    pub state: String,
    /// Block changes refused during the call.
    pub blocked: Vec<(String, String)>,
    /// The operator jumped to this block instead of the call running.
    pub operator: Option<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Counterexample {
    pub initial: String,
    pub steps: Vec<Step>,
    /// Index in `steps` where the repeated cycle starts (lassos only).
    pub loop_from: Option<usize>,
    pub explanation: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Outcome {
    pub property: String,
    pub holds: bool,
    /// False when the state graph was cut: a "holds" is then not established.
    pub complete: bool,
    pub counterexample: Option<Counterexample>,
}

/// A path: the initial state, then (edge index in the source's list, target) per call.
type Path = Vec<(usize, usize)>;

fn bfs(
    g: &Graph,
    start: usize,
    allowed: &dyn Fn(usize) -> bool,
    target: &dyn Fn(usize) -> bool,
    skip_start: bool,
) -> Option<(usize, Path)> {
    let n = g.states.len();
    let mut parent: Vec<Option<(usize, usize)>> = vec![None; n];
    let mut seen = vec![false; n];
    let mut q = VecDeque::new();
    if !skip_start {
        if target(start) {
            return Some((start, Vec::new()));
        }
        seen[start] = true;
    }
    q.push_back(start);
    while let Some(s) = q.pop_front() {
        for (ei, e) in g.edges[s].iter().enumerate() {
            let t = e.to;
            if t >= n || !allowed(t) || seen[t] {
                continue;
            }
            seen[t] = true;
            parent[t] = Some((s, ei));
            if target(t) {
                let mut path = Vec::new();
                let mut cur = t;
                while let Some((p, ei)) = parent[cur] {
                    path.push((ei, cur));
                    if p == start {
                        break;
                    }
                    cur = p;
                }
                path.reverse();
                return Some((t, path));
            }
            q.push_back(t);
        }
    }
    None
}

/// Strongly connected components of the subgraph induced by `allowed`; returns the component
/// of every state (usize::MAX outside) and whether each component has a cycle.
fn sccs(g: &Graph, allowed: &dyn Fn(usize) -> bool) -> (Vec<usize>, Vec<bool>) {
    let n = g.states.len();
    let mut order = Vec::with_capacity(n);
    let mut seen = vec![false; n];
    for s0 in 0..n {
        if seen[s0] || !allowed(s0) {
            continue;
        }
        seen[s0] = true;
        let mut stack = vec![(s0, 0usize)];
        while let Some((s, i)) = stack.pop() {
            if let Some(e) = g.edges[s].get(i) {
                stack.push((s, i + 1));
                let t = e.to;
                if t < n && allowed(t) && !seen[t] {
                    seen[t] = true;
                    stack.push((t, 0));
                }
            } else {
                order.push(s);
            }
        }
    }
    let mut rev: Vec<Vec<usize>> = vec![Vec::new(); n];
    for s in 0..n {
        for e in &g.edges[s] {
            if e.to < n && allowed(s) && allowed(e.to) {
                rev[e.to].push(s);
            }
        }
    }
    let mut comp = vec![usize::MAX; n];
    let mut cyclic = Vec::new();
    for &s0 in order.iter().rev() {
        if comp[s0] != usize::MAX {
            continue;
        }
        let c = cyclic.len();
        let mut members = 0;
        comp[s0] = c;
        let mut stack = vec![s0];
        while let Some(s) = stack.pop() {
            members += 1;
            for &p in &rev[s] {
                if comp[p] == usize::MAX {
                    comp[p] = c;
                    stack.push(p);
                }
            }
        }
        let self_loop = g.edges[s0].iter().any(|e| e.to == s0);
        cyclic.push(members > 1 || self_loop);
    }
    (comp, cyclic)
}

fn steps_of(g: &Graph, from: usize, path: &Path, first_call: usize) -> Vec<Step> {
    let mut cur = from;
    let mut out = Vec::new();
    for (k, &(ei, to)) in path.iter().enumerate() {
        let e = &g.edges[cur][ei];
        let name = |b: usize| g.block_names.get(b).cloned().unwrap_or_default();
        out.push(Step {
            call: first_call + k,
            answers: e.answers.clone(),
            state: g.describe(to),
            blocked: e.blocked.iter().map(|(a, b)| (name(*a), name(*b))).collect(),
            operator: e.operator.map(name),
        });
        cur = to;
    }
    out
}

fn lasso(
    g: &Graph,
    prefix: &Path,
    s: usize,
    allowed: &dyn Fn(usize) -> bool,
    explanation: String,
) -> Counterexample {
    let mut steps = steps_of(g, 0, prefix, 1);
    let loop_from = steps.len();
    if let Some((_, cyc)) = bfs(g, s, allowed, &|t| t == s, true) {
        steps.extend(steps_of(g, s, &cyc, loop_from + 1));
    }
    Counterexample { initial: g.describe(0), steps, loop_from: Some(loop_from), explanation }
}

fn finite(g: &Graph, path: &Path, explanation: String) -> Counterexample {
    Counterexample {
        initial: g.describe(0),
        steps: steps_of(g, 0, path, 1),
        loop_from: None,
        explanation,
    }
}

fn outcome(g: &Graph, name: String, cx: Option<Counterexample>) -> Outcome {
    Outcome { property: name, holds: cx.is_none(), complete: g.cut.is_none(), counterexample: cx }
}

/// Checks a temporal property.
pub fn check_property(g: &Graph, name: &str, p: &Property) -> Outcome {
    let f = |s: usize| p.formula.holds(&g.states[s]);
    let all = |_: usize| true;
    let not_f = |s: usize| !f(s);
    let cx = match p.temporal {
        Temporal::Always => bfs(g, 0, &all, &not_f, false).map(|(s, path)| {
            finite(g, &path, format!("reaches {}, where the formula is false", g.describe(s)))
        }),
        Temporal::Eventually => {
            if f(0) {
                None
            } else {
                let (comp, cyclic) = sccs(g, &not_f);
                bfs(g, 0, &not_f, &|s| comp[s] != usize::MAX && cyclic[comp[s]], false).map(
                    |(s, path)| {
                        lasso(
                            g,
                            &path,
                            s,
                            &|t| !f(t) && comp[t] == comp[s],
                            "a run that never satisfies the formula: this cycle avoids it forever"
                                .into(),
                        )
                    },
                )
            }
        }
        Temporal::AlwaysEventually => {
            let (comp, cyclic) = sccs(g, &not_f);
            bfs(g, 0, &all, &|s| comp[s] != usize::MAX && cyclic[comp[s]], false).map(|(s, path)| {
                lasso(g, &path, s, &|t| !f(t) && comp[t] == comp[s], "after this prefix, the cycle can repeat forever without satisfying the formula".into())
            })
        }
        Temporal::EventuallyAlways => {
            let (comp, cyclic) = sccs(g, &all);
            bfs(g, 0, &all, &|s| !f(s) && cyclic[comp[s]], false).map(|(s, path)| {
                lasso(
                    g,
                    &path,
                    s,
                    &|t| comp[t] == comp[s],
                    "a cycle through a state violating the formula can repeat forever".into(),
                )
            })
        }
    };
    outcome(g, name.to_string(), cx)
}

/// Every reachable state can still reach a block of `safe`.
pub fn check_safe_blocks(g: &Graph, safe: &[usize]) -> Outcome {
    let n = g.states.len();
    let mut ok = vec![false; n];
    let mut rev: Vec<Vec<usize>> = vec![Vec::new(); n];
    for s in 0..n {
        for e in &g.edges[s] {
            if e.to < n {
                rev[e.to].push(s);
            }
        }
    }
    // States with dropped transitions might reach a safe block through them: unknown, so they
    // count as able to (a failure is then only reported when it is certain).
    let mut q: VecDeque<usize> = (0..n)
        .filter(|&s| {
            safe.contains(&g.states[s].block) || g.incomplete.get(s).copied().unwrap_or(true)
        })
        .collect();
    for &s in &q {
        ok[s] = true;
    }
    while let Some(s) = q.pop_front() {
        for &p in &rev[s] {
            if !ok[p] {
                ok[p] = true;
                q.push_back(p);
            }
        }
    }
    let names: Vec<String> = safe.iter().filter_map(|&b| g.block_names.get(b).cloned()).collect();
    let cx = bfs(g, 0, &|_| true, &|s| !ok[s], false).map(|(s, path)| {
        finite(
            g,
            &path,
            format!("from {} no run can reach a safe block ({})", g.describe(s), names.join(", ")),
        )
    });
    outcome(g, format!("every state can reach a safe block ({})", names.join(", ")), cx)
}

/// No reachable call has a block change refused by a forbidden deroute.
pub fn check_no_blocked(g: &Graph) -> Outcome {
    let n = g.states.len();
    let src = |s: usize| g.edges[s].iter().any(|e| !e.blocked.is_empty());
    let cx = bfs(g, 0, &|_| true, &src, false).map(|(s, mut path)| {
        if let Some(ei) = g.edges[s].iter().position(|e| !e.blocked.is_empty()) {
            let to = g.edges[s][ei].to.min(n.saturating_sub(1));
            path.push((ei, to));
        }
        finite(g, &path, "a block change is refused by a forbidden deroute in the last call".into())
    });
    outcome(g, "no block change is ever refused (forbidden deroutes never block)".into(), cx)
}

/// No reachable state where every call is refused a block change (the plan is stuck until an
/// operator intervenes).
pub fn check_deadlock_free(g: &Graph) -> Outcome {
    let stuck = |s: usize| {
        !g.incomplete.get(s).copied().unwrap_or(true)
            && !g.edges[s].is_empty()
            && g.edges[s].iter().all(|e| !e.blocked.is_empty())
    };
    let cx = bfs(g, 0, &|_| true, &stuck, false).map(|(s, path)| {
        finite(
            g,
            &path,
            format!("in {} every possible call is refused its block change", g.describe(s)),
        )
    });
    outcome(g, "no reachable state where every successor is forbidden".into(), cx)
}

/// Human-readable rendering of an outcome.
pub fn render(o: &Outcome) -> String {
    // A counterexample is a real run even on a cut graph; only "holds" needs the whole graph.
    let verdict = match (o.holds, o.complete) {
        (true, true) => "holds",
        (true, false) => "holds on the explored part only (state space cut: not established)",
        (false, _) => "FAILS",
    };
    let mut s = format!("{}: {verdict}\n", o.property);
    if let Some(cx) = &o.counterexample {
        s.push_str(&format!("  {}\n  start: {}\n", cx.explanation, cx.initial));
        for (i, st) in cx.steps.iter().enumerate() {
            if cx.loop_from == Some(i) {
                s.push_str("  -- cycle (repeats forever) --\n");
            }
            let ans: Vec<String> = st.answers.iter().map(|a| a.to_string()).collect();
            match &st.operator {
                Some(b) => s.push_str(&format!(
                    "  call {:>3}  operator jumps to '{b}' -> {}",
                    st.call, st.state
                )),
                None => s.push_str(&format!(
                    "  call {:>3}  answers [{}] -> {}",
                    st.call,
                    ans.join(" "),
                    st.state
                )),
            }
            for (a, b) in &st.blocked {
                s.push_str(&format!("  (refused: '{a}' -> '{b}')"));
            }
            s.push('\n');
        }
    }
    s
}

/// Parses a property against the graph's block names and checks it.
pub fn check_text(g: &Graph, text: &str) -> Result<Outcome, PropertyError> {
    let p = super::property::parse(text, &g.block_names)?;
    if p.formula.uses_last_block() && !g.last_block_kept {
        return Err(PropertyError {
            message:
                "last_block(..) needs a graph that keeps the last block (BuildOptions::last_block)"
                    .into(),
            text: text.to_string(),
            at: (0, text.len()).into(),
        });
    }
    Ok(check_property(g, text, &p))
}
