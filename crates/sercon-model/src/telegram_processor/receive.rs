//! Receive telegrams (410B §4.2.1 receive header, §4.2.2 data containers by POS/LEN,
//! §4.1 3H.10-11, 4H.12-15, 5H.8, 5H.15, 0BH RECADR, 25H/26H THRPT/THR; 816 §2.9, §2.10.2).

use sercon_regs::Variant;
use sercon_regs::ram::header::{Buffering, HeaderKind};

use super::status::{INT_NEWADR, INT_REND, INT_RERR, INT_RMISS, INT_RSTART, ProgErr};
use super::transmit::raise_sc;
use super::walk::{self, Containers};
use super::walk_memo;
use super::{Block, Cur, HeaderWord0, RxNow, RxRole, advance, prog_error, reg25, set_flmdtadr};
use crate::chip::{Chain, Chip};
use crate::service_container::{self, ScMode};

/// A receive header as the processor holds it from its reading at `load` to the end of its
/// telegram (410B §4.2.1): word 0 as read, TLEN (word 2) and PT (word 3, cut to the variant's
/// pointer width). Word 0 is kept whole, not decoded into its fields: the processor writes
/// it back with only VAL, RERR and (ACHK = 0) ADR changed ("Modified by controller at
/// beginning and end of receive telegrams"), which are set in place; its other bits are
/// read where they decide (docs/performance.md, session 26, rxchain). TRT decides only at
/// `load`; NERR is read afresh where it is counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct RxHead {
    /// Word 0: ADR 7-0, DMA 8, DBUF 9, VAL 10, ACHK 11, TCHK 12, RERR 13, marker 15-14 = 00.
    pub(crate) w0: u16,
    /// TLEN: the telegram's length in data words, without the address.
    pub(crate) tlen: u16,
    /// PT: the word address of the next header or the end marker.
    pub(crate) pt: u16,
}

/// 410B §4.2.1 receive header word 0: VAL (bit 10).
const VAL: u16 = 1 << 10;
/// 410B §4.2.1 receive header word 0: RERR (bit 13).
const RERR: u16 = 1 << 13;

impl HeaderWord0 for RxHead {
    #[inline]
    fn w0(self) -> u16 {
        self.w0
    }
}

impl RxHead {
    /// The header of words `w`, whose word 0 marks a receive header (`walk::header_words`
    /// classified it: 410B §4.2.1, ERRATA "telegram header marker bits").
    #[inline]
    pub(crate) fn from_words(variant: Variant, w: [u16; 5]) -> RxHead {
        let [w0, _trt, tlen, w3, _nerr] = w;
        debug_assert_eq!(HeaderKind::classify(w0), Ok(HeaderKind::Receive));
        RxHead {
            w0,
            tlen,
            pt: w3 & variant.pointer_mask(),
        }
    }

    /// ACHK (0.11).
    #[inline]
    pub(crate) fn achk(self) -> bool {
        self.w0 & (1 << 11) != 0
    }

    /// TCHK (0.12).
    #[inline]
    pub(crate) fn tchk(self) -> bool {
        self.w0 & (1 << 12) != 0
    }

    /// RERR (0.13).
    #[inline]
    pub(crate) fn rerr(self) -> bool {
        self.w0 & RERR != 0
    }

    /// The header with VAL set to `val`.
    #[inline]
    fn with_val(self, val: bool) -> RxHead {
        RxHead {
            w0: (self.w0 & !VAL) | u16::from(val) << 10,
            ..self
        }
    }

    /// The header with RERR set to `rerr`.
    #[inline]
    fn with_rerr(self, rerr: bool) -> RxHead {
        RxHead {
            w0: (self.w0 & !RERR) | u16::from(rerr) << 13,
            ..self
        }
    }

    /// The header with ADR set to `adr`.
    #[inline]
    fn with_adr(self, adr: u8) -> RxHead {
        RxHead {
            w0: (self.w0 & 0xFF00) | u16::from(adr),
            ..self
        }
    }
}

