//! The C field types of ABI messages, read as upstream reads them for every plan: from
//! `$PAPARAZZI_HOME/conf/abi.xml`, class `airborne` (a missing file or class is an error, as
//! upstream's). Without a Paparazzi home a built-in table of the messages the corpus binds with
//! `vars` stands in.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

use crate::passes::CompileError;

/// Message name → field types.
#[derive(Debug, Default)]
pub struct AbiTable(HashMap<String, Vec<String>>);

impl AbiTable {
    /// The field types of a message.
    pub fn fields(&self, msg: &str) -> Option<&[String]> {
        self.0.get(msg).map(Vec::as_slice)
    }

    /// `HOME/conf/abi.xml`, read once per process.
    pub fn of_home(home: &Path) -> Result<Arc<AbiTable>, CompileError> {
        static CACHE: OnceLock<Mutex<HashMap<PathBuf, Arc<AbiTable>>>> = OnceLock::new();
        let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
        if let Some(t) = cache.lock().ok().and_then(|c| c.get(home).cloned()) {
            return Ok(t);
        }
        let t = Arc::new(Self::read(&home.join("conf/abi.xml"))?);
        if let Ok(mut c) = cache.lock() {
            c.insert(home.to_path_buf(), t.clone());
        }
        Ok(t)
    }

    fn read(path: &Path) -> Result<AbiTable, CompileError> {
        let env = |m: String| CompileError::environment(format!("{}: {m}", path.display()));
        let text = std::fs::read_to_string(path).map_err(|e| env(e.to_string()))?;
        let opts = roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() };
        let doc =
            roxmltree::Document::parse_with_options(&text, opts).map_err(|e| env(e.to_string()))?;
        let class = doc
            .descendants()
            .find(|n| n.has_tag_name("msg_class") && n.attribute("name") == Some("airborne"))
            .ok_or_else(|| env("no msg_class 'airborne'".into()))?;
        let mut map = HashMap::new();
        for m in class.children().filter(|n| n.has_tag_name("message")) {
            let Some(name) = m.attribute("name") else { continue };
            let types = m
                .children()
                .filter(|f| f.has_tag_name("field"))
                .map(|f| f.attribute("type").unwrap_or("").to_string())
                .collect();
            map.insert(name.to_string(), types);
        }
        Ok(AbiTable(map))
    }

    /// The stand-in without a Paparazzi home.
    pub fn builtin() -> Arc<AbiTable> {
        static T: OnceLock<Arc<AbiTable>> = OnceLock::new();
        T.get_or_init(|| {
            let f = vec!["float".to_string(); 3];
            Arc::new(AbiTable(HashMap::from([("RANGE_FORCEFIELD".to_string(), f)])))
        })
        .clone()
    }
}
