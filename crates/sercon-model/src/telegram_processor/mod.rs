//! The telegram processor (410B §1, §4.2.1–§4.2.3): at each communication cycle it works
//! through the transmission block COMPT0/1 chosen by the phase, header by header along PT
//! to the end marker, sending transmit telegrams TRT µs after the end of the MST and
//! expecting receive telegrams, storing their data by POS/LEN.
//!
//! Everything is scheduled per telegram on MCLK ticks: a header becomes current, its
//! start (transmit) or its window (receive) is an event, the frame's end is an event.
//! Frames from the line arrive ahead of time ([`RxFrame`]) and are queued until their
//! start. Every walk over the RAM is bounded, so no RAM contents can hang or panic the
//! model; what is wrong is reported in PROGERR_FL (410B §4.1 17H) with INT_PROGERR.
//!
//! Readings where the documents are silent: `docs/spec-notes.md`, "Telegram processor
//! and MST".

pub(crate) mod early_start;
mod fifo;
mod host;
mod layout;
pub(crate) use layout::{RamWords, possible_blocks, prove as prove_layout};
mod line_out;
mod output_bound;
pub(crate) use output_bound::next_tx_bound;
mod receive;
pub(crate) use receive::RxHead;
pub(crate) mod status;
mod transmit;
mod walk;
mod walk_memo;

use crate::first_queue::FirstQueue;

use sercon_regs::Register;
use sercon_regs::ram::header::TxEnable;
use sercos_wire::time::Instant;

use crate::chip::{Chain, Chip};
use crate::interrupts::INT_COMEND;
use crate::mclk::Due;
use fifo::DmaFifos;
pub(crate) use fifo::FifoState;
use status::{INT_PROGERR, INT_RWAIT, INT_TEND, ProgErr};

use crate::serial_port::HeardFrame;
/// A frame the receiver saw: the serial port's [`RxFrame`], handed to the processor as
/// soon as its line segment reaches the chip.
pub use crate::serial_port::RxFrame;

/// What the processor does with the header that is current.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Cur {
    /// A transmit telegram due at tick `start` (header read into NTH at `read`).
    Tx { at: u16, hdr: TxHead, start: u64 },
    /// A receive telegram expected from tick `open`; with TCHK (`hdr.tchk()`, never changed
    /// while the header is current) it must start by `close`, which is 0 without (an
    /// `Option` would make the current header, copied whole in the hot path, 8 bytes longer).
    Rx {
        at: u16,
        hdr: RxHead,
        open: u64,
        close: u64,
        announced: bool,
    },
    /// The end marker, reached at `ready`; the block ends when the last telegram has.
    End { at: u16, ready: u64 },
}

// The current header stays four words long (its `Option` included): it is read and written
// whole in the processor's hot path, where every byte more costs copies.
const _: () = assert!(std::mem::size_of::<Option<Cur>>() == 32);

/// A transmit header as the processor holds it from its reading into NTH (`load`) to its
/// telegram's start (410B §4.2.1; 816 §2.10.1.2): word 0 as read, TLEN (word 2) and PT
/// (word 3, cut to the variant's pointer width). Word 0 is kept whole, not decoded into its
/// fields: the processor writes it back with EN = 0 (EN = 1, "the circuit sets EN to 0
/// after the transmit telegram has been started") and the 816 reads VAL again at the start,
/// both set in place (as `receive::RxHead`). TRT decides only at `load`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TxHead {
    /// Word 0: ADR 7-0, DMA 8, DBUF 9, VAL 10, EN 12-11, bit 13, marker 15-14 = 01.
    pub(crate) w0: u16,
    /// TLEN: the telegram's length in data words, without the address.
    pub(crate) tlen: u16,
    /// PT: the word address of the next header or the end marker.
    pub(crate) pt: u16,
}

impl TxHead {
    /// The header of words `w`, whose word 0 marks a transmit header (`walk::header_words`
    /// classified it: 410B §4.2.1, ERRATA "telegram header marker bits").
    #[inline]
    pub(crate) fn from_words(variant: sercon_regs::Variant, w: [u16; 4]) -> TxHead {
        let [w0, _trt, tlen, w3] = w;
        debug_assert_eq!(
            sercon_regs::ram::header::HeaderKind::classify(w0),
            Ok(sercon_regs::ram::header::HeaderKind::Transmit)
        );
        TxHead {
            w0,
            tlen,
            pt: w3 & variant.pointer_mask(),
        }
    }

    /// EN (0.12-11).
    #[inline]
    pub(crate) fn en(self) -> TxEnable {
        TxEnable::from_code(self.w0 >> 11)
    }

    /// The header with VAL set to `val`.
    #[inline]
    pub(crate) fn with_val(self, val: bool) -> TxHead {
        TxHead {
            w0: (self.w0 & !(1 << 10)) | u16::from(val) << 10,
            ..self
        }
    }

    /// The header with EN set to `en`.
    #[inline]
    pub(crate) fn with_en(self, en: TxEnable) -> TxHead {
        TxHead {
            w0: (self.w0 & !(3 << 11)) | (en as u16) << 11,
            ..self
        }
    }
}

/// Word 0 of a telegram header as the processor holds it (`TxHead`, `receive::RxHead`), kept
/// whole: the fields both kinds of header share (410B §4.2.1 word 0: ADR 7-0, DMA 8, DBUF 9,
/// VAL 10), read from the word where they decide.
pub(crate) trait HeaderWord0: Copy {
    /// Word 0 as read.
    fn w0(self) -> u16;

    /// ADR (word 0 bits 7-0).
    #[inline]
    fn adr(self) -> u8 {
        self.w0() as u8
    }

    /// DMA (0.8).
    #[inline]
    fn dma(self) -> bool {
        self.w0() & (1 << 8) != 0
    }

    /// DBUF (0.9).
    #[inline]
    fn dbuf(self) -> bool {
        self.w0() & (1 << 9) != 0
    }

    /// VAL (0.10).
    #[inline]
    fn val(self) -> bool {
        self.w0() & (1 << 10) != 0
    }

    /// Where the telegram's data lives (410B §4.2.2: DMA, DBUF).
    #[inline]
    fn buffering(self) -> sercon_regs::ram::header::Buffering {
        use sercon_regs::ram::header::Buffering;
        // DMA and DBUF (0.8, 0.9) read as one 2-bit field: DMA = 1 is DMA whatever DBUF.
        let b = match (self.w0() >> 8) & 3 {
            0 => Buffering::Single,
            2 => Buffering::Double,
            _ => Buffering::Dma,
        };
        debug_assert_eq!(b, Buffering::from_bits(self.dma(), self.dbuf()));
        b
    }
}

impl HeaderWord0 for TxHead {
    #[inline]
    fn w0(self) -> u16 {
        self.w0
    }
}

/// A transmission block being processed (410B §4.1 3H.6 COMACT = 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Block {
    /// 0 or 1 (3H.7 COMBLK).
    pub(crate) block: u8,
    /// The end of the MST: the tick TRT counts from.
    pub(crate) ref_tick: u64,
    /// The current header; `None` before the first is read.
    pub(crate) cur: Option<Cur>,
    /// Headers walked so far (bounded).
    pub(crate) steps: u32,
    /// Tick at which the last telegram of the block ended.
    pub(crate) last_end: u64,
    /// The block's number among the blocks the chip started, which the header addresses it
    /// reaches are stamped with ([`Visits`]); 0 for a block no step started (a walk ahead's,
    /// `output_bound`), which has reached none.
    pub(crate) stamp: Stamp,
    /// Debug builds: the header addresses reached, as a set of the block's own, against
    /// which every stamp is checked.
    #[cfg(debug_assertions)]
    pub(crate) shadow: Visited,
}

