//! Upstream compatibility, decided once: where upstream's generator prints a known mistake
//! (EGM96 heights where the geoid is negative, `WAYPOINTS_GLOBAL` of "D M S" coordinates, the
//! `exceeding_time` sign), the emitter prints either upstream's text ([`Compat::Upstream`],
//! `--upstream-compat`) or the right one ([`Compat::Corrected`], each difference announced as a
//! located `fpl::W020`). The choice is one value handed to the emitter; `Choices` applies it
//! where a value is printed and keeps the corrections it made.

use crate::diag::Diagnostic;
use crate::span::Span;

use super::geoid::Node;

/// Which text is printed where upstream's output is known to be wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Compat {
    /// The right values; each place upstream differs is announced.
    #[default]
    Corrected,
    /// What upstream prints, its known mistakes included (`--upstream-compat`).
    Upstream,
}

impl Compat {
    /// `upstream` under [`Compat::Upstream`], else `ours`.
    pub fn pick<T>(self, ours: T, upstream: T) -> T {
        match self {
            Compat::Corrected => ours,
            Compat::Upstream => upstream,
        }
    }
}

/// Which printed value a geoid height goes into (for the correction messages).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum GeoidUse {
    /// `NAV_MSL0`.
    Reference,
    /// A `WAYPOINTS_LLA` row (`false`) or a `WAYPOINTS_LLA_WGS84` row (`true`).
    Row(bool),
}

/// The choice, applied value by value, and the corrections made.
#[derive(Debug, Clone)]
pub(crate) struct Choices {
    pub compat: Compat,
    /// Geoid nodes where upstream prints a wrong height: (use, true metres, upstream's, span).
    geoid_fixes: Vec<(GeoidUse, f64, f64, Span)>,
    /// Waypoints given in "D M S": (name, span).
    global_fixes: Vec<(String, Span)>,
}

impl Choices {
    pub fn new(compat: Compat) -> Self {
        Choices { compat, geoid_fixes: Vec::new(), global_fixes: Vec::new() }
    }

    /// The geoid height printed for `node`.
    pub fn geoid_height(&mut self, node: Node, span: Span, used: GeoidUse) -> f64 {
        if self.compat == Compat::Corrected && node.upstream_is_wrong() {
            self.geoid_fixes.push((used, node.metres(), node.upstream(), span));
        }
        self.compat.pick(node.metres(), node.upstream())
    }

    /// The `WAYPOINTS_GLOBAL` flag printed.
    pub fn global_flag(&mut self, global: bool, upstream: bool, name: &str, span: Span) -> bool {
        if self.compat == Compat::Corrected && global != upstream {
            self.global_fixes.push((name.to_string(), span));
        }
        self.compat.pick(global, upstream)
    }

    /// The corrections made, as located warnings (none under [`Compat::Upstream`]).
    pub fn corrections(&self) -> Vec<Diagnostic> {
        let mut out = Vec::new();
        for (used, true_m, up_m, span) in &self.geoid_fixes {
            if *used == GeoidUse::Reference {
                out.push(Diagnostic::correction(
                    format!(
                        "NAV_MSL0 is {:.0} mm: the EGM96 geoid height at the reference is {true_m:.2} m; \
                         upstream prints {:.0} ({up_m:.2} m, 655.36 m too high)",
                        1000.0 * true_m,
                        1000.0 * up_m
                    ),
                    *span,
                    GEOID_WHY,
                ));
            }
        }
        let rows: Vec<_> = self.geoid_fixes.iter().filter(|f| f.0 != GeoidUse::Reference).collect();
        if let Some((_, true_m, up_m, span)) = rows.first() {
            out.push(Diagnostic::correction(
                format!(
                    "{} rows of WAYPOINTS_LLA (local msl) and WAYPOINTS_LLA_WGS84 (.alt) lie where the EGM96 \
                     geoid height is negative (here {true_m:.2} m); upstream prints {up_m:.2} m there",
                    rows.len() / 2
                ),
                *span,
                GEOID_WHY,
            ));
        }
        for (name, span) in &self.global_fixes {
            out.push(Diagnostic::correction(
                format!(
                    "waypoint '{name}' is given by latitude and longitude: WAYPOINTS_GLOBAL is TRUE; \
                     upstream prints FALSE because it re-reads \"D M S\" coordinates as plain floats"
                ),
                *span,
                "a FALSE flag makes the waypoint local: it moves with the local origin instead of \
                 staying fixed on the ground; --upstream-compat prints FALSE as upstream does",
            ));
        }
        out
    }
}

/// Why upstream's geoid heights are wrong where the geoid is negative.
const GEOID_WHY: &str = "upstream assembles the 16-bit grid value and sign-extends it with a shift pair \
    that does nothing on 64-bit OCaml, so negative heights come out 655.36 m too high; \
    --upstream-compat prints upstream's value";
