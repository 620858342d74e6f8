//! Trace wiring: what crosses a segment becomes [`TraceRecord`]s, kept until simulated time
//! has passed them (the fast path knows arrivals ahead of time) and then written in time
//! order to the log, the capture and the hash; pin events go to a VCD at the end.

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

use sercon_model::pins::PinEvent;
use sercon_model::serial_port::{LineSegment, LineSignal, Shared};
use sercon_model::vcd_trace::{Timescale, TracedChip, write_vcd};
use sercos_wire::line::{BitVec, Coding, Decoded, Decoder, LineConfig, LineError, Polarity};
use sercos_wire::telegram::Origin;
use sercos_wire::time::{BitRate, Instant};

use crate::config::{CaptureFormat, TraceConfig};
use crate::error::SimError;
use crate::trace::{
    LogFormat, PcapNgTrace, PcapTrace, SegmentId, TelegramLog, TraceHash, TraceHasher, TraceRecord,
    TraceSink,
};

/// What a run's traces hold at its end.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TraceOutput {
    /// The telegram log (empty when off).
    pub log: Vec<u8>,
    /// The capture file (empty when off).
    pub capture: Vec<u8>,
    /// The VCD file (empty when off).
    pub vcd: Vec<u8>,
    /// The hash over the records, when on.
    pub hash: Option<TraceHash>,
    /// Records written to the log and the hash.
    pub records: u64,
}

#[derive(Debug, Clone)]
enum What {
    Telegram(Shared<[u8]>),
    Error(LineError, Vec<u8>),
}

#[derive(Debug, Clone)]
struct Pending {
    time: u64,
    /// Written no earlier than this (ps): the end of the bits it was decoded from, which a
    /// segment entering the fibre before then may still cut ([`Recorder::observe`]).
    safe: u64,
    segment: u16,
    seq: u64,
    origin: Origin,
    bit_rate: Option<BitRate>,
    what: What,
}

impl PartialEq for Pending {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Pending {}
impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Pending {
    fn cmp(&self, other: &Self) -> Ordering {
        (self.time, self.segment, self.seq).cmp(&(other.time, other.segment, other.seq))
    }
}

/// The capture writer in use.
enum Capture {
    Pcap(PcapTrace<Vec<u8>>),
    PcapNg(PcapNgTrace<Vec<u8>>),
}

/// Collects and writes the traces of one run.
pub(crate) struct Recorder {
    cfg: TraceConfig,
    pending: BinaryHeap<Reverse<Pending>>,
    seq: u64,
    log: Option<TelegramLog<Vec<u8>>>,
    capture: Option<Capture>,
    hasher: Option<TraceHasher>,
    records: u64,
    /// Per traced chip: header and events (simulation time).
    vcd: Vec<(TracedChip, Vec<PinEvent>)>,
    /// Records from this instant (ps) on are kept even once simulated time has passed them:
    /// the RS-485 bus may still garble them ([`Recorder::hold_from`]).
    hold: u64,
    /// Per traced segment (index: its id), the last telegram bits that entered it, while a
    /// segment starting inside them may still cut them.
    entered: Vec<Option<Entered>>,
}

/// Bits that entered a segment, and whose they are.
#[derive(Debug, Clone)]
struct Entered {
    seg: LineSegment,
    origin: Origin,
}

impl Recorder {
    pub(crate) fn new(cfg: TraceConfig) -> Result<Self, SimError> {
        let capture = match cfg.capture {
            Some((seg, CaptureFormat::Pcap)) => {
                Some(Capture::Pcap(PcapTrace::new(Vec::new(), Some(seg))?))
            }
            Some((seg, CaptureFormat::PcapNg)) => {
                Some(Capture::PcapNg(PcapNgTrace::new(Vec::new(), Some(seg))?))
            }
            None => None,
        };
        Ok(Recorder {
            log: cfg.log.map(|f| TelegramLog::new(Vec::new(), f)),
            hasher: cfg.hash.then(TraceHasher::new),
            capture,
            cfg,
            pending: BinaryHeap::new(),
            seq: 0,
            records: 0,
            vcd: Vec::new(),
            hold: u64::MAX,
            entered: Vec::new(),
        })
    }