/// The header addresses the blocks reach (410B §4.2.1 PT: a header reached twice in one block
/// means a list that never reaches its end marker, `load`), one stamp per RAM word: the
/// number of the last block that reached a header there ([`Block::stamp`]). A block start
/// takes the next number instead of clearing a set of its own (a 2048-bit set was cleared at
/// every block start and carried with the block: ring-8 −0.6 % instructions a cycle,
/// docs/performance.md, session 29).
#[derive(Clone)]
pub(crate) struct Visits {
    /// Per RAM word: the number of the last block that reached a header there (0: none);
    /// as many as the larger RAM has words (816 §2.5: 2048), so that every header address
    /// (`Variant::pointer_mask`) has one.
    stamps: Box<[Stamp; STAMPS]>,
    /// The number of the last block started (0: none yet).
    last: Stamp,
}

/// A block's number in [`Visits`]: one byte, so that a chip's stamps take 2 KiB, not the
/// 8 KiB of `u32` numbers (nine chips' 72 KiB did not stay in the level-1 data cache: the
/// stamp's load was a fifth of ring-8's D1 misses in cachegrind, 93 → 61 a cycle with one
/// byte). The stamps are cleared once every 255 blocks instead ([`Visits::start`]).
pub(crate) type Stamp = u8;

/// One stamp per word of the larger RAM (816 §2.5: 2048 words).
const STAMPS: usize = sercon_regs::Variant::Sercon816.ram_words() as usize;

impl Default for Visits {
    fn default() -> Self {
        Visits {
            stamps: Box::new([0; STAMPS]),
            last: 0,
        }
    }
}

/// What the stamps say: the last block's number and the addresses it reached (older stamps
/// match no block that can still be asked about, [`Visits::start`]), not 2048 numbers.
impl std::fmt::Debug for Visits {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let reached: Vec<usize> = (0..STAMPS)
            .filter(|&a| self.last != 0 && self.stamps[a] == self.last)
            .collect();
        f.debug_struct("Visits")
            .field("last", &self.last)
            .field("reached", &reached)
            .finish()
    }
}

impl Visits {
    /// The number of a block starting now: no word carries it yet.
    fn start(&mut self) -> Stamp {
        self.last = self.last.wrapping_add(1);
        if self.last == 0 {
            // Every number used: the stamps start afresh (no word may carry the new one).
            self.stamps.fill(0);
            self.last = 1;
        }
        self.last
    }

    /// Whether block `stamp` reached `addr` (never for stamp 0, a block not started). The
    /// stamps of a block are kept until the next starts: asked of the block in progress
    /// (or of one not started).
    fn reached(&self, stamp: Stamp, addr: u16) -> bool {
        stamp != 0 && self.stamps[usize::from(addr) % STAMPS] == stamp
    }

    /// Marks `addr` reached by block `stamp` (≠ 0, the block in progress); returns whether it
    /// was already. Addresses count modulo 2048, as the set of bits did (a header address is
    /// a masked pointer, `Variant::pointer_mask`, below that anyway).
    fn mark(&mut self, stamp: Stamp, addr: u16) -> bool {
        let s = &mut self.stamps[usize::from(addr) % STAMPS];
        let seen = *s == stamp;
        *s = stamp;
        seen
    }
}

/// One bit per RAM word (2048 words at most, 816 §2.5): the headers a walk ahead has reached
/// (`output_bound`), and in debug builds a block's ([`Block::shadow`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Visited([u64; 32]);

impl Visited {
    pub(crate) const EMPTY: Visited = Visited([0; 32]);

    /// Marks `addr`; returns whether it was marked already.
    pub(crate) fn mark(&mut self, addr: u16) -> bool {
        let (i, bit) = (usize::from(addr / 64) % 32, 1u64 << (addr % 64));
        let Some(w) = self.0.get_mut(i) else {
            return false;
        };
        let seen = *w & bit != 0;
        *w |= bit;
        seen
    }
}

/// What a frame being received is to the processor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RxRole {
    /// Not for us (not expected, wrong address or outside the window).
    Ignored,
    /// An MST (ADR 255 and one data byte).
    Mst,
    /// The expected telegram of the receive header at `at`.
    Telegram { at: u16, hdr: RxHead },
}

/// A frame whose start has passed: what its end reads (not the whole [`HeardFrame`], whose
/// instants it no longer needs: docs/performance.md, session 12, rxnow).
#[derive(Debug, Clone)]
pub(crate) struct RxNow {
    /// The frame's bytes (ADR and data, FCS stripped).
    pub(crate) bytes: crate::serial_port::Shared<[u8]>,
    /// The frame ended with a flag and its FCS matched.
    pub(crate) fcs_ok: bool,
    pub(crate) end_tick: u64,
    pub(crate) role: RxRole,
}

impl RxNow {
    /// The frame in progress ends as `f` ends (a frame the receiver took back and replaced,
    /// [`take_back_frame`]), at `end_tick`.
    pub(crate) fn end_as(&mut self, f: HeardFrame, end_tick: u64) {
        self.end_tick = end_tick;
        self.bytes = f.bytes;
        self.fcs_ok = f.fcs_ok;
    }
}

/// MST bookkeeping (slave reception, master ring delay).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct MstState {
    /// Tick of the end of the last good MST (slave).
    pub(crate) last_end: Option<u64>,
    /// Tick by which the next MST must have been received (slave); a `Due`, not an
    /// `Option<u64>`, so that the step's and the next tick's tests are one comparison each
    /// (a deadline whose sum saturated is none: never reached).
    pub(crate) deadline: Due,
    /// The previous expected MST was missing.
    pub(crate) missed_prev: bool,
    /// A miss was counted since the last good MST (its late arrival is not checked again).
    pub(crate) missed_since: bool,
}

/// An instant no frame queued in [`TelegramProcessor::rx_queue`] starts after
/// ([`TelegramProcessor::on_rx_frame`]). Starts of queued frames are never moved (a
/// report that takes a frame's place has its start; take-backs and pops only remove), so
/// the start of the frame pushed last at the back stays one; [`Instant::MAX`] (the
/// default, e.g. after a reset, which keeps the queue) until one is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct QueueBound(pub(crate) Instant);

impl Default for QueueBound {
    fn default() -> Self {
        QueueBound(Instant::MAX)
    }
}