/// ERRATA "Telegrams": the MST is ADR 255 with one data byte.
pub(crate) fn is_mst(bytes: &[u8]) -> bool {
    bytes.len() == 2 && bytes.first() == Some(&255)
}

/// The first queued frame starts at `tick`. Returns the frame in progress when it is an
/// accepted telegram whose end [`Chip::advance_to`]'s loop would take next at once
/// (`chain`, `rx_end_is_next`): [`super::step`] then processes that end as its step would,
/// without the frame being kept in `rx_now` in between.
pub(super) fn frame_start(
    chip: &mut Chip,
    tick: u64,
    chain: &Chain,
) -> Option<(RxNow, crate::mclk::Due)> {
    let (_, frame) = chip.tp.rx_queue.pop_front()?;
    chip.tp.last_taken = Some(frame.start);
    // No frame starts while one is in progress: its start waits for that one's end
    // (`first_frame_tick`, `release_held_starts`).
    debug_assert!(chip.tp.rx_now.is_none(), "a frame started inside another");
    let start = frame.start;
    let end_tick = chip.clock.tick_at_or_after(frame.end).max(tick);
    // A start held behind the frame before it is judged at its own tick (its window, an
    // MST's timing); it is processed here.
    let at = match chip.tp.held_start {
        Some((s, k)) if s == start => {
            chip.tp.held_start = None;
            k
        }
        _ => tick,
    };
    let role = if is_mst(&frame.bytes) {
        crate::mst::mst_start(chip, at);
        RxRole::Mst
    } else {
        accept(chip, tick, at, &frame.bytes)
    };
    if role == RxRole::Ignored {
        // Its end would change nothing (nothing asks for an ignored frame in progress): no
        // event for it.
        if !chip.tp.replacing.is_empty() {
            take_replacement(chip, start, tick);
        }
        return None;
    }
    if matches!(role, RxRole::Telegram { .. })
        && chip.tp.replacing.is_empty()
        && let Some(others) = super::rx_end_is_next(chip, end_tick)
        && chain.allows(chip, end_tick)
    {
        let now = RxNow {
            bytes: frame.bytes,
            fcs_ok: frame.fcs_ok,
            end_tick,
            role,
        };
        return Some((now, others));
    }
    chip.tp.rx_now = Some(RxNow {
        bytes: frame.bytes,
        fcs_ok: frame.fcs_ok,
        end_tick,
        role,
    });
    if !chip.tp.replacing.is_empty() {
        take_replacement(chip, start, tick);
    }
    None
}

/// A frame taken back and replaced (`take_back_frame`) has just started at `tick`: it
/// decided at its start, its replacement gives its end (to the frame in progress).
#[cold]
#[inline(never)]
fn take_replacement(chip: &mut Chip, start: sercos_wire::time::Instant, tick: u64) {
    let Some(i) = chip.tp.replacing.iter().position(|f| f.start == start) else {
        return;
    };
    let r = chip.tp.replacing.swap_remove(i);
    let end_tick = chip.clock.tick_at_or_after(r.end).max(tick);
    if let Some(now) = chip.tp.rx_now.as_mut() {
        now.end_as(r, end_tick);
    }
}

