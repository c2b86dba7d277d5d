//! A suite map in memory: NavFn costs (50..=253 traversable, 254 obstacle), row-major, plus the
//! cases to run on it. This is the campaign's IR; readers and generators produce it, the runner,
//! the writer and the transforms consume it. It knows nothing of files.

/// NavFn cost of an obstacle / border cell.
pub const OBSTACLE: u8 = 254;
/// NavFn free-space cost (COST_NEUTRAL).
pub const FREE: u8 = 50;
/// Highest traversable NavFn cost.
pub const MAX_TRAVERSABLE: u8 = 253;

/// One case of a `test.txt`: a path *from* `(x0, y0)` *to* `(x1, y1)` (x = column, y = row).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct Case {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Case {
    pub fn new(x0: u32, y0: u32, x1: u32, y1: u32) -> Self {
        Case { x0, y0, x1, y1 }
    }
}

/// A map with its cases, in NavFn costs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SuiteMap {
    /// Category folder name (`circus`, `free`, …, or `ROS`).
    pub category: String,
    /// Map folder name inside the category.
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// `width*height` NavFn costs, cell `(x, y)` at `y*width + x`.
    pub costs: Vec<u8>,
    pub cases: Vec<Case>,
}

impl SuiteMap {
    /// A map of `w×h` cells all of cost `fill`, with the 254 border NavFn's set-up would impose.
    pub fn filled(category: &str, name: &str, w: u32, h: u32, fill: u8) -> Self {
        let mut m = SuiteMap {
            category: category.to_string(),
            name: name.to_string(),
            width: w,
            height: h,
            costs: vec![fill; (w * h) as usize],
            cases: Vec::new(),
        };
        m.stamp_border();
        m
    }

    pub fn idx(&self, x: u32, y: u32) -> usize {
        (y * self.width + x) as usize
    }

    pub fn get(&self, x: u32, y: u32) -> u8 {
        self.costs[self.idx(x, y)]
    }

    pub fn set(&mut self, x: u32, y: u32, v: u8) {
        let i = self.idx(x, y);
        self.costs[i] = v;
    }

    /// Overwrite the outer ring with 254, as NavFn's set-up does (so the file shows what NavFn sees).
    pub fn stamp_border(&mut self) {
        let (w, h) = (self.width, self.height);
        for x in 0..w {
            self.set(x, 0, OBSTACLE);
            self.set(x, h - 1, OBSTACLE);
        }
        for y in 0..h {
            self.set(0, y, OBSTACLE);
            self.set(w - 1, y, OBSTACLE);
        }
    }

    pub fn is_free(&self, x: u32, y: u32) -> bool {
        self.get(x, y) < OBSTACLE
    }

    /// All traversable cells in index order.
    pub fn traversable_cells(&self) -> Vec<(u32, u32)> {
        let mut v = Vec::new();
        for y in 0..self.height {
            for x in 0..self.width {
                if self.is_free(x, y) {
                    v.push((x, y));
                }
            }
        }
        v
    }

    /// 4-connected component label of every traversable cell (`u32::MAX` for obstacles).
    /// NavFn propagates over 4-neighbours, so this is exactly its notion of reachability when
    /// no cycle limit bites.
    pub fn components(&self) -> (Vec<u32>, u32) {
        let n = self.costs.len();
        let mut label = vec![u32::MAX; n];
        let mut count = 0u32;
        let w = self.width as usize;
        let mut stack = Vec::new();
        for s in 0..n {
            if label[s] != u32::MAX || self.costs[s] >= OBSTACLE {
                continue;
            }
            label[s] = count;
            stack.push(s);
            while let Some(c) = stack.pop() {
                let (x, y) = (c % w, c / w);
                let mut visit = |nb: usize| {
                    if label[nb] == u32::MAX && self.costs[nb] < OBSTACLE {
                        label[nb] = count;
                        stack.push(nb);
                    }
                };
                if x > 0 {
                    visit(c - 1);
                }
                if x + 1 < w {
                    visit(c + 1);
                }
                if y > 0 {
                    visit(c - w);
                }
                if c + w < n {
                    visit(c + w);
                }
            }
            count += 1;
        }
        (label, count)
    }
}