/// The telegram processor's state. Owned by [`Chip`]; reset with the chip.
#[derive(Debug, Clone, Default)]
pub(crate) struct TelegramProcessor {
    pub(crate) block: Option<Block>,
    /// The tick at which block [`TelegramProcessor::pending_block_no`] starts (the end of
    /// the MST), none without a block pending; a `Due`, as `MstState::deadline`
    /// ([`TelegramProcessor::pending_block`] gives both).
    pub(crate) pending_block_at: Due,
    /// The number of the block pending at `pending_block_at` (0 without one).
    pub(crate) pending_block_no: u8,
    /// Frames delivered ahead of time, ordered by start, each with the MCLK tick of its
    /// start (computed once when queued: the event loop asks for it on every turn). The
    /// first in place: on a steady ring a frame mostly comes to an empty queue (a slave
    /// takes its MST before its MDT comes) and is taken from the front.
    pub(crate) rx_queue: FirstQueue<(u64, HeardFrame)>,
    /// No frame in `rx_queue` starts after this instant (`on_rx_frame`): a frame that starts
    /// at or after it goes to the back without a look at the queue's last entry.
    pub(crate) rx_queue_bound: QueueBound,
    pub(crate) rx_now: Option<RxNow>,
    /// The start of the last frame taken from `rx_queue` (its start processed, or passed
    /// over): a take-back of a frame that starts no later finds it taken. The frame in
    /// progress (`rx_now`) is that frame: none starts while one is in progress
    /// (`first_frame_tick`), and an ignored one leaves `rx_now` empty.
    pub(crate) last_taken: Option<Instant>,
    /// The first frame whose start was held behind the frame in progress
    /// (`receive::release_held_starts`): its start instant and the tick of that start, at
    /// which its receive window (410B §4.2.1 TCHK) and an MST's timing are judged.
    pub(crate) held_start: Option<(Instant, u64)>,
    /// The frame the receiver was still decoding at the end of the bits received, taken at
    /// its start before its end had come (`early_start`).
    pub(crate) early: Option<early_start::EarlyFrame>,
    /// Frames that replace a queued frame of the same start the receiver took back
    /// ([`take_back_frame`]): the queued one decides at its start, as a chip that had
    /// taken it would have; the replacement gives its end.
    pub(crate) replacing: Vec<HeardFrame>,
    /// End of the telegram being sent (3H.9 FLTMT while there is one); a `Due`, as
    /// `MstState::deadline`.
    pub(crate) tx_end: Due,
    /// The transmitter is busy until this tick.
    pub(crate) tx_busy_until: u64,
    /// 410B §4.1 3H.10 FLRWAIT.
    pub(crate) flrwait: bool,
    /// 410B §4.1 3H.11 FLREC.
    pub(crate) flrec: bool,
    /// 410B §4.1 21H THTPT, 22H THT, 23H THWPT, 24H THW, 25H THRPT, 26H THR.
    pub(crate) thtpt: u16,
    pub(crate) tht: u16,
    pub(crate) thwpt: u16,
    pub(crate) thw: u16,
    pub(crate) thrpt: u16,
    pub(crate) thr: u16,
    /// 410B §4.1 0BH PHASREC (7-0) and RECADR (15-8).
    pub(crate) phasrec: u8,
    pub(crate) recadr: u8,
    /// 410B §4.1 11H TCYCDEL.
    pub(crate) tcycdel: u16,
    /// 410B §4.1 17H PROGERR_FL.
    pub(crate) progerr: u16,
    pub(crate) fifo: DmaFifos,
    pub(crate) mst: MstState,
    /// Telegram bytes being assembled (reused: no allocation per telegram).
    pub(crate) txbuf: Vec<u8>,
    /// One data record for the service containers (reused).
    pub(crate) record: Vec<u16>,
    /// The containers of one telegram (reused).
    pub(crate) containers: Vec<walk::Container>,
    /// Container walks kept under the layout proof (`walk_memo`).
    pub(crate) walk_memo: walk_memo::WalkMemo,
    /// The next transmit header ahead of the current receive header, remembered
    /// (`output_bound`).
    pub(crate) tx_ahead: std::cell::Cell<Option<output_bound::TxAhead>>,
    /// The first transmit header of a block's list, remembered (`output_bound`).
    pub(crate) block_ahead: std::cell::Cell<Option<output_bound::BlockAhead>>,
    /// The controller wrote RAM words a remembered walk ahead had read (`output_bound`:
    /// receive data or a service container laid over headers ahead) since this was last
    /// cleared (`Chip::advance_before_output`).
    pub(crate) walk_overwritten: std::cell::Cell<bool>,
    /// A block's walk was held at its start (`output_bound::next_block_bound`: what the
    /// processor still writes before it may change the list) since this was last cleared
    /// (`Chip::next_output_bound`): that bound is the block's start, not its first transmit
    /// telegram, and is found afresh, never remembered (spec-notes "Held block walks").
    pub(crate) walk_held: std::cell::Cell<bool>,
    /// Programming errors and blocks ended early so far (wrapping): a kept output bound does
    /// not outlive one (`Chip::advance_before_output`).
    pub(crate) irregular: u32,
    /// The header addresses the blocks reached.
    pub(crate) visits: Visits,
}

/// Most headers one block may walk: every header has at least two words.
fn max_steps(chip: &Chip) -> u32 {
    u32::from(chip.cfg.variant.ram_words()) / 2 + 1
}

/// 410B §4.1 3H.8 ENTMT.
pub(crate) fn entmt(chip: &Chip) -> bool {
    chip.engine.regs.stored(Register::Ctrl3) & (1 << 8) != 0
}

/// Whether the telegram processor works through transmission blocks: SERCOS interface
/// mode (MSTEN) or data telegrams enabled (ENTMT). Reading (spec-notes "when the
/// telegram processor runs"): a chip fresh out of reset (both 0) leaves its RAM, which
/// has no reset value, alone.
pub(crate) fn tp_enabled(chip: &Chip) -> bool {
    chip.engine.s.msten || entmt(chip)
}

/// The bits of 25H the chip reads: (MSTTCHK, PHAS12, FLMDTADR).
pub(crate) fn reg25(chip: &Chip) -> (bool, bool, bool) {
    let w = chip.engine.regs.stored(Register::Thrpt);
    (w & (1 << 10) != 0, w & (1 << 11) != 0, w & (1 << 12) != 0)
}

/// Sets or clears FLMDTADR (25H.12), which the chip sets and clears itself (816 §2.9.2).
pub(crate) fn set_flmdtadr(chip: &mut Chip, value: bool) {
    let w = chip.engine.regs.stored(Register::Thrpt);
    let w = (w & !(1 << 12)) | (u16::from(value) << 12);
    chip.engine.regs.set_stored(Register::Thrpt, w);
}

/// Records a programming error (410B §4.1 17H PROGERR_FL, 5H.14 INT_PROGERR).
pub(crate) fn prog_error(chip: &mut Chip, e: ProgErr) {
    chip.tp.irregular = chip.tp.irregular.wrapping_add(1);
    chip.tp.progerr |= e.bit();
    chip.engine.flags.raise_hi(INT_PROGERR);
}

impl TelegramProcessor {
    /// The next tick at which the processor has something to do. A receive window's
    /// opening, a transmit telegram's end and the end marker are events only when an
    /// enabled interrupt output carries their flag (`int_out`: `Settings::int_out_lo`);
    /// otherwise they are applied with the processor's next event or a bus access
    /// ([`apply_quiet_events`]).
    pub(crate) fn next_tick(&self, int_out: u16) -> Option<u64> {
        let others = self.next_tick_but_rx(int_out);
        match &self.rx_now {
            Some(r) => Some(others.map_or(r.end_tick, |t| t.min(r.end_tick))),
            None => others,
        }
    }

    /// [`TelegramProcessor::next_tick`] without the end of the frame in progress.
    #[inline]
    pub(crate) fn next_tick_but_rx(&self, int_out: u16) -> Option<u64> {
        let (best, any) = self.next_tick_but_rx_parts(int_out);
        any.then_some(best)
    }

    /// The block pending (its start tick and number), if any.
    pub(crate) fn pending_block(&self) -> Option<(u64, u8)> {
        self.pending_block_at
            .get()
            .map(|t| (t, self.pending_block_no))
    }

