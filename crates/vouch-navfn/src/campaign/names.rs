//! The campaign's vocabulary as types: checked properties, metamorphic relations (with their
//! exactness), case outcomes and finding kinds. Each serialises to the name the JSON reports
//! have always used (`obstacle_free_queues`, `embed_path@embed3`, `found`, `suboptimal`, …),
//! and orders like that name, so report maps keep their key order.

use std::cmp::Ordering;
use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::campaign::transform::Transform;

/// A property checked on every run (search trace, final state, or reachability).
/// Variants are declared in the alphabetical order of their names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Property {
    /// `FinitePotentialPath`: every path point has a cell of finite potential within ±0.5.
    FinitePotentialPath,
    /// A non-empty path implies the start potential was finite when extraction began.
    NoPathWithoutFinitePotential,
    /// No obstacle cell is ever in a priority buffer.
    ObstacleFreeQueues,
    /// The path starts at the NavFn start and ends at the NavFn goal.
    PathEndPoints,
    /// `PositionSafe`: finite potential only on open cells.
    PositionSafe,
    /// `Progress`: every finite non-goal cell has a lower 4-neighbour.
    Progress,
    /// Without a cycle limit, start reached ⇔ start and goal 4-connected.
    ReachabilityIsConnectivity,
    /// `ValidPath`: every path point has an open cell within ±0.5.
    ValidPath,
}

impl Property {
    /// The properties of the core's run-time plan checks (`crate::checks`).
    pub const PLAN_CHECKS: [Property; 5] = [
        Property::ValidPath,
        Property::FinitePotentialPath,
        Property::PositionSafe,
        Property::Progress,
        Property::PathEndPoints,
    ];

    /// The properties the search observer checks while NavFn runs.
    pub const SEARCH_TRACE: [Property; 2] =
        [Property::ObstacleFreeQueues, Property::NoPathWithoutFinitePotential];

    /// The report name.
    pub fn name(self) -> &'static str {
        match self {
            Property::FinitePotentialPath => "finite_potential_path",
            Property::NoPathWithoutFinitePotential => "no_path_without_finite_potential",
            Property::ObstacleFreeQueues => "obstacle_free_queues",
            Property::PathEndPoints => "path_end_points",
            Property::PositionSafe => "position_safe",
            Property::Progress => "progress",
            Property::ReachabilityIsConnectivity => "reachability_is_connectivity",
            Property::ValidPath => "valid_path",
        }
    }
}

