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
    // A block about to start (master: after its MST): its first transmit telegram.
    if let Some((t, block)) = tp.pending_block() {
        consider(next_block_bound(chip, t, block));
    }
    if chip.engine.s.is_sercos_slave() {
        // 410B §4.2.1 TRT "after end of MST": a slave's block starts at the end of an MST
        // it receives (crate::mst): the first MST's block bounds its telegrams; a later
        // MST (its block would abort that one) bounds them by its end.
        let mut first = true;
        let mut mst = |end_tick: u64, fcs_ok: bool, bytes: &[u8]| {
            let bound = if first {
                mst_block_bound(chip, end_tick, fcs_ok, bytes)
            } else {
                Some(end_tick)
            };
            first = false;
            bound
        };
        if let Some(now) = &tp.rx_now
            && now.role == super::RxRole::Mst
        {
            consider(mst(now.end_tick, now.fcs_ok, &now.bytes));
        }
        for (tick, f) in tp.rx_queue.iter().filter(|(_, f)| is_mst(&f.bytes)) {
            consider(mst(
                chip.clock.tick_at_or_after(f.end).max(*tick),
                f.fcs_ok,
                &f.bytes,
            ));
        }
    }
    if let Some(b) = &tp.block {
        match b.cur {
            // 410B §4.2.1 TRT: the current transmit telegram starts at its time. One whose
            // EN is 0 (read into NTH, not read again at its start) sends nothing there: the
            // next enabled one in the list bounds what follows, as the walks below find it.
            Some(Cur::Tx { start, hdr, .. }) if hdr.en() != TxEnable::Off => consider(Some(start)),
            Some(Cur::Tx { hdr, .. }) => consider(next_tx_memo(chip, b, hdr.pt)),
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

/// The first transmit telegram of the block an MST ending at `end_tick` starts
/// (`crate::mst::mst_end`: a good MST of an expected phase, the processor on); none for an
/// MST that starts no block.
fn mst_block_bound(chip: &Chip, end_tick: u64, fcs_ok: bool, bytes: &[u8]) -> Option<u64> {
    if !fcs_ok || !super::tp_enabled(chip) {
        return None;
    }
    let phase = bytes.get(1).copied().unwrap_or(0);
    let block = crate::mst::phase_block(chip, phase)?;
    next_block_bound(chip, end_tick, block)
}

/// The TRT tick of the first enabled transmit header of block `block` starting at `tick`
/// (410B §4.2.1: COMPT0/1 in RAM words 0/1 point to its first header; TRT counts from the
/// block's start; the headers are walked in list order), when nothing the processor does
/// before `tick` can change what that walk reads; `tick` itself otherwise (a held walk:
/// [`TelegramProcessor::walk_held`](super::TelegramProcessor::walk_held)).
#[inline]
fn next_block_bound(chip: &Chip, tick: u64, block: u8) -> Option<u64> {
    let Some(guard) = writes_before(chip, tick) else {
        chip.tp.walk_held.set(true);
        return Some(tick);
    };
    if let Some(m) = chip.tp.block_ahead.get()
        && m.block == block
        && same_proof(chip, m.epoch, block)
        && !guard.within(m.lo, m.hi)
    {
        // Every header the walk read lies in `lo .. hi`: no write of `guard` hits one.
        let found = m.trt.map(|trt| {
            tick.saturating_add(u64::from(trt).saturating_mul(chip.engine.pre.period()))
        });
        debug_assert_eq!(
            Some(found),
            walk_block(chip, tick, block, guard).map(|w| w.tick),
            "remembered block walk"
        );
        return found;
    }
    walk_block_and_keep(chip, tick, block, guard)
}

/// [`next_block_bound`] without a walk kept: walked, and kept unless held.
#[inline(never)]
fn walk_block_and_keep(chip: &Chip, tick: u64, block: u8, guard: Writes) -> Option<u64> {
    match walk_block(chip, tick, block, guard) {
        Some(found) => {
            let epoch = chip.layout_epoch.get();
            if same_proof(chip, epoch, block) {
                chip.tp.block_ahead.set(Some(BlockAhead {
                    block,
                    epoch,
                    trt: found.trt,
                    lo: found.lo,
                    hi: found.hi,
                }));
            }
            found.tick
        }
        None => {
            chip.tp.walk_held.set(true);
            Some(tick)
        }
    }
}

/// The walk of [`next_block_bound`] from block `block`'s COMPT, starting at `tick`; `None`
/// when it reads a header `guard` writes (held).
fn walk_block(chip: &Chip, tick: u64, block: u8, guard: Writes) -> Option<Walk> {
    let compt = walk::word(&chip.ram, u32::from(block & 1)).unwrap_or(0);
    let b = Block {
        block,
        ref_tick: tick,
        cur: None,
        steps: 0,
        last_end: tick,
        stamp: 0,
        #[cfg(debug_assertions)]
        shadow: super::Visited::EMPTY,
    };
    let mut clear = true;
    let found = next_tx_in_list_with(chip, &b, compt, |at, words, end| {
        // A header whose words the processor writes before the block starts: the walk may
        // not hold (the end marker's own TEND word changes nothing the walk reads).
        let hit = |w: Option<u32>| {
            w.is_some_and(|w| w >= u32::from(at) && w < u32::from(at) + words as u32)
        };
        if hit(guard.nmsterr)
            || (hit(guard.tend) && !(end && guard.tend == Some(u32::from(at) + 1)))
        {
            clear = false;
        }
        clear
    });
    clear.then_some(found)
}

/// What the walk of [`next_block_bound`] found, remembered while the layout proof it was
/// made under stands (`epoch`, `Chip::layout_epoch`): the walk from COMPT reads the pointer
/// word and the headers up to the first enabled transmit header (410B §4.2.1, §4.2
/// COMPT0/1), all read by the proof; of what the processor writes only a transmit header's
/// EN changes it ([`ram_written`] drops it when it lies in `lo .. hi`), and a host write
/// drops it (`Chip::touched`, `Chip::write_ram`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct BlockAhead {
    block: u8,
    epoch: u64,
    /// The first enabled transmit header's TRT (µs after the block's start).
    trt: Option<u16>,
    /// The RAM words the walk read: `lo .. hi`.
    lo: u32,
    hi: u32,
}

/// RAM words the processor may still write before a block starts at `tick` when the
/// current block has nothing left but its end marker: that marker's TEND word and, if the
/// MST window closes first, NMSTERR (410B §4.2 word 10).
#[derive(Debug, Clone, Copy)]
struct Writes {
    tend: Option<u32>,
    nmsterr: Option<u32>,
}

impl Writes {
    /// Whether a word it writes lies in `lo .. hi`.
    fn within(self, lo: u32, hi: u32) -> bool {
        [self.tend, self.nmsterr]
            .into_iter()
            .flatten()
            .any(|w| w >= lo && w < hi)
    }
}

/// [`Writes`] before `tick`; `None` when the current block may still receive or send
/// (a receive telegram writes data, VAL and NERR; a transmit telegram EN and its service
/// container: not followed here).
fn writes_before(chip: &Chip, tick: u64) -> Option<Writes> {
    let tp = &chip.tp;
    if tp
        .rx_now
        .as_ref()
        .is_some_and(|r| matches!(r.role, super::RxRole::Telegram { .. }))
    {
        return None;
    }
    let tend = match &tp.block {
        None => None,
        Some(super::Block {
            cur: Some(Cur::End { at, .. }),
            ..
        }) => Some(u32::from(*at) + 1),
        Some(_) => return None,
    };
    let nmsterr = tp
        .mst
        .deadline
        .get()
        .filter(|d| *d < tick)
        .map(|_| u32::from(sercon_regs::ram::NMSTERR));
    Some(Writes { tend, nmsterr })
}

/// What a walk of the header list found ahead of a receive header: valid in the same
/// block until the header it found is loaded (the list is walked in order, so every receive
/// header before it finds the same one). A host access drops it (`Chip::touched`), and so
/// does a write of the controller itself to the words it read ([`ram_written`]: receive data
/// or a service container laid over headers ahead, a programming error, or a transmit
/// header's EN).
///
/// It also holds in a later block of the same number while the layout proof it was made
/// under stands (`epoch`, `Chip::layout_epoch`): a block starts at its COMPT and loads its
/// headers by PT (410B §4.2.1, §4.2 COMPT0/1), one step each, so with the pointer words,
/// the headers' marker bits and PT unchanged (the proof read them, and only a host write,
/// which gives a new proof, changes them) the header current after as many steps is the
/// same, with the same headers reached before it; the walk ahead of it then reads the same
/// words, and the TRT it found counts from the new block's start (`trt`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TxAhead {
    ref_tick: u64,
    block: u8,
    /// `Block::steps` when the walk was made.
    from_steps: u32,
    /// `Block::steps` at which the found transmit header becomes current (`u32::MAX`: none
    /// ahead).
    until_steps: u32,
    /// Its TRT (µs after the block's start).
    trt: Option<u16>,
    /// The layout proof the walk was made under (`Chip::layout_epoch`; `None`: none held).
    epoch: Option<u64>,
    /// The RAM words the walk read: `lo .. hi`.
    lo: u32,
    hi: u32,
}

