//! The standard library on the 43 uncurated recordings of ../shared/mavlink/tlogs_wild2: zero
//! violations on every one (a test per recording), and the sessions its README documents
//! recognised (mission uploads, clears, downloads, guided-mode items). The README's figures come
//! from pymavlink, independently of this crate.

use std::path::PathBuf;
use std::sync::Arc;

use vouch_mav::dialect::load_dialect_file;
use vouch_mav::monitor::Monitor;
use vouch_mav::monitor::offline::{RecordingReport, check_tlog};

fn shared() -> Option<PathBuf> {
    vouch_testkit::shared("mavlink", "tlogs_wild2/README.md")
}

fn run(file: &str) -> Option<RecordingReport> {
    let dir = shared()?;
    let dialect =
        Arc::new(load_dialect_file(&dir.join("definitions/ardupilotmega.xml")).expect("dialect"));
    let data = std::fs::read(dir.join("tlogs_wild2").join(file)).expect("read tlog");
    let mut m = Monitor::with_stdlib(dialect, &[]).expect("stdlib loads");
    let r = check_tlog(&data, &mut m);
    for p in r.summary.protocols.iter().filter(|p| p.started + p.unverifiable + p.violations > 0) {
        eprintln!(
            "  {:<24} started {:>4} completed {:>4} abandoned {:>4} unfinished {:>3} violations {} unverifiable {}",
            p.name, p.started, p.completed, p.abandoned, p.unfinished, p.violations, p.unverifiable
        );
    }
    assert!(r.codec.frames > 0, "{file}: no frame read");
    assert_eq!(
        r.violations.len(),
        0,
        "{file}: {}",
        r.violations.iter().take(5).map(|v| v.to_string()).collect::<Vec<_>>().join("\n")
    );
    assert_eq!(r.summary.forgeries, 0, "{file}: forgeries cannot be told offline");
    Some(r)
}

fn proto(r: &RecordingReport, name: &str) -> (u64, u64) {
    r.summary.protocol(name).map(|p| (p.started, p.completed)).unwrap_or((0, 0))
}

macro_rules! clean {
    ($($test:ident => $file:literal,)*) => {$(
        #[test]
        fn $test() {
            run($file);
        }
    )*};
}

clean! {
    ardusub_pixhawk_2019_rovvision => "ardusub_pixhawk_mavproxy_2019_rovvision.tlog",
    ardusub_pixhawk_2019_robosub => "ardusub_pixhawk_mavproxy_2019_robosub.tlog",
    ardusub_sitl_2026_sauvc => "ardusub_sitl_mavproxy_2026_sauvc.tlog",
    ardusub_sitl_2025_autotest => "ardusub_sitl_autotest_2025_sample.tlog",
    ardusub_sitl_2022_uuv => "ardusub_sitl_mavproxy_gcs_2022_uuv.tlog",
    ardurover_sitl_2022_allseaing => "ardurover_sitl_mavproxy_2022_allseaing.tlog",
    ardurover_sitl_2026_solar => "ardurover_sitl_mavproxy_gcs_2026_solar.tlog",
    ardurover_pixhawk1_2024_strawberry => "ardurover_pixhawk1_mavproxy_2024_strawberry.tlog",
    ardurover_sitl_2017_gsimon2 => "ardurover_sitl_mavproxy_2017_gsimon2.tlog",
    ardurover_sitl_2017_anthonybuo => "ardurover_sitl_mavproxy_2017_anthonybuo.tlog",
    arduplane_sitl_2025_ece492 => "arduplane_sitl_mavproxy_gcs_2025_ece492.tlog",
    arduplane_pixhawk_2018_wskgcs => "arduplane_pixhawk_mavproxy_2018_wskgcs.tlog",
    arduplane_sitl_2023_kuav => "arduplane_sitl_mavproxy_2023_kuav.tlog",
    arduplane_sitl_2016_ardutesis => "arduplane_sitl_mavproxy_2016_ardutesis.tlog",
    arduplane_sitl_2017_mikesayer => "arduplane_sitl_mavproxy_2017_mikesayer.tlog",
    arduplane_vtol_sitl_2025_yakup => "arduplane_vtol_sitl_mavproxy_2025_yakup.tlog",
    arduplane_cuavx7_2024_gcsv2 => "arduplane_cuavx7_mavproxy_2024_gcsv2.tlog",
    arducopter_sitl_2024_lrsfei => "arducopter_sitl_mavproxy_2024_lrsfei.tlog",
    arducopter_sitl_2022_pymavtut => "arducopter_sitl_mavproxy_gcs_2022_pymavtut.tlog",
    arducopter_pixhawk_2019_csun_hexa => "arducopter_pixhawk_mavproxy_2019_csun_hexa.tlog",
    arducopter_fmuv5_2019_fugaintegrum => "arducopter_fmuv5_mavproxy_2019_fugaintegrum.tlog",
    arducopter_sitl_2017_rosws => "arducopter_sitl_mavproxy_2017_rosws.tlog",
    arducopter_pixhawk_2018_moana => "arducopter_pixhawk_mavproxy_2018_moana.tlog",
    arducopter_pixhawk6c_2024_c2 => "arducopter_pixhawk6c_mavproxy_missionplanner_2024_c2.tlog",
    arducopter_sitl_2026_mavlinkflood => "arducopter_sitl_mavproxy_2026_mavlinkflood.tlog",
    arducopter_sitl_2026_paramflood => "arducopter_sitl_mavproxy_2026_paramflood.tlog",
    arducopter_sitl_2018_masterthesis => "arducopter_sitl_mavproxy_2018_masterthesis.tlog",
    arducopter_pixhawk_2016_paramset => "arducopter_pixhawk_mavproxy_2016_paramset.tlog",
    arducopter_sitl_2015_gvsu => "arducopter_sitl_mavproxy_2015_gvsu.tlog",
    arducopter_sitl_2026_paramset_reposition => "arducopter_sitl_mavproxy_2026_paramset_reposition.tlog",
    arducopter_sitl_2016_gusbus => "arducopter_sitl_mavproxy_2016_gusbus.tlog",
    arducopter_cubeorange_2024_upload => "arducopter_cubeorange_mavproxy_script_2024_upload.tlog",
    px4_plane_2023_supervisor => "px4_plane_mavproxy_2023_supervisor.tlog",
    px4_quad_2024_avalanche => "px4_quad_mavproxy_2024_avalanche.tlog",
    px4_quad_2023_tfg => "px4_quad_mavproxy_2023_tfg.tlog",
    px4_quad_2019_fugaintegrum => "px4_quad_mavproxy_2019_fugaintegrum.tlog",
    generic_rover_2025_crawler => "generic_rover_mavproxy_2025_crawler.tlog",
}