/// Decides at `tick` whether the frame starting at tick `at` (earlier when its start was
/// held behind the frame before it) is the expected receive telegram.
fn accept(chip: &mut Chip, tick: u64, at_tick: u64, bytes: &[u8]) -> RxRole {
    // Only the current header's fields, matched in place (the block carries a 256-byte
    // bitmap; the header is not copied out whole either).
    let Some(Block {
        cur:
            Some(Cur::Rx {
                at,
                hdr,
                open,
                close,
                ..
            }),
        ..
    }) = chip.tp.block
    else {
        return RxRole::Ignored;
    };
    // 410B §4.2.1 TCHK: "The time of receiving is checked": outside the window the frame
    // is not this telegram.
    if at_tick < open || (hdr.tchk() && at_tick > close) {
        return RxRole::Ignored;
    }
    let adr = bytes.first().copied().unwrap_or(0);
    // 25H.11 PHAS12 read only when it decides.
    if hdr.achk() && adr != hdr.adr() && !reg25(chip).1 {
        // 410B §4.2.1 ACHK = 1: "Telegrams are received if the address is valid".
        return RxRole::Ignored;
    }
    // Accepted: 3H.10 FLRWAIT falls, 3H.11 FLREC rises, 4H.13 INT_RSTART, 25H/26H.
    chip.tp.flrwait = false;
    chip.tp.flrec = true;
    chip.engine.flags.raise_lo(INT_RSTART);
    chip.tp.thrpt = at & 0x03FF;
    chip.tp.thr = walk::word(&chip.ram, u32::from(at)).unwrap_or(0);
    let mut h = hdr;
    if h.buffering() != Buffering::Double {
        // 410B §4.2.1 VAL, single buffer or DMA: "telegram data is invalid (VAL = 0)";
        // "Modified by controller at beginning and end of receive telegrams".
        h = h.with_val(false);
        write_word0(chip, at, h);
    }
    // The next header is read at the start of this telegram (816 §2.10.1.2, Figure 6).
    advance(chip, tick, hdr.pt);
    RxRole::Telegram { at, hdr: h }
}

/// Writes word 0 of the receive header at `at` as `h` holds it; the header's other words stay
/// as they are in the RAM.
fn write_word0(chip: &mut Chip, at: u16, h: RxHead) {
    let w0 = h.w0;
    walk::set_word(&mut chip.ram, u32::from(at), w0);
    // VAL, RERR, ADR: the marker bits stay (a header status word).
    super::output_bound::status_written(chip, u32::from(at), 1);
}

/// Increments NERR (receive header word 4), saturating (spec-notes "NERR").
fn count_error(chip: &mut Chip, at: u16) {
    let a = u32::from(at) + 4;
    let n = walk::word(&chip.ram, a).unwrap_or(0);
    walk::set_word(&mut chip.ram, a, n.saturating_add(1));
    super::output_bound::status_written(chip, a, 1);
}

/// The frame being received, `now`, ended at `tick`.
// Inlined into `Chip::advance_to` (its one call, `step`): measured both ways again with
// the receive header held as `RxHead` (session 26, rxchain: kept out of line, a ring-8
// cycle took ≈ 500 instructions more; session 18 had found the opposite with the header
// decoded).
#[inline]
pub(super) fn frame_end(chip: &mut Chip, tick: u64, now: RxNow) {
    match now.role {
        RxRole::Ignored => {}
        RxRole::Mst => crate::mst::mst_end(chip, tick, now.fcs_ok, &now.bytes),
        RxRole::Telegram { at, hdr } => {
            finish(chip, tick, at, hdr, &now.bytes, now.fcs_ok);
        }
    }
    if chip.tp.rx_queue.front().is_some_and(|(t, _)| *t < tick) {
        release_held_starts(chip, tick);
    }
}

/// The frames whose start was held behind the frame that ended at `tick`
/// (`first_frame_tick`) start here; the first keeps its own start tick to be judged at
/// (`frame_start`).
#[cold]
#[inline(never)]
fn release_held_starts(chip: &mut Chip, tick: u64) {
    if let Some((k, f)) = chip.tp.rx_queue.front() {
        chip.tp.held_start = Some((f.start, *k));
    }
    for (t, _) in chip.tp.rx_queue.iter_mut() {
        if *t >= tick {
            break;
        }
        *t = tick;
    }
}

