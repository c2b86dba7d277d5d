//! Values of configuration keys, read as mavlink-router reads them (booleans `true`/`false` or a
//! number, comma-separated lists, decimal numbers) but strictly: what mavlink-router would read
//! as 0 by accident (`atoi` of a word) is an error here.

use super::error::{ConfError, ConfErrorKind};
use super::ini::{Entry, Ini};

/// Reads values of entries, reporting bad ones at their place.
pub(super) struct Values<'a> {
    pub ini: &'a Ini,
}

impl Values<'_> {
    pub fn bad(&self, e: &Entry, expected: &str) -> ConfError {
        let msg = format!("`{}` = `{}`: expected {expected}", e.key, e.value);
        self.ini.err(ConfErrorKind::BadValue, e.value_at, msg)
    }

    pub fn boolean(&self, e: &Entry) -> Result<bool, ConfError> {
        let v = e.value.as_str();
        if v.eq_ignore_ascii_case("true") {
            Ok(true)
        } else if v.eq_ignore_ascii_case("false") {
            Ok(false)
        } else {
            v.parse::<i64>().map(|n| n != 0).map_err(|_| self.bad(e, "true, false, 1 or 0"))
        }
    }

    pub fn number(&self, e: &Entry, max: u64) -> Result<u64, ConfError> {
        match e.value.parse::<u64>() {
            Ok(n) if n <= max => Ok(n),
            _ => Err(self.bad(e, &format!("a whole number from 0 to {max}"))),
        }
    }

    /// A signed number (mavlink-router's `RetryTimeout` is an `int`).
    pub fn signed(&self, e: &Entry) -> Result<i64, ConfError> {
        e.value.parse::<i64>().map_err(|_| self.bad(e, "a whole number"))
    }

    /// A comma-separated list of numbers up to `max` (blank items are skipped).
    pub fn list(&self, e: &Entry, max: u64) -> Result<Vec<u64>, ConfError> {
        e.value
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|s| match s.parse::<u64>() {
                Ok(n) if n <= max => Ok(n),
                _ => {
                    Err(self.bad(e, &format!("a comma-separated list of numbers from 0 to {max}")))
                }
            })
            .collect()
    }

    pub fn ids(&self, e: &Entry) -> Result<Vec<u8>, ConfError> {
        Ok(self.list(e, 255)?.into_iter().map(|n| n as u8).collect())
    }

    pub fn msg_ids(&self, e: &Entry) -> Result<Vec<u32>, ConfError> {
        Ok(self.list(e, 0xFF_FFFF)?.into_iter().map(|n| n as u32).collect())
    }

    /// One of `choices` (case-insensitive), as its index.
    pub fn choice(&self, e: &Entry, choices: &[&str]) -> Result<usize, ConfError> {
        choices
            .iter()
            .position(|c| c.eq_ignore_ascii_case(&e.value))
            .ok_or_else(|| self.bad(e, &format!("one of {}", choices.join(", "))))
    }
}

#[cfg(test)]
mod tests {
    use super::super::ini::Source;
    use super::*;

    #[test]
    fn values_as_mavlink_router_writes_them_and_strict_errors() {
        let mut ini = Ini::default();
        let text = "[G]\nA = TRUE\nB = 0\nC = 0, 33 ,253\nD = 2,x\nE = 256\nF = Server\n";
        ini.add(Source { name: "t.conf".into(), text: text.into() }).unwrap();
        let v = Values { ini: &ini };
        let s = &ini.sections[0];
        assert!(v.boolean(s.get("a").unwrap()).unwrap());
        assert!(!v.boolean(s.get("b").unwrap()).unwrap());
        assert_eq!(v.msg_ids(s.get("c").unwrap()).unwrap(), vec![0, 33, 253]);
        let e = v.msg_ids(s.get("d").unwrap()).unwrap_err();
        assert_eq!((e.kind, e.line_col()), (ConfErrorKind::BadValue, (5, 5)));
        assert!(v.ids(s.get("e").unwrap()).is_err());
        assert_eq!(v.choice(s.get("f").unwrap(), &["normal", "server"]).unwrap(), 1);
        assert!(v.boolean(s.get("f").unwrap()).is_err());
    }
}
