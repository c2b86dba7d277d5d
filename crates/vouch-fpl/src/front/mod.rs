//! The FPL front end: reads a Paparazzi flight plan the way upstream does and produces the
//! typed, resolved [`FlightPlan`] or located [`Diagnostics`]. Everything XML stays here.
//!
//! Pipeline (each step a module):
//! 1. [`tolerant`]: length-preserving pre-pass that neutralises what xml-light accepts and
//!    strict XML rejects; then `tree`: roxmltree parse into an owned element tree whose
//!    attribute values are read from the original text.
//! 2. `include`: `<includes>` expansion exactly like upstream's `fp_proc` (renaming,
//!    parameter substitution, re-printing of procedure attributes).
//! 3. `expand`: `<path>` expansion and relative waypoints (`wp_qdr`/`wp_dist`).
//! 4. `build` (the driver, with the schema checks), `plan` and `stages` (typed building over
//!    the shared `ctx`): checks against the DTD (unknown elements/attributes, required
//!    attributes), typed values, expressions parsed, names resolved, implicit `HOME` block.

mod build;
mod ctx;
mod expand;
mod expanded;
mod include;
mod plan;
mod schema;
mod stages;
pub mod tolerant;
mod tree;
pub(crate) mod values;

use std::path::{Path, PathBuf};

use crate::ast::FlightPlan;
use crate::diag::{Diagnostic, Diagnostics, ErrorKind};
use crate::span::SourceMap;

/// Front-end options.
#[derive(Debug, Clone)]
pub struct Options {
    /// Extra directories searched for included procedures after the including file's own
    /// directory (upstream searches `conf/flight_plans`). When empty, the nearest ancestor
    /// directory of the plan that holds a `flight_plan.dtd` is used, which is where
    /// `conf/flight_plans` is in a Paparazzi tree and in `shared/fpl/corpus`.
    pub search_dirs: Vec<PathBuf>,
    /// Accept the VFPG `<forbidden_deroutes>` extension (default true). When false the element
    /// is rejected like upstream's DTD does.
    pub allow_forbidden_deroutes: bool,
    /// Search included procedures exactly as upstream does (`--upstream-compat`): the plan's
    /// directory, then [`Options::upstream_flight_plans`], and nothing else.
    pub upstream_includes: bool,
    /// Upstream's fallback directory for procedures: `$PAPARAZZI_HOME/conf/flight_plans`
    /// (upstream's `$PAPARAZZI_HOME` defaults to `$HOME/paparazzi`). Without
    /// [`Options::upstream_includes`] it is only consulted to warn when upstream would include
    /// another file than vouch does.
    pub upstream_flight_plans: Option<PathBuf>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            search_dirs: Vec::new(),
            allow_forbidden_deroutes: true,
            upstream_includes: false,
            upstream_flight_plans: upstream_flight_plans(None),
        }
    }
}

/// `conf/flight_plans` of the Paparazzi home upstream uses: `home` when given, else
/// `$PAPARAZZI_HOME`, else `$HOME/paparazzi` (upstream's `Env.paparazzi_home`).
pub fn upstream_flight_plans(home: Option<&Path>) -> Option<PathBuf> {
    let home = match home {
        Some(h) => h.to_path_buf(),
        None => match std::env::var_os("PAPARAZZI_HOME") {
            Some(h) => PathBuf::from(h),
            None => PathBuf::from(std::env::var_os("HOME")?).join("paparazzi"),
        },
    };
    Some(home.join("conf").join("flight_plans"))
}

/// Parses the flight plan at `path` with default [`Options`].
pub fn parse_file(path: impl AsRef<Path>) -> Result<FlightPlan, Diagnostics> {
    parse_file_with(path, &Options::default())
}

/// Parses the flight plan at `path`.
pub fn parse_file_with(path: impl AsRef<Path>, opts: &Options) -> Result<FlightPlan, Diagnostics> {
    let path = path.as_ref();
    match std::fs::read(path) {
        Ok(bytes) => {
            let text = String::from_utf8_lossy(&bytes).into_owned();
            parse_str_at(path, text, opts)
        }
        Err(e) => Err(Diagnostics::new(
            vec![Diagnostic::error(
                ErrorKind::Io,
                format!("cannot read {}: {e}", path.display()),
                None,
            )],
            SourceMap::default(),
        )),
    }
}

/// Parses `text` as if it were the file at `path` (includes are searched from its directory).
pub fn parse_str_at(path: &Path, text: String, opts: &Options) -> Result<FlightPlan, Diagnostics> {
    let mut sources = SourceMap::default();
    let main = sources.add(path.display().to_string(), text);
    let mut search = vec![path.parent().map(Path::to_path_buf).unwrap_or_default()];
    if opts.search_dirs.is_empty() {
        search.extend(flight_plans_dir(path));
    } else {
        search.extend(opts.search_dirs.iter().cloned());
    }
    let mut ctx = ctx::Ctx::new(sources, opts.clone(), search, path.to_path_buf());
    let plan = build::run(&mut ctx, main);
    ctx.finish(plan)
}

/// Parses `text` with no file behind it (includes are searched in the current directory).
pub fn parse_str(name: &str, text: &str) -> Result<FlightPlan, Diagnostics> {
    parse_str_at(Path::new(name), text.to_string(), &Options::default())
}

/// Nearest ancestor directory containing `flight_plan.dtd` (upstream's `conf/flight_plans`).
fn flight_plans_dir(path: &Path) -> Option<PathBuf> {
    let abs = std::fs::canonicalize(path).ok()?;
    abs.ancestors().skip(1).find(|d| d.join("flight_plan.dtd").is_file()).map(Path::to_path_buf)
}