    /// [`TelegramProcessor::next_tick_but_rx`] as a [`Due`] (the event loop's form: no
    /// candidate is `u64::MAX`, see [`Due`]; debug-checked against the general form).
    #[inline]
    pub(crate) fn next_due_but_rx(&self, int_out: u16) -> Due {
        // With no candidate `best` stays `u64::MAX`: none; a candidate of `u64::MAX` is none
        // too (see `Due`).
        let (best, _) = self.next_tick_but_rx_parts(int_out);
        Due::from_raw(best)
    }

    /// The earliest of [`TelegramProcessor::next_tick_but_rx`]'s candidates (`u64::MAX`
    /// with none) and whether there is one.
    #[inline(always)]
    fn next_tick_but_rx_parts(&self, int_out: u16) -> (u64, bool) {
        let events = int_out;
        // The earliest of the candidates (`any`: there is one; a tick of u64::MAX counts).
        let mut best = u64::MAX;
        let mut any = false;
        // `Due`s: a minimum without a tag's branch (none is `u64::MAX`, no candidate).
        if events & INT_TEND != 0 {
            best = best.min(self.tx_end.raw());
            any |= self.tx_end.is_some();
        }
        best = best.min(self.mst.deadline.raw());
        any |= self.mst.deadline.is_some();
        best = best.min(self.pending_block_at.raw());
        any |= self.pending_block_at.is_some();
        let mut consider = |t: u64| {
            any = true;
            best = best.min(t);
        };
        if let Some(b) = &self.block {
            match b.cur {
                Some(Cur::Tx { start, .. }) => consider(start),
                Some(Cur::Rx {
                    hdr,
                    open,
                    close,
                    announced,
                    ..
                }) => {
                    if !announced && events & INT_RWAIT != 0 {
                        consider(open);
                    } else if hdr.tchk() {
                        consider(close);
                    }
                }
                Some(Cur::End { ready, .. }) if events & INT_COMEND != 0 => consider(ready),
                Some(Cur::End { .. }) | None => {}
            }
        }
        (best, any)
    }

