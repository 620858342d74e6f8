//! The RS-485 bus of 410B §1 Fig. 4: every node hears every transmission after the bus
//! delay, and a transmission that starts while another is on the bus garbles both
//! (spec-notes "RS-485 bus").
//!
//! The bus keeps the line its drivers made since the current transmission began
//! ([`BusLine`]). A telegram that starts while the line is driven is laid onto it on the
//! line's bit grid, from the first bit boundary at or after its start ([`compose`]): where
//! both drive the same level the line has it, where they differ the line keeps its level
//! (the receivers' fail-safe input holds its output while the differential voltage is
//! near zero), where one drives alone the line is its. The receivers are handed the line
//! from that boundary on, followed by [`IDLE_TAIL_BITS`] of the undriven bus; each receiver
//! takes it as the continuation of the telegram it was receiving (`Chip::line_input`), so
//! that telegram's frame ends as the garbled line makes it end. The telegram log gets the
//! line's frames again from the transmission's start.

use sercon_model::serial_port::{LineSegment, LineSignal};
use sercos_wire::line::{BitVec, Bits};
use sercos_wire::time::{Duration, Instant};

use super::{Simulation, origin_of};

/// Bits of the undriven bus (a steady level: no edges, 410B §1 NRZI data 1s) handed to the
/// receivers after a garbled line: more than the six 1s an HDLC frame may hold, so a frame
/// the garbling left open is aborted within the segment that garbled it.
pub(super) const IDLE_TAIL_BITS: u64 = 16;

/// The line of the bus since its current transmission began.
#[derive(Debug, Clone)]
pub(super) struct BusLine {
    /// The first bit.
    start: Instant,
    bit_time: Duration,
    /// Level before the first bit.
    level_before: bool,
    /// What the drivers put on the bus, one level per bit time.
    drive: BitVec,
    /// What the receivers were handed (faults applied), from `start`, for the telegram log.
    seen: BitVec,
    /// Each driver from the instant its telegram was laid onto the line.
    origins: Vec<(Instant, usize)>,
}

impl BusLine {
    /// The end of the last driven bit.
    pub(super) fn end(&self) -> Instant {
        self.start
            .saturating_add(self.bit_time.saturating_mul(self.drive.len()))
    }
}

/// A telegram laid onto the driven line ([`compose`]).
#[derive(Debug)]
struct Composed {
    /// The line's bit at which the telegram joins it.
    k: u64,
    /// The line from bit `k` on, both drivers combined, until the last driven bit.
    bits: BitVec,
    /// The line's level before bit `k`.
    level_before: bool,
}

/// Lays `x` (light levels from `x_start`, a telegram of the line's bit time) onto `line` from
/// the first bit boundary of the line at or after `x_start` (`None` at another bit time, or
/// when `x` starts before the line). `x`'s bits keep their order from that boundary on: a
/// telegram starting off the line's grid moves by less than one bit time.
fn compose(
    line: &BusLine,
    x_start: Instant,
    x_bit_time: Duration,
    x: Bits<'_>,
) -> Option<Composed> {
    let bt = line.bit_time.as_picos();
    if x_bit_time != line.bit_time || bt == 0 || x_start < line.start {
        return None;
    }
    let k = x_start
        .saturating_duration_since(line.start)
        .as_picos()
        .div_ceil(bt);
    let d = line.drive.bits();
    let dlen = u64::try_from(d.len()).ok()?;
    let xlen = u64::try_from(x.len()).ok()?;
    let level_before = match k.checked_sub(1) {
        Some(i) => d.get(usize::try_from(i).ok()?).unwrap_or(line.level_before),
        None => line.level_before,
    };
    let n = dlen.saturating_sub(k).max(xlen);
    let mut bits = BitVec::with_capacity(usize::try_from(n).unwrap_or(0));
    let mut level = level_before;
    for i in 0..n {
        let a = usize::try_from(k + i).ok().and_then(|j| d.get(j));
        let b = usize::try_from(i).ok().and_then(|j| x.get(j));
        level = match (a, b) {
            (Some(a), Some(b)) if a == b => a,
            // Two drivers against each other: the receivers hold their level.
            (Some(_), Some(_)) => level,
            (Some(v), None) | (None, Some(v)) => v,
            (None, None) => level,
        };
        bits.push(level);
    }
    Some(Composed {
        k,
        bits,
        level_before,
    })
}

/// A telegram that cannot be laid onto the line (another bit time): it alone is garbled,
/// every other bit inverted after its opening flag, so that receivers see a broken frame.
fn garbled_alone(seg: LineSegment, bits: Bits<'_>) -> LineSegment {
    let keep = seg.hint.as_ref().map_or(0, |h| h.offset) + 8;
    let mut g = BitVec::with_capacity(bits.len());
    for (i, b) in bits.iter().enumerate() {
        g.push(b ^ (i as u64 >= keep && i % 2 == 1));
    }
    LineSegment::bits(seg.start, seg.bit_time, g, seg.level_before)
}

/// `prefix`'s first `k` bits followed by every bit of `rest`.
fn joined(prefix: &BitVec, k: u64, rest: Bits<'_>) -> BitVec {
    let head = prefix.bits();
    let k = usize::try_from(k).unwrap_or(usize::MAX).min(head.len());
    let mut out = BitVec::with_capacity(k.saturating_add(rest.len()));
    for b in head.iter().take(k).chain(rest.iter()) {
        out.push(b);
    }
    out
}

