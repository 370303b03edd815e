//! Stack watermark: paint the free stack with a pattern at start-up, later find the
//! deepest word that was overwritten. Measures the worst case that actually happened
//! (every handler preempting every other as often as the run made them).

/// Pattern written into the unused stack.
const PAINT: u32 = 0xC0FF_EE55;

extern "C" {
    /// Lowest address of the stack region (cortex-m-rt's link.x).
    static mut _stack_end: u32;
    /// Initial stack pointer, one past the highest stack word (cortex-m-rt's link.x).
    static mut _stack_start: u32;
}

/// Fills the stack from its lowest word up to `margin` bytes below the current stack
/// pointer with [`PAINT`]. Call once, early, with interrupts disabled (RTIC's `init`).
#[inline(never)]
pub fn paint(margin: usize) {
    let sp = current_sp();
    let low = core::ptr::addr_of_mut!(_stack_end) as usize;
    let high = sp.saturating_sub(margin) & !3;
    let mut p = low;
    while p < high {
        // SAFETY: [low, sp - margin) is inside the stack region (link.x) and below the
        // current stack pointer, so nothing live is stored there.
        unsafe { core::ptr::write_volatile(p as *mut u32, PAINT) };
        p = p.wrapping_add(4);
    }
}

/// Bytes of stack used so far: from the top down to the deepest overwritten word.
pub fn used() -> u32 {
    let low = core::ptr::addr_of_mut!(_stack_end) as usize;
    let high = core::ptr::addr_of_mut!(_stack_start) as usize;
    let mut p = low;
    while p < high {
        // SAFETY: reads inside the stack region, word aligned (link.x aligns both ends).
        if unsafe { core::ptr::read_volatile(p as *const u32) } != PAINT {
            break;
        }
        p = p.wrapping_add(4);
    }
    high.saturating_sub(p) as u32
}

fn current_sp() -> usize {
    cortex_m::register::msp::read() as usize
}
