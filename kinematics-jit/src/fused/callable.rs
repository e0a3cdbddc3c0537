//! One function of a fused set, looked up once and called many times:
//! the lengths of its arrays checked, the upper halves of the vector
//! registers cleared where the code is VEX-encoded, then the machine code
//! entered.

use super::*;

/// What the machine code hands back to [`trampoline`].
pub(super) struct Frame<'a> {
    pub(super) helper: &'a mut dyn Helper,
    pub(super) len: usize,
}

/// The function the machine code calls for [`Op::Call`]: the frame's
/// helper on the buffer, with any panic caught.
#[allow(unsafe_code)]
pub(super) extern "C" fn trampoline(f: *mut f64, frame: *mut c_void, argument: u64) -> i64 {
    // SAFETY: the machine code passes on the buffer and frame pointers
    // `Callable::call` gave it: a buffer of `len` values, which the code
    // itself does not touch while the helper runs, and a `Frame` living
    // for the call.
    let (frame, f) = unsafe {
        let frame = &mut *frame.cast::<Frame<'_>>();
        let f = std::slice::from_raw_parts_mut(f, frame.len);
        (frame, f)
    };
    let helper = &mut *frame.helper;
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| helper.call(f, argument)))
        .unwrap_or(HELPER_PANICKED)
}

pub(super) type Entry = unsafe extern "C" fn(*mut f64, *mut c_void, *const *mut f64) -> i64;

/// The finalized code as a function pointer.
#[allow(unsafe_code)]
pub(super) fn entry(code: *const u8) -> Entry {
    // SAFETY: `code` is the address of the function compiled above with
    // three pointer arguments and an i64 result in the host's default
    // calling convention, which is `Entry`'s.
    unsafe { std::mem::transmute::<*const u8, Entry>(code) }
}

/// One function of a [`Fused`] set with `I` input and `O` output ports,
/// looked up once ([`Fused::function`]).
#[derive(Clone, Copy)]
pub struct Callable<'a, const I: usize, const O: usize> {
    pub(super) entry: Entry,
    /// How many values the code reads from each input port and writes
    /// into each output port.
    pub(super) need_in: [usize; I],
    pub(super) need_out: [usize; O],
    pub(super) len: usize,
    pub(super) vex: bool,
    pub(super) code: PhantomData<&'a Fused>,
}

impl<const I: usize, const O: usize> fmt::Debug for Callable<'_, I, O> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Callable")
            .field("len", &self.len)
            .field("inputs", &self.need_in)
            .field("outputs", &self.need_out)
            .finish_non_exhaustive()
    }
}

impl<const I: usize, const O: usize> Callable<'_, I, O> {
    /// As [`Fused::call_ports`].
    #[allow(unsafe_code)]
    #[inline]
    pub fn call(
        &self,
        f: &mut [f64],
        helper: &mut dyn Helper,
        inputs: [&[f64]; I],
        outputs: [&mut [f64]; O],
    ) -> i64 {
        if f.len() != self.len
            || inputs.iter().zip(&self.need_in).any(|(p, &n)| p.len() < n)
            || outputs
                .iter()
                .zip(&self.need_out)
                .any(|(p, &n)| p.len() < n)
        {
            return -1;
        }
        let mut table = [core::ptr::null_mut::<f64>(); 2 * PORTS];
        for (slot, p) in table.iter_mut().zip(inputs) {
            *slot = p.as_ptr().cast_mut();
        }
        for (slot, p) in table[PORTS..].iter_mut().zip(outputs) {
            *slot = p.as_mut_ptr();
        }
        let mut frame = Frame {
            helper,
            len: self.len,
        };
        clear_upper(self.vex);
        // SAFETY: every offset the code reads or writes was checked
        // against the layout's length, which is `f`'s; the code uses no
        // port beyond the I inputs and O outputs (checked when the
        // function was looked up), and each of those holds at least as
        // many values as it uses (checked above); the inputs are only
        // read, and the outputs are borrowed mutably for the call; the
        // frame lives for the call, and the trampoline reads it as a
        // `Frame`.
        unsafe {
            (self.entry)(
                f.as_mut_ptr(),
                (&mut frame as *mut Frame<'_>).cast::<c_void>(),
                table.as_ptr(),
            )
        }
    }
}
