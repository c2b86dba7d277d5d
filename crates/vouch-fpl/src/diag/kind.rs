//! The kinds of errors, each with a stable code.

use serde::Serialize;

/// What went wrong; tools match on this (or on its [`code`](ErrorKind::code)) rather than on
/// message texts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum ErrorKind {
    /// Reading a file failed.
    Io,
    /// Not well-formed XML even for upstream's lenient reader (unclosed tag, ...).
    Xml,
    /// The root element is not `<flight_plan>`.
    WrongRoot,
    /// An element not allowed at that place.
    UnexpectedElement,
    /// A stage tag that does not exist (case-sensitive, as upstream).
    UnknownStage,
    /// An attribute not declared for that element.
    UnknownAttribute,
    /// A required attribute is missing.
    MissingAttribute,
    /// A required element is missing (`<waypoints>`, `<blocks>`, a `HOME` waypoint, ...).
    MissingElement,
    /// The plan has no block or no waypoint.
    EmptyPlan,
    /// Two blocks with the same name.
    DuplicateBlock,
    /// Two written waypoints with the same name (upstream silently uses the first; vouch
    /// refuses it; duplicates created by relative waypoints stay warnings, as they are upstream's
    /// own doing).
    DuplicateWaypoint,
    /// A deroute / exception / `IndexOfBlock` / forbidden deroute names no block.
    UnknownBlock,
    /// A stage or sector corner names no waypoint.
    UnknownWaypoint,
    /// A number that does not parse (`Float expected`).
    BadNumber,
    /// A number that parses but is out of its range (latitude beyond 90, negative height...).
    NumberOutOfRange,
    /// An attribute value outside its fixed set (vmode, hmode, loop, orientation, wp_frame...).
    BadValue,
    /// An expression that does not lex or parse.
    BadExpression,
    /// An included procedure file cannot be found or read.
    IncludeNotFound,
    /// An include that (directly or indirectly) includes itself.
    IncludeLoop,
    /// A procedure parameter with neither argument nor default value.
    MissingParam,
    /// A stage kind upstream refuses inside procedures (`guided`, `oval`, `path`, ...).
    ProcedureStage,
    /// Inconsistent attributes on one element (both `approaching_time` and `exceeding_time`,
    /// both `vars` and `handler`, `pitch="auto"` with `vmode="throttle"`, ...).
    Conflict,
    /// Attributes that cannot produce code (upstream's generator-level failures: no altitude
    /// for an `alt` vertical mode, `glide` without a route, ...).
    Generation,
    /// More than 256 blocks, or more than 256 stages in a block (the C runtime's `uint8_t`).
    TooLarge,
    /// The Paparazzi home lacks what the generator reads (`data/srtm/WW15MGH.DAC[.bz2]`,
    /// `conf/abi.xml`), or it is broken.
    Environment,
    /// A geofence limit below the ground, security or home-mode altitude (upstream: exit 1).
    Geofence,
    /// A flight-plan variable that cannot become a setting (empty short name, `handler`
    /// without or with both `module`/`header`, persistent setting of unknown type).
    Settings,
    /// Non-fatal: something accepted the way upstream accepts it, worth knowing.
    Warning,
    /// Non-fatal: vouch prints a different value than upstream because upstream's is wrong.
    Correction,
    /// Non-fatal: an attribute upstream never reads in this context (it passes unchecked).
    Unread,
    /// Non-fatal (upstream's NOTICE): an altitude below `ground_alt + security_height`.
    LowAltitude,
    /// Non-fatal (upstream's warning): a waypoint farther than `max_dist_from_home` from HOME.
    FarFromHome,
    /// Non-fatal (upstream's warning): the reference is close to a UTM zone border.
    UtmZoneBorder,
    /// Non-fatal (upstream's NOTICE): `hmode="route"` without `from` uses the last waypoint.
    RouteWithoutFrom,
    /// Non-fatal (upstream's warnings and NOTICEs): geofence limits set, or below the default
    /// altitude.
    GeofenceNotice,
    /// Non-fatal (upstream's MAJOR NOTICE): an altitude below the SRTM terrain height.
    BelowTerrain,
    /// Non-fatal: an SRTM tile where a waypoint lies cannot be read, so its terrain is not
    /// checked (upstream skips it silently).
    TerrainUnchecked,
    /// Non-fatal: `--upstream-compat` printed upstream's output where it is known to be wrong.
    UpstreamMistake,
}

impl ErrorKind {
    /// The stable code shown with the message (`fpl::E001` ...; `fpl::W000` for warnings).
    pub fn code(self) -> &'static str {
        match self {
            ErrorKind::Io => "fpl::E001",
            ErrorKind::Xml => "fpl::E002",
            ErrorKind::WrongRoot => "fpl::E003",
            ErrorKind::UnexpectedElement => "fpl::E004",
            ErrorKind::UnknownStage => "fpl::E005",
            ErrorKind::UnknownAttribute => "fpl::E006",
            ErrorKind::MissingAttribute => "fpl::E007",
            ErrorKind::MissingElement => "fpl::E008",
            ErrorKind::EmptyPlan => "fpl::E009",
            ErrorKind::DuplicateBlock => "fpl::E010",
            ErrorKind::DuplicateWaypoint => "fpl::E011",
            ErrorKind::UnknownBlock => "fpl::E012",
            ErrorKind::UnknownWaypoint => "fpl::E013",
            ErrorKind::BadNumber => "fpl::E014",
            ErrorKind::NumberOutOfRange => "fpl::E015",
            ErrorKind::BadValue => "fpl::E016",
            ErrorKind::BadExpression => "fpl::E017",
            ErrorKind::IncludeNotFound => "fpl::E018",
            ErrorKind::IncludeLoop => "fpl::E019",
            ErrorKind::MissingParam => "fpl::E020",
            ErrorKind::ProcedureStage => "fpl::E021",
            ErrorKind::Conflict => "fpl::E022",
            ErrorKind::Generation => "fpl::E023",
            ErrorKind::TooLarge => "fpl::E024",
            ErrorKind::Environment => "fpl::E025",
            ErrorKind::Geofence => "fpl::E026",
            ErrorKind::Settings => "fpl::E027",
            ErrorKind::Warning => "fpl::W000",
            ErrorKind::Correction => "fpl::W020",
            ErrorKind::Unread => "fpl::W021",
            ErrorKind::LowAltitude => "fpl::W022",
            ErrorKind::FarFromHome => "fpl::W023",
            ErrorKind::UtmZoneBorder => "fpl::W024",
            ErrorKind::RouteWithoutFrom => "fpl::W025",
            ErrorKind::GeofenceNotice => "fpl::W026",
            ErrorKind::BelowTerrain => "fpl::W027",
            ErrorKind::TerrainUnchecked => "fpl::W028",
            ErrorKind::UpstreamMistake => "fpl::W029",
        }
    }
}
