//! Combinations of assembly modes: the [`ModeSet`] trait that every
//! generated `…Modes` type implements, and the lazy iterators over all
//! 2^k combinations of a mechanism's k two-mode blocks ([`AllModes`]) and
//! over the assemblies in each ([`Assemblies`]).
//!
//! Nothing here holds more than one combination: a chain of a hundred
//! dyads has 2^100 assemblies, of which a caller takes the few it wants
//! (with [`Iterator::nth`], which skips without assembling, or by naming
//! the modes of each block in a `…Modes` value).

use super::Mode;

/// The assembly modes of a mechanism, one per block with two closed-form
/// solutions: implemented by the `…Modes` struct that `mechanism!`
/// generates (whose fields name the blocks by their unknowns).
///
/// Combination number i (in the order of [`AllModes`]) has block j in
/// [`Mode::Minus`] where bit j of i is set: i = Σ_j [mode_j = Minus] 2^j.
pub trait ModeSet: Copy {
    /// The number k of blocks with two modes (2^k combinations).
    const BLOCKS: usize;

    /// The mode of block `j` (in solve order); `Plus` for `j ≥ BLOCKS`.
    fn mode(&self, j: usize) -> Mode;

    /// Sets the mode of block `j`; nothing for `j ≥ BLOCKS`.
    fn set_mode(&mut self, j: usize, mode: Mode);

    /// Every block in [`Mode::Plus`]: combination 0.
    fn all_plus() -> Self;
}

/// Every combination of modes of a [`ModeSet`], lazily, as a binary
/// counter over the blocks: combination i has block j in
/// [`Mode::Minus`] where bit j of i is set. Holds one combination;
/// [`Iterator::nth`] adds n to the counter in O(k) without visiting the
/// combinations in between. [`Iterator::size_hint`] is exact while the
/// number left fits a `usize` (k < 64 on 64-bit targets).
///
/// ```
/// use kinematics_core::closed::{AllModes, Mode, ModeSet};
/// #[derive(Clone, Copy, Debug, PartialEq)]
/// struct Two([Mode; 2]);
/// impl ModeSet for Two {
///     const BLOCKS: usize = 2;
///     fn mode(&self, j: usize) -> Mode { self.0.get(j).copied().unwrap_or_default() }
///     fn set_mode(&mut self, j: usize, m: Mode) { if let Some(x) = self.0.get_mut(j) { *x = m } }
///     fn all_plus() -> Self { Two([Mode::Plus; 2]) }
/// }
/// use Mode::{Minus as M, Plus as P};
/// let all: Vec<Two> = AllModes::<Two>::new().collect();
/// assert_eq!(all, [Two([P, P]), Two([M, P]), Two([P, M]), Two([M, M])]);
/// assert_eq!(AllModes::<Two>::new().nth(2), Some(Two([P, M])));
/// assert_eq!(AllModes::<Two>::new().size_hint(), (4, Some(4)));
/// ```
#[derive(Debug, Clone)]
pub struct AllModes<M> {
    /// The next combination, or `None` once every one has been returned.
    next: Option<M>,
}

impl<M: ModeSet> AllModes<M> {
    /// Starts at combination 0 (every block `Plus`).
    #[must_use]
    pub fn new() -> Self {
        AllModes {
            next: Some(M::all_plus()),
        }
    }

    /// Adds `n` to the counter `m` (bit j of the index is block j's mode);
    /// `None` past the last combination.
    fn advance(mut m: M, mut n: usize) -> Option<M> {
        let mut carry = false;
        let mut j = 0;
        while n != 0 || carry {
            if j >= M::BLOCKS {
                return None;
            }
            let bit = usize::from(m.mode(j) == Mode::Minus) + (n & 1) + usize::from(carry);
            m.set_mode(
                j,
                if bit & 1 == 1 {
                    Mode::Minus
                } else {
                    Mode::Plus
                },
            );
            carry = bit >= 2;
            n >>= 1;
            j += 1;
        }
        Some(m)
    }

    /// The number of combinations left, where it fits a `usize`.
    fn remaining(&self) -> Option<usize> {
        let Some(m) = self.next else { return Some(0) };
        let total = u32::try_from(M::BLOCKS)
            .ok()
            .and_then(|k| 1usize.checked_shl(k))?;
        let index = (0..M::BLOCKS)
            .filter(|&j| m.mode(j) == Mode::Minus)
            .fold(0usize, |i, j| i | 1 << j);
        Some(total - index)
    }
}

impl<M: ModeSet> Default for AllModes<M> {
    fn default() -> Self {
        Self::new()
    }
}

impl<M: ModeSet> Iterator for AllModes<M> {
    type Item = M;

