//! `vouch fpl aircraft`: the flight-plan part of Paparazzi's `gen_aircraft` step. Reads
//! `conf/conf.xml`, finds the aircraft's flight plan and writes `flight_plan.h`,
//! `flight_plan.xml` (the dump), a copy of the plan and, with `--settings`, `settings.xml` and
//! `settings.h` where `gen_aircraft` writes them ([`vouch_fpl::aircraft::layout`]). A file is
//! only written when its content changes, through a temporary file renamed over it, so an
//! error never leaves a partial file behind.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Args;
use vouch_fpl::aircraft::{find, layout};
use vouch_fpl::emit::EmitOptions;
use vouch_fpl::pipeline::{Request, build};

use super::rejected;
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch fpl aircraft`.
#[derive(Args)]
pub struct AircraftArgs {
    /// Aircraft name (the `name` of an <aircraft> in conf.xml)
    #[arg(long)]
    name: String,
    /// Build target: the headers go to var/aircrafts/AC/TARGET/generated/
    #[arg(long, default_value = "ap")]
    target: String,
    /// Paparazzi home (default: $PAPARAZZI_HOME)
    #[arg(long, value_name = "DIR")]
    paparazzi_home: Option<PathBuf>,
    /// Configuration file (default: PAPARAZZI_HOME/conf/conf.xml)
    #[arg(long, value_name = "FILE")]
    conf: Option<PathBuf>,
    /// Directory for the generated headers (gen_aircraft's -ac_dir: DIR/generated/)
    #[arg(long, value_name = "DIR")]
    ac_dir: Option<PathBuf>,
    /// Directory for the aircraft's dump, settings and configuration copy (gen_aircraft's -conf_dir)
    #[arg(long, value_name = "DIR")]
    conf_dir: Option<PathBuf>,
    /// Generate the flight-plan files (the default when neither --flight-plan nor --settings is given)
    #[arg(long)]
    flight_plan: bool,
    /// Generate settings.xml and settings.h from the plan's variables (an aircraft whose
    /// airframe, telemetry or modules add settings gets those from gen_aircraft)
    #[arg(long)]
    settings: bool,
    /// Both of the above (gen_aircraft's -all for the flight-plan part)
    #[arg(long)]
    all: bool,
    /// Print exactly what upstream prints, its known mistakes included, procedures searched
    /// in upstream's order, and upstream's "No SRTM data found to check altitude." line
    #[arg(long)]
    upstream_compat: bool,
}

/// `vouch fpl aircraft`: one line per file on standard output (`updated` / `unchanged`).
pub fn aircraft(a: AircraftArgs, ctx: &mut Ctx) -> CmdResult {
    let home = a
        .paparazzi_home
        .clone()
        .or_else(|| std::env::var_os("PAPARAZZI_HOME").map(PathBuf::from))
        .ok_or_else(|| {
            Failure::usage("no Paparazzi home: give --paparazzi-home or set PAPARAZZI_HOME")
        })?;
    let conf = a.conf.clone().unwrap_or_else(|| home.join("conf/conf.xml"));
    let ac = find(&conf, &home.join("conf"), &a.name).map_err(|e| {
        if e.is_io() { Failure::Usage(miette::Report::new(e)) } else { Failure::rejected(e) }
    })?;
    let places = layout(&home, &ac, &a.target, a.ac_dir.as_deref(), a.conf_dir.as_deref());
    let (fp, settings) = match (a.flight_plan || a.all, a.settings || a.all) {
        (false, false) => (true, false),
        chosen => chosen,
    };
    let req = Request {
        emit: EmitOptions {
            // As gen_aircraft: the plan's full path on line 1 of the header.
            source_path: ac.flight_plan.display().to_string(),
            upstream_compat: a.upstream_compat,
            paparazzi_home: Some(home.clone()),
            ..EmitOptions::default()
        },
        front: vouch_fpl::front::Options {
            upstream_includes: a.upstream_compat,
            upstream_flight_plans: vouch_fpl::front::upstream_flight_plans(Some(&home)),
            ..Default::default()
        },
        dump: fp,
        settings,
    };
    let built = build(&ac.flight_plan, &req).map_err(rejected)?;
    super::report_built(ctx, &built, a.upstream_compat);
    let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    if fp {
        files.push((places.flight_plan_h, built.header.into_bytes()));
        files.push((places.flight_plan_xml, built.dump.unwrap_or_default().into_bytes()));
        let source =
            std::fs::read(&ac.flight_plan).map_err(|e| Failure::io(&ac.flight_plan, &e))?;
        let name = ac.flight_plan.file_name().unwrap_or_default();
        files.push((places.plan_copy_dir.join(name), source));
    }
    if let Some(s) = built.settings {
        files.push((places.settings_xml, s.xml.into_bytes()));
        files.push((places.settings_h, s.header.into_bytes()));
    }
    for (path, bytes) in &files {
        let changed = write_if_changed(path, bytes)?;
        writeln!(ctx.out, "{}: {}", if changed { "updated" } else { "unchanged" }, path.display())?;
    }
    Ok(Exit::Ok)
}

/// Writes `bytes` to `path` unless it already holds them: into a temporary file in the same
/// directory, renamed over `path` (never a partial file). True when written.
fn write_if_changed(path: &Path, bytes: &[u8]) -> Result<bool, Failure> {
    if std::fs::read(path).is_ok_and(|old| old == bytes) {
        return Ok(false);
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| Failure::io(dir, &e))?;
    let mut tmp = tempfile::NamedTempFile::new_in(dir).map_err(|e| Failure::io(dir, &e))?;
    tmp.write_all(bytes).map_err(|e| Failure::io(path, &e))?;
    tmp.persist(path).map_err(|e| Failure::io(path, &e.error))?;
    Ok(true)
}