    /// The next tick, given the start tick of the first queued frame (computed by the
    /// chip, which knows the clock).
    pub(crate) fn next_tick_with(&self, first_frame: Option<u64>, int_out: u16) -> Option<u64> {
        match (self.next_tick(int_out), first_frame) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Queues a frame the receiver saw (contract with `serial_port`): processed at its
    /// start and end.
    /// `start_tick` is the first MCLK tick at or after the frame's start.
    #[inline(always)]
    pub(crate) fn on_rx_frame(&mut self, start_tick: u64, frame: HeardFrame) {
        // Keep the queue ordered by start; frames normally arrive in order. A frame that
        // starts at or after the kept bound starts at or after the last one queued: it
        // goes to the back, as the look at the last one below decides (debug-checked).
        let in_order = frame.start >= self.rx_queue_bound.0;
        debug_assert!(
            !in_order
                || self
                    .rx_queue
                    .back()
                    .is_none_or(|(_, last)| last.start <= frame.start),
            "a frame before the last one queued passed the queue's bound"
        );
        if in_order
            || self
                .rx_queue
                .back()
                .is_none_or(|(_, last)| last.start <= frame.start)
        {
            // Every frame queued starts at or before this one (the queue is in order).
            self.rx_queue_bound.0 = frame.start;
            self.rx_queue.push_back((start_tick, frame));
        } else {
            let idx = self
                .rx_queue
                .partition_point(|(_, f)| f.start <= frame.start);
            self.rx_queue.insert(idx, (start_tick, frame));
        }
    }
}

/// The receiver took back the frame starting at `start` (its bits were cut by the next
/// segment: another driver on the RS-485 bus, 410B Fig. 4; spec-notes "RS-485 bus") and
/// reported the frame the line showed from that start in its place, if that one has ended
/// yet. The frame keeps what it decided at its start (telegram or MST, accepted or not: the
/// bits before the cut are the same), whether the chip has taken that start or not, so the
/// chip's time at the cut does not matter; it ends as the new report ends, or, not ended
/// yet, at its own end in error.
#[cold]
#[inline(never)]
pub(crate) fn take_back_frame(chip: &mut Chip, start: Instant) {
    // Taken: its start was processed (in progress, or over: ended, or passed over as not
    // for this chip). A start held behind a frame still in progress (`first_frame_tick`) is
    // not taken yet, whatever the chip's time.
    let in_progress = chip.tp.rx_now.is_some() && chip.tp.last_taken == Some(start);
    let taken = in_progress || chip.tp.last_taken.is_some_and(|t| t >= start);
    let q = &mut chip.tp.rx_queue;
    // The earlier report comes first among frames of one start (`on_rx_frame`).
    let first = q.iter().position(|(_, f)| f.start == start);
    if taken {
        // The new report is of a frame whose start is behind: the frame in progress takes
        // its end; one already over stays as it was decided (its report is dropped).
        let new = first.and_then(|i| q.remove(i));
        if in_progress && let Some(now) = chip.tp.rx_now.as_mut() {
            match new {
                Some((_, f)) => {
                    let tick = chip.clock.tick_at_or_after(start);
                    let end_tick = chip.clock.tick_at_or_after(f.end).max(tick);
                    now.end_as(f, end_tick);
                }
                None => now.fcs_ok = false,
            }
        }
    } else if let Some(i) = first {
        // Still queued: it stays for its start, the replacement is kept for its end.
        let later = q.iter().skip(i + 1).position(|(_, f)| f.start == start);
        let new = later.and_then(|k| q.remove(i + 1 + k)).map(|(_, f)| f);
        let replacing = match new {
            Some(f) => f,
            None => match q.get(i) {
                Some((_, old)) => HeardFrame {
                    fcs_ok: false,
                    ..old.clone()
                },
                None => return,
            },
        };
        chip.tp.replacing.retain(|f| f.start != start);
        chip.tp.replacing.push(replacing);
    }
    // Cached bounds counted the frame taken back.
    chip.rx_queue_changed();
}

/// Whether a received frame is an MST (ADR 255 and one byte, 410B §4.2).
pub(crate) fn frame_is_mst(bytes: &[u8]) -> bool {
    receive::is_mst(bytes)
}

/// The tick of the first queued frame's start; `None` while a frame is in progress.
///
/// Two frames the receiver reports overlap only where they share a flag, the closing one of
/// the first being the opening one of the next (HDLC; a telegram cut inside its closing flag
/// by the next one's, a repeater's own telegram over the one it repeats, 410B §1): the first
/// ends when that flag is whole, and the next starts there (`receive::frame_end` moves a
/// start held so to that tick). Taking the next one's start at the flag's start ended the
/// first before its flag was whole, so that a cut of that flag still to come, which breaks the
/// first telegram on the line, came too late for it on a chip that had taken the next start
/// already but not on one handed the cut first (the master's NERR apart on the simulator's
/// two paths, found by the mixed property test; spec-notes "A frame starts once the frame in
/// progress has ended"). The frame in progress ends no later than any queued frame starts,
/// so while it lasts the processor's next tick is its own ([`TelegramProcessor::next_tick`]).
pub(crate) fn first_frame_tick(chip: &Chip) -> Option<u64> {
    if chip.tp.rx_now.is_some() {
        return None;
    }
    chip.tp.rx_queue.front().map(|(tick, _)| *tick)
}

/// The next tick at which the telegram processor acts: its other events' and the frame
/// in progress's end or, with none in progress, the first queued frame's start
/// ([`first_frame_tick`]): [`TelegramProcessor::next_tick_with`] in one comparison.
pub(crate) fn next_tick(chip: &Chip) -> Option<u64> {
    let tp = &chip.tp;
    let others = tp.next_tick_but_rx(chip.engine.s.int_out_lo);
    let frame = match &tp.rx_now {
        Some(r) => Some(r.end_tick),
        None => tp.rx_queue.front().map(|(tick, _)| *tick),
    };
    let next = match (others, frame) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    debug_assert_eq!(
        next,
        tp.next_tick_with(first_frame_tick(chip), chip.engine.s.int_out_lo)
    );
    next
}

/// [`next_tick`] as a [`Due`] (the event loop's form; debug-checked against it).
#[inline]
pub(crate) fn next_due(chip: &Chip) -> Due {
    let tp = &chip.tp;
    let others = tp.next_due_but_rx(chip.engine.s.int_out_lo);
    let frame = match &tp.rx_now {
        Some(r) => Due::at(r.end_tick),
        None => Due::from_option(tp.rx_queue.front().map(|(tick, _)| *tick)),
    };
    let next = others.min(frame);
    debug_assert_eq!(next, Due::from_option(next_tick(chip)));
    next
}

/// A communication cycle started at `tick` (timing control): a master sends the MST and
/// processes the block after it; without MST the block's times count from the cycle start.
// 410B §4.1 0CH.0-1: MSTEN/MSTMASTER; §4.2.1 TRT "after end of MST".
pub(crate) fn on_cycle_start(chip: &mut Chip, tick: u64) {
    if !tp_enabled(chip) {
        return;
    }
    let Some(block) = chip.engine.cycle.run.map(|r| r.block) else {
        return;
    };
    let s = chip.engine.s;
    let ref_tick = if s.sends_mst() {
        crate::mst::send_mst(chip, tick)
    } else if s.is_sercos_slave() {
        // A slave's blocks start with the MST it receives (crate::mst).
        return;
    } else {
        tick
    };
    chip.tp.pending_block_at = Due::at(ref_tick);
    chip.tp.pending_block_no = block;
}

/// Processes one event due at `tick` (the earliest the processor has); returns the tick of
/// the last event processed: `tick`, or the end of a received telegram started here whose
/// end the loop would have taken next at once (`chain`, `receive::frame_start`); and, after
/// such a joined end, the processor's next tick as [`next_tick`] would find it (`Some`,
/// found from the other events' tick and the receive queue), `None` when the caller must
/// find it.
// Inlined into `Chip::advance_to`, its one call (release).
#[inline(always)]
pub(crate) fn step(chip: &mut Chip, tick: u64, chain: &Chain) -> (u64, Option<Due>) {
    // What happened before this tick and was no event of its own goes first, as at its
    // own tick (those at this tick come in the order below).
    if let Some(before) = tick.checked_sub(1) {
        let _ = apply_quiet_events(chip, before);
    }
    if chip.tp.tx_end.is(tick) {
        transmit::end(chip, tick);
        return (tick, None);
    }
    let (end, now, others) = if chip.tp.rx_now.as_ref().is_some_and(|r| r.end_tick == tick) {
        let Some(now) = chip.tp.rx_now.take() else {
            return (tick, None);
        };
        (tick, now, None)
    } else if first_frame_tick(chip) == Some(tick) {
        // A telegram whose end is the next event is ended here: the step at its end takes
        // the quiet events before it first, as above (debug builds compare with the two
        // steps, `Chip::advance_to`).
        let Some((now, others)) = receive::frame_start(chip, tick, chain) else {
            return (tick, None);
        };
        let end = now.end_tick;
        if let Some(before) = end.checked_sub(1) {
            let _ = apply_quiet_events(chip, before);
        }
        (end, now, Some(others))
    } else {
        step_rest(chip, tick);
        return (tick, None);
    };
    receive::frame_end(chip, end, now);
    // After a joined frame the processor's next tick is the earlier of its other events
    // (`rx_end_is_next`: left as they were) and the next queued frame's start.
    let next = others.map(|o| o.min(Due::from_option(first_frame_tick(chip))));
    debug_assert!(
        next.is_none_or(|n| n.get() == next_tick(chip)),
        "joined frame's next tick"
    );
    (end, next)
}

/// [`step`]'s events after the receiver's: a block's start, the MST deadline, the current
/// header's.
#[inline]
fn step_rest(chip: &mut Chip, tick: u64) {
    if chip.tp.pending_block_at.is(tick) {
        chip.tp.pending_block_at = Due::NONE;
        start_pending_block(chip, tick, chip.tp.pending_block_no);
        return;
    }
    if chip.tp.mst.deadline.is(tick) {
        crate::mst::deadline(chip, tick);
        return;
    }
    // Only the current header (the block carries a 256-byte bitmap: not copied).
    let Some(b) = chip.tp.block.as_ref() else {
        return;
    };
    match b.cur {
        Some(Cur::Tx { at, hdr, start }) if start == tick => transmit::start(chip, tick, at, hdr),
        Some(Cur::Rx {
            at,
            hdr,
            open,
            close,
            ..
        }) => {
            // The window opens at this tick (after the events above of the same tick, which
            // may have moved on to another header).
            let _ = announce_opened(chip, tick);
            let closes = hdr.tchk() && close == tick;
            if closes && held_in_window(chip, tick) {
                return;
            }
            if closes {
                receive::missing(chip, at, hdr);
                advance(chip, tick, hdr.pt);
            } else if open != tick {
                // Defensive: an event in the past cannot be processed any more.
                abort_block(chip, tick);
            }
        }
        Some(Cur::End { at, ready }) if ready == tick => end_marker(chip, tick, at),
        _ => abort_block(chip, tick),
    }
}

/// At the close of the current receive window (tick `close`), whether a frame that started in
/// it waits for the frame in progress to end (`first_frame_tick`): then the window closes at
/// that end instead, after the held start, which is judged against the window at its own tick
/// (`receive::frame_start`; 410B §4.2.1 TCHK: a telegram that started in its window is not
/// missing; spec-notes "A frame starts once the frame in progress has ended").
#[cold]
#[inline(never)]
fn held_in_window(chip: &mut Chip, close: u64) -> bool {
    let Some(end) = chip.tp.rx_now.as_ref().map(|r| r.end_tick) else {
        return false;
    };
    if chip.tp.rx_queue.front().is_none_or(|(k, _)| *k > close) {
        return false;
    }
    if let Some(Block {
        cur: Some(Cur::Rx { close: c, .. }),
        ..
    }) = chip.tp.block.as_mut()
    {
        *c = end.max(close);
    }
    true
}

/// Applies, in their order, the events due at or before `tick` that were no events of
/// their own because no enabled interrupt output carries their flag
/// (`Settings::int_out_lo`): the end of the telegram being sent, the opening of the
/// current receive window, the end marker. Nothing can see them before the processor's
/// next event or a bus access, which apply them first with the values they had at their
/// ticks (spec-notes "Events nobody sees at once").
/// Returns whether it applied any.
pub(crate) fn apply_quiet_events(chip: &mut Chip, tick: u64) -> bool {
    let mut applied = false;
    // One comparison (`Due::due_by`).
    if chip.tp.tx_end.due_by(tick) {
        transmit::end(chip, chip.tp.tx_end.raw());
        applied = true;
    }
    applied |= announce_opened(chip, tick);
    // The current header matched in place, not copied out.
    if let Some(Block {
        cur: Some(Cur::End { at, ready }),
        ..
    }) = chip.tp.block
        && ready <= tick
    {
        end_marker(chip, ready, at);
        applied = true;
    }
    applied
}

/// Whether the end of a received telegram at tick `e`, started at this step, is the
/// processor's next event (what [`next_tick`] would find once the frame is in progress,
/// with the frame's end first among the events of its tick, as [`step`] takes them): no
/// other event of the processor comes before `e`, and no telegram's end is at `e` (`step`
/// takes it first); the end marker is not current (its quiet event reads the frame in
/// progress, `busy_until`). Then returns the processor's other next tick
/// ([`TelegramProcessor::next_tick_but_rx`]), which the frame's end leaves as it is: the
/// quiet events before it apply a telegram's end that is no event (not counted) or open a
/// receive window that is none (its close counts either way), and the end itself changes
/// no header, block or MST state.
#[inline]
pub(crate) fn rx_end_is_next(chip: &Chip, e: u64) -> Option<Due> {
    let tp = &chip.tp;
    if tp.tx_end.is(e)
        || matches!(
            tp.block,
            Some(Block {
                cur: Some(Cur::End { .. }),
                ..
            })
        )
    {
        return None;
    }
    let others = tp.next_due_but_rx(chip.engine.s.int_out_lo);
    // None (`u64::MAX`) is at or after every tick.
    (others.raw() >= e).then_some(others)
}

/// Whether an event [`apply_quiet_events`] applies may be pending (a transmit telegram
/// being sent, a receive window not yet opened, the end marker current).
pub(crate) fn has_quiet_events(chip: &Chip) -> bool {
    chip.tp.tx_end.is_some()
        || matches!(
            chip.tp.block,
            Some(Block {
                cur: Some(
                    Cur::Rx {
                        announced: false,
                        ..
                    } | Cur::End { .. }
                ),
                ..
            })
        )
}

/// Opens the receive window of the current header if it opened at or before `tick` and
/// is not open yet: 410B §4.1 4H.12 INT_RWAIT "start waiting for receive telegram", 3H.10
/// FLRWAIT, 23H/24H THWPT/THW (the telegram that is expected), the header word as it is
/// then (the processor writes it only in its own events; a host write applies the
/// opening first).
/// Returns whether it did.
fn announce_opened(chip: &mut Chip, tick: u64) -> bool {
    // Read and flagged in place: the current header is not copied out and back.
    let Some(Block {
        cur:
            Some(Cur::Rx {
                at,
                open,
                announced: announced @ false,
                ..
            }),
        ..
    }) = chip.tp.block.as_mut()
    else {
        return false;
    };
    if *open > tick {
        return false;
    }
    *announced = true;
    let at = *at;
    chip.tp.flrwait = true;
    chip.tp.thwpt = at;
    chip.tp.thw = walk::word(&chip.ram, u32::from(at)).unwrap_or(0);
    chip.engine.flags.raise_lo(INT_RWAIT);
    true
}

fn set_cur(chip: &mut Chip, cur: Option<Cur>) {
    if let Some(b) = chip.tp.block.as_mut() {
        b.cur = cur;
    }
}

/// [`start_block`] out of line, for a block that starts at the end of the chip's own MST or
/// at its cycle start (`on_cycle_start`, [`step`]'s pending block): the master's.
#[inline(never)]
fn start_pending_block(chip: &mut Chip, tick: u64, block: u8) {
    start_block(chip, tick, block);
}

/// Starts processing transmission block `block` at `tick` (the end of the MST).
// 410B §4.1 0CH.2-3 COMBLK0/1, §4.2 COMPT0-1 "Start of transmission blocks 0-1".
// Inlined into a slave's MST end (`crate::mst::mst_end`), with the first header's load; out
// of line for the master's step (`start_pending_block`): docs/performance.md, session 30.
#[inline(always)]
pub(crate) fn start_block(chip: &mut Chip, tick: u64, block: u8) {
    if chip.tp.block.is_some() {
        // The previous block has not reached its end marker: its telegrams overlap the
        // next cycle's.
        prog_error(chip, ProgErr::Overlap);
        abort_block(chip, tick);
    }
    // A layout proof made for the other block's list only (410B §4.1 0CH.2 COMBLK0, 0CH.3:
    // the registers choose a cycle's block) does not know what this block's processing
    // writes (a service container wrapping over the pointer words, §4.2.4, say): it is
    // made afresh (found by fuzz target chip_ram_line: block 1 ran between a proof for block
    // 0 and its next use, and its aborted receive header's service container wrote COMPT0).
    if let Some((_, proved)) = chip.layout.get()
        && proved & (1 << (block & 1)) == 0
    {
        chip.set_layout(None);
    }
    let stamp = chip.tp.visits.start();
    chip.tp.block = Some(Block {
        block,
        ref_tick: tick,
        cur: None,
        steps: 0,
        last_end: tick,
        stamp,
        #[cfg(debug_assertions)]
        shadow: Visited::EMPTY,
    });
    let compt = walk::word(&chip.ram, u32::from(block & 1)).unwrap_or(0);
    load(chip, tick, compt);
}

/// Ends the block in progress early: a receive telegram still expected counts as missing.
pub(crate) fn abort_block(chip: &mut Chip, _tick: u64) {
    chip.tp.irregular = chip.tp.irregular.wrapping_add(1);
    if let Some(b) = chip.tp.block.take()
        && let Some(Cur::Rx { at, hdr, .. }) = b.cur
    {
        receive::missing(chip, at, hdr);
    }
    chip.tp.flrwait = false;
    chip.tp.fifo.tx_want = 0;
}

/// Moves on to the header at `pt` at `tick`.
// Inlined into its callers (a receive window's close in `step_rest`, a telegram's end):
// one call less per header (helper slaveadv2, session 33).
#[inline(always)]
pub(crate) fn advance(chip: &mut Chip, tick: u64, pt: u16) {
    load(chip, tick, pt);
}

/// The header the processor moves to cannot be processed (a programming error, 17H
/// PROGERR_FL): the block ends at `tick`. The header before it is done with — its telegram
/// started (the next header is read at a telegram's start, 816 §2.10.1.2) or its window
/// closed and counted it missing — so it is no receive telegram still expected: 410B §4.2.1
/// NERR counts a missing telegram once (and RERR, 5H.8 INT_RMISS, a service container's
/// RECERR likewise follow it once), not again at the block's end.
#[cold]
fn abort_loading(chip: &mut Chip, tick: u64) {
    set_cur(chip, None);
    abort_block(chip, tick);
}

/// Reads the header at `ptr` (410B §4.2.1 PT: "Word address within the RAM of the next
/// telegram header or the end marker") and makes it current.
// Inlined into `advance`, `start_block` and `transmit::start`: one call less per header (performance.md
// "loadcur"), a receive header's decoding with it (`load_rx`).
#[inline(always)]
fn load(chip: &mut Chip, tick: u64, ptr: u16) {
    let limit = max_steps(chip);
    let Some(b) = chip.tp.block.as_mut() else {
        return;
    };
    b.steps += 1;
    let steps = b.steps;
    let ref_tick = b.ref_tick;
    let stamp = b.stamp;
    chip.tp.flrwait = false;
    if steps > limit {
        // A list that never reaches its end marker loops.
        prog_error(chip, ProgErr::NoEndMarker);
        abort_loading(chip, tick);
        return;
    }
    let variant = chip.cfg.variant;
    let ptr = ptr & variant.pointer_mask();
    #[cfg(debug_assertions)]
    let shadow = chip.tp.block.as_mut().is_some_and(|b| b.shadow.mark(ptr));
    debug_assert_ne!(stamp, 0, "a block started without a stamp");
    let seen = chip.tp.visits.mark(stamp, ptr);
    #[cfg(debug_assertions)]
    debug_assert_eq!(seen, shadow, "the visit stamps against the block's own set");
    if seen {
        // A header reached twice in one block: the list loops and never reaches its end
        // marker (410B §4.2.1 PT). Found at once, so a loop costs one pass over its headers.
        prog_error(chip, ProgErr::NoEndMarker);
        abort_loading(chip, tick);
        return;
    }
    let words = match walk::header_words(&chip.ram, variant, ptr) {
        Ok(w) => w,
        Err(e) => {
            prog_error(chip, e);
            abort_loading(chip, tick);
            return;
        }
    };
    // Each kind decoded and stored by its own function: one arm's fields are not merged
    // with the other's on the way to `b.cur` (performance.md "loadcur").
    match words {
        walk::HeaderWords::Transmit(w) => load_tx(chip, tick, ptr, ref_tick, w),
        walk::HeaderWords::Receive(w) => load_rx(chip, tick, ptr, ref_tick, w),
        // Processed once the block's last telegram has ended (`end_marker`): no turn
        // before that.
        walk::HeaderWords::End => {
            let ready = busy_until(chip, tick).unwrap_or(tick);
            set_cur(chip, Some(Cur::End { at: ptr, ready }));
        }
    }
}

/// The tick `us` µs after `ref_tick` (the end of the MST), saturating.
fn at_us(chip: &Chip, ref_tick: u64, us: u64) -> u64 {
    ref_tick.saturating_add(us.saturating_mul(chip.engine.pre.period()))
}

/// Makes the transmit header at `ptr` (its words `w`) current (`load`).
#[inline(never)]
fn load_tx(chip: &mut Chip, tick: u64, ptr: u16, ref_tick: u64, w: [u16; 4]) {
    // 410B §4.2.1 transmit header; the kind was classified by `header_words`, so it
    // decodes (word 0 kept whole, `TxHead`).
    let hdr = TxHead::from_words(chip.cfg.variant, w);
    #[cfg(debug_assertions)]
    {
        let general = sercon_regs::ram::header::TxHeader::from_words(chip.cfg.variant, w);
        debug_assert!(
            general.is_ok_and(|g| g.to_words(chip.cfg.variant)[0] == hdr.w0
                && (g.pt, g.tlen) == (hdr.pt, hdr.tlen)
                && (g.adr, g.dma, g.dbuf, g.val, g.en)
                    == (hdr.adr(), hdr.dma(), hdr.dbuf(), hdr.val(), hdr.en())),
            "load_tx: TxHead differs from TxHeader"
        );
    }
    // 410B §4.2.1 TRT: "Time for the start of telegram in µs after the end of MST".
    let start = at_us(chip, ref_tick, u64::from(w[1]));
    let start = if start < tick {
        // Due before its header was reached: the telegrams overlap in time.
        prog_error(chip, ProgErr::Overlap);
        tick
    } else {
        start
    };
    transmit::prepare(chip, ptr, &hdr);
    set_cur(
        chip,
        Some(Cur::Tx {
            at: ptr,
            hdr,
            start,
        }),
    );
}

/// Makes the receive header at `ptr` (its words `w`) current (`load`).
// Inlined into `load` (session 26 measured it out of line as cheaper; with a slave's block
// start inlined into its MST's end and the master's AT headers loaded in `advance`, inline
// is −0.4 % on ring-8 and −0.5 % on ring-254: docs/performance.md, session 30).
#[inline(always)]
fn load_rx(chip: &mut Chip, tick: u64, ptr: u16, ref_tick: u64, w: [u16; 5]) {
    // 410B §4.2.1 receive header; the kind was classified by `header_words`, so it
    // decodes (word 0 kept whole, `RxHead`).
    let hdr = RxHead::from_words(chip.cfg.variant, w);
    #[cfg(debug_assertions)]
    {
        let general = sercon_regs::ram::header::RxHeader::from_words(chip.cfg.variant, w);
        debug_assert!(
            general.is_ok_and(|g| g.to_words(chip.cfg.variant)[0] == hdr.w0
                && g.pt == hdr.pt
                && g.tlen == hdr.tlen
                && (g.adr, g.dma, g.dbuf, g.val, g.achk, g.tchk, g.rerr)
                    == (
                        hdr.adr(),
                        hdr.dma(),
                        hdr.dbuf(),
                        hdr.val(),
                        hdr.achk(),
                        hdr.tchk(),
                        hdr.rerr()
                    ))
        );
    }
    let trt = u64::from(w[1]);
    let (open, close) = if hdr.tchk() {
        // 410B §4.2.1 TCHK with §4.1 18H/19H JTRDEL1/2, the receive window
        // (spec-notes "receive window"): TRT − JTRDEL1 ..= TRT + JTRDEL2.
        let j1 = u64::from(chip.engine.regs.stored(Register::Jtrdel1));
        let j2 = u64::from(chip.engine.regs.stored(Register::Jtrdel2));
        (
            at_us(chip, ref_tick, trt.saturating_sub(j1)).max(tick),
            at_us(chip, ref_tick, trt.saturating_add(j2)).max(tick),
        )
    } else {
        (tick, 0)
    };
    set_cur(
        chip,
        Some(Cur::Rx {
            at: ptr,
            hdr,
            open,
            close,
            announced: false,
        }),
    );
}

/// The end marker is current at `tick`: the block ends once its last telegram has.
// 410B §4.2.3 TEND: "Time after end of MST at which the last telegram has ended (in µs)".
fn end_marker(chip: &mut Chip, tick: u64, at: u16) {
    if let Some(later) = busy_until(chip, tick) {
        set_cur(chip, Some(Cur::End { at, ready: later }));
        return;
    }
    let Some(b) = chip.tp.block.take() else {
        return;
    };
    let tend = chip
        .engine
        .pre
        .periods_begun_in(b.last_end.saturating_sub(b.ref_tick));
    walk::set_word(
        &mut chip.ram,
        u32::from(at) + 1,
        u16::try_from(tend).unwrap_or(u16::MAX),
    );
    output_bound::status_written(chip, u32::from(at) + 1, 1);
    // 410B §4.1 4H.4 INT_COMEND "end of transmission block"; 3H.6 COMACT falls.
    chip.engine.flags.raise_lo(INT_COMEND);
}

/// When the block's last telegram ends, if one is still being sent or received after
/// `tick` (410B §4.2.3 TEND: the block ends with its last telegram).
fn busy_until(chip: &Chip, tick: u64) -> Option<u64> {
    let busy_tx = chip.tp.tx_end.get().filter(|t| *t > tick);
    let busy_rx = chip
        .tp
        .rx_now
        .as_ref()
        .filter(|r| matches!(r.role, RxRole::Telegram { .. }) && r.end_tick > tick)
        .map(|r| r.end_tick);
    busy_tx.max(busy_rx)
}

/// Whether a block is being processed (3H.6 COMACT) and which (3H.7 COMBLK).
pub(crate) fn comact(chip: &Chip) -> Option<u8> {
    chip.tp.block.map(|b| b.block)
}

/// Sends `chip.tp.txbuf` on the line at `at`; the instant after its closing flag.
pub(crate) fn send_line(chip: &mut Chip, at: Instant) -> Option<Instant> {
    line_out::send(chip, at)
}

/// The RAM word at `addr` (0 outside the RAM).
pub(crate) fn ram_word(chip: &Chip, addr: u16) -> u16 {
    walk::word(&chip.ram, u32::from(addr)).unwrap_or(0)
}

/// Writes the RAM word at `addr` (nothing outside the RAM).
pub(crate) fn set_ram_word(chip: &mut Chip, addr: u16, value: u16) {
    walk::set_word(&mut chip.ram, u32::from(addr), value);
    output_bound::ram_written(chip, u32::from(addr), 1);
}

#[cfg(test)]
mod tests {
    use super::*;
    use sercon_regs::Variant;
    use sercon_regs::ram::header::TxHeader;

