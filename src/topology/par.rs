//! Small helpers for writing disjoint ranges of a buffer from several rayon tasks.

use rayon::prelude::*;

/// A raw view of a mutable buffer that rayon tasks may share when every task writes a disjoint
/// range (guaranteed by the callers: ranges come from monotone prefix sums or fixed strides).
#[derive(Clone, Copy)]
pub(crate) struct Shared<T> {
    ptr: *mut T,
    len: usize,
}

unsafe impl<T: Send> Send for Shared<T> {}
unsafe impl<T: Send> Sync for Shared<T> {}

impl<T> Shared<T> {
    pub(crate) fn new(v: &mut [T]) -> Self {
        Shared {
            ptr: v.as_mut_ptr(),
            len: v.len(),
        }
    }

    /// The sub-slice `a..b`.
    ///
    /// # Safety
    /// No other live slice obtained from this view may overlap `a..b`.
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn range(&self, a: usize, b: usize) -> &mut [T] {
        assert!(a <= b && b <= self.len, "disjoint range out of bounds");
        std::slice::from_raw_parts_mut(self.ptr.add(a), b - a)
    }
}

/// Elements per rayon task.
pub(crate) const CHUNK: usize = 2048;

/// Runs `f(lo, hi)` over `0..n` split into chunks, in parallel when there is more than one chunk.
#[allow(dead_code)]
pub(crate) fn for_chunks<F>(n: usize, f: F)
where
    F: Fn(usize, usize) + Sync + Send,
{
    if n <= CHUNK {
        f(0, n);
        return;
    }
    let chunks = n.div_ceil(CHUNK);
    (0..chunks)
        .into_par_iter()
        .for_each(|c| f(c * CHUNK, ((c + 1) * CHUNK).min(n)));
}

/// Like [`for_chunks`] but stops at the first error.
pub(crate) fn try_for_chunks<E, F>(n: usize, f: F) -> Result<(), E>
where
    E: Send,
    F: Fn(usize, usize) -> Result<(), E> + Sync + Send,
{
    if n <= CHUNK {
        return f(0, n);
    }
    let chunks = n.div_ceil(CHUNK);
    (0..chunks)
        .into_par_iter()
        .try_for_each(|c| f(c * CHUNK, ((c + 1) * CHUNK).min(n)))
}

/// `out[i] = f(i)` for every element, in parallel chunks when large.
pub(crate) fn fill<T, F>(out: &mut [T], f: F)
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    if out.len() <= 4 * CHUNK {
        for (i, o) in out.iter_mut().enumerate() {
            *o = f(i);
        }
    } else {
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, ch)| {
            for (j, o) in ch.iter_mut().enumerate() {
                *o = f(c * CHUNK + j);
            }
        });
    }
}

/// `(0..chunks).map(f).collect()`, in parallel when there is more than one chunk.
pub(crate) fn map_chunks<T, F>(chunks: usize, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    if chunks <= 1 {
        (0..chunks).map(f).collect()
    } else {
        (0..chunks).into_par_iter().map(f).collect()
    }
}
