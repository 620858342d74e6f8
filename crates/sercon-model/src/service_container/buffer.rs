//! The write and read buffers of a service container and their pointers (410B §4.2.4
//! words 2 and 3: WRDATPT/WRDATLAST, RDDATPT/RDDATLAST).
//!
//! The windows themselves (present and last position, final step, advancing) are
//! sercon-regs' [`ScBufferWindow`]; here the words of a step are moved between a record and
//! the container's RAM. Positions after the last one are sent as 0 and never stored.

use sercon_regs::ram::service_rules::ScBufferWindow;

use super::container_ram::ContainerRam;

/// Fills `info` with `count` words of `window`'s buffer (0 after the last position);
/// returns how many record words were filled.
pub(super) fn copy_out(
    window: ScBufferWindow,
    ram: &mut ContainerRam<'_>,
    count: u8,
    info: &mut [u16],
) -> u8 {
    let mut filled = 0;
    for (slot, position) in info.iter_mut().zip(window.positions(count)) {
        *slot = match position {
            Some(p) => ram.buffer_word(p),
            None => 0,
        };
        filled += 1;
    }
    filled
}

/// Stores up to `count` words of `info` into `window`'s buffer (words after the last
/// position are dropped); returns how many were stored.
pub(super) fn copy_in(
    window: ScBufferWindow,
    ram: &mut ContainerRam<'_>,
    count: u8,
    info: &[u16],
) -> u8 {
    let mut stored = 0;
    for (word, position) in info.iter().zip(window.positions(count)) {
        let taken = match position {
            Some(p) => ram.set_buffer_word(p, *word),
            None => false,
        };
        stored += u8::from(taken);
    }
    stored
}
