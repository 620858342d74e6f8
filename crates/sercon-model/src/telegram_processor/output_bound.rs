//! The earliest tick at which the telegram processor may start a telegram of its own: a
//! lower bound a simulation may sleep until when nothing else of the chip is observable.

use sercon_regs::ram::header::{Header, RxHeader, TxEnable, TxHeader};

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
/// header before it finds the same one). A host access drops it (`Chip::touched`), and so
/// does a write of the controller itself to the words it read ([`ram_written`]: receive data
/// or a service container laid over headers ahead, a programming error).
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
    /// The RAM words the walk read: `lo .. hi`.
    lo: u32,
    hi: u32,
}

/// The controller wrote the RAM words `from .. from + len` (receive data, a header's VAL or
/// NERR, TEND, NMSTERR): a remembered walk that read any of them is dropped.
pub(crate) fn ram_written(chip: &Chip, from: u32, len: usize) {
    if let Some(m) = chip.tp.tx_ahead.get() {
        let end = from.saturating_add(u32::try_from(len).unwrap_or(u32::MAX));
        if from < m.hi && end > m.lo {
            chip.tp.tx_ahead.set(None);
        }
    }
}

/// The controller wrote RAM it does not name word by word (a service container, 410B
/// §4.2.4): a remembered walk is dropped.
pub(crate) fn ram_rewritten(chip: &Chip) {
    chip.tp.tx_ahead.set(None);
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
        debug_assert_eq!(m.tick, next_tx_in_list(chip, b, pt).tick);
        return m.tick;
    }
    let found = next_tx_in_list(chip, b, pt);
    chip.tp.tx_ahead.set(Some(TxAhead {
        ref_tick: b.ref_tick,
        block: b.block,
        from_steps: b.steps,
        until_steps: found
            .tx
            .map_or(u32::MAX, |i| b.steps.saturating_add(1).saturating_add(i)),
        tick: found.tick,
        lo: found.lo,
        hi: found.hi,
    }));
    found.tick
}

/// What [`next_tx_in_list`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Walk {
    /// The TRT tick of the transmit telegram found.
    tick: Option<u64>,
    /// How many headers before it.
    tx: Option<u32>,
    /// The RAM words read: `lo .. hi`.
    lo: u32,
    hi: u32,
}

/// The TRT tick of the first transmit header with EN ≠ 0 from `pt` on, and how many headers
/// before it; none at the end marker, a header the processor would refuse or has reached in
/// this block, or the block's step limit.
fn next_tx_in_list(chip: &Chip, b: &Block, pt: u16) -> Walk {
    let variant = chip.cfg.variant;
    let period = chip.engine.pre.period();
    let mut ptr = pt & variant.pointer_mask();
    let steps = max_steps(chip).saturating_sub(b.steps);
    let mut walk = Walk {
        tick: None,
        tx: None,
        lo: u32::from(ptr),
        hi: u32::from(ptr),
    };
    // A header reached twice in one block ends it (`load`: the list loops): no telegram
    // after it. The headers already reached count, so the controller's own writes to them
    // (VAL, NERR of the current header) cannot change what this walk found.
    let mut visited = b.visited;
    for i in 0..steps {
        if visited.mark(ptr) {
            return walk;
        }
        // The words `header_at` reads (the longest header, clipped by the RAM's end).
        let at = u32::from(ptr);
        walk.lo = walk.lo.min(at);
        walk.hi = walk
            .hi
            .max(at.saturating_add(HEADER_WORDS_MAX))
            .min(u32::from(variant.ram_words()));
        let Ok(header) = walk::header_at(&chip.ram, variant, ptr) else {
            return walk;
        };
        match header {
            Header::Transmit(h) if h.en != TxEnable::Off => {
                // 410B §4.2.1 TRT: µs after the end of the MST.
                walk.tick = Some(
                    b.ref_tick
                        .saturating_add(u64::from(h.trt).saturating_mul(period)),
                );
                walk.tx = Some(i);
                return walk;
            }
            Header::Transmit(h) => ptr = h.pt & variant.pointer_mask(),
            Header::Receive(h) => ptr = h.pt & variant.pointer_mask(),
            Header::End(_) => return walk,
        }
    }
    walk
}

/// The most words a header has (410B §4.2.1).
const HEADER_WORDS_MAX: u32 = if RxHeader::WORDS > TxHeader::WORDS {
    RxHeader::WORDS as u32
} else {
    TxHeader::WORDS as u32
};
