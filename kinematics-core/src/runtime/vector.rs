//! [`Vector`]: a point's position, velocity or acceleration in a run-time
//! [`Motion`](super::Motion), held inline.

use core::fmt;
use core::ops::{Deref, DerefMut};

use alloc::vec::Vec;

/// A point's position, velocity or acceleration in a run-time model: its
/// 2 (planar) or 3 (spatial) components, held inline (no allocation of
/// its own), read and written as a slice `&[f64]` of that length.
///
/// ```
/// use kinematics_core::runtime::Vector;
/// let v = Vector::from([3.0, 4.0]);
/// assert_eq!(v.len(), 2);
/// assert_eq!(v[1], 4.0);
/// // Euclidean norm √(x² + y²), through the slice's iterator.
/// let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
/// assert_eq!(norm, 5.0);
/// assert_eq!(v, [3.0, 4.0][..]);
/// ```
#[derive(Clone, Copy, PartialEq)]
pub struct Vector {
    /// The components, those past `len` zero.
    values: [f64; 3],
    /// 2 or 3.
    len: usize,
}

impl Vector {
    /// The zero vector of `dimension` components (2 or 3; any other
    /// value is taken as 3).
    #[must_use]
    pub const fn zeros(dimension: usize) -> Self {
        Self {
            values: [0.0; 3],
            len: if dimension == 2 { 2 } else { 3 },
        }
    }

    /// The vector of `dimension` components (2 or 3, as
    /// [`Vector::zeros`]) whose component `i` is `f(i)`.
    pub(super) fn from_fn(dimension: usize, mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v = Self::zeros(dimension);
        for (i, x) in v.as_mut_slice().iter_mut().enumerate() {
            *x = f(i);
        }
        v
    }

    /// The components as a slice.
    #[inline]
    #[must_use]
    pub fn as_slice(&self) -> &[f64] {
        &self.values[..self.len]
    }

    /// The components as a mutable slice (of fixed length).
    #[inline]
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        &mut self.values[..self.len]
    }
}

impl Deref for Vector {
    type Target = [f64];
    #[inline]
    fn deref(&self) -> &[f64] {
        self.as_slice()
    }
}

impl DerefMut for Vector {
    #[inline]
    fn deref_mut(&mut self) -> &mut [f64] {
        self.as_mut_slice()
    }
}

impl AsRef<[f64]> for Vector {
    fn as_ref(&self) -> &[f64] {
        self.as_slice()
    }
}

impl fmt::Debug for Vector {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_slice(), f)
    }
}

impl From<[f64; 2]> for Vector {
    fn from([x, y]: [f64; 2]) -> Self {
        Self {
            values: [x, y, 0.0],
            len: 2,
        }
    }
}

impl From<[f64; 3]> for Vector {
    fn from(values: [f64; 3]) -> Self {
        Self { values, len: 3 }
    }
}

impl From<Vector> for Vec<f64> {
    fn from(v: Vector) -> Self {
        v.as_slice().to_vec()
    }
}

impl PartialEq<[f64]> for Vector {
    fn eq(&self, other: &[f64]) -> bool {
        self.as_slice() == other
    }
}

impl PartialEq<Vec<f64>> for Vector {
    fn eq(&self, other: &Vec<f64>) -> bool {
        self.as_slice() == other.as_slice()
    }
}

impl<'a> IntoIterator for &'a Vector {
    type Item = &'a f64;
    type IntoIter = core::slice::Iter<'a, f64>;
    fn into_iter(self) -> Self::IntoIter {
        self.as_slice().iter()
    }
}

#[cfg(test)]
mod tests {
    use super::Vector;

    #[test]
    fn reads_and_writes_as_a_slice_of_its_dimension() {
        let mut v = Vector::zeros(3);
        v.copy_from_slice(&[1.0, 2.0, 3.0]);
        assert_eq!(v.as_slice(), &[1.0, 2.0, 3.0]);
        let mut w = Vector::from_fn(2, |i| 5.0 + i as f64);
        w[0] += 1.0;
        assert_eq!(w, vec![6.0, 6.0]);
        assert_eq!(w.len(), 2);
        assert_eq!(format!("{w:?}"), "[6.0, 6.0]");
        assert_eq!(Vec::from(v), vec![1.0, 2.0, 3.0]);
        assert_ne!(Vector::zeros(2), Vector::zeros(3));
    }
}
