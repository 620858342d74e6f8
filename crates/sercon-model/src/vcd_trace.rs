//! Writing traced output pins of one or more chips as a VCD (value change dump) waveform.
//!
//! Every chip becomes one `$scope module` named after it; every traced pin of that chip one
//! 1-bit `wire` named after the pin (the datasheet's name, e.g. `CON_CLK`, 410B §2 Table 1).
//! The initial level of every wire is written at time 0 in a `$dumpvars` block, then the pin
//! events follow in time order.
//!
//! ## Timescale and rounding
//!
//! Simulated time is integer picoseconds (DESIGN.md). A VCD file counts time in whole units of
//! its timescale: [`Timescale::Picoseconds`] is exact; with [`Timescale::Nanoseconds`] or
//! [`Timescale::Microseconds`] an instant that is not a whole number of units (one bit at
//! 16 Mbit/s is 62.5 ns) is **rounded to the nearest unit, halves rounded up** (62.5 ns →
//! 63 ns). Rounding is monotonic, so the order of edges is kept; two edges of one pin that
//! round to the same unit are both written and a viewer shows the later level.
//!
//! ```
//! use sercon_model::pins::{Pin, PinEvent, PinSet};
//! use sercon_model::vcd_trace::{Timescale, TracedChip, VcdWriter};
//! use sercos_wire::time::Instant;
//!
//! let chip = TracedChip::new("master", PinSet::of(&[Pin::ConClk]), |_| false)?;
//! let mut out = Vec::new();
//! let mut vcd = VcdWriter::new(&mut out, Timescale::Nanoseconds, &[chip])?;
//! vcd.record(0, &PinEvent { at: Instant::from_picos(62_500), pin: Pin::ConClk, level: true })?;
//! vcd.finish(Instant::from_picos(1_000_000))?;
//! assert!(String::from_utf8_lossy(&out).contains("#63"));
//! # Ok::<(), sercon_model::vcd_trace::VcdTraceError>(())
//! ```

use std::io::Write;

use sercos_wire::time::Instant;
use vcd::{IdCode, SimulationCommand, TimescaleUnit, Value};

use crate::pins::{Pin, PinEvent, PinSet};

/// The time unit of a VCD file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Timescale {
    /// 1 ps: every simulated instant is exact.
    Picoseconds,
    /// 1 ns: instants are rounded to the nearest nanosecond (halves up).
    #[default]
    Nanoseconds,
    /// 1 µs: instants are rounded to the nearest microsecond (halves up).
    Microseconds,
}

impl Timescale {
    /// Picoseconds in one unit of this timescale.
    pub const fn picos_per_unit(self) -> u64 {
        match self {
            Timescale::Picoseconds => 1,
            Timescale::Nanoseconds => 1_000,
            Timescale::Microseconds => 1_000_000,
        }
    }

    /// Parses `ps`, `ns` or `us` (also `µs`).
    pub fn from_name(name: &str) -> Option<Timescale> {
        match name {
            "ps" => Some(Timescale::Picoseconds),
            "ns" => Some(Timescale::Nanoseconds),
            "us" | "µs" => Some(Timescale::Microseconds),
            _ => None,
        }
    }

    /// The VCD time of `t`: whole units, rounded to the nearest unit with halves rounded up.
    pub const fn ticks(self, t: Instant) -> u64 {
        let unit = self.picos_per_unit();
        let ps = t.as_picos();
        // Split to avoid overflow of `ps + unit / 2` near u64::MAX.
        let whole = ps / unit;
        let rest = ps % unit;
        if unit > 1 && rest >= unit.div_ceil(2) {
            whole + 1
        } else {
            whole
        }
    }

    const fn vcd_unit(self) -> TimescaleUnit {
        match self {
            Timescale::Picoseconds => TimescaleUnit::PS,
            Timescale::Nanoseconds => TimescaleUnit::NS,
            Timescale::Microseconds => TimescaleUnit::US,
        }
    }
}

