//! PNG picture of one plan: the map (obstacles black, costs as grey), the potential of reached
//! cells as a heat map (yellow near the goal → purple far away), and the path in red with the
//! start (green) and goal (blue) marked. Encoded with the `png` crate.

use std::io::Write;

use crate::checks::{PlanView, reached};
use crate::core::{COST_OBS, Cell, NavFn, POT_HIGH};

/// What a picture shows: one plan (its start marked in green, its goal in blue) and the
/// orientation.
#[derive(Clone, Copy, Debug)]
pub struct PictureInput<'a> {
    pub plan: PlanView<'a>,
    /// Draw row 0 at the bottom (ROS maps), as the map image shows it.
    pub flip_y: bool,
    /// Cells to ring in a colour (the body check's contacts and closest lethal cell).
    pub marks: &'a [([usize; 2], [u8; 3])],
}

impl<'a> PictureInput<'a> {
    /// Picture of the last plan of `nav` (NavFn start/goal; set `flip_y` for ROS maps).
    pub fn of(nav: &'a NavFn, flip_y: bool) -> Self {
        PictureInput { plan: PlanView::of(nav), flip_y, marks: &[] }
    }
}

/// An RGB image.
pub struct Rgb {
    pub width: usize,
    pub height: usize,
    pub data: Vec<u8>,
}

impl Rgb {
    fn put(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            let i = 3 * (y as usize * self.width + x as usize);
            self.data[i..i + 3].copy_from_slice(&c);
        }
    }
}

/// Pixels per cell: small maps are enlarged to about 800 px, large ones drawn 1:1 or 2:1.
pub fn cell_scale(nx: usize, ny: usize) -> usize {
    (800 / nx.max(ny).max(1)).clamp(1, 40)
}

/// Heat-map colour for t in [0, 1] (0 = goal): yellow → orange → magenta → deep purple.
fn heat(t: f32) -> [u8; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [252.0, 231.0, 37.0],
        [248.0, 149.0, 64.0],
        [204.0, 71.0, 120.0],
        [126.0, 3.0, 168.0],
        [33.0, 12.0, 90.0],
    ];
    let t = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let i = (t.floor() as usize).min(STOPS.len() - 2);
    let f = t - i as f32;
    let mut c = [0u8; 3];
    for k in 0..3 {
        c[k] = (STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * f) as u8;
    }
    c
}

/// Render the picture.
pub fn render(pic: &PictureInput) -> Rgb {
    let (p, flip_y) = (&pic.plan, pic.flip_y);
    let s = cell_scale(p.nx, p.ny);
    let (w, h) = (p.nx * s, p.ny * s);
    let mut img = Rgb { width: w, height: h, data: vec![0; w * h * 3] };
    let max_pot =
        p.potential.iter().copied().filter(|&v| v < POT_HIGH).fold(0.0f32, f32::max).max(1.0);
    let row_of = |y: usize| if flip_y { p.ny - 1 - y } else { y };
    for y in 0..p.ny {
        for x in 0..p.nx {
            let i = y * p.nx + x;
            let cost = p.costs.get(i).copied().unwrap_or(COST_OBS);
            let pot = p.potential.get(i).copied().unwrap_or(POT_HIGH);
            let colour = if cost >= COST_OBS && !reached(pot) {
                [0, 0, 0]
            } else if reached(pot) {
                // sqrt spreads the colours over the near field, where the path ends
                heat((pot / max_pot).sqrt())
            } else {
                let g = 235 - ((cost.saturating_sub(50)) as u32 * 150 / 203) as u8;
                [g, g, g]
            };
            let py = row_of(y) * s;
            for dy in 0..s {
                for dx in 0..s {
                    img.put((x * s + dx) as i64, (py + dy) as i64, colour);
                }
            }
        }
    }
    // NavFn path coordinates are cell indices: a point (x, y) is the centre of cell (x, y)
    let to_px = |q: [f32; 2]| -> (i64, i64) {
        let px = (q[0] as f64 + 0.5) * s as f64;
        let y = if flip_y { p.ny as f64 - 1.0 - q[1] as f64 } else { q[1] as f64 };
        (px as i64, ((y + 0.5) * s as f64) as i64)
    };
    let thick = (s as i64 / 6).max(1);
    for pair in p.path.windows(2) {
        line(&mut img, to_px(pair[0]), to_px(pair[1]), thick, [230, 20, 20]);
    }
    if let [only] = p.path {
        dot(&mut img, to_px(*only), thick, [230, 20, 20]);
    }
    let marker = (s as i64 / 3).max(5);
    let centre = |c: Cell| to_px([c.x as f32, c.y as f32]);
    dot(&mut img, centre(p.start), marker, [20, 200, 60]);
    dot(&mut img, centre(p.goal), marker, [30, 90, 255]);
    for &([x, y], colour) in pic.marks {
        ring(&mut img, to_px([x as f32, y as f32]), marker + thick, thick, colour);
    }
    img
}

fn ring(img: &mut Rgb, (cx, cy): (i64, i64), r: i64, thick: i64, c: [u8; 3]) {
    let inner = (r - thick).max(0);
    for dy in -r..=r {
        for dx in -r..=r {
            let d2 = dx * dx + dy * dy;
            if d2 <= r * r && d2 >= inner * inner {
                img.put(cx + dx, cy + dy, c);
            }
        }
    }
}

fn dot(img: &mut Rgb, (cx, cy): (i64, i64), r: i64, c: [u8; 3]) {
    for dy in -r..=r {
        for dx in -r..=r {
            if dx * dx + dy * dy <= r * r {
                img.put(cx + dx, cy + dy, c);
            }
        }
    }
}

fn line(img: &mut Rgb, a: (i64, i64), b: (i64, i64), thick: i64, c: [u8; 3]) {
    let steps = (b.0 - a.0).abs().max((b.1 - a.1).abs()).max(1);
    for k in 0..=steps {
        let x = a.0 + (b.0 - a.0) * k / steps;
        let y = a.1 + (b.1 - a.1) * k / steps;
        dot(img, (x, y), thick, c);
    }
}

/// Encode an image as PNG.
pub fn write_png<W: Write>(out: W, img: &Rgb) -> Result<(), png::EncodingError> {
    let mut enc = png::Encoder::new(out, img.width as u32, img.height as u32);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header()?;
    writer.write_image_data(&img.data)?;
    writer.finish()
}

/// Render and write a PNG file.
pub fn save_png(path: &std::path::Path, p: &PictureInput) -> std::io::Result<()> {
    let file = std::fs::File::create(path)?;
    write_png(std::io::BufWriter::new(file), &render(p)).map_err(std::io::Error::other)
}
