//! Stack watermark: cortex-m-rt's `paint-stack` fills the whole stack region with
//! [`cortex_m_rt::STACK_PAINT_VALUE`] before `main`; [`used`] finds the deepest word that was
//! overwritten since. Measures the worst case that actually happened (every handler
//! preempting every other as often as the run made them). QEMU images only: the feature is
//! turned on by the `qemu` and `emulated` features.

use cortex_m_rt::STACK_PAINT_VALUE;

extern "C" {
    /// Lowest address of the stack region (cortex-m-rt's link.x).
    static mut _stack_end: u32;
    /// Initial stack pointer, one past the highest stack word (cortex-m-rt's link.x).
    static mut _stack_start: u32;
}

/// Bytes of stack used so far: from the top down to the deepest overwritten word.
pub fn used() -> u32 {
    let low = core::ptr::addr_of_mut!(_stack_end) as usize;
    let high = core::ptr::addr_of_mut!(_stack_start) as usize;
    let mut p = low;
    while p < high {
        // SAFETY: reads inside the stack region, word aligned (link.x aligns both ends).
        if unsafe { core::ptr::read_volatile(p as *const u32) } != STACK_PAINT_VALUE {
            break;
        }
        p = p.wrapping_add(4);
    }
    high.saturating_sub(p) as u32
}