/// Completes the receive telegram of header `at` with `bytes` (ADR + data).
fn finish(chip: &mut Chip, tick: u64, at: u16, hdr: RxHead, bytes: &[u8], fcs_ok: bool) {
    chip.tp.flrec = false;
    if let Some(b) = chip.tp.block.as_mut() {
        b.last_end = b.last_end.max(tick);
    }
    let adr = bytes.first().copied().unwrap_or(0);
    // 410B §4.1 0BH RECADR: "Address of receive telegram".
    chip.tp.recadr = adr;
    // 410B §4.2.1 TLEN: a frame of another length is not this telegram (spec-notes).
    let ok = fcs_ok && bytes.len() == 1 + 2 * usize::from(hdr.tlen);
    let mut h = hdr;
    // Re-read word 0's VAL: only the controller changes it for receive telegrams
    // (816 §2.10.1.1), but keep NERR from the RAM. 25H.11 PHAS12 read only when it decides.
    if ok && reg25(chip).1 {
        // 410B §4.1 25H.12 FLMDTADR: "Address of receive telegram equal to expected
        // value"; 816 §2.9.2: an MDT with another address resets it.
        let matches = adr == hdr.adr();
        set_flmdtadr(chip, matches);
        if hdr.achk() && !matches {
            // Phase 1/2: an MDT for another drive ends the wait without data.
            chip.engine.flags.raise_lo(INT_REND);
            rscend(chip);
            return;
        }
    }
    if !ok {
        // 410B §4.2.1 RERR "errored or not received", NERR "Error counter"; 4H.15
        // INT_RERR; data unchanged; 5H.8 INT_RMISS on the second in a row.
        if hdr.rerr() {
            chip.engine.flags.raise_hi(INT_RMISS);
        }
        h = h.with_rerr(true);
        write_word0(chip, at, h);
        count_error(chip, at);
        chip.engine.flags.raise_lo(INT_RERR | INT_REND);
        service_error(chip, at, h);
        rscend(chip);
        return;
    }
    // DMA and DBUF (410B §4.2.1) read once: the writes below change VAL, RERR and ADR only.
    let buffering = hdr.buffering();
    store(chip, at, &h, buffering, bytes);
    if !hdr.achk() && adr != hdr.adr() {
        // 410B §4.2.1 ACHK = 0: "The received address is stored at ADR"; 5H.15
        // INT_NEWADR "address change" (spec-notes).
        h = h.with_adr(adr);
        chip.engine.flags.raise_hi(INT_NEWADR);
    }
    let val = match buffering {
        // 410B §4.2.1 VAL, double buffer: the buffer just written becomes the valid one.
        Buffering::Double => !hdr.val(),
        _ => true,
    };
    h = h.with_rerr(false).with_val(val);
    write_word0(chip, at, h);
    chip.engine.flags.raise_lo(INT_REND);
    rscend(chip);
}

/// 816 §2.10.2.2 INT_RSCEND: "at the end of a receive telegram, if there are no service
/// container that need to be worked on or in case the work is completed".
fn rscend(chip: &mut Chip) {
    if chip.cfg.variant == Variant::Sercon816 {
        chip.engine.flags.set_rscend(true);
    }
}