    /// The visit stamps answer as a set of reached addresses per block would (`Visited`, the
    /// set they replace): a block reaches an address once, a new block has reached none of
    /// its predecessors' addresses, a block not started (stamp 0) none, and after every
    /// number was used the stamps start afresh.
    #[test]
    fn visit_stamps_are_a_set_per_block() {
        let mut v = Visits::default();
        let check = |v: &mut Visits, addrs: &[u16]| {
            let stamp = v.start();
            assert_ne!(stamp, 0);
            let mut set = Visited::EMPTY;
            for &a in addrs {
                let mut ahead = set;
                assert_eq!(v.reached(stamp, a), ahead.mark(a), "{a}");
                assert_eq!(v.mark(stamp, a), set.mark(a), "{a}");
                assert!(v.reached(stamp, a));
                assert!(!v.reached(0, a), "a block not started reached {a}");
            }
        };
        let list = [16, 31, 40, 16, 2047, 0, 31];
        assert!(
            !v.reached(0, 16) && !v.reached(0, 1000),
            "a block not started reached"
        );
        // Marking twice in one block is seen; the next block starts with none reached.
        let stamp = v.start();
        assert!(!v.mark(stamp, 16));
        assert!(v.mark(stamp, 16));
        let next = v.start();
        assert!(
            !v.reached(next, 16),
            "a new block reached its predecessor's address"
        );
        assert!(!v.mark(next, 16));
        check(&mut v, &list);
        check(&mut v, &list);
        // Addresses count modulo 2048, as the set's bits did.
        let stamp = v.start();
        let mut set = Visited::EMPTY;
        for a in [5u16, 2048 + 5, 4095, 2047] {
            assert_eq!(v.mark(stamp, a), set.mark(a), "{a}");
        }
        // Every number used: a stamp left from before cannot make the new block's.
        v.last = Stamp::MAX - 1;
        let old = v.start();
        assert_eq!(old, Stamp::MAX);
        v.mark(old, 100);
        v.stamps[200] = 1;
        let wrapped = v.start();
        assert_eq!(wrapped, 1);
        assert!(
            !v.reached(wrapped, 200),
            "a stamp from before the numbers wrapped"
        );
        assert!(!v.mark(wrapped, 100));
        assert!(!v.mark(wrapped, 200));
    }

