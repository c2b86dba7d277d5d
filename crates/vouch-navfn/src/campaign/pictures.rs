//! Counterexample pictures: two panels side by side, same scale.
//! Left: the cost map (grey, darker = more expensive; obstacles dark red) with NavFn's path in
//! blue and the 8-connected optimum in green, start (NavFn start) as a green dot, goal blue.
//! Right: the core's picture (potential heat map, NavFn path in red).

use std::collections::BTreeSet;
use std::path::Path;

use crate::campaign::error::CampaignError;
use crate::campaign::evaluate::{PreparedMap, picture_path, prepare};
use crate::campaign::exec::{navfn_ends, run_case};
use crate::campaign::grid::{Case, OBSTACLE};
use crate::campaign::names::FindingKind;
use crate::campaign::optimal::grid_optimum;
use crate::campaign::report::{Finding, Report};
use crate::campaign::suite_io::{read_test_file, walk_suite};
use crate::picture::{PictureInput, Rgb, cell_scale, render, write_png};
use crate::suite::{CaseRunner, RunMode};

/// Writes a picture of every finding of `report` (not the oracle mismatches and approximate
/// relations, which a picture of one run does not show) into `dir`, and records its path in the
/// finding. The maps of the findings are read again from `suite`, one at a time.
pub fn write_pictures(
    dir: &Path,
    report: &mut Report,
    suite: &Path,
    mode: RunMode,
) -> Result<(), CampaignError> {
    let write_err = |path: &Path| {
        let path = path.to_path_buf();
        move |source| CampaignError::Write { path, source }
    };
    std::fs::create_dir_all(dir).map_err(write_err(dir))?;
    let pictured =
        |f: &Finding| !matches!(f.kind, FindingKind::OracleMismatch | FindingKind::ApproxRelation);
    let wanted: BTreeSet<(String, String)> = report
        .findings
        .iter()
        .filter(|f| pictured(f))
        .map(|f| (f.category.clone(), f.map.clone()))
        .collect();
    if wanted.is_empty() {
        return Ok(());
    }
    for entry in walk_suite(suite)? {
        let entry = entry?;
        if !wanted.contains(&(entry.category.clone(), entry.name.clone())) {
            continue;
        }
        let pm = prepare(read_test_file(&entry.test_txt, &entry.category, &entry.name)?, false);
        for f in report.findings.iter_mut() {
            if !pictured(f) || f.category != entry.category || f.map != entry.name {
                continue;
            }
            let p = picture_path(dir, f);
            counterexample_png(&p, &pm, f.case as usize, mode).map_err(write_err(&p))?;
            f.picture = Some(p.display().to_string());
        }
    }
    Ok(())
}

fn put(img: &mut Rgb, x: i64, y: i64, c: [u8; 3]) {
    if x >= 0 && y >= 0 && (x as usize) < img.width && (y as usize) < img.height {
        let i = 3 * (y as usize * img.width + x as usize);
        img.data[i..i + 3].copy_from_slice(&c);
    }
}

fn dot(img: &mut Rgb, (cx, cy): (i64, i64), r: i64, c: [u8; 3]) {
    for dy in -r..=r {
        for dx in -r..=r {
            if dx * dx + dy * dy <= r * r {
                put(img, cx + dx, cy + dy, c);
            }
        }
    }
}

fn polyline(img: &mut Rgb, pts: &[(i64, i64)], r: i64, c: [u8; 3]) {
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let steps = (b.0 - a.0).abs().max((b.1 - a.1).abs()).max(1);
        for k in 0..=steps {
            dot(img, (a.0 + (b.0 - a.0) * k / steps, a.1 + (b.1 - a.1) * k / steps), r, c);
        }
    }
    if let [only] = pts {
        dot(img, *only, r, c);
    }
}

/// Render the picture of case `k` of `pm` in `mode` and write it to `out`.
pub fn counterexample_png(
    out: &Path,
    pm: &PreparedMap,
    k: usize,
    mode: RunMode,
) -> std::io::Result<()> {
    let m = &pm.map;
    let case: Case = *m
        .cases
        .get(k)
        .ok_or_else(|| std::io::Error::other(format!("no case {k} in {}", m.name)))?;
    let mut runner = CaseRunner::new();
    run_case(&mut runner, m, &pm.setup_costs, &case, mode, None).map_err(std::io::Error::other)?;
    let nav = runner.nav();
    let (nx, ny) = (m.width as usize, m.height as usize);
    let (start, goal) = navfn_ends(mode, &case);
    let optimum = grid_optimum(
        &pm.setup_costs,
        m.width,
        m.height,
        (start.x as u32, start.y as u32),
        (goal.x as u32, goal.y as u32),
    );

    let right = render(&PictureInput::of(nav, false));
    let s = cell_scale(nx, ny);
    let (pw, ph) = (nx * s, ny * s);
    let gap = 8;
    let mut img = Rgb {
        width: 2 * pw + gap,
        height: ph.max(right.height),
        data: vec![255; (2 * pw + gap) * ph.max(right.height) * 3],
    };
    for y in 0..ny {
        for x in 0..nx {
            let c = pm.setup_costs[y * nx + x];
            let colour = if c >= OBSTACLE {
                [120, 20, 20]
            } else {
                let g = 245 - ((u32::from(c) - 50) * 170 / 203) as u8;
                [g, g, g]
            };
            for dy in 0..s {
                for dx in 0..s {
                    put(&mut img, (x * s + dx) as i64, (y * s + dy) as i64, colour);
                }
            }
        }
    }
    let px = |x: f64, y: f64| (((x + 0.5) * s as f64) as i64, ((y + 0.5) * s as f64) as i64);
    let r = (s as i64 / 8).max(1);
    if let Some(o) = &optimum {
        let pts: Vec<_> = o.cells.iter().map(|&(x, y)| px(f64::from(x), f64::from(y))).collect();
        polyline(&mut img, &pts, r + 1, [40, 170, 60]);
    }
    let path: Vec<_> =
        nav.path_recorded().iter().map(|q| px(f64::from(q[0]), f64::from(q[1]))).collect();
    polyline(&mut img, &path, r, [30, 70, 230]);
    let marker = (s as i64 / 3).max(2);
    dot(&mut img, px(start.x as f64, start.y as f64), marker, [20, 200, 60]);
    dot(&mut img, px(goal.x as f64, goal.y as f64), marker, [30, 90, 255]);
    // Right panel: the core's rendering, copied in.
    for y in 0..right.height {
        let src = &right.data[3 * y * right.width..3 * (y + 1) * right.width];
        let dst_start = 3 * (y * img.width + pw + gap);
        img.data[dst_start..dst_start + src.len()].copy_from_slice(src);
    }
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let f = std::fs::File::create(out)?;
    write_png(std::io::BufWriter::new(f), &img).map_err(std::io::Error::other)
}
