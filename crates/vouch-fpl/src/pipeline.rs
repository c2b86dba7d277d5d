//! Whole-file conveniences over the phases: parse a plan file, run the three passes, emit the
//! header. Every failure is a located [`Diagnostics`].

use std::path::Path;

use crate::diag::Diagnostics;
use crate::emit::{compile_plan, EmitOptions};
use crate::front::parse_file;

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
