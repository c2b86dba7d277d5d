//! The gradient cache of path extraction (`gradx`/`grady` upstream), stored in column bands.
//!
//! `calcPath` caches the normalised gradient of each cell it interpolates from. It is a memo of
//! a pure function of the potential, so where it is kept changes no result; what it changes is
//! memory traffic. Row-major, a descent that crosses `k` rows touches `k` rows of the array, a
//! page each on maps a few hundred cells wide, and every such page is faulted in twice (read
//! as the zero page by the cache test, then copied on the first write). Stored in bands of
//! [`BAND`] columns, band after band with the rows of a band contiguous, the same descent
//! touches a page per eight rows of each band it crosses: on a 1000² map a diagonal plan
//! touches about a seventh of the pages. Maps at most a band wide keep the row-major layout
//! (a slot is the cell's index), where it costs no arithmetic.

/// Band width in columns.
const BAND: usize = 64;
const BAND_SHIFT: u32 = BAND.trailing_zeros();

/// Where each cell's gradient is kept.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct GradLayout {
    /// Columns; maps at most [`BAND`] wide are row-major.
    nx: usize,
    /// Slots per band (`ny` rows of a band).
    band_stride: usize,
}

impl GradLayout {
    /// The slot of cell (`col`, `row`).
    #[cfg(test)]
    fn slot(&self, col: usize, row: usize) -> usize {
        if self.nx <= BAND { row * self.nx + col } else { self.banded_slot(col, row) }
    }

    /// The slot of cell (`col`, `row`) of a map wider than a band.
    #[inline(always)]
    fn banded_slot(&self, col: usize, row: usize) -> usize {
        (col >> BAND_SHIFT) * self.band_stride + (row << BAND_SHIFT) + (col & (BAND - 1))
    }

    /// The slots of the 2×2 block with cell `n` = (`col`, `row`) at its lower left: (col, row),
    /// (col+1, row), (col, row+1), (col+1, row+1); `col + 1 < nx`.
    #[inline(always)]
    pub(crate) fn block(&self, n: usize, col: usize, row: usize) -> [usize; 4] {
        if self.nx <= BAND {
            let nx = self.nx;
            return [n, n + 1, n + nx, n + nx + 1];
        }
        let s00 = self.banded_slot(col, row);
        // the next column is in the next band when this one is a band's last
        let s01 = if col & (BAND - 1) == BAND - 1 {
            s00 + self.band_stride - (BAND - 1)
        } else {
            s00 + 1
        };
        [s00, s01, s00 + BAND, s01 + BAND]
    }
}

/// Gradients `(gx, gy)` per cell, and the slots cached since the last reset.
#[derive(Debug, Default)]
pub(crate) struct GradCache {
    layout: GradLayout,
    slots: Vec<[f32; 2]>,
    /// Slots written since the last reset (reset clears these instead of the whole array).
    touched: Vec<u32>,
}

impl GradCache {
    /// A zeroed cache for an `nx`×`ny` map (`nx·ny < 2^31`, checked by the caller). Fresh
    /// zeroed memory, so pages a plan never touches take none.
    pub(crate) fn new(nx: usize, ny: usize) -> GradCache {
        let size = if nx <= BAND { nx * ny } else { nx.div_ceil(BAND) * BAND * ny };
        GradCache {
            layout: GradLayout { nx, band_stride: BAND * ny },
            slots: vec![[0.0; 2]; size],
            touched: Vec::new(),
        }
    }

    /// The layout, the slots and the list of written slots, apart (path extraction keeps
    /// them in locals: behind one `&mut` the compiler would reload the slots after each push
    /// to the list).
    #[inline(always)]
    pub(crate) fn parts(&mut self) -> (GradLayout, &mut [[f32; 2]], &mut Vec<u32>) {
        (self.layout, &mut self.slots, &mut self.touched)
    }

    /// Forgets every cached gradient (`setupNavFn`'s clearing of `gradx`/`grady`).
    pub(crate) fn reset(&mut self) {
        for &s in &self.touched {
            if let Some(g) = self.slots.get_mut(s as usize) {
                *g = [0.0; 2];
            }
        }
        self.touched.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::GradCache;

    /// Every cell has its own slot, inside the array, for narrow, band-wide and wide maps;
    /// the block's slots are those of its four cells.
    #[test]
    fn slots_are_distinct_and_blocks_are_their_cells() {
        for (nx, ny) in [(1, 5), (3, 3), (10, 7), (64, 4), (65, 3), (128, 2), (130, 9), (1000, 2)] {
            let cache = GradCache::new(nx, ny);
            let g = cache.layout;
            let mut seen = vec![false; cache.slots.len()];
            for row in 0..ny {
                for col in 0..nx {
                    let s = g.slot(col, row);
                    assert!(s < cache.slots.len(), "{nx}x{ny}: ({col},{row}) outside");
                    assert!(!seen[s], "{nx}x{ny}: ({col},{row}) shares a slot");
                    seen[s] = true;
                    if col + 1 < nx && row + 1 < ny {
                        let expected = [
                            g.slot(col, row),
                            g.slot(col + 1, row),
                            g.slot(col, row + 1),
                            g.slot(col + 1, row + 1),
                        ];
                        assert_eq!(g.block(row * nx + col, col, row), expected);
                    }
                }
            }
            assert!(cache.slots.len() <= 2 * nx * ny, "{nx}x{ny}: {}", cache.slots.len());
        }
    }

    /// A reset forgets exactly what was set.
    #[test]
    fn reset_forgets_what_was_cached() {
        let mut g = GradCache::new(100, 100);
        let s = g.layout.slot(70, 33);
        let (_, slots, touched) = g.parts();
        slots[s] = [0.5, -0.25];
        touched.push(s as u32);
        g.reset();
        assert!(g.slots.iter().all(|&v| v == [0.0, 0.0]));
        assert!(g.touched.is_empty());
    }
}
