//! Paparazzi's aircraft configuration, as far as the flight plan goes: `conf/conf.xml` is read
//! the way upstream's `gen_aircraft` reads it (the `<aircraft>` with that `name`; names and
//! `ac_id`s must be unique), the aircraft's `flight_plan` is found under `conf/`, and the
//! places `gen_aircraft` writes to are computed:
//!
//! | file | place |
//! | --- | --- |
//! | `flight_plan.h`, `settings.h` | `$PAPARAZZI_HOME/var/aircrafts/AC/TARGET/generated/` (`-ac_dir D`: `D/generated/`) |
//! | `flight_plan.xml` (the dump), `settings.xml` | `$PAPARAZZI_HOME/var/aircrafts/AC/` (`-conf_dir D`: `D/`) |
//! | a copy of the plan | `var/aircrafts/AC/conf/<directory of the plan under conf/>/` |
//!
//! Reading only: the caller writes the files.

use std::path::{Path, PathBuf};

/// Why the aircraft cannot be found.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum AircraftError {
    /// `conf.xml` cannot be read.
    #[error("cannot read {0}: {1}")]
    #[diagnostic(code(fpl::E028))]
    Read(PathBuf, String),
    /// `conf.xml` is not well-formed.
    #[error("{0}: not well-formed XML: {1}")]
    #[diagnostic(code(fpl::E028))]
    Xml(PathBuf, String),
    /// Two aircraft share a name or an id (upstream stops there too).
    #[error("{0}: aircraft {1} '{2}' appears twice")]
    #[diagnostic(code(fpl::E028))]
    Duplicate(PathBuf, &'static str, String),
    /// No aircraft of that name.
    #[error("aircraft '{1}' not found in {0}")]
    #[diagnostic(
        code(fpl::E028),
        help("the names are the `name` attributes of conf.xml's <aircraft> elements")
    )]
    NotFound(PathBuf, String),
    /// The aircraft has no flight plan.
    #[error("aircraft '{1}' in {0} has no flight_plan attribute")]
    #[diagnostic(code(fpl::E028))]
    NoFlightPlan(PathBuf, String),
}

/// One aircraft of `conf.xml`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Aircraft {
    pub name: String,
    pub ac_id: String,
    /// The `flight_plan` attribute, relative to `conf/` (e.g. `flight_plans/basic.xml`).
    pub flight_plan_rel: String,
    /// The plan file (`conf_dir/flight_plan_rel`).
    pub flight_plan: PathBuf,
}

/// Finds aircraft `name` in the conf file `conf_xml`; plans are relative to `conf_dir`.
pub fn find(conf_xml: &Path, conf_dir: &Path, name: &str) -> Result<Aircraft, AircraftError> {
    let path = conf_xml.to_path_buf();
    let bytes =
        std::fs::read(conf_xml).map_err(|e| AircraftError::Read(path.clone(), e.to_string()))?;
    // Bytes that are not text are a rejected configuration, not a failed read.
    let text = String::from_utf8(bytes).map_err(|e| {
        AircraftError::Xml(
            path.clone(),
            format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        )
    })?;
    find_in(&text, conf_xml, conf_dir, name)
}

impl AircraftError {
    /// Whether `conf.xml` could not be read at all (an I/O problem, exit 2 in the CLI) rather
    /// than read and rejected.
    pub fn is_io(&self) -> bool {
        matches!(self, AircraftError::Read(..))
    }
}

/// [`find`] on the text of a conf file (`conf_xml` names it in errors).
pub fn find_in(
    text: &str,
    conf_xml: &Path,
    conf_dir: &Path,
    name: &str,
) -> Result<Aircraft, AircraftError> {
    let path = conf_xml.to_path_buf();
    let opts = roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() };
    let doc = roxmltree::Document::parse_with_options(text, opts)
        .map_err(|e| AircraftError::Xml(path.clone(), e.to_string()))?;
    let all: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("aircraft")).collect();
    let (mut names, mut ids) = (Vec::new(), Vec::new());
    for a in &all {
        let (n, id) = (a.attribute("name").unwrap_or(""), a.attribute("ac_id").unwrap_or(""));
        if names.contains(&n) {
            return Err(AircraftError::Duplicate(path, "name", n.to_string()));
        }
        if ids.contains(&id) {
            return Err(AircraftError::Duplicate(path, "ac_id", id.to_string()));
        }
        names.push(n);
        ids.push(id);
    }
    let ac = all
        .iter()
        .find(|a| a.attribute("name") == Some(name))
        .ok_or_else(|| AircraftError::NotFound(path.clone(), name.to_string()))?;
    let rel = ac
        .attribute("flight_plan")
        .filter(|f| !f.trim().is_empty())
        .ok_or_else(|| AircraftError::NoFlightPlan(path.clone(), name.to_string()))?
        .trim()
        .to_string();
    Ok(Aircraft {
        name: name.to_string(),
        ac_id: ac.attribute("ac_id").unwrap_or("").to_string(),
        flight_plan: conf_dir.join(&rel),
        flight_plan_rel: rel,
    })
}

/// Where `gen_aircraft` puts the flight-plan outputs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Layout {
    pub flight_plan_h: PathBuf,
    pub flight_plan_xml: PathBuf,
    pub settings_xml: PathBuf,
    pub settings_h: PathBuf,
    /// Directory the plan is copied into.
    pub plan_copy_dir: PathBuf,
}

/// The places for aircraft `ac` built for `target` in Paparazzi home `home` (`ac_dir` and
/// `conf_dir` are `gen_aircraft`'s `-ac_dir` and `-conf_dir`).
pub fn layout(
    home: &Path,
    ac: &Aircraft,
    target: &str,
    ac_dir: Option<&Path>,
    conf_dir: Option<&Path>,
) -> Layout {
    let default_dir = home.join("var/aircrafts").join(&ac.name);
    let aircraft_dir = conf_dir.map_or_else(|| default_dir.clone(), Path::to_path_buf);
    let gen_dir = match ac_dir {
        Some(d) => d.join("generated"),
        None => default_dir.join(target).join("generated"),
    };
    let rel_dir =
        Path::new(&ac.flight_plan_rel).parent().map(Path::to_path_buf).unwrap_or_default();
    Layout {
        flight_plan_h: gen_dir.join("flight_plan.h"),
        flight_plan_xml: aircraft_dir.join("flight_plan.xml"),
        settings_xml: aircraft_dir.join("settings.xml"),
        settings_h: gen_dir.join("settings.h"),
        plan_copy_dir: aircraft_dir.join("conf").join(rel_dir),
    }
}