/// The controller wrote the RAM words `from .. from + len` (a transmit header's EN,
/// NMSTERR; receive data and the status words of [`status_written`] while no layout proof
/// holds): a remembered walk that read any of them is dropped.
pub(crate) fn ram_written(chip: &Chip, from: u32, len: usize) {
    let end = from.saturating_add(u32::try_from(len).unwrap_or(u32::MAX));
    if let Some(m) = chip.tp.tx_ahead.get()
        && from < m.hi
        && end > m.lo
    {
        chip.tp.tx_ahead.set(None);
        chip.tp.walk_overwritten.set(true);
    }
    if let Some(m) = chip.tp.block_ahead.get()
        && from < m.hi
        && end > m.lo
    {
        chip.tp.block_ahead.set(None);
    }
    // A refused layout proof rests on the words it read; the processor's own writes over
    // them (receive data laid over a header, 410B §4.2.2: what refused it) may take the
    // conflict away, and a fresh proof would then hold: found again (a proof that holds
    // sees only header status words written over read words, which change no list).
    if let Some((false, _)) = chip.layout.get() {
        refusal_written(chip, from, len);
    }
}

/// The controller stored receive data in the RAM words `from .. from + len` (410B §4.2.2).
/// While the layout proof holds, those words lie on no word it read (`telegram_processor::
/// layout`: no written word but a header's status words lies on a header, a control word or
/// a pointer word), so on none a walk ahead reads: a remembered walk stands. Otherwise as
/// [`ram_written`].
#[inline]
pub(crate) fn data_written(chip: &Chip, from: u32, len: usize) {
    if !matches!(chip.layout.get(), Some((true, _))) {
        ram_written(chip, from, len);
        return;
    }
    debug_assert!(
        !chip
            .layout_read
            .borrow()
            .any(from, u32::try_from(len).unwrap_or(u32::MAX)),
        "receive data stored over a word the layout proof read"
    );
}