/// Stores the data of a good telegram container by container (410B §4.2.2 POS: "Position
/// of the data block within the telegram in number of words").
fn store(chip: &mut Chip, at: u16, h: &RxHead, buffering: Buffering, bytes: &[u8]) {
    debug_assert_eq!(buffering, h.buffering());
    if let Some(c) = walk_memo::kept(chip, at, HeaderKind::Receive, buffering) {
        // Walked before under the layout proof that still stands: the same container, no
        // walk error (`walk_memo`).
        if buffering != Buffering::Dma && !c.control.svfl {
            #[cfg(debug_assertions)]
            let general = {
                let mut general = chip.clone();
                let ends = store_list(&mut general, h, buffering, bytes, &[c]);
                store_errors(&mut general, None, ends);
                general
            };
            store_kept(chip, &c, h, buffering, bytes);
            #[cfg(debug_assertions)]
            check_kept_store(chip, &general);
            return;
        }
        let ends = store_list(chip, h, buffering, bytes, std::slice::from_ref(&c));
        store_errors(chip, None, ends);
        return;
    }
    let mut walk = Containers::new(&chip.ram, at, HeaderKind::Receive, buffering);
    // The usual telegram has one container (ERRATA "data containers", LASTDC = 1 on the
    // first): it is stored from here, without the reused list (docs/performance.md,
    // session 12, frameq). The walk reads the same containers either way.
    let first = walk.next();
    let second = first.and_then(|_| walk.next());
    if second.is_none() {
        let walk_error = walk.error;
        #[cfg(debug_assertions)]
        {
            let all: Vec<walk::Container> =
                Containers::new(&chip.ram, at, HeaderKind::Receive, buffering).collect();
            debug_assert_eq!(all.as_slice(), first.as_slice(), "one-container walk");
        }
        walk_memo::keep(
            chip,
            at,
            HeaderKind::Receive,
            buffering,
            first.as_slice(),
            walk_error,
        );
        let ends = store_list(chip, h, buffering, bytes, first.as_slice());
        store_errors(chip, walk_error, ends);
        return;
    }
    let mut list = std::mem::take(&mut chip.tp.containers);
    list.clear();
    list.extend(first);
    list.extend(second);
    // One push per container (`extend` takes the generic path for this iterator: a size
    // hint and a capacity check per element).
    for c in walk.by_ref() {
        list.push(c);
    }
    let walk_error = walk.error;
    let ends = store_list(chip, h, buffering, bytes, &list);
    chip.tp.containers = list;
    store_errors(chip, walk_error, ends);
}

/// [`store`] of a good telegram whose one container `c` is kept (`walk_memo`: no walk
/// error) and is no service container, buffered in the RAM (410B §4.2.1 DMA = 0): its LEN
/// words from word POS of the telegram's data (410B §4.2.2) written in place into the buffer
/// that is not valid (410B §4.2.1 VAL, DBUF; the one buffer when DBUF = 0); a container
/// reaching past the data is a container overrun, nothing stored (as [`store_list`]).
#[inline(always)]
fn store_kept(
    chip: &mut Chip,
    c: &walk::Container,
    h: &RxHead,
    buffering: Buffering,
    bytes: &[u8],
) {
    let pos = usize::from(c.pos);
    let len = usize::from(c.control.len);
    let data = bytes.get(1..).unwrap_or(&[]);
    let Some(src) = data.get(2 * pos..2 * (pos + len)) else {
        // An empty container always lies inside the data (and writes nothing).
        if len != 0 {
            prog_error(chip, ProgErr::ContainerOverrun);
        }
        return;
    };
    write_buffer(chip, c.buffer(buffering, !h.val()), src, len);
}

/// Writes a container's words `src` (`len` of them, little-endian) to its buffer at `dst`
/// in the RAM (410B §4.2.2: the buffer that is not valid), for [`store_kept`] and
/// [`store_list`].
#[inline(always)]
fn write_buffer(chip: &mut Chip, dst: u32, src: &[u8], len: usize) {
    match walk::words_mut(&mut chip.ram, dst, len) {
        Some(ram) => copy_le_words(ram, src),
        // Only the words inside the RAM are written (the walk keeps containers inside).
        None => {
            for (i, w) in le_words(src).enumerate() {
                walk::set_word(&mut chip.ram, dst + i as u32, w);
            }
        }
    }
    super::output_bound::data_written(chip, dst, len);
}

/// Debug builds: the chip after [`store_kept`] is `general`, the chip the general store
/// ([`store_list`] with the kept container) left.
#[cfg(debug_assertions)]
fn check_kept_store(chip: &Chip, general: &Chip) {
    debug_assert_eq!(
        format!("{general:?}"),
        format!("{chip:?}"),
        "a kept container's telegram stored the short way"
    );
}

