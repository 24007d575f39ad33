//! Fallible allocation of the big host buffers a run sizes by its particles (diagnostic grids,
//! output text): a failure is an [`AllocError`] naming the buffer and its bytes, which the run
//! reports (exit 3, `status: "failed"`) instead of aborting the process.

use crate::plan::fmt_bytes;

/// An allocation that failed: what it was for and how many bytes it asked for.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("could not allocate {bytes} bytes ({}) for {what}", fmt_bytes(*bytes as f64))]
pub struct AllocError {
    /// The buffer.
    pub what: &'static str,
    /// Bytes asked for.
    pub bytes: u64,
}

/// Bytes of `n` values of `T`.
fn bytes_of<T>(n: usize) -> u64 {
    (n as u64).saturating_mul(size_of::<T>() as u64)
}

/// An empty vector with room for exactly `n` values.
pub fn with_capacity<T>(n: usize, what: &'static str) -> Result<Vec<T>, AllocError> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| AllocError { what, bytes: bytes_of::<T>(n) })?;
    Ok(v)
}

/// `n` copies of `value`.
pub fn filled<T: Clone>(n: usize, value: T, what: &'static str) -> Result<Vec<T>, AllocError> {
    let mut v = with_capacity(n, what)?;
    v.resize(n, value);
    Ok(v)
}

/// Pushes `x`, growing `v` as `Vec::push` does (amortised doubling) but failing instead of
/// aborting.
pub fn push<T>(v: &mut Vec<T>, x: T, what: &'static str) -> Result<(), AllocError> {
    if v.len() == v.capacity() {
        v.try_reserve(1).map_err(|_| AllocError { what, bytes: bytes_of::<T>(2 * v.capacity().max(4)) })?;
    }
    v.push(x);
    Ok(())
}

/// Room for `extra` more bytes in `s`, exactly.
pub fn reserve_str(s: &mut String, extra: usize, what: &'static str) -> Result<(), AllocError> {
    s.try_reserve_exact(extra).map_err(|_| AllocError { what, bytes: extra as u64 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_allocation_names_the_buffer_and_bytes() {
        let e = with_capacity::<u64>(1 << 60, "test grid").unwrap_err();
        assert_eq!((e.what, e.bytes), ("test grid", 1 << 63));
        assert!(e.to_string().starts_with("could not allocate") && e.to_string().contains("test grid"), "{e}");
        let mut s = String::new();
        assert!(reserve_str(&mut s, usize::MAX / 2, "text").is_err());
        let mut v = filled(3, 7u32, "small").unwrap();
        push(&mut v, 8, "small").unwrap();
        assert_eq!(v, [7, 7, 7, 8]);
    }
}