    /// Adds a chip to the VCD; returns its index there.
    pub(crate) fn add_vcd_chip(&mut self, chip: TracedChip) -> usize {
        self.vcd.push((chip, Vec::new()));
        self.vcd.len() - 1
    }

    /// Records a pin event (at simulation time) of VCD chip `index`.
    pub(crate) fn pin_event(&mut self, index: usize, event: PinEvent) {
        if let Some((_, evs)) = self.vcd.get_mut(index) {
            evs.push(event);
        }
    }

    /// Whether records on `segment` are wanted at all.
    pub(crate) fn wants(&self, segment: usize) -> bool {
        let Ok(s) = u16::try_from(segment) else {
            return false;
        };
        let logged = (self.log.is_some() || self.hasher.is_some())
            && self.cfg.log_segment.is_none_or(|l| l.0 == s);
        let captured = self.cfg.capture.is_some_and(|(c, _)| c.0 == s);
        logged || captured
    }

    /// `seg` entered `segment` (simulation time): its telegrams and frames in error. Bits
    /// that start inside the bits that entered before cut them there (a repeater's own
    /// telegram over one it repeats, 410B §1): their records are replaced by what the line
    /// then carried ([`Recorder::cut_entered`]). A steady signal (a fault's darkness or
    /// light) leaves them as they entered: the receivers' diagnostics report that cut
    /// (spec-notes "Repeater collisions", "Trace times").
    pub(crate) fn observe(&mut self, segment: usize, seg: &LineSegment, origin: Origin) {
        if !self.wants(segment) {
            return;
        }
        let Ok(id) = u16::try_from(segment) else {
            return;
        };
        if matches!(seg.signal, LineSignal::Bits(_))
            && self
                .entered
                .get(segment)
                .and_then(Option::as_ref)
                .is_some_and(|e| {
                    seg.start >= e.seg.start && e.seg.end().is_some_and(|end| seg.start < end)
                })
        {
            self.cut_entered(segment, id, seg, origin);
            return;
        }
        self.observe_fresh(segment, id, seg, origin);
    }

    /// [`Recorder::observe`] of a segment that cuts nothing.
    fn observe_fresh(&mut self, segment: usize, id: u16, seg: &LineSegment, origin: Origin) {
        if self.entered.len() <= segment {
            self.entered.resize(segment + 1, None);
        }
        let LineSignal::Bits(bits) = &seg.signal else {
            if let Some(e) = self.entered.get_mut(segment) {
                *e = None;
            }
            return;
        };
        let bit_rate = bit_rate_of(seg);
        let bt = seg.bit_time;
        let safe = seg.end().unwrap_or(seg.start).as_picos();
        let at = |pos: u64| seg.start.saturating_add(bt.saturating_mul(pos)).as_picos();
        if let Some(hint) = &seg.hint {
            let time = at(hint.offset);
            self.push(
                (time, safe),
                id,
                origin,
                bit_rate,
                What::Telegram(hint.telegram.clone()),
            );
        } else {
            for (pos, what) in decode_bits(seg.level_before, bits) {
                self.push((at(pos), safe), id, origin, bit_rate, what);
            }
        }
        if let Some(e) = self.entered.get_mut(segment) {
            *e = Some(Entered {
                seg: seg.clone(),
                origin,
            });
        }
    }