/// Errors while writing a VCD trace.
#[derive(Debug, thiserror::Error)]
pub enum VcdTraceError {
    /// The output could not be written.
    #[error("cannot write the VCD output: {0}")]
    Io(#[from] std::io::Error),
    /// A chip name is empty or holds characters a VCD identifier cannot hold.
    #[error(
        "chip name {0:?} cannot be a VCD scope name (use letters, digits, '_', '-', '.', no spaces)"
    )]
    BadChipName(String),
    /// Two chips have the same name.
    #[error("two traced chips are both named {0:?}")]
    DuplicateChipName(String),
    /// An event names a chip index that was not declared.
    #[error("no traced chip number {0}")]
    UnknownChip(usize),
    /// An event is earlier than one already written.
    #[error("pin event at {at} is earlier than the last written event at {last}")]
    OutOfOrder {
        /// The late event's time.
        at: Instant,
        /// The time of the last written event.
        last: Instant,
    },
}

/// One chip in a trace: its scope name, the pins traced, and their levels at time 0.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TracedChip {
    name: String,
    pins: PinSet,
    initial: Vec<(Pin, bool)>,
}

impl TracedChip {
    /// A chip named `name` tracing `pins`, whose initial levels are given by `level`
    /// (typically `|p| chip.pin_level(p)` before the run starts).
    pub fn new(
        name: &str,
        pins: PinSet,
        level: impl Fn(Pin) -> bool,
    ) -> Result<TracedChip, VcdTraceError> {
        let valid = !name.is_empty()
            && name
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.'));
        if !valid {
            return Err(VcdTraceError::BadChipName(name.to_owned()));
        }
        Ok(TracedChip {
            name: name.to_owned(),
            pins,
            initial: pins.iter().map(|p| (p, level(p))).collect(),
        })
    }

    /// The scope name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The traced pins.
    pub fn pins(&self) -> PinSet {
        self.pins
    }
}

/// A wire of the trace: its VCD id code and last written level.
#[derive(Debug, Clone, Copy)]
struct Wire {
    id: IdCode,
    level: bool,
}

/// Streams pin events of one or more chips into a VCD file.
///
/// Events must be recorded in non-decreasing time across all chips; events of pins a chip
/// does not trace and events that do not change a wire's level are skipped.
pub struct VcdWriter<W: Write> {
    vcd: vcd::Writer<W>,
    timescale: Timescale,
    /// Per chip, per pin (index in [`Pin::ALL`]): the wire, if traced.
    wires: Vec<[Option<Wire>; Pin::ALL.len()]>,
    last_at: Instant,
    last_tick: u64,
}

fn pin_index(pin: Pin) -> usize {
    Pin::ALL.iter().position(|p| *p == pin).unwrap_or(0)
}

fn value(level: bool) -> Value {
    if level { Value::V1 } else { Value::V0 }
}

impl<W: Write> VcdWriter<W> {
    /// Writes the header (timescale, one module per chip, one wire per traced pin) and the
    /// initial levels at time 0.
    pub fn new(
        out: W,
        timescale: Timescale,
        chips: &[TracedChip],
    ) -> Result<VcdWriter<W>, VcdTraceError> {
        for (i, c) in chips.iter().enumerate() {
            if chips.iter().take(i).any(|o| o.name == c.name) {
                return Err(VcdTraceError::DuplicateChipName(c.name.clone()));
            }
        }
        let mut vcd = vcd::Writer::new(out);
        vcd.version(concat!("sercon-model ", env!("CARGO_PKG_VERSION")))?;
        vcd.timescale(1, timescale.vcd_unit())?;
        let mut wires = Vec::with_capacity(chips.len());
        for chip in chips {
            vcd.add_module(&chip.name)?;
            let mut row = [None; Pin::ALL.len()];
            for &(pin, level) in &chip.initial {
                let id = vcd.add_wire(1, pin.name())?;
                if let Some(slot) = row.get_mut(pin_index(pin)) {
                    *slot = Some(Wire { id, level });
                }
            }
            vcd.upscope()?;
            wires.push(row);
        }
        vcd.enddefinitions()?;
        vcd.timestamp(0)?;
        vcd.begin(SimulationCommand::Dumpvars)?;
        for row in &wires {
            for w in row.iter().flatten() {
                vcd.change_scalar(w.id, value(w.level))?;
            }
        }
        vcd.end()?;
        Ok(VcdWriter {
            vcd,
            timescale,
            wires,
            last_at: Instant::ZERO,
            last_tick: 0,
        })
    }

