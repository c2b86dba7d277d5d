//! Upstream's SRTM checks (UPSTREAM_CHECKS.md H8, H12c, A2, A3): the plan's `alt` against the
//! terrain at the reference, then every waypoint's altitude (the `dummy` one first) against the
//! terrain at its position, where a tile exists. Below the terrain is upstream's
//! `MAJOR NOTICE`, quoted with upstream's text and the element as upstream prints it.
//!
//! Conditions as upstream's: strictly below; no tile at the reference is reported once
//! ([`Coverage::NoTile`], upstream's `No SRTM data found to check altitude.`), no tile at a
//! waypoint silently skips it. Where upstream fails instead, vouch decides:
//! * an unreadable tile (short, not decompressible) at the reference is error `fpl::E025`, as
//!   upstream stops there (`End_of_file`); at a waypoint upstream skips the check silently, vouch
//!   skips it too and says so once per tile (`fpl::W028`);
//! * a position in a tile's southernmost half row, where upstream's index falls past the tile
//!   (upstream stops with `index out of bounds` at the reference, skips a waypoint), is not
//!   checked ([`Coverage::OffTile`] at the reference).

use std::path::PathBuf;

use crate::ast::FlightPlan;
use crate::ast::expanded::Node;
use crate::diag::{Diagnostic, ErrorKind};
use crate::passes::{CompileError, CompileErrorKind};
use crate::span::Span;

use super::geo::{self, Geo};
use super::srtm::{Sample, SearchPath};

/// What the reference's terrain check could do.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Coverage {
    /// Checked against this tile.
    Tile(PathBuf),
    /// No tile covers the reference: upstream prints `No SRTM data found to check altitude.`
    NoTile {
        /// The tile searched for (`N43E001`).
        name: String,
        /// The directories searched.
        searched: Vec<PathBuf>,
    },
    /// A tile exists but upstream's sample falls past its end (upstream stops there).
    OffTile(PathBuf),
}

/// The terrain notices of a plan, in upstream's order.
#[derive(Debug, Clone)]
pub struct Terrain {
    /// A3 for the plan's altitude at the reference.
    pub reference: Vec<Diagnostic>,
    /// A3 for waypoints, and the unreadable tiles they fall in.
    pub waypoints: Vec<Diagnostic>,
    /// What happened at the reference.
    pub coverage: Coverage,
}

/// A waypoint as upstream checks it: name, position, altitude (the WAYPOINTS_UTM column),
/// where to point at.
pub(crate) struct Point<'a> {
    /// `None` for upstream's implicit `dummy` waypoint.
    pub name: Option<&'a str>,
    pub geo: Geo,
    pub alt: f64,
    pub span: Span,
}

/// Runs the checks against the tiles of `search`.
pub(crate) fn check(
    plan: &FlightPlan,
    points: &[Point<'_>],
    search: &SearchPath,
) -> Result<Terrain, CompileError> {
    let reference =
        Geo { lat: geo::rad_of_deg(plan.lat0.value), lon: geo::rad_of_deg(plan.lon0.value) };
    let mut quoted = Quoted { plan, tree: None };
    let mut reference_notices = Vec::new();
    let alt = plan.alt.value;
    let coverage = match search.sample(reference.lat, reference.lon) {
        Sample::NoTile(name) => Coverage::NoTile { name, searched: search.searched().to_vec() },
        Sample::Unreadable(e) => {
            return Err(CompileError {
                message: format!("{e}: the terrain at the reference cannot be checked"),
                span: Some(plan.lat0.text.span),
                kind: CompileErrorKind::Environment,
            });
        }
        Sample::OffTile(t) => Coverage::OffTile(t.path.clone()),
        Sample::Height(h, t) => {
            if alt < h {
                let element = quoted.plan()?;
                reference_notices.push(notice(alt, h, &element, plan.alt.text.span, &t.path));
            }
            Coverage::Tile(t.path.clone())
        }
    };
    let mut out = Terrain { reference: reference_notices, waypoints: Vec::new(), coverage };
    let mut unreadable: Vec<PathBuf> = Vec::new();
    for p in points {
        match search.sample(p.geo.lat, p.geo.lon) {
            Sample::Height(h, t) if p.alt < h => {
                let element = quoted.waypoint(p.name)?;
                out.waypoints.push(notice(p.alt, h, &element, p.span, &t.path));
            }
            Sample::Unreadable(e) if !unreadable.contains(&e.path) => {
                unreadable.push(e.path.clone());
                out.waypoints.push(Diagnostic::warning_of(
                    ErrorKind::TerrainUnchecked,
                    format!(
                        "{e}: the terrain at waypoint '{}' is not checked",
                        p.name.unwrap_or("dummy")
                    ),
                    Some(p.span),
                ));
            }
            _ => {}
        }
    }
    Ok(out)
}

/// Upstream's A3 line, word for word, as the message.
fn notice(alt: f64, terrain: f64, element: &str, span: Span, tile: &std::path::Path) -> Diagnostic {
    Diagnostic::warning_of(
        ErrorKind::BelowTerrain,
        format!("MAJOR NOTICE: below SRTM ground altitude ({alt:.0}<{terrain:.0}) in {element}"),
        Some(span),
    )
    .with_help(format!(
        "the terrain height is the sample upstream reads in {} (one row south of the nearest)",
        tile.display()
    ))
}

/// The elements upstream quotes, printed on demand (only when a notice fires).
struct Quoted<'a> {
    plan: &'a FlightPlan,
    tree: Option<Node>,
}

impl Quoted<'_> {
    fn tree(&mut self) -> Result<&Node, CompileError> {
        if self.tree.is_none() {
            self.tree = Some(super::dump::processed(self.plan)?.0);
        }
        Ok(self.tree.get_or_insert_with(Node::default))
    }

    fn plan(&mut self) -> Result<String, CompileError> {
        Ok(super::xml_light::to_string(self.tree()?))
    }

    /// The waypoint as upstream's list holds it (localised); the implicit `dummy` is
    /// upstream's constant element.
    fn waypoint(&mut self, name: Option<&str>) -> Result<String, CompileError> {
        let Some(name) = name else {
            let a = |n: &str, v: &str| (n.to_string(), v.to_string());
            let dummy = Node::new(
                "waypoint",
                vec![a("name", "dummy"), a("x", "0."), a("y", "0.")],
                Vec::new(),
            );
            return Ok(super::xml_light::to_string(&dummy));
        };
        let tree = self.tree()?;
        let found = tree
            .children
            .iter()
            .filter(|c| c.tag.eq_ignore_ascii_case("waypoints"))
            .flat_map(|w| &w.children)
            .find(|w| w.attr("name") == Some(name));
        Ok(found
            .map(super::xml_light::to_string)
            .unwrap_or_else(|| format!("<waypoint name=\"{name}\"/>")))
    }
}
