//! Whole-file conveniences over the phases: parse a plan file, run the three passes, emit the
//! header (and, on request, the dump and the settings), for one plan or many in parallel.
//! Every failure is a located [`Diagnostics`].

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::diag::{Diagnostic, Diagnostics};
use crate::emit::settings::Settings;
use crate::emit::{EmitOptions, compile_plan, compile_plan_full};
use crate::front::{Options, parse_file, parse_file_with};

/// Parse, the three passes, emission: `vouch fpl compile` without the file writing.
/// `opts.source_path` is filled with `path` when empty. Errors of the front end and of the back
/// end are both located in the plan's sources ([`Diagnostics::is_io`] tells an unreadable file).
pub fn compile_file(path: &Path, opts: &EmitOptions) -> Result<String, Diagnostics> {
    let plan = parse_file(path)?;
    let mut o = opts.clone();
    if o.source_path.is_empty() {
        o.source_path = path.display().to_string();
    }
    compile_plan(&plan, &o).map_err(|e| e.to_diagnostics(&plan.sources))
}

/// The warnings `compile` gives for a parsed plan (upstream's notices and warnings, the
/// announced corrections), located; for `vouch fpl lint`, so that it reports what `compile`
/// warns about. A plan the back end rejects gives its error.
pub fn generator_warnings(
    plan: &crate::ast::FlightPlan,
    opts: &EmitOptions,
) -> Result<Vec<Diagnostic>, Diagnostics> {
    let e = compile_plan_full(plan, opts).map_err(|e| e.to_diagnostics(&plan.sources))?;
    Ok(e.notices.into_iter().chain(e.corrections).collect())
}

/// What to build for a plan.
#[derive(Debug, Clone, Default)]
pub struct Request {
    /// Front-end options (include search path, extensions).
    pub front: Options,
    /// Emission options; `source_path` empty means "the path as given".
    pub emit: EmitOptions,
    /// Also build upstream's dump.
    pub dump: bool,
    /// Also build the settings.
    pub settings: bool,
}

/// Everything built for one plan.
#[derive(Debug, Clone)]
pub struct Built {
    /// `flight_plan.h`.
    pub header: String,
    /// `flight_plan.xml` (upstream's dump), when requested.
    pub dump: Option<String>,
    /// `settings.xml` and `settings.h`, when requested.
    pub settings: Option<Settings>,
    /// The front end's warnings, upstream's notices, then the announced corrections, located.
    pub warnings: Vec<Diagnostic>,
    /// Whether an SRTM tile covered the reference (upstream prints `No SRTM data found to
    /// check altitude.` when none did).
    pub terrain: crate::emit::terrain::Coverage,
}

/// Builds the requested outputs of one plan.
pub fn build(path: &Path, req: &Request) -> Result<Built, Diagnostics> {
    finish(path, parse_file_with(path, &req.front)?, req)
}

/// Builds many plans in parallel (rayon), in the order given. The geoid grid is read once; a
/// thread decompresses it ahead while the plans are parsed.
pub fn build_many(paths: &[PathBuf], req: &Request) -> Vec<Result<Built, Diagnostics>> {
    let stop = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|scope| {
        scope.spawn(|| {
            if let Ok(g) = req.emit.geoid() {
                g.prefetch(&stop);
            }
        });
        let parsed: Vec<_> = paths.par_iter().map(|p| parse_file_with(p, &req.front)).collect();
        // From here on each plan reads only as far into the grid as its nodes need.
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        paths.par_iter().zip(parsed).map(|(path, plan)| finish(path, plan?, req)).collect()
    })
}

/// The back end for a parsed plan.
fn finish(path: &Path, plan: crate::ast::FlightPlan, req: &Request) -> Result<Built, Diagnostics> {
    let mut opts = req.emit.clone();
    if opts.source_path.is_empty() {
        opts.source_path = path.display().to_string();
    }
    let reject = |e: crate::passes::CompileError| e.to_diagnostics(&plan.sources);
    let emitted = compile_plan_full(&plan, &opts).map_err(reject)?;
    let dump = req.dump.then(|| crate::emit::dump::dump(&plan)).transpose().map_err(reject)?;
    let settings = req
        .settings
        .then(|| crate::emit::settings::settings(&plan, &opts.version))
        .transpose()
        .map_err(reject)?;
    let mut warnings = plan.warnings.clone();
    warnings.extend(emitted.notices);
    warnings.extend(emitted.corrections);
    Ok(Built { header: emitted.header, dump, settings, warnings, terrain: emitted.terrain })
}