    /// Records one event of chip number `chip` (its index in the list given to [`new`]).
    ///
    /// [`new`]: VcdWriter::new
    pub fn record(&mut self, chip: usize, event: &PinEvent) -> Result<(), VcdTraceError> {
        let row = self
            .wires
            .get_mut(chip)
            .ok_or(VcdTraceError::UnknownChip(chip))?;
        if event.at < self.last_at {
            return Err(VcdTraceError::OutOfOrder {
                at: event.at,
                last: self.last_at,
            });
        }
        let Some(Some(wire)) = row.get_mut(pin_index(event.pin)) else {
            return Ok(()); // pin not traced for this chip
        };
        if wire.level == event.level {
            return Ok(());
        }
        wire.level = event.level;
        let id = wire.id;
        self.last_at = event.at;
        let tick = self.timescale.ticks(event.at);
        if tick != self.last_tick {
            self.vcd.timestamp(tick)?;
            self.last_tick = tick;
        }
        self.vcd.change_scalar(id, value(event.level))?;
        Ok(())
    }

    /// Records a slice of events of one chip, in order.
    pub fn record_all(&mut self, chip: usize, events: &[PinEvent]) -> Result<(), VcdTraceError> {
        events.iter().try_for_each(|e| self.record(chip, e))
    }

    /// Writes a final timestamp at `end` (so a viewer shows the tail of the run) and flushes.
    /// Pass `&mut out` to [`new`](VcdWriter::new) to keep the output afterwards.
    pub fn finish(mut self, end: Instant) -> Result<(), VcdTraceError> {
        let tick = self.timescale.ticks(end);
        if tick > self.last_tick {
            self.vcd.timestamp(tick)?;
        }
        self.vcd.flush()?;
        Ok(())
    }
}