    fn next(&mut self) -> Option<M> {
        let m = self.next?;
        self.next = Self::advance(m, 1);
        Some(m)
    }

    fn nth(&mut self, n: usize) -> Option<M> {
        self.next = self.next.and_then(|m| Self::advance(m, n));
        self.next()
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        match self.remaining() {
            Some(r) => (r, Some(r)),
            None => (usize::MAX, None),
        }
    }
}

impl<M: ModeSet> core::iter::FusedIterator for AllModes<M> {}

/// Every assembly of a mechanism at given drivers, lazily: for each
/// combination of modes of [`AllModes`], the modes and the assembly in
/// them (what `assemble_in` returns). Returned by the generated
/// `assemble_all`; [`Iterator::nth`] skips combinations without
/// assembling them.
#[derive(Debug, Clone)]
pub struct Assemblies<M, F> {
    /// The combinations still to assemble.
    modes: AllModes<M>,
    /// Assembles in the given modes.
    assemble: F,
}

impl<M: ModeSet, F> Assemblies<M, F> {
    /// The assemblies `assemble(&modes)` for every combination `modes`.
    pub fn new(assemble: F) -> Self {
        Assemblies {
            modes: AllModes::new(),
            assemble,
        }
    }
}

impl<M: ModeSet, R, F: FnMut(&M) -> R> Iterator for Assemblies<M, F> {
    type Item = (M, R);

    fn next(&mut self) -> Option<(M, R)> {
        let m = self.modes.next()?;
        Some((m, (self.assemble)(&m)))
    }

    fn nth(&mut self, n: usize) -> Option<(M, R)> {
        let m = self.modes.nth(n)?;
        Some((m, (self.assemble)(&m)))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.modes.size_hint()
    }
}

impl<M: ModeSet, R, F: FnMut(&M) -> R> core::iter::FusedIterator for Assemblies<M, F> {}

#[cfg(test)]
mod tests {
    use super::{AllModes, Assemblies, Mode, ModeSet};

    /// 100 blocks, as a generated `…Modes` holds them.
    #[derive(Clone, Copy, Debug, PartialEq)]
    struct Many([Mode; 100]);

    impl ModeSet for Many {
        const BLOCKS: usize = 100;
        fn mode(&self, j: usize) -> Mode {
            self.0.get(j).copied().unwrap_or_default()
        }
        fn set_mode(&mut self, j: usize, mode: Mode) {
            if let Some(m) = self.0.get_mut(j) {
                *m = mode;
            }
        }
        fn all_plus() -> Self {
            Many([Mode::Plus; 100])
        }
    }

    /// The index of a combination (its low 64 blocks).
    fn index(m: &Many) -> u64 {
        (0..64)
            .filter(|&j| m.mode(j) == Mode::Minus)
            .fold(0, |i, j| i | 1 << j)
    }

    #[test]
    fn nth_skips_by_adding_to_the_counter() {
        let mut all = AllModes::<Many>::new();
        assert_eq!(all.size_hint(), (usize::MAX, None));
        let m = all.nth(0b1011).expect("in range");
        assert_eq!(index(&m), 0b1011);
        assert_eq!(index(&all.next().expect("in range")), 0b1100);
        let m = all.nth(1000).expect("in range");
        assert_eq!(index(&m), 0b1101 + 1000);
        assert!((64..100).all(|j| m.mode(j) == Mode::Plus));
        // A carry past the 64th block: 2^64 − 1 + 1.
        let mut low = Many::all_plus();
        (0..64).for_each(|j| low.set_mode(j, Mode::Minus));
        let m = AllModes { next: Some(low) }.nth(1).expect("in range");
        assert!((0..100).all(|j| (m.mode(j) == Mode::Minus) == (j == 64)));
        // The last, 2^100 − 1, after 2^100 − 2; nothing after it.
        let mut top = Many([Mode::Minus; 100]);
        top.set_mode(0, Mode::Plus);
        let mut all = AllModes { next: Some(top) };
        let m = all.nth(1).expect("the last");
        assert!((0..100).all(|j| m.mode(j) == Mode::Minus));
        assert_eq!(all.next(), None);
        assert_eq!(AllModes { next: Some(top) }.nth(2), None);
    }

    #[test]
    fn assemblies_assemble_only_what_is_taken() {
        let calls = core::cell::Cell::new(0);
        let mut all = Assemblies::<Many, _>::new(|m: &Many| {
            calls.set(calls.get() + 1);
            index(m)
        });
        assert_eq!(all.nth(1 << 40).map(|(_, i)| i), Some(1 << 40));
        assert_eq!(all.next().map(|(_, i)| i), Some((1 << 40) + 1));
        assert_eq!(calls.get(), 2);
    }
}
