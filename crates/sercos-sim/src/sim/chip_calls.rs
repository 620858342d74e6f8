//! The chip calls of the simulation's hot path, named by the role of the node they serve.
//!
//! In a normal build each is the chip's own method, inlined. With the `split-profile`
//! feature each role's call is a function of its own that is never inlined and never
//! merged with another role's, so that a profiler's inclusive cost per function splits a
//! cycle into the slaves' chips (their receivers, run-aheads and takes), the master's chip
//! and the simulation itself (`scripts/chip-split.sh`; docs/performance.md, session 28).
//! The feature changes nothing the simulation does, only where its instructions are
//! counted (and adds a call per chip call).

use sercon_model::Chip;
use sercon_model::serial_port::LineSegment;
use sercos_wire::time::Instant;

/// `chip.line_input_at_level(seg)` for node `j` (0: the master).
#[inline(always)]
pub(super) fn input(j: usize, chip: &mut Chip, seg: LineSegment) {
    #[cfg(feature = "split-profile")]
    if j == 0 {
        split::master_input(chip, seg)
    } else {
        split::slave_input(chip, seg)
    }
    #[cfg(not(feature = "split-profile"))]
    {
        let _ = j;
        chip.line_input_at_level(seg)
    }
}

/// `chip.advance_to(t)` for node `j`, at its wake or in a run-ahead.
#[inline(always)]
pub(super) fn advance(j: usize, chip: &mut Chip, t: Instant) {
    #[cfg(feature = "split-profile")]
    if j == 0 {
        split::master_advance(chip, t)
    } else {
        split::slave_advance(chip, t)
    }
    #[cfg(not(feature = "split-profile"))]
    {
        let _ = j;
        chip.advance_to(t)
    }
}

/// `chip.take_line_output_until(t, out)` for node `j`.
#[inline(always)]
pub(super) fn take(j: usize, chip: &mut Chip, t: Instant, out: &mut Vec<LineSegment>) {
    #[cfg(feature = "split-profile")]
    if j == 0 {
        split::master_take(chip, t, out)
    } else {
        split::slave_take(chip, t, out)
    }
    #[cfg(not(feature = "split-profile"))]
    if j == 0 {
        // The master's take: its MST or MDT (410B §4.1 0CH, §4.2.1), mostly alone.
        chip.take_own_line_output_until(t, out)
    } else {
        chip.take_line_output_until(t, out)
    }
}

/// One never-inlined function per role and call; each passes a different constant through
/// `black_box` so that the linker cannot fold two of them into one.
#[cfg(feature = "split-profile")]
mod split {
    use std::hint::black_box;

    use sercon_model::Chip;
    use sercon_model::serial_port::LineSegment;
    use sercos_wire::time::Instant;

    #[inline(never)]
    pub(super) fn master_input(chip: &mut Chip, seg: LineSegment) {
        black_box(1u8);
        chip.line_input_at_level(seg)
    }

    #[inline(never)]
    pub(super) fn slave_input(chip: &mut Chip, seg: LineSegment) {
        black_box(2u8);
        chip.line_input_at_level(seg)
    }

    #[inline(never)]
    pub(super) fn master_advance(chip: &mut Chip, t: Instant) {
        black_box(3u8);
        chip.advance_to(t)
    }

    #[inline(never)]
    pub(super) fn slave_advance(chip: &mut Chip, t: Instant) {
        black_box(4u8);
        chip.advance_to(t)
    }

    #[inline(never)]
    pub(super) fn master_take(chip: &mut Chip, t: Instant, out: &mut Vec<LineSegment>) {
        black_box(5u8);
        chip.take_own_line_output_until(t, out)
    }

    #[inline(never)]
    pub(super) fn slave_take(chip: &mut Chip, t: Instant, out: &mut Vec<LineSegment>) {
        black_box(6u8);
        chip.take_line_output_until(t, out)
    }
}
