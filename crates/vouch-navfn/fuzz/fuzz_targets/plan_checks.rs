//! Any small cost map and any two cells: NavFn (paper A*, navfn Dijkstra) never panics and
//! every plan passes the run-time checks.
#![no_main]
use libfuzzer_sys::fuzz_target;
use vouch_navfn::checks::{check_plan, PlanView};
use vouch_navfn::core::{Algo, Cell, NoObserver};
use vouch_navfn::suite::{CaseRunner, CostInput, MapRef};

fuzz_target!(|data: &[u8]| {
    if data.len() < 6 {
        return;
    }
    let nx = 3 + data[0] as usize % 30;
    let ny = 3 + data[1] as usize % 30;
    let cell = |a: u8, b: u8| Cell::new(a as usize % nx, b as usize % ny);
    let (from, to) = (cell(data[2], data[3]), cell(data[4], data[5]));
    let map: Vec<u8> = (0..nx * ny).map(|i| data.get(6 + i).map_or(50, |&b| b.max(50))).collect();
    let mut runner = CaseRunner::new();
    for algo in [Algo::Astar, Algo::Dijkstra] {
        let r = runner.run_navfn(
            MapRef { bytes: &map, nx, ny, costs: CostInput::Raw },
            algo,
            from,
            to,
            &mut NoObserver,
        );
        assert!(r.is_ok());
        let nav = runner.nav();
        // the property checks assume open end points, as the CLI requires
        let open = |c: Cell| nav.costs()[c.y * nx + c.x] < 254;
        if open(from) && open(to) {
            let report = check_plan(&PlanView::of(nav));
            assert!(report.is_ok(), "{:?}", report.violations);
        }
    }
    let _ = runner.run_paper(&map, nx, ny, from, to, &mut NoObserver);
});