impl Simulation {
    /// 410B Fig. 4: the bus carries own telegrams only; overlapping ones are garbled.
    pub(super) fn propagate_bus(&mut self, seg: LineSegment, origin: usize) {
        // Only the telegram: the bus carries no filler.
        let (seg, _) = seg.split_filler();
        let LineSignal::Bits(bits) = &seg.signal else {
            return;
        };
        let bits = bits.clone();
        let Some(s) = self.segments.get_mut(0) else {
            return;
        };
        if s.keep_last {
            s.keep_entered(&seg, origin);
        }
        if s.faults.broken_at(seg.start) {
            return;
        }
        let end = seg.end().unwrap_or(seg.start);
        let mut seg = seg;
        if seg.start < self.bus_busy_until {
            // Two drivers at once.
            self.stats.collisions += 1;
            if let Some(line) = self.bus_line.take()
                && let Some(c) = compose(&line, seg.start, seg.bit_time, bits.bits())
            {
                self.garble(line, c, origin);
                return;
            }
            seg = garbled_alone(seg, bits.bits());
        }
        self.bus_busy_until = self.bus_busy_until.max(end);
        let Some(s) = self.segments.get_mut(0) else {
            return;
        };
        let seg = s.faults.apply(seg);
        let delay = s.delay;
        self.recorder.observe(0, &seg, origin_of(origin));
        self.recorder.hold_from(seg.start);
        self.bus_line = match &seg.signal {
            LineSignal::Bits(seen) => Some(BusLine {
                start: seg.start,
                bit_time: seg.bit_time,
                level_before: seg.level_before,
                drive: BitVec::from_bits(bits.bits()),
                seen: BitVec::from_bits(seen.bits()),
                origins: vec![(seg.start, origin)],
            }),
            _ => None,
        };
        self.hand_to_all(seg.delayed(delay), origin);
    }

    /// Hands the line from the composed telegram's boundary on to every receiver, and the
    /// line since the transmission began to the telegram log.
    #[cold]
    fn garble(&mut self, mut line: BusLine, c: Composed, origin: usize) {
        let at = line.start.saturating_add(line.bit_time.saturating_mul(c.k));
        let mut handed = c.bits.clone();
        let last = handed.bits().get(handed.bits().len().wrapping_sub(1));
        let idle = last.unwrap_or(c.level_before);
        for _ in 0..IDLE_TAIL_BITS {
            handed.push(idle);
        }
        let part = LineSegment::bits(at, line.bit_time, handed, c.level_before);
        let Some(s) = self.segments.get_mut(0) else {
            return;
        };
        let part = s.faults.apply(part);
        let delay = s.delay;
        line.drive = joined(&line.drive, c.k, c.bits.bits());
        if let LineSignal::Bits(b) = &part.signal {
            line.seen = joined(&line.seen, c.k, b.bits());
        }
        line.origins.push((at, origin));
        self.bus_busy_until = self.bus_busy_until.max(line.end());
        let whole = LineSegment::bits(
            line.start,
            line.bit_time,
            line.seen.clone(),
            line.level_before,
        );
        let origins = line.origins.clone();
        self.recorder.observe_again(0, &whole, |t| {
            let o = origins
                .iter()
                .rev()
                .find(|(from, _)| *from <= t)
                .or(origins.first())
                .map_or(0, |(_, o)| *o);
            origin_of(o)
        });
        self.bus_line = Some(line);
        self.hand_to_all(part.delayed(delay), origin);
    }

    /// Delivers `seg` (simulation time, at the receivers) to every node powered then.
    fn hand_to_all(&mut self, seg: LineSegment, origin: usize) {
        for i in 0..self.nodes.len() {
            if self.nodes.get(i).is_some_and(|n| n.powered_at(seg.start)) {
                self.deliver(i, seg.clone(), origin, false);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BT: Duration = Duration::from_picos(62_500);

    fn line(bits: &[bool]) -> BusLine {
        let mut drive = BitVec::new();
        for b in bits {
            drive.push(*b);
        }
        BusLine {
            start: Instant::from_picos(1_000_000),
            bit_time: BT,
            level_before: false,
            seen: drive.clone(),
            drive,
            origins: vec![(Instant::from_picos(1_000_000), 1)],
        }
    }

    fn bits(v: &[bool]) -> BitVec {
        let mut b = BitVec::new();
        for x in v {
            b.push(*x);
        }
        b
    }

    #[test]
    fn a_telegram_joins_at_the_next_bit_boundary_and_agreeing_levels_pass() {
        let l = line(&[true, false, true, true]);
        // Starting a quarter bit into bit 1: joins at bit 2.
        let x = bits(&[true, false, false]);
        let c = compose(
            &l,
            Instant::from_picos(1_000_000 + 62_500 + 15_000),
            BT,
            x.bits(),
        )
        .expect("composes");
        assert_eq!(c.k, 2);
        assert!(!c.level_before);
        // Bit 2: both 1 → 1; bit 3: 1 against 0 → held 1; then x alone: 0.
        assert_eq!(
            c.bits.bits().iter().collect::<Vec<_>>(),
            [true, true, false]
        );
    }

    #[test]
    fn only_the_same_bit_time_and_no_earlier_start_compose() {
        let l = line(&[true, false]);
        let x = bits(&[true]);
        assert!(
            compose(
                &l,
                Instant::from_picos(1_000_000),
                BT.saturating_mul(2),
                x.bits()
            )
            .is_none()
        );
        assert!(compose(&l, Instant::from_picos(999_999), BT, x.bits()).is_none());
        // From the line's own start: the whole line is composed.
        let c = compose(&l, Instant::from_picos(1_000_000), BT, x.bits()).expect("composes");
        assert_eq!(c.k, 0);
        assert_eq!(c.bits.bits().iter().collect::<Vec<_>>(), [true, false]);
    }
}