    /// `seg` entered `segment` inside the bits that entered before (`entered`): their
    /// records are taken back and decoded again as the line carried them up to the cut. Of
    /// the same bit time, that is their bits up to the end of the bit the cut falls in and
    /// `seg`'s bits on from there, decoded as one (as a receiver continues bits cut by a
    /// telegram, `Receiver::resume_cut`: the frame in progress ends at `seg`'s opening
    /// flag, in error); of another, their whole bits up to the cut. `seg`'s own records
    /// then follow at its own times.
    #[cold]
    #[inline(never)]
    fn cut_entered(&mut self, segment: usize, id: u16, seg: &LineSegment, origin: Origin) {
        let Some(prev) = self.entered.get_mut(segment).and_then(Option::take) else {
            return;
        };
        let LineSignal::Bits(prev_bits) = &prev.seg.signal else {
            return;
        };
        self.take_back_from(id, prev.seg.start);
        let bt = prev.seg.bit_time;
        let elapsed = seg
            .start
            .saturating_duration_since(prev.seg.start)
            .as_picos();
        let bt_ps = bt.as_picos().max(1);
        let joined = match &seg.signal {
            LineSignal::Bits(b) if seg.bit_time == bt => Some(b),
            _ => None,
        };
        let whole = if joined.is_some() {
            elapsed.div_ceil(bt_ps)
        } else {
            elapsed / bt_ps
        };
        let whole = usize::try_from(whole).unwrap_or(usize::MAX);
        let mut line = prev_bits
            .bits()
            .slice(0, whole.min(prev_bits.bits().len()))
            .map(BitVec::from_bits)
            .unwrap_or_default();
        if let Some(b) = joined {
            // From the level the line is at (a sender continues from it; NRZI reads an
            // inverted telegram the same, and the receivers take it so, `Simulation::deliver`).
            let invert = seg.level_before != prev.seg.level_at(seg.start);
            for bit in b.bits().iter() {
                line.push(bit != invert);
            }
        }
        let bit_rate = bit_rate_of(&prev.seg);
        for (pos, what) in decode_bits(prev.seg.level_before, &line) {
            let t = prev.seg.start.saturating_add(bt.saturating_mul(pos));
            if t < seg.start {
                // Final: nothing can enter before `seg` any more.
                self.push((t.as_picos(), 0), id, prev.origin, bit_rate, what);
            }
        }
        self.observe_fresh(segment, id, seg, origin);
    }

    /// Keeps the records from `t` on (and every later one) until [`Recorder::hold_from`]
    /// moves on: the RS-485 bus's current transmission may still be garbled by another
    /// driver, and its records then replaced ([`Recorder::observe_again`]).
    pub(crate) fn hold_from(&mut self, t: Instant) {
        self.hold = t.as_picos();
    }

    /// Replaces the records of `segment` from `seg`'s start on (held, [`Recorder::hold_from`])
    /// by what `seg`'s bits decode to, each with the origin `origin_at` gives for its start:
    /// the line of the RS-485 bus since its transmission began, garbled by a second driver.
    #[cold]
    pub(crate) fn observe_again(
        &mut self,
        segment: usize,
        seg: &LineSegment,
        origin_at: impl Fn(Instant) -> Origin,
    ) {
        if !self.wants(segment) {
            return;
        }
        let (Ok(id), LineSignal::Bits(bits)) = (u16::try_from(segment), &seg.signal) else {
            return;
        };
        self.take_back_from(id, seg.start);
        let bit_rate = bit_rate_of(seg);
        for (pos, what) in decode_bits(seg.level_before, bits) {
            let t = seg.start.saturating_add(seg.bit_time.saturating_mul(pos));
            self.push((t.as_picos(), 0), id, origin_at(t), bit_rate, what);
        }
        // The bus's line since its transmission began: what enters next starts after it.
        if let Some(e) = self.entered.get_mut(segment) {
            *e = None;
        }
    }

    /// Drops the records of segment `id` from `from` on, not yet written.
    fn take_back_from(&mut self, id: u16, from: Instant) {
        let from = from.as_picos();
        let kept: Vec<Reverse<Pending>> = std::mem::take(&mut self.pending)
            .into_vec()
            .into_iter()
            .filter(|Reverse(p)| p.segment != id || p.time < from)
            .collect();
        self.pending = kept.into();
    }

    /// Queues a record at `time`, written no earlier than `safe` (ps).
    fn push(
        &mut self,
        (time, safe): (u64, u64),
        segment: u16,
        origin: Origin,
        bit_rate: Option<BitRate>,
        what: What,
    ) {
        self.seq += 1;
        self.pending.push(Reverse(Pending {
            time,
            safe,
            segment,
            seq: self.seq,
            origin,
            bit_rate,
            what,
        }));
    }

    /// Writes the records before `now` (nothing earlier can come any more).
    #[inline(always)]
    pub(crate) fn flush_before(&mut self, now: Instant) -> Result<(), SimError> {
        // Called after every event: the usual answer (nothing due) without a call.
        let bound = now.as_picos().min(self.hold);
        if self
            .pending
            .peek()
            .is_none_or(|Reverse(top)| top.time >= bound || top.safe > now.as_picos())
        {
            return Ok(());
        }
        self.flush_due(bound, now.as_picos())
    }