/// The controller wrote a header status word that no walk ahead reads for what it finds: a
/// receive header's word 0 (VAL, RERR, ADR: 410B §4.2.1 "Modified by controller at beginning
/// and end of receive telegrams"), its NERR (word 4), the end marker's TEND (410B §4.2.3).
/// While the layout proof holds, the header the processor writes back is the RAM's
/// (`Chip::layout_proof`: refused while one it holds is not), so the marker bits stay; the
/// walks read a receive header's marker bits and PT and an end marker's marker bits only
/// (`next_tx_in_list`): a remembered walk stands. Otherwise as [`ram_written`].
pub(crate) fn status_written(chip: &Chip, from: u32, len: usize) {
    if !matches!(chip.layout.get(), Some((true, _))) {
        ram_written(chip, from, len);
    } else if cfg!(debug_assertions)
        && let Some(m) = chip.tp.tx_ahead.get()
        && let Some(b) = &chip.tp.block
        && let Some(Cur::Rx { hdr, .. }) = b.cur
        && m.block == b.block
        && m.from_steps <= b.steps
        && b.steps < m.until_steps
    {
        // What the walk found is what a fresh walk finds after the write.
        let fresh = next_tx_in_list(chip, b, hdr.pt);
        debug_assert_eq!(
            fresh
                .tx
                .map_or(u32::MAX, |i| b.steps.saturating_add(1).saturating_add(i)),
            m.until_steps,
            "a status write at {from} moved the walk ahead"
        );
    }
}

/// [`ram_written`] with the layout proof refused: dropped if the words written were read.
#[cold]
#[inline(never)]
fn refusal_written(chip: &Chip, from: u32, len: usize) {
    if chip
        .layout_read
        .borrow()
        .any(from, u32::try_from(len).unwrap_or(u32::MAX))
    {
        chip.set_layout(None);
    }
}

/// The controller wrote RAM it does not name word by word (a service container, 410B
/// §4.2.4): a remembered walk is dropped, and a refused layout proof is found again (see
/// [`ram_written`]).
pub(crate) fn ram_rewritten(chip: &Chip) {
    chip.tp.tx_ahead.set(None);
    chip.tp.block_ahead.set(None);
    chip.tp.walk_overwritten.set(true);
    if let Some((false, _)) = chip.layout.get() {
        chip.set_layout(None);
    }
}