/// README: "mission download x26 (by 255/0)"; ArduPilot reports an empty mission as count 0
/// and the client then reads item 0 (home) beyond the count.
#[test]
fn arducopter_sitl_2021_beyondterra_downloads_with_reads_of_home() {
    let Some(r) = run("arducopter_sitl_mavproxy_missionplanner_2021_beyondterra.tlog") else {
        return;
    };
    assert_eq!(proto(&r, "mission_download").0, 26);
}

/// README: "mission upload x1; mission clear x1 (by 255/0)": the clear's ACCEPTED arrives after
/// the MISSION_COUNT that followed it at once; nothing else opens a mission write.
#[test]
fn arducopter_sitl_2021_extractor_clear_then_upload() {
    let Some(r) = run("arducopter_sitl_mavproxy_missionplanner_2021_extractor.tlog") else {
        return;
    };
    // the clear and the upload behind it: one session
    assert_eq!(proto(&r, "mission_upload"), (1, 1));
}

/// README: "mission upload x1; mission clear x1", ArduPlane 3.6: the same back-to-back order.
#[test]
fn arduplane_sitl_2017_winddrone_clear_then_upload() {
    let Some(r) = run("arduplane_sitl_mavproxy_2017_winddrone.tlog") else {
        return;
    };
    // the clear and the upload behind it: one session
    assert_eq!(proto(&r, "mission_upload"), (1, 1));
}

/// README: "guided: GUIDED mode, MISSION_ITEM current=2": each guided-mode item is answered by
/// one MISSION_ACK and is no upload.
#[test]
fn arducopter_sitl_2020_csun_guided_items() {
    let Some(r) = run("arducopter_sitl_mavproxy_script_2020_csun_guided.tlog") else {
        return;
    };
    let (started, completed) = proto(&r, "mission_upload");
    assert!(started > 0 && started == completed, "guided items {started}, answered {completed}");
}

/// README: "guided: MISSION_ITEM current=2" (a MISSION_ITEM_INT, answered MAV_MISSION_ERROR).
#[test]
fn arducopter_sitl_2020_pvardupilot_guided_item() {
    let Some(r) = run("arducopter_sitl_mavproxy_script_2020_pvardupilot.tlog") else {
        return;
    };
    assert_eq!(proto(&r, "mission_upload"), (1, 1));
}

/// README: "mission download x1 (by 255/0)", "MISSION_ITEM current=2" sent to 0/0.
#[test]
fn arducopter_sitl_2023_dronemission_download_and_guided_item() {
    let Some(r) = run("arducopter_sitl_mavproxy_missionplanner_2023_dronemission.tlog") else {
        return;
    };
    assert!(proto(&r, "mission_download").1 >= 1);
    assert_eq!(proto(&r, "mission_upload"), (1, 1));
}
