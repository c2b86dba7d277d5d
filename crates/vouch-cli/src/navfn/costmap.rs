//! `vouch navfn costmap`: the static layer of a ROS map inflated as nav2's `InflationLayer`
//! does it, written as a PGM (image orientation) or raw bytes (row 0 = bottom); and the
//! footprint and inflation arguments shared with `plan`, `check-bag` and `inflation`.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use vouch_navfn::costmap::{
    Body, BodyCheck, BodyReport, CostmapError, DEFAULT_PADDING, Footprint, INSCRIBED,
    InflationLayer, InflationParams, LETHAL, costmap_resolution, sha256_hex,
};
use vouch_navfn::maps::{RosMap, load_ros_map};

use super::{map_failure, write_file};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// The robot's body: `--robot-radius` or `--footprint` (nav2's two ways).
#[derive(Args, Clone, Debug, Default)]
pub struct BodyArgs {
    /// Circular robot of this radius in metres (nav2 robot_radius; a 16-gon)
    #[arg(long, value_name = "M", conflicts_with = "footprint")]
    pub robot_radius: Option<f64>,
    /// Robot polygon in metres, robot frame, as nav2's footprint parameter: '[[x,y],[x,y],...]'
    #[arg(long, value_name = "POLYGON", allow_hyphen_values = true)]
    pub footprint: Option<String>,
    /// Footprint padding in metres (nav2 footprint_padding; default the float 0.01)
    #[arg(long, value_name = "M")]
    pub footprint_padding: Option<f64>,
}

impl BodyArgs {
    /// The padded footprint, if a body was given.
    pub fn footprint(&self) -> Result<Option<Footprint>, Failure> {
        let pad = self.footprint_padding.unwrap_or(DEFAULT_PADDING);
        if !pad.is_finite() || pad < 0.0 {
            return Err(Failure::usage(format!("--footprint-padding {pad}: expected ≥ 0")));
        }
        let f = match (&self.footprint, self.robot_radius) {
            (Some(s), _) => Footprint::from_polygon_str(s, pad),
            (None, Some(r)) => Footprint::from_radius(r, pad),
            (None, None) => return Ok(None),
        };
        f.map(Some).map_err(costmap_failure)
    }
}

/// nav2's inflation layer parameters.
#[derive(Args, Clone, Debug)]
pub struct InflationArgs {
    /// inflation_radius in metres (nav2 default 0.55)
    #[arg(long, default_value_t = 0.55, value_name = "M")]
    pub inflation_radius: f64,
    /// cost_scaling_factor (nav2 default 10.0)
    #[arg(long, default_value_t = 10.0, value_name = "K")]
    pub cost_scaling_factor: f64,
    /// Unknown cells take any non-zero inflation cost (nav2 inflate_unknown)
    #[arg(long)]
    pub inflate_unknown: bool,
    /// Unknown cells are obstacles for the inflation (nav2 inflate_around_unknown)
    #[arg(long)]
    pub inflate_around_unknown: bool,
}

impl InflationArgs {
    /// As the library's parameters.
    pub fn params(&self) -> InflationParams {
        InflationParams {
            inflation_radius: self.inflation_radius,
            cost_scaling_factor: self.cost_scaling_factor,
            inflate_unknown: self.inflate_unknown,
            inflate_around_unknown: self.inflate_around_unknown,
        }
    }
}

/// A bad footprint or parameter: rejected input (exit 1).
pub fn costmap_failure(e: CostmapError) -> Failure {
    Failure::rejected(e)
}

/// Arguments of `vouch navfn costmap`.
#[derive(Args)]
#[command(after_help = after_help!(
    [
        "vouch navfn costmap map.yaml --robot-radius 0.22 --inflation-radius 0.55 --cost-scaling-factor 3 -o costmap.pgm",
        "vouch navfn costmap map.yaml --footprint '[[0.3,0.2],[0.3,-0.2],[-0.3,-0.2],[-0.3,0.2]]' -o costmap.bin"
    ],
    "0 written, 1 map or parameter rejected, 2 usage or I/O error"
))]
pub struct CostmapArgs {
    /// Map: map_server YAML (naming a PGM/PNG), or a PGM/PNG image
    map: PathBuf,
    #[command(flatten)]
    body: BodyArgs,
    #[command(flatten)]
    inflation: InflationArgs,
    /// Output: `.pgm` (P5, image orientation, the cost values as grey) or anything else for raw
    /// bytes, row 0 = bottom row (ROS Costmap2D order)
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Print a JSON summary
    #[arg(long)]
    json: bool,
}

/// The static layer of `map`'s file inflated for the body (none: a point robot).
pub fn inflate(
    map: &RosMap,
    footprint: Option<&Footprint>,
    params: InflationParams,
) -> Result<(Vec<u8>, InflationLayer), Failure> {
    let inscribed = footprint.map_or(0.0, Footprint::inscribed_radius);
    let layer =
        InflationLayer::new(params, costmap_resolution(map), inscribed).map_err(costmap_failure)?;
    let mut costs = map.costmap.clone();
    layer.inflate(&mut costs, map.width, map.height);
    Ok((costs, layer))
}