    /// The one-byte stamps wrap every 255 blocks: over several wraps, each block's stamps
    /// answer as a set of its own would, with addresses that earlier blocks (before and
    /// after a wrap) reached.
    #[test]
    fn visit_stamps_stay_a_set_per_block_across_wraps() {
        let mut v = Visits::default();
        let blocks = 4 * usize::from(Stamp::MAX) + 7;
        for n in 0..blocks {
            let stamp = v.start();
            assert_ne!(stamp, 0);
            let mut set = Visited::EMPTY;
            // A few addresses shared by every block, a few of this block's own, each twice.
            let own = u16::try_from(n % 2048).unwrap_or(0);
            for a in [16, own, 2047, own.wrapping_mul(7) % 2048, 16, own] {
                let mut ahead = set;
                assert_eq!(v.reached(stamp, a), ahead.mark(a), "block {n} {a}");
                assert_eq!(v.mark(stamp, a), set.mark(a), "block {n} {a}");
                assert!(v.reached(stamp, a), "block {n} {a}");
            }
        }
    }

    /// Every transmit header word 0 (marker 01, 410B §4.2.1) with the other words of a few
    /// kinds: what `TxHead` reads and writes in place is what decoding the header into
    /// `TxHeader`, changing the field and encoding it again gives.
    #[test]
    fn tx_word0_in_place_is_the_decoded_header() {
        for variant in Variant::ALL {
            for w0 in 0x4000..0x8000u16 {
                for (tlen, w3) in [(0, 0), (3, 0x0123), (0xFFFF, 0xFFFF)] {
                    let words = [w0, 17, tlen, w3];
                    let Ok(g) = TxHeader::from_words(variant, words) else {
                        panic!("{w0:#06x} is a transmit header");
                    };
                    let h = TxHead::from_words(variant, words);
                    assert_eq!(
                        (h.adr(), h.dma(), h.dbuf(), h.val(), h.en()),
                        (g.adr, g.dma, g.dbuf, g.val, g.en),
                        "{w0:#06x}"
                    );
                    assert_eq!((h.tlen, h.pt, h.buffering()), (g.tlen, g.pt, g.buffering()));
                    let word0 = |g: TxHeader| g.to_words(variant)[0];
                    assert_eq!(h.w0, word0(g));
                    for b in [false, true] {
                        assert_eq!(h.with_val(b).w0, word0(TxHeader { val: b, ..g }));
                    }
                    for en in [
                        TxEnable::Off,
                        TxEnable::Once,
                        TxEnable::Continuous,
                        TxEnable::OnAddress,
                    ] {
                        assert_eq!(h.with_en(en).w0, word0(TxHeader { en, ..g }));
                    }
                }
            }
        }
    }