/// [`next_tx_in_list`] from the current receive header, remembered (a master walks its
/// AT headers once, not once per AT and cycle: [`TxAhead`]).
#[inline]
fn next_tx_memo(chip: &Chip, b: &Block, pt: u16) -> Option<u64> {
    let period = chip.engine.pre.period();
    if let Some(m) = chip.tp.tx_ahead.get()
        && m.block == b.block
        && m.from_steps <= b.steps
        && b.steps < m.until_steps
        && (m.ref_tick == b.ref_tick || m.epoch.is_some_and(|e| same_proof(chip, e, b.block)))
    {
        let tick = m.trt.map(|trt| {
            b.ref_tick
                .saturating_add(u64::from(trt).saturating_mul(period))
        });
        #[cfg(debug_assertions)]
        {
            let fresh = next_tx_in_list(chip, b, pt);
            debug_assert_eq!(tick, fresh.tick, "remembered walk ahead: its tick");
            debug_assert_eq!(
                fresh
                    .tx
                    .map_or(u32::MAX, |i| b.steps.saturating_add(1).saturating_add(i)),
                m.until_steps,
                "remembered walk ahead: its header"
            );
            debug_assert!(
                fresh.lo >= m.lo && fresh.hi <= m.hi,
                "remembered walk ahead: its words"
            );
        }
        return tick;
    }
    walk_ahead(chip, b, pt)
}

/// [`next_tx_memo`] without a walk kept: walked and kept.
#[inline(never)]
fn walk_ahead(chip: &Chip, b: &Block, pt: u16) -> Option<u64> {
    let found = next_tx_in_list(chip, b, pt);
    let epoch = chip.layout_epoch.get();
    chip.tp.tx_ahead.set(Some(TxAhead {
        ref_tick: b.ref_tick,
        block: b.block,
        from_steps: b.steps,
        until_steps: found
            .tx
            .map_or(u32::MAX, |i| b.steps.saturating_add(1).saturating_add(i)),
        trt: found.trt,
        epoch: same_proof(chip, epoch, b.block).then_some(epoch),
        lo: found.lo,
        hi: found.hi,
    }));
    found.tick
}

/// Whether the layout proof numbered `epoch` (`Chip::layout_epoch`) still stands and holds
/// for block `block`'s list.
#[inline]
fn same_proof(chip: &Chip, epoch: u64, block: u8) -> bool {
    chip.layout_epoch.get() == epoch
        && matches!(chip.layout.get(), Some((true, proved)) if proved & (1 << (block & 1)) != 0)
}

/// What [`next_tx_in_list`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Walk {
    /// The TRT tick of the transmit telegram found.
    tick: Option<u64>,
    /// Its TRT.
    trt: Option<u16>,
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
    next_tx_in_list_with(chip, b, pt, |_, _, _| true)
}

/// [`next_tx_in_list`], asking `keep(address, words, is_end_marker)` of every header it
/// reads whether to go on (`false`: the walk ends there, finding nothing).
fn next_tx_in_list_with(
    chip: &Chip,
    b: &Block,
    pt: u16,
    mut keep: impl FnMut(u16, usize, bool) -> bool,
) -> Walk {
    let variant = chip.cfg.variant;
    let period = chip.engine.pre.period();
    let mut ptr = pt & variant.pointer_mask();
    let steps = max_steps(chip).saturating_sub(b.steps);
    let mut walk = Walk {
        tick: None,
        trt: None,
        tx: None,
        lo: u32::from(ptr),
        hi: u32::from(ptr),
    };
    // A header reached twice in one block ends it (`load`: the list loops): no telegram
    // after it. The headers already reached count, so the controller's own writes to them
    // (VAL, NERR of the current header) cannot change what this walk found.
    // The block's own reached in its stamps, the walk's in a set of its own.
    let mut visited = super::Visited::EMPTY;
    #[cfg(debug_assertions)]
    let mut shadow = b.shadow;
    for i in 0..steps {
        let seen = chip.tp.visits.reached(b.stamp, ptr) || visited.mark(ptr);
        #[cfg(debug_assertions)]
        debug_assert_eq!(
            seen,
            shadow.mark(ptr),
            "a walk ahead's stamps against its set"
        );
        if seen {
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
        let (words, end) = match header {
            Header::Transmit(_) => (TxHeader::WORDS, false),
            Header::Receive(_) => (RxHeader::WORDS, false),
            Header::End(_) => (sercon_regs::ram::header::EndMarker::WORDS, true),
        };
        if !keep(ptr, words, end) {
            return walk;
        }
        match header {
            Header::Transmit(h) if h.en != TxEnable::Off => {
                // 410B §4.2.1 TRT: µs after the end of the MST.
                walk.tick = Some(
                    b.ref_tick
                        .saturating_add(u64::from(h.trt).saturating_mul(period)),
                );
                walk.trt = Some(h.trt);
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