/// The programming errors a store ran into: the walk's own, then a container outside the
/// telegram's data, then an RFIFO overrun (`ends`: `(overrun, fifo_overrun)`).
fn store_errors(chip: &mut Chip, walk_error: Option<ProgErr>, ends: (bool, bool)) {
    let (overrun, fifo_overrun) = ends;
    if let Some(e) = walk_error {
        prog_error(chip, e);
    }
    if overrun {
        prog_error(chip, ProgErr::ContainerOverrun);
    }
    if fifo_overrun {
        prog_error(chip, ProgErr::DmaFifo);
    }
}

/// Stores the containers `list` of a good telegram; returns `(overrun, fifo_overrun)`:
/// a container reached past the telegram's data (the rest not stored), the RFIFO held
/// unread words.
// Inlined at its three calls (LLVM kept it out of line with `#[inline]`): the call's own
// cost (register saves, arguments) was about a third of a one-container store.
#[inline(always)]
fn store_list(
    chip: &mut Chip,
    h: &RxHead,
    buffering: Buffering,
    bytes: &[u8],
    list: &[walk::Container],
) -> (bool, bool) {
    let variant = chip.cfg.variant;
    let data = bytes.get(1..).unwrap_or(&[]);
    let mut overrun = false;
    let mut fifo_overrun = false;
    let block = chip.tp.block.as_ref().map(|b| b.ref_tick);
    for c in list.iter() {
        let pos = usize::from(c.pos);
        let len = usize::from(c.control.len);
        // The container's words must lie inside the telegram's data (an empty container
        // always does).
        let Some(src) = data
            .get(2 * pos..2 * (pos + len))
            .or((len == 0).then_some(&[][..]))
        else {
            overrun = true;
            break;
        };
        match buffering {
            // RFIFO collects the block's DMA receive data; words of an earlier block still
            // unread are an overrun (spec-notes "Master DMA layout").
            Buffering::Dma => {
                let mut record = std::mem::take(&mut chip.tp.record);
                record.clear();
                record.extend(le_words(src));
                fifo_overrun |= chip.tp.fifo.store_rx(block, &record);
                if c.control.svfl {
                    service_receive(chip, variant, c, &record);
                }
                chip.tp.record = record;
            }
            // Double buffer: write the buffer that is not valid (VAL selects the valid one),
            // straight from the telegram (the record only for a service container).
            _ => {
                write_buffer(chip, c.buffer(buffering, !h.val()), src, len);
                if c.control.svfl {
                    let mut record = std::mem::take(&mut chip.tp.record);
                    record.clear();
                    record.extend(le_words(src));
                    service_receive(chip, variant, c, &record);
                    chip.tp.record = record;
                }
            }
        }
    }
    (overrun, fifo_overrun)
}

/// A service container (SVFL) received `record` (410B §4.2.4).
fn service_receive(chip: &mut Chip, variant: Variant, c: &walk::Container, record: &[u16]) {
    let mode = ScMode::from_scmaster(c.control.scmaster);
    let nsv = c.control.nsv;
    let o = service_container::on_receive(&mut chip.ram, variant, nsv, mode, record, true);
    raise_sc(chip, nsv, o.int_sc);
    super::output_bound::ram_rewritten(chip);
}

/// The little-endian words of `bytes` (410B §4.2.2: the telegram's data words low byte
/// first); `chunks_exact(2)` gives pairs only.
fn le_words(bytes: &[u8]) -> impl Iterator<Item = u16> + '_ {
    bytes.chunks_exact(2).map(|p| match p {
        [lo, hi] => u16::from_le_bytes([*lo, *hi]),
        _ => 0,
    })
}

