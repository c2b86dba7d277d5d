//! Storage of the per-cell arrays the propagation sweeps: potential, cost, blocked flags.
//!
//! Corner to corner on a large map the propagation front crosses every row, and each update
//! reads three rows of three arrays: with 4 KiB pages the front's working set is thousands
//! of pages, far more than the TLB holds, and every update pays page walks. On request
//! ([`super::NavFn::set_huge_pages`]) arrays of at least [`HUGE_PAGE`] bytes are anonymous
//! mappings advised as transparent huge pages (`memmap2`, no `unsafe` here); otherwise, and for
//! smaller arrays, they are plain vectors. Not by default: the first touch of a fresh huge page
//! can cost far more kernel time than the page walks it saves (on virtual machines whose host
//! backs guest memory lazily, a one-shot 4000² plan then varied by a third in CPU time), so it
//! pays in a long-running planner that keeps its arrays, not in a process that plans once. The mapping is exactly as
//! long as the array, so a huge page never extends past it: only the 2 MiB-aligned ranges
//! inside get huge pages, and the memory taken is what a vector of the same length takes
//! (untouched parts take none). Where the kernel declines the advice (THP disabled, other
//! systems) the mapping is an ordinary zeroed one.

use std::ops::{Deref, DerefMut};

use bytemuck::Pod;
use memmap2::MmapMut;

/// Size of a transparent huge page on x86-64 Linux.
const HUGE_PAGE: usize = 2 << 20;

/// A fixed-length array of `T`, zero-initialised, on huge pages when it is large.
pub(crate) struct CellArray<T: Pod> {
    store: Store<T>,
}

enum Store<T> {
    Heap(Vec<T>),
    /// Exactly the bytes of the elements (page-aligned, hence aligned for any `T`).
    Mapped(MmapMut),
}

impl<T: Pod> CellArray<T> {
    /// `len` zeroed elements, on huge pages if `huge` and the array is large.
    pub(crate) fn zeroed(len: usize, huge: bool) -> Self {
        let bytes = len * size_of::<T>();
        if huge
            && bytes >= HUGE_PAGE
            && let Some(store) = Self::mapped(bytes)
        {
            return CellArray { store };
        }
        CellArray { store: Store::Heap(vec![T::zeroed(); len]) }
    }

    /// `len` copies of `v`.
    pub(crate) fn filled(len: usize, v: T, huge: bool) -> Self {
        let mut a = Self::zeroed(len, huge);
        a.fill(v);
        a
    }

    fn mapped(bytes: usize) -> Option<Store<T>> {
        let map = MmapMut::map_anon(bytes).ok()?;
        #[cfg(target_os = "linux")]
        {
            // advice only: where it is refused the mapping works with normal pages
            let _ = map.advise(memmap2::Advice::HugePage);
        }
        Some(Store::Mapped(map))
    }
}

impl<T: Pod> Deref for CellArray<T> {
    type Target = [T];
    #[inline(always)]
    fn deref(&self) -> &[T] {
        match &self.store {
            Store::Heap(v) => v,
            Store::Mapped(map) => bytemuck::cast_slice(map),
        }
    }
}

impl<T: Pod> DerefMut for CellArray<T> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [T] {
        match &mut self.store {
            Store::Heap(v) => v,
            Store::Mapped(map) => bytemuck::cast_slice_mut(map),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{CellArray, HUGE_PAGE};

    /// Small and mapped arrays have their length, start zeroed and hold what is written.
    #[test]
    fn arrays_small_and_mapped() {
        for (len, huge) in [(0, true), (1, true), (1000, false), (HUGE_PAGE / 4 + 3, true)] {
            let mut a = CellArray::<f32>::filled(len, 1.5, huge);
            assert_eq!(a.len(), len);
            assert!(a.iter().all(|&v| v == 1.5));
            if let Some(last) = a.last_mut() {
                *last = 2.0;
            }
            assert_eq!(a.iter().filter(|&&v| v == 2.0).count(), (len > 0) as usize);
            let z = CellArray::<u8>::zeroed(len * 4, huge);
            assert_eq!(z.len(), len * 4);
            assert!(z.iter().all(|&v| v == 0));
        }
    }
}