    /// Frames queued out of order, with pops, take-backs and a reset (which keeps the
    /// queue, the bound back at its default) in between, end in the order of their starts
    /// (equal starts in the order they came), as the queue without its bound orders them
    /// (`on_rx_frame`: the bound's short way and the look at the last entry decide alike).
    #[test]
    fn the_receive_queue_stays_in_order_with_its_bound() {
        use crate::serial_port::HeardFrame;
        let frame = |start: u64, n: u8| HeardFrame {
            start: Instant::from_picos(start),
            end: Instant::from_picos(start + 1),
            bytes: std::rc::Rc::from(vec![n]),
            fcs_ok: true,
        };
        // (start, what happens first: 0 nothing, 1 a pop, 2 a reset, 3 the last removed).
        let steps: [(u64, u8); 14] = [
            (10, 0),
            (30, 0),
            (20, 0),
            (20, 1),
            (5, 0),
            (40, 3),
            (35, 0),
            (25, 2),
            (50, 0),
            (45, 1),
            (45, 0),
            (60, 3),
            (55, 2),
            (1, 0),
        ];
        let mut tp = TelegramProcessor::default();
        let mut model: Vec<(u64, u8)> = Vec::new();
        for (n, &(start, before)) in (0u8..).zip(steps.iter()) {
            match before {
                1 => {
                    tp.rx_queue.pop_front();
                    if !model.is_empty() {
                        model.remove(0);
                    }
                }
                2 => {
                    let queued = std::mem::take(&mut tp.rx_queue);
                    tp = TelegramProcessor::default();
                    tp.rx_queue = queued;
                }
                3 => {
                    tp.rx_queue.pop_back();
                    model.pop();
                }
                _ => {}
            }
            tp.on_rx_frame(start, frame(start, n));
            let at = model.partition_point(|(s, _)| *s <= start);
            model.insert(at, (start, n));
            let queued: Vec<(u64, u8)> = tp
                .rx_queue
                .iter()
                .map(|(t, f)| (*t, f.bytes.first().copied().unwrap_or(0)))
                .collect();
            assert_eq!(queued, model, "after frame {n} at {start}");
        }
    }
}