/// Runs `vouch navfn costmap`.
pub fn run(a: CostmapArgs, ctx: &mut Ctx) -> CmdResult {
    let map = load_ros_map(&a.map, true).map_err(map_failure)?;
    let footprint = a.body.footprint()?;
    let (costs, layer) = inflate(&map, footprint.as_ref(), a.inflation.params())?;
    if let Some(path) = &a.output {
        let is_pgm = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("pgm"));
        let bytes = if is_pgm { pgm_bytes(&costs, map.width, map.height) } else { costs.clone() };
        write_file(path, &bytes)?;
    }
    let sha = sha256_hex(&costs);
    let count = |f: &dyn Fn(u8) -> bool| costs.iter().filter(|&&c| f(c)).count();
    let lethal = count(&|c| c == LETHAL);
    let inscribed = count(&|c| c == INSCRIBED);
    let inflated = count(&|c| c > 0 && c < INSCRIBED);
    if a.json {
        ctx.out.json(&serde_json::json!({
            "width": map.width, "height": map.height,
            "resolution": costmap_resolution(&map),
            "inscribed_radius": layer.inscribed_radius(),
            "circumscribed_radius": footprint.as_ref().map(Footprint::circumscribed_radius),
            "cell_inflation_radius": layer.cell_inflation_radius(),
            "lethal": lethal, "inscribed": inscribed, "inflated": inflated,
            "sha256": sha,
        }))?;
    } else {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{}x{}  inscribed radius {:.6} m  inflation {} cells  lethal {lethal}  inscribed {inscribed}  inflated {inflated}",
            map.width,
            map.height,
            layer.inscribed_radius(),
            layer.cell_inflation_radius()
        );
        let _ = writeln!(s, "sha256 {sha}");
        ctx.out.write_all(s.as_bytes())?;
    }
    Ok(Exit::Ok)
}

/// P5 PGM, maxval 255, the top image row first (the costmap's last row).
fn pgm_bytes(costs: &[u8], w: usize, h: usize) -> Vec<u8> {
    let mut out = format!("P5\n{w} {h}\n255\n").into_bytes();
    for row in costs.chunks_exact(w.max(1)).rev().take(h) {
        out.extend_from_slice(row);
    }
    out
}

/// The body the check uses: the disc of `--robot-radius` or the `--footprint` polygon as
/// given (nav2's padding is a margin, not the robot).
pub fn body_shape(args: &BodyArgs) -> Result<Option<Body>, Failure> {
    let Some(f) = args.footprint()? else { return Ok(None) };
    Ok(Some(match f.spec {
        vouch_navfn::costmap::FootprintSpec::Radius(r) => Body::Disc(r),
        vouch_navfn::costmap::FootprintSpec::Polygon(p) => Body::Polygon(p),
    }))
}

/// The body check of `poses` (x, y, yaw) against the static layer of `map`.
pub fn body_check(
    map: &RosMap,
    args: &BodyArgs,
    window: f64,
    poses: &[[f64; 3]],
) -> Result<BodyReport, Failure> {
    if !window.is_finite() || window < 0.0 {
        return Err(Failure::usage(format!("--clearance-window {window}: expected ≥ 0")));
    }
    let body =
        body_shape(args)?.ok_or_else(|| Failure::usage("no --robot-radius or --footprint"))?;
    let check = BodyCheck {
        costs: &map.costmap,
        width: map.width,
        height: map.height,
        world: map.world(),
        body,
        window,
    };
    Ok(check.check(poses))
}

/// The picture's marks: contacts in magenta, the closest lethal cell in cyan.
pub fn body_marks(b: &BodyReport) -> Vec<([usize; 2], [u8; 3])> {
    let mut marks: Vec<([usize; 2], [u8; 3])> =
        b.violations.iter().map(|v| (v.cell, [255, 0, 255])).collect();
    marks.extend(b.min.map(|m| (m.cell, [0, 230, 230])));
    marks.dedup();
    marks
}

/// Contacts listed in the text form; the JSON form has them all.
const CONTACTS_SHOWN: usize = 10;

/// The body check as text: verdict, minimum clearance and where, each contact.
pub fn print_body(ctx: &mut Ctx, b: &BodyReport) -> Result<(), Failure> {
    let verdict =
        if b.is_ok() { "ok".to_string() } else { format!("{} contacts", b.violations.len()) };
    let clearance = match &b.min {
        Some(m) => format!(
            "min clearance {:.4} m at pose {} (lethal cell {},{} at {:.3},{:.3})",
            m.clearance, m.pose, m.cell[0], m.cell[1], m.cell_xy[0], m.cell_xy[1]
        ),
        None => format!("min clearance ≥ {} m", b.window),
    };
    writeln!(ctx.out, "body {verdict}  {clearance}")?;
    for v in b.violations.iter().take(CONTACTS_SHOWN) {
        writeln!(
            ctx.out,
            "body contact: pose {} → {} touches lethal cell {},{} at {:.3},{:.3}",
            v.pose,
            v.pose + 1,
            v.cell[0],
            v.cell[1],
            v.cell_xy[0],
            v.cell_xy[1]
        )?;
    }
    if b.violations.len() > CONTACTS_SHOWN {
        writeln!(
            ctx.out,
            "body contact: … {} more (--json lists all)",
            b.violations.len() - CONTACTS_SHOWN
        )?;
    }
    Ok(())
}