/// Writes the little-endian words of `src` (410B §4.2.2) over `ram`, as many as both hold
/// (whole pairs only).
#[inline(always)]
fn copy_le_words(ram: &mut [u16], src: &[u8]) {
    ram.iter_mut().zip(le_words(src)).for_each(|(r, w)| *r = w);
}

/// Service containers of an errored or missing telegram record RECERR (410B §4.2.4).
fn service_error(chip: &mut Chip, at: u16, h: RxHead) {
    let variant = chip.cfg.variant;
    let mut list = std::mem::take(&mut chip.tp.containers);
    list.clear();
    list.extend(Containers::new(
        &chip.ram,
        at,
        HeaderKind::Receive,
        h.buffering(),
    ));
    for c in list.iter().filter(|c| c.control.svfl) {
        let mode = ScMode::from_scmaster(c.control.scmaster);
        let nsv = c.control.nsv;
        let o = service_container::on_receive(&mut chip.ram, variant, nsv, mode, &[], false);
        raise_sc(chip, nsv, o.int_sc);
        super::output_bound::ram_rewritten(chip);
    }
    chip.tp.containers = list;
}

/// The expected telegram of header `at` did not come (window closed, block ended).
// 410B §4.2.1 RERR "errored or not received"; 5H.8 INT_RMISS "receive telegram missing
// twice": RERR still set from the last cycle makes this the second in a row.
pub(super) fn missing(chip: &mut Chip, at: u16, hdr: RxHead) {
    chip.tp.flrwait = false;
    // Re-read: the header in RAM is the truth (RERR of the previous cycle).
    let rerr_before = walk::word(&chip.ram, u32::from(at)).is_some_and(|w| w & (1 << 13) != 0);
    if rerr_before {
        chip.engine.flags.raise_hi(INT_RMISS);
    }
    let mut h = hdr.with_rerr(true);
    if let Some(w0) = walk::word(&chip.ram, u32::from(at)) {
        h = h.with_val(w0 & VAL != 0);
    }
    write_word0(chip, at, h);
    count_error(chip, at);
    service_error(chip, at, h);
}

#[cfg(test)]
mod tests {
    use super::*;
    use sercon_regs::ram::header::RxHeader;

    /// Every receive header word 0 (marker 00, 410B §4.2.1) with the other words of a few
    /// kinds: what `RxHead` reads and writes in place is what decoding the header into
    /// `RxHeader`, changing the field and encoding it again gives.
    #[test]
    fn word0_in_place_is_the_decoded_header() {
        for variant in Variant::ALL {
            for w0 in 0..0x4000u16 {
                for (tlen, w3) in [(0, 0), (3, 0x0123), (0xFFFF, 0xFFFF)] {
                    let words = [w0, 17, tlen, w3, 5];
                    let Ok(g) = RxHeader::from_words(variant, words) else {
                        panic!("{w0:#06x} is a receive header");
                    };
                    let h = RxHead::from_words(variant, words);
                    assert_eq!(
                        (
                            h.adr(),
                            h.dma(),
                            h.dbuf(),
                            h.val(),
                            h.achk(),
                            h.tchk(),
                            h.rerr()
                        ),
                        (g.adr, g.dma, g.dbuf, g.val, g.achk, g.tchk, g.rerr),
                        "{w0:#06x}"
                    );
                    assert_eq!((h.tlen, h.pt, h.buffering()), (g.tlen, g.pt, g.buffering()));
                    let word0 = |g: RxHeader| g.to_words(variant)[0];
                    assert_eq!(h.w0, word0(g));
                    for b in [false, true] {
                        assert_eq!(h.with_val(b).w0, word0(RxHeader { val: b, ..g }));
                        assert_eq!(h.with_rerr(b).w0, word0(RxHeader { rerr: b, ..g }));
                    }
                    for adr in [0, 1, 0x5A, 0xFF] {
                        assert_eq!(h.with_adr(adr).w0, word0(RxHeader { adr, ..g }));
                    }
                }
            }
        }
    }
}
