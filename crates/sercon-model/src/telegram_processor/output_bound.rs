//! The earliest tick at which the telegram processor may start a telegram of its own: a
//! lower bound a simulation may sleep until when nothing else of the chip is observable.

use sercon_regs::ram::header::{Header, TxEnable};

use super::receive::is_mst;
use super::walk;
use super::{Block, Cur, max_steps};
use crate::chip::Chip;

/// The earliest MCLK tick at which the processor may start sending (a transmit telegram,
/// or a block whose first telegram may be due at once); `None` when nothing it has queued
/// or in progress can lead to a transmission before the timing control's next cycle start.
pub(crate) fn next_tx_bound(chip: &Chip) -> Option<u64> {
    let tp = &chip.tp;
    let mut best: Option<u64> = None;
    let mut consider = |t: Option<u64>| {
        if let Some(t) = t {
            best = Some(best.map_or(t, |b: u64| b.min(t)));
        }
    };
    // A block about to start (master: after its MST) may begin with a telegram due at once.
    consider(tp.pending_block.map(|(t, _)| t));
    if chip.engine.s.is_sercos_slave() {
        // 410B §4.2.1 TRT "after end of MST": a slave's block starts at the end of an MST
        // it receives (crate::mst), the earliest its telegrams can go.
        if let Some(now) = &tp.rx_now
            && now.role == super::RxRole::Mst
        {
            consider(Some(now.end_tick));
        }
        if let Some((tick, f)) = tp.rx_queue.iter().find(|(_, f)| is_mst(&f.bytes)) {
            consider(Some(chip.clock.tick_at_or_after(f.end).max(*tick)));
        }
    }
    if let Some(b) = &tp.block {
        match b.cur {
            // 410B §4.2.1 TRT: the current transmit telegram starts at its time.
            Some(Cur::Tx { start, .. }) => consider(Some(start)),
            // The headers are walked in list order (PT) and a transmit telegram never
            // starts before its TRT, nor before the one ahead of it: the next enabled
            // transmit header in the list bounds every later one.
            Some(Cur::Rx { hdr, .. }) => consider(next_tx_memo(chip, b, hdr.pt)),
            Some(Cur::End { .. }) => {}
            None => consider(Some(b.ref_tick)),
        }
    }
    best
}

/// What a walk of the header list found ahead of a receive header: valid in the same
/// block until the header it found is loaded (the list is walked in order, so every receive
/// header before it finds the same one). A host access drops it (`Chip::touched`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TxAhead {
    ref_tick: u64,
    block: u8,
    /// `Block::steps` when the walk was made.
    from_steps: u32,
    /// `Block::steps` at which the found transmit header becomes current (`u32::MAX`: none
    /// ahead).
    until_steps: u32,
    /// Its TRT tick.
    tick: Option<u64>,
}

/// [`next_tx_in_list`] from the current receive header, remembered (a master walks its
/// AT headers once per cycle, not once per AT).
fn next_tx_memo(chip: &Chip, b: &Block, pt: u16) -> Option<u64> {
    if let Some(m) = chip.tp.tx_ahead.get()
        && m.ref_tick == b.ref_tick
        && m.block == b.block
        && m.from_steps <= b.steps
        && b.steps < m.until_steps
    {
        debug_assert_eq!(m.tick, next_tx_in_list(chip, b, pt).map(|(t, _)| t));
        return m.tick;
    }
    let found = next_tx_in_list(chip, b, pt);
    chip.tp.tx_ahead.set(Some(TxAhead {
        ref_tick: b.ref_tick,
        block: b.block,
        from_steps: b.steps,
        until_steps: found.map_or(u32::MAX, |(_, i)| b.steps.saturating_add(1 + i)),
        tick: found.map(|(t, _)| t),
    }));
    found.map(|(t, _)| t)
}

/// The TRT tick of the first transmit header with EN ≠ 0 from `pt` on, and how many headers
/// before it; `None` at the end marker, a header the processor would refuse, or the block's
/// step limit.
fn next_tx_in_list(chip: &Chip, b: &Block, pt: u16) -> Option<(u64, u32)> {
    let variant = chip.cfg.variant;
    let period = chip.engine.pre.period();
    let mut ptr = pt & variant.pointer_mask();
    let steps = max_steps(chip).saturating_sub(b.steps);
    for i in 0..steps {
        match walk::header_at(&chip.ram, variant, ptr).ok()? {
            Header::Transmit(h) if h.en != TxEnable::Off => {
                // 410B §4.2.1 TRT: µs after the end of the MST.
                let tick = b
                    .ref_tick
                    .saturating_add(u64::from(h.trt).saturating_mul(period));
                return Some((tick, i));
            }
            Header::Transmit(h) => ptr = h.pt & variant.pointer_mask(),
            Header::Receive(h) => ptr = h.pt & variant.pointer_mask(),
            Header::End(_) => return None,
        }
    }
    None
}
