//! The driver's line protocol, read side: the records of an `X` answer, crashes, answer lists
//! and state changes (see the comment at the top of `c/explore_driver.c`).

use super::{CRun, DriverError, Expansion, Second, protocol};

pub(super) fn finish(ex: &mut Expansion, run: Option<CRun>) {
    ex.runs.extend(run);
}

pub(super) fn done_run(jump: Option<usize>, answers: Vec<i64>) -> CRun {
    CRun::Done {
        jump,
        answers,
        events: Vec::new(),
        after: Vec::new(),
        seconds: Vec::new(),
        hidden: Vec::new(),
        joined: None,
    }
}

/// `A <status> k a1..ak` or `A <status> J b`.
pub(super) fn crashed(rest: &str) -> Result<CRun, DriverError> {
    let (st, rest) = rest.split_once(' ').unwrap_or((rest, "0"));
    let status = st.parse::<i64>().map_err(|_| protocol(format!("bad status '{st}'")))?;
    Ok(match rest.strip_prefix("J ") {
        Some(b) => CRun::Crashed { status, answers: Vec::new(), jump: Some(parse_num(b)?) },
        None => CRun::Crashed { status, answers: parse_answers(rest)?, jump: None },
    })
}

/// One line of an `X` answer other than its end: a record starts (`P`, `J`, `L`) or the current
/// one goes on (`S`, `T`, `H`, event lines). `states` are the requested state and its copies.
pub(super) fn record_line(
    ex: &mut Expansion,
    cur: &mut Option<CRun>,
    l: &str,
    states: (&[u8], &[Vec<u8>]),
) -> Result<(), DriverError> {
    let (tag, rest) = l.split_once(' ').unwrap_or((l, ""));
    match (tag, cur.as_mut()) {
        ("P", _) => {
            finish(ex, cur.take());
            *cur = Some(done_run(None, parse_answers(rest)?));
        }
        ("J", _) => {
            finish(ex, cur.take());
            *cur = Some(done_run(Some(parse_num(rest)?), Vec::new()));
        }
        ("L", _) => {
            finish(ex, cur.take());
            ex.runs.push(CRun::TooLong { answers: parse_answers(rest)? });
        }
        ("S", Some(CRun::Done { after, .. })) => *after = apply_changes(states.0, rest)?,
        ("M", Some(CRun::Done { joined, .. })) => *joined = Some(parse_num(rest)?),
        ("T", Some(CRun::Done { seconds, .. })) => {
            let (i, changes) = rest.split_once(' ').unwrap_or((rest, ""));
            if let Some((a, b)) = i.split_once('-') {
                // copies a to b met the explored run (`T a-b =`)
                let (a, b) = (parse_num(a)?, parse_num(b)?);
                if b < a || b >= states.1.len() || changes.trim() != "=" {
                    return Err(protocol(format!("bad T line '{l}'")));
                }
                seconds.extend((a..=b).map(|_| Second::Met));
                return Ok(());
            }
            let base = states.1.get(parse_num(i)?).ok_or_else(|| protocol("T line for no copy"))?;
            seconds.push(match changes.trim() {
                "!" => Second::Differs(Vec::new()),
                _ => Second::Same(apply_changes(base, changes)?),
            })
        }
        // (a run that did not end is reported as such already)
        ("H", Some(CRun::Done { hidden, .. })) => hidden.push(parse_num(rest)?),
        ("H", _) => {}
        ("S" | "T" | "M", _) => return Err(protocol(format!("{tag} line outside a run"))),
        (_, Some(CRun::Done { seconds, events, .. })) => match seconds.last_mut() {
            Some(Second::Differs(ev2)) => ev2.push(l.to_string()),
            _ => events.push(l.to_string()),
        },
        _ => return Err(protocol(format!("unexpected line '{l}'"))),
    }
    Ok(())
}

pub(super) fn parse_hex(text: &str) -> Result<Vec<u8>, DriverError> {
    hex::decode(text.trim()).map_err(|e| protocol(format!("bad hexadecimal state: {e}")))
}

pub(super) fn parse_num(text: &str) -> Result<usize, DriverError> {
    text.trim().parse().map_err(|_| protocol(format!("bad number '{text}'")))
}

/// `base` with the ` offset=value` changes of a driver line applied.
pub(super) fn apply_changes(base: &[u8], changes: &str) -> Result<Vec<u8>, DriverError> {
    let mut s = base.to_vec();
    for w in changes.split_whitespace() {
        let (o, v) = w.split_once('=').ok_or_else(|| protocol(format!("bad change '{w}'")))?;
        let o: usize = o.parse().map_err(|_| protocol(format!("bad offset '{o}'")))?;
        let v: u8 = v.parse().map_err(|_| protocol(format!("bad byte '{v}'")))?;
        *s.get_mut(o).ok_or_else(|| protocol(format!("offset {o} out of the state")))? = v;
    }
    Ok(s)
}

pub(super) fn parse_answers(rest: &str) -> Result<Vec<i64>, DriverError> {
    let mut it = rest.split_whitespace();
    let n: usize = it
        .next()
        .and_then(|w| w.parse().ok())
        .ok_or_else(|| protocol(format!("bad answer list '{rest}'")))?;
    let v = it
        .map(|w| w.parse::<i64>().map_err(|_| protocol(format!("bad answer '{w}'"))))
        .collect::<Result<Vec<_>, _>>()?;
    if v.len() != n {
        return Err(protocol(format!("answer count mismatch in '{rest}'")));
    }
    Ok(v)
}