impl fmt::Display for Property {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What a metamorphic relation states (see `metamorphic.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RelationKind {
    /// Start reached ⇔ start and goal connected, on the transformed map.
    Reachability,
    /// Every property holds on the transformed run.
    Properties,
    /// Embedding: identical potentials on the embedded cells.
    EmbedPotential,
    /// Embedding: the shifted path, within rounding.
    EmbedPath,
    /// Symmetry: start potentials within a relative tolerance (approximate).
    ApproxStartPotential,
    /// Symmetry: path costs within a relative tolerance (approximate).
    ApproxPathCost,
}

impl RelationKind {
    const ALL: [RelationKind; 6] = [
        RelationKind::Reachability,
        RelationKind::Properties,
        RelationKind::EmbedPotential,
        RelationKind::EmbedPath,
        RelationKind::ApproxStartPotential,
        RelationKind::ApproxPathCost,
    ];

    /// The name before `@` in reports.
    pub fn name(self) -> &'static str {
        match self {
            RelationKind::Reachability => "reachability",
            RelationKind::Properties => "properties",
            RelationKind::EmbedPotential => "embed_potential",
            RelationKind::EmbedPath => "embed_path",
            RelationKind::ApproxStartPotential => "approx_start_potential",
            RelationKind::ApproxPathCost => "approx_path_cost",
        }
    }

    /// Exact relations must hold on every case (a violation is a failure of the campaign);
    /// approximate ones are findings about NavFn's asymmetry.
    pub fn exact(self) -> bool {
        !matches!(self, RelationKind::ApproxStartPotential | RelationKind::ApproxPathCost)
    }
}

/// One relation under one transform, named `kind@transform` (e.g. `embed_path@embed3`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Relation {
    /// What is stated.
    pub kind: RelationKind,
    /// Between the original run and the run on this transform.
    pub transform: Transform,
}

impl Relation {
    /// Whether a violation is a failure (exact) or a finding (approximate).
    pub fn exact(self) -> bool {
        self.kind.exact()
    }
}

impl fmt::Display for Relation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}@{}", self.kind.name(), self.transform.label())
    }
}

impl FromStr for Relation {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (k, t) = s.split_once('@').ok_or_else(|| format!("relation `{s}`: no `@`"))?;
        let kind = RelationKind::ALL
            .into_iter()
            .find(|r| r.name() == k)
            .ok_or_else(|| format!("unknown relation `{k}`"))?;
        Ok(Relation { kind, transform: t.parse()? })
    }
}

impl Ord for Relation {
    /// The order of the names: no kind name is a prefix of another, so comparing kind names
    /// first and transform labels second is comparing `kind@label`.
    fn cmp(&self, o: &Self) -> Ordering {
        self.kind
            .name()
            .cmp(o.kind.name())
            .then_with(|| self.transform.label().cmp(&o.transform.label()))
    }
}

impl PartialOrd for Relation {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

impl Serialize for Relation {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for Relation {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

/// Something that failed on a case: a property or an exact relation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Failed {
    /// A property.
    Property(Property),
    /// An exact relation.
    Relation(Relation),
}

/// How a case ended (golden/README.md, "Outcome statistics").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// NavFn returned a path.
    #[default]
    Found,
    /// Start and goal are the same cell.
    StartIsGoal,
    /// Start not reached and not 4-connected to the goal.
    Unreachable,
    /// Start connected but not reached: the cycle limit cut the search short.
    CycleLimit,
    /// Start reached but `calcPath` failed.
    PathFailed,
}

/// The kind of a finding. Variants are declared in the alphabetical order of their names
/// (findings are sorted by kind).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FindingKind {
    /// An approximate relation did not hold (a finding about NavFn, not a failure).
    ApproxRelation,
    /// A property failed.
    CheckFailed,
    /// A path with a turn sharper than 90°.
    Obtuse,
    /// The oracle answered differently.
    OracleMismatch,
    /// NavFn's oscillation test fired.
    Oscillation,
    /// An exact relation failed.
    RelationFailed,
    /// A path costing more than the threshold ratio × the optimum.
    Suboptimal,
}

impl FindingKind {
    /// The report name.
    pub fn name(self) -> &'static str {
        match self {
            FindingKind::ApproxRelation => "approx_relation",
            FindingKind::CheckFailed => "check_failed",
            FindingKind::Obtuse => "obtuse",
            FindingKind::OracleMismatch => "oracle_mismatch",
            FindingKind::Oscillation => "oscillation",
            FindingKind::RelationFailed => "relation_failed",
            FindingKind::Suboptimal => "suboptimal",
        }
    }
}

impl fmt::Display for FindingKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn declaration_order_is_name_order() {
        let props = [
            Property::FinitePotentialPath,
            Property::NoPathWithoutFinitePotential,
            Property::ObstacleFreeQueues,
            Property::PathEndPoints,
            Property::PositionSafe,
            Property::Progress,
            Property::ReachabilityIsConnectivity,
            Property::ValidPath,
        ];
        assert!(props.windows(2).all(|w| w[0] < w[1] && w[0].name() < w[1].name()));
        let kinds = [
            FindingKind::ApproxRelation,
            FindingKind::CheckFailed,
            FindingKind::Obtuse,
            FindingKind::OracleMismatch,
            FindingKind::Oscillation,
            FindingKind::RelationFailed,
            FindingKind::Suboptimal,
        ];
        assert!(kinds.windows(2).all(|w| w[0] < w[1] && w[0].name() < w[1].name()));
        for k in kinds {
            assert_eq!(serde_json::to_value(k).expect("json"), k.name());
        }
    }

    #[test]
    fn relations_round_trip_through_their_names() {
        for s in ["embed_path@embed3", "approx_path_cost@mirror_x", "reachability@rot90"] {
            let r: Relation = s.parse().expect("parses");
            assert_eq!(r.to_string(), s);
            assert_eq!(serde_json::to_value(r).expect("json"), s);
        }
        assert!(!"approx_start_potential@rot180".parse::<Relation>().expect("parses").exact());
        assert!("nope@rot90".parse::<Relation>().is_err());
        let mut names: Vec<String> = Vec::new();
        let mut rels: Vec<Relation> = Vec::new();
        for kind in RelationKind::ALL {
            for transform in Transform::ALL_BASIC {
                rels.push(Relation { kind, transform });
                names.push(Relation { kind, transform }.to_string());
            }
        }
        rels.sort();
        names.sort();
        assert_eq!(rels.iter().map(Relation::to_string).collect::<Vec<_>>(), names);
        assert!("embed_path@twist".parse::<Relation>().is_err());
        let f: Vec<Failed> =
            serde_json::from_str(r#"["progress","embed_path@embed3"]"#).expect("parses");
        assert_eq!(f[0], Failed::Property(Property::Progress));
    }
}