/// Writes the events of several chips, each list in time order, as one VCD: the lists are
/// merged by time (ties keep chip order), and the file ends at `end`.
pub fn write_vcd<W: Write>(
    out: W,
    timescale: Timescale,
    chips: &[(TracedChip, &[PinEvent])],
    end: Instant,
) -> Result<(), VcdTraceError> {
    let headers: Vec<TracedChip> = chips.iter().map(|(c, _)| c.clone()).collect();
    let mut w = VcdWriter::new(out, timescale, &headers)?;
    let mut merged: Vec<(usize, &PinEvent)> = chips
        .iter()
        .enumerate()
        .flat_map(|(i, (_, evs))| evs.iter().map(move |e| (i, e)))
        .collect();
    // Stable: equal times keep chip order, then each chip's own order.
    merged.sort_by_key(|(_, e)| e.at);
    for (i, e) in merged {
        w.record(i, e)?;
    }
    w.finish(end)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parses a VCD back: for each (scope, wire) the list of (time, level) changes, initial
    /// `$dumpvars` values included at time 0.
    fn parse(text: &[u8]) -> (vcd::Header, Vec<(u64, IdCode, bool)>) {
        let mut p = vcd::Parser::new(text);
        let header = p.parse_header().expect("header parses");
        let mut t = 0;
        let mut changes = Vec::new();
        for cmd in p {
            match cmd.expect("command parses") {
                vcd::Command::Timestamp(ts) => t = ts,
                vcd::Command::ChangeScalar(id, v) => changes.push((t, id, v == Value::V1)),
                _ => {}
            }
        }
        (header, changes)
    }

    fn ev(ps: u64, pin: Pin, level: bool) -> PinEvent {
        PinEvent {
            at: Instant::from_picos(ps),
            pin,
            level,
        }
    }

    #[test]
    fn rounding_to_nearest_unit_halves_up() {
        let ns = Timescale::Nanoseconds;
        assert_eq!(ns.ticks(Instant::from_picos(62_499)), 62);
        assert_eq!(ns.ticks(Instant::from_picos(62_500)), 63);
        assert_eq!(ns.ticks(Instant::from_picos(62_000)), 62);
        assert_eq!(
            Timescale::Microseconds.ticks(Instant::from_picos(1_499_999)),
            1
        );
        assert_eq!(
            Timescale::Picoseconds.ticks(Instant::from_picos(62_500)),
            62_500
        );
        assert_eq!(ns.ticks(Instant::MAX), u64::MAX / 1000 + 1);
    }

    #[test]
    fn two_chips_round_trip_through_the_vcd_parser() {
        let pins = PinSet::of(&[Pin::ConClk, Pin::DivClk]);
        let master = TracedChip::new("master", pins, |p| p == Pin::DivClk).expect("name");
        let slave = TracedChip::new("slave1", PinSet::of(&[Pin::Int0]), |_| false).expect("name");
        let m_events = [
            ev(1_000_000, Pin::ConClk, true),
            ev(2_000_000, Pin::DivClk, false),
            ev(3_000_000, Pin::DivClk, true),
            ev(5_000_000, Pin::ConClk, false),
            ev(5_000_000, Pin::Int0, true), // not traced on the master: skipped
        ];
        let s_events = [
            ev(2_500_000, Pin::Int0, true),
            ev(2_600_000, Pin::Int0, true),
        ];
        let mut out = Vec::new();
        write_vcd(
            &mut out,
            Timescale::Nanoseconds,
            &[(master, &m_events[..]), (slave, &s_events[..])],
            Instant::from_picos(10_000_000),
        )
        .expect("written");
        let (header, changes) = parse(&out);
        assert_eq!(header.timescale, Some((1, TimescaleUnit::NS)));
        let id = |scope: &str, wire: &str| header.find_var(&[scope, wire]).expect("wire").code;
        let con = id("master", "CON_CLK");
        let div = id("master", "DIV_CLK");
        let int0 = id("slave1", "INT0");
        assert!(header.find_var(&["master", "INT0"]).is_none());
        let of = |w: IdCode| -> Vec<(u64, bool)> {
            changes
                .iter()
                .filter(|c| c.1 == w)
                .map(|c| (c.0, c.2))
                .collect()
        };
        assert_eq!(of(con), vec![(0, false), (1_000, true), (5_000, false)]);
        assert_eq!(of(div), vec![(0, true), (2_000, false), (3_000, true)]);
        // The repeated level at 2.6 µs is not written again.
        assert_eq!(of(int0), vec![(0, false), (2_500, true)]);
        assert!(String::from_utf8_lossy(&out).trim_end().ends_with("#10000"));
    }

    #[test]
    fn picoseconds_keep_62_5_ns() {
        let chip = TracedChip::new("c", PinSet::of(&[Pin::TxD]), |_| true).expect("name");
        let mut out = Vec::new();
        let mut w = VcdWriter::new(&mut out, Timescale::Picoseconds, &[chip]).expect("header");
        w.record_all(
            0,
            &[ev(62_500, Pin::TxD, false), ev(125_000, Pin::TxD, true)],
        )
        .expect("recorded");
        w.finish(Instant::from_picos(125_000)).expect("finished");
        let (header, changes) = parse(&out);
        assert_eq!(header.timescale, Some((1, TimescaleUnit::PS)));
        let times: Vec<u64> = changes.iter().map(|c| c.0).collect();
        assert_eq!(times, vec![0, 62_500, 125_000]);
    }

    #[test]
    fn errors_are_values() {
        assert!(matches!(
            TracedChip::new("two words", PinSet::ALL, |_| false),
            Err(VcdTraceError::BadChipName(_))
        ));
        assert!(TracedChip::new("", PinSet::ALL, |_| false).is_err());
        let a = TracedChip::new("a", PinSet::ALL, |_| false).expect("name");
        assert!(matches!(
            VcdWriter::new(Vec::new(), Timescale::Nanoseconds, &[a.clone(), a.clone()]),
            Err(VcdTraceError::DuplicateChipName(_))
        ));
        let mut w = VcdWriter::new(Vec::new(), Timescale::Nanoseconds, &[a]).expect("header");
        assert!(matches!(
            w.record(3, &ev(0, Pin::Int0, true)),
            Err(VcdTraceError::UnknownChip(3))
        ));
        w.record(0, &ev(5_000, Pin::Int0, true)).expect("in order");
        assert!(matches!(
            w.record(0, &ev(4_000, Pin::Int1, true)),
            Err(VcdTraceError::OutOfOrder { .. })
        ));
    }
}