    /// [`Recorder::flush_before`] when something is due: the records before `bound` (ps)
    /// whose bits can no longer be cut at `now` (ps).
    fn flush_due(&mut self, bound: u64, now: u64) -> Result<(), SimError> {
        while let Some(Reverse(top)) = self.pending.peek() {
            if top.time >= bound || top.safe > now {
                break;
            }
            let Some(Reverse(p)) = self.pending.pop() else {
                break;
            };
            self.write(&p)?;
        }
        Ok(())
    }

    fn write(&mut self, p: &Pending) -> Result<(), SimError> {
        let time = Instant::from_picos(p.time);
        let seg = SegmentId(p.segment);
        let mut rec = match &p.what {
            What::Telegram(b) => TraceRecord::telegram(time, seg, p.origin, b),
            What::Error(e, r) => TraceRecord::line_error(time, seg, p.origin, *e, r),
        };
        if let Some(r) = p.bit_rate {
            rec = rec.with_bit_rate(r);
        }
        if self.cfg.log_segment.is_none_or(|l| l == seg) {
            let mut counted = false;
            if let Some(log) = &mut self.log {
                log.record(&rec)?;
                counted = true;
            }
            if let Some(h) = &mut self.hasher {
                h.record(&rec)?;
                counted = true;
            }
            if counted {
                self.records += 1;
            }
        }
        match &mut self.capture {
            Some(Capture::Pcap(c)) => c.record(&rec)?,
            Some(Capture::PcapNg(c)) => c.record(&rec)?,
            None => {}
        }
        Ok(())
    }

    /// Writes everything up to `end`, the end of the run, and hands the traces over. Records
    /// after it are left out: the fast path knows arrivals ahead of time, the reference path
    /// only what was sent by then, and a trace holds what the line carried during the run.
    pub(crate) fn finish(mut self, end: Instant) -> Result<TraceOutput, SimError> {
        self.flush_due(end.as_picos().saturating_add(1), u64::MAX)?;
        let mut out = TraceOutput {
            records: self.records,
            hash: self.hasher.take().map(TraceHasher::finish),
            ..TraceOutput::default()
        };
        if let Some(log) = self.log.take() {
            out.log = log.finish()?;
        }
        match self.capture.take() {
            Some(Capture::Pcap(c)) => out.capture = c.finish()?,
            Some(Capture::PcapNg(c)) => out.capture = c.finish()?,
            None => {}
        }
        if !self.vcd.is_empty() {
            // Pin changes up to the end only (a chip moved on by its host's access may have
            // recorded some after it).
            let chips: Vec<(TracedChip, &[PinEvent])> = self
                .vcd
                .iter()
                .map(|(c, e)| {
                    let upto = e.partition_point(|p| p.at <= end);
                    (c.clone(), e.get(..upto).unwrap_or(&[]))
                })
                .collect();
            write_vcd(&mut out.vcd, Timescale::Nanoseconds, &chips, end)?;
        }
        Ok(out)
    }
}

/// The bit rate of `seg`'s bit time, if it is one of the line's.
fn bit_rate_of(seg: &LineSegment) -> Option<BitRate> {
    BitRate::ALL
        .into_iter()
        .find(|r| r.bit_time() == seg.bit_time)
}

/// What an explicit bit segment holds (410B §1 NRZI line, light levels from
/// `level_before`): each telegram or frame in error with the bit position of its start.
fn decode_bits(level_before: bool, bits: &BitVec) -> Vec<(u64, What)> {
    let polarity = if level_before {
        Polarity::LightOnLow
    } else {
        Polarity::LightOnHigh
    };
    let mut dec = Decoder::new(LineConfig::new(Coding::Nrzi, polarity));
    let mut found = Vec::new();
    dec.push(bits.bits(), |d| {
        let what = match d {
            Decoded::Telegram(f) => What::Telegram(Shared::from(f.bytes)),
            Decoded::Error { error, received } => What::Error(error, received.to_vec()),
        };
        found.push((d.start(), what));
    });
    found
}

/// The log formats, for callers that name them.
pub fn log_format_name(f: LogFormat) -> &'static str {
    match f {
        LogFormat::Text => "text",
        LogFormat::JsonLines => "json",
    }
}
