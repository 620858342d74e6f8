//! The write and read buffers of a service container and their pointers (410B §4.2.4
//! words 2 and 3: WRDATPT/WRDATLAST, RDDATPT/RDDATLAST).
//!
//! A step moves NINFO words starting at the present position. Positions are offsets
//! from SCPTn (regs reading: the buffer starts at offset 5). A step is the *final* step
//! of a buffer when it covers the last position; positions after the last one are sent
//! as 0 and never stored.

use super::container_ram::ContainerRam;

/// The present and last positions of one buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Window {
    /// WRDATPT / RDDATPT: present position.
    pub(super) present: u8,
    /// WRDATLAST / RDDATLAST: last position.
    pub(super) last: u8,
}

impl Window {
    /// Whether a step of `count` words from the present position reaches the last
    /// position (also when the present position is already past it).
    pub(super) fn is_final(self, count: u8) -> bool {
        u16::from(self.present) + u16::from(count) > u16::from(self.last)
    }

    /// Whether the present position is past the last one (nothing left).
    pub(super) fn is_exhausted(self) -> bool {
        self.present > self.last
    }

    /// The present position after a step of `count` words; the 8-bit pointer stops at
    /// 255 instead of wrapping to the start (spec-notes "Service containers").
    pub(super) fn advanced(self, count: u8) -> u8 {
        self.present.saturating_add(count)
    }

    /// The positions a step of `count` words covers, each with whether it is inside the
    /// buffer (≤ last).
    fn positions(self, count: u8) -> impl Iterator<Item = Option<u8>> {
        (0..count).map(move |i| {
            let position = u16::from(self.present) + u16::from(i);
            u8::try_from(position).ok().filter(|p| *p <= self.last)
        })
    }

    /// Fills `info` with `count` words from the buffer (0 after the last position);
    /// returns how many record words were filled.
    pub(super) fn copy_out(self, ram: &mut ContainerRam<'_>, count: u8, info: &mut [u16]) -> u8 {
        let mut filled = 0;
        for (slot, position) in info.iter_mut().zip(self.positions(count)) {
            *slot = match position {
                Some(p) => ram.buffer_word(p),
                None => 0,
            };
            filled += 1;
        }
        filled
    }

    /// Stores up to `count` words of `info` into the buffer (words after the last
    /// position are dropped); returns how many were stored.
    pub(super) fn copy_in(self, ram: &mut ContainerRam<'_>, count: u8, info: &[u16]) -> u8 {
        let mut stored = 0;
        for (word, position) in info.iter().zip(self.positions(count)) {
            let taken = match position {
                Some(p) => ram.set_buffer_word(p, *word),
                None => false,
            };
            stored += u8::from(taken);
        }
        stored
    }
}
