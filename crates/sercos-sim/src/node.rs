//! A node: one controller model, the program on its host processor, and its own clock.

use sercon_model::Chip;
use sercon_model::pins::{Pin, PinSet};
use sercon_model::serial_port::{LineSegment, LineSignal};
use sercon_model::serial_settings::{TestMode, TxdOutput, test_mode, txd_outputs};
use sercos_wire::time::Instant;

use crate::clock::NodeClock;
use crate::config::NodeConfig;
use crate::host::{HostProgram, NodeBus, Wake};

/// 410B §4.1 1H.3 REPON.
const REPON: u16 = 1 << 3;
/// Host wakes in a row at one instant before the node is left alone (a program that
/// keeps an interrupt toggling cannot hang the simulation).
pub(crate) const MAX_HOST_WAKES: usize = 64;

/// A copy a repeater's chip is expected to release (`Node::expect`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ExpectedCopy {
    /// Its start at the repeater's output (local time).
    pub(crate) at: Instant,
    /// The node whose output it copies.
    pub(crate) origin: usize,
    /// A copy of a replay (a repair, a power-on): every receiver behind gets it, as it
    /// gets the replay itself (`Simulation::propagate`).
    pub(crate) replayed: bool,
    /// It carries bits (a telegram), not a steady signal: only such a copy is what a
    /// telegram the chip puts out at its instant is (else the telegram is the chip's own,
    /// which shadows a steady signal's copy, 410B §1).
    pub(crate) bits: bool,
}

/// One node of the ring.
pub(crate) struct Node {
    pub(crate) cfg: NodeConfig,
    pub(crate) chip: Chip,
    pub(crate) host: Box<dyn HostProgram>,
    pub(crate) clock: NodeClock,
    pub(crate) powered: bool,
    /// Scheduled power-off windows (simulation time), from the fault list.
    pub(crate) off_windows: Vec<(Instant, Instant)>,
    /// The host's deadline (local time).
    pub(crate) host_deadline: Option<Instant>,
    /// Levels of INT0, INT1 when the host last looked.
    pub(crate) ints: (bool, bool),
    /// The last wake was for an interrupt pin change: if a pin is still active when the host
    /// returns, it is woken once more (level-triggered INT0/INT1, 410B §2).
    pub(crate) rewake: bool,
    /// The current wake is such a second wake (it earns no further one).
    pub(crate) rewaking: bool,
    /// INT0 or INT1 differed from what the host last saw while its wake was under way (a
    /// change it could not take then): it is woken again when the wake ends, even if the
    /// pin is back at the level it saw ([`Node::note_pins`]).
    pub(crate) changed_while_busy: bool,
    /// Exact path: the repeater's copies of what was delivered, not yet released, oldest
    /// first.
    pub(crate) expect: std::collections::VecDeque<ExpectedCopy>,
    /// End of the last own telegram (local): the background resumes there.
    pub(crate) resume: Option<Instant>,
    /// The last segment on the output line (simulation time), when levels are followed.
    pub(crate) last_out: Option<LineSegment>,
    /// Follow the output line's level (reference path).
    pub(crate) track_levels: bool,
    /// Start of the last input segment (local time).
    pub(crate) in_floor: Instant,
    /// How far the output the chip released reaches (simulation time; the output floor as
    /// the last segment taken from the chip left it): beyond it, the output line holds what
    /// the fast path put out ahead of the chip (`Simulation::repeat_out`).
    pub(crate) chip_out_end: Instant,
    /// Where the chip's last output ended in node time (a node whose clock drifts:
    /// [`Node::map_out_after`]).
    pub(crate) out_local_end: Instant,
    /// Where the last input and output segments of bits ended, in both times (a node whose
    /// clock drifts: [`Node::map_in`], [`Node::map_out`]).
    pub(crate) contig: Contiguity,
    /// The chip repeats its input (1H.3 REPON, transmitter on, no test mode).
    pub(crate) repeating: bool,
    /// The pending wake event.
    pub(crate) wake: Option<Instant>,
    /// The chip ran past its own output up to the master's next telegram since its wake
    /// was last set (`Simulation::run_ahead`): the next wake set may be a placeholder.
    pub(crate) ran_past: bool,
    /// The pending wake is a placeholder at the chip's time (`Simulation::park`), not the
    /// node's next wake: a delivery before it runs the chip ahead as if there were none.
    pub(crate) parked: bool,
    /// The pending wake was parked by a joined wake (`sim/join_wake.rs`) without moving the
    /// queue's entry, which still holds the wake before: moved when the wake is next set,
    /// or at the event's end (`Simulation::queue_joined_parks`).
    pub(crate) park_unqueued: bool,
    /// The node is in the simulation's touched list (`Simulation::touch`): it is served
    /// once the event's nodes are. Kept with the node, where a delivery has it at hand.
    pub(crate) is_touched: bool,
    /// The node is marked for the simulation's rewake list (`Simulation::set_rewakes`;
    /// `rewake_done`'s node stays marked off the list).
    pub(crate) is_rewake: bool,
    /// Index in the VCD, if traced.
    pub(crate) vcd: Option<usize>,
    /// The host's wake under way, suspended in a bus access (`sim/host_run.rs`): it is not
    /// woken again meanwhile.
    pub(crate) host_run: Option<Box<crate::host_coroutine::HostRun>>,
    /// No pin traced (`vcd`), no host wake under way (`host_run`), no second wake pending
    /// (`rewake`) and no deadline (`host_deadline`): kept by [`Node::note_host`] wherever
    /// one of them changes (a wake under way taken out of its node to go on is put back or
    /// ends in [`Node::woke`]), so that [`Node::quiet_host`] asks one field for the four
    /// (debug builds compare them).
    pub(crate) host_idle: bool,
}

/// The ends of a drifting node's last input and output segments of bits, in simulation
/// and in node time: a segment that starts where the one before ended goes on from its end
/// in the other time too, and one that starts after it no earlier than that end
/// ([`Node::map_in`], [`Node::map_out`]).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Contiguity {
    /// The last input's end: (simulation time, node time).
    input: Option<(Instant, Instant)>,
    /// The last output's end: (node time, simulation time).
    output: Option<(Instant, Instant)>,
}

/// `start` in the other time: where the last segment's bits ended (`last`: their end in
/// this time and in the other) when it starts there; when it starts after that end,
/// `map(start)` but no earlier than the end in the other time; else `map(start)`. `last`
/// becomes the end of `seg`'s bits (a steady segment keeps it).
///
/// A receiver takes the line in the order it comes and a repeater forwards it so (410B §1).
/// The bits keep their length in both times (spec-notes "Own clocks"), so their end lies up
/// to length × the clock error apart from where the clock maps it: mapped alone, a segment
/// that follows the bits closer than that would start before their end in the other time
/// and reach the receiver out of order, which cut it (a slave's AT 12.7 ns after the MST it
/// follows, at a repeater 1000 ppm slow: the AT lost). It starts at their end instead, as if
/// it followed them at once.
fn follow(
    last: &mut Option<(Instant, Instant)>,
    start: Instant,
    seg: &LineSegment,
    map: impl Fn(Instant) -> Instant,
) -> Instant {
    let other = match *last {
        Some((here, there)) if here == start => there,
        Some((here, there)) if here < start => map(start).max(there),
        _ => map(start),
    };
    if let Some(n) = seg.bit_len() {
        let len = seg.bit_time.saturating_mul(n);
        *last = Some((start.saturating_add(len), other.saturating_add(len)));
    }
    other
}

impl Node {
    /// The chip's AT from `start` to `end` sent on past its output floor `before` by the
    /// fast path (`send_on_plain`, `send_through`, a run of them): the output's reach moves
    /// to `end`. Returns the fast path's collisions it makes (`SimStats::fast_path_collisions`):
    /// one when it cut a telegram the fast path put out ahead of the chip (`route_output`),
    /// one more when it is `held` behind another at a repeater's output (`repeat_out`).
    #[inline(always)]
    pub(crate) fn sent_through(
        &mut self,
        start: Instant,
        before: Instant,
        end: Instant,
        held: bool,
    ) -> u64 {
        let cut = start < before && before > self.chip_out_end;
        self.chip_out_end = end;
        u64::from(cut) + u64::from(held)
    }

    /// Node time of an input segment starting at `start` (simulation time). The line's bit
    /// times are not scaled by the node's clock error (spec-notes "Own clocks"), so the
    /// bits of a segment take the same time in both; a segment that starts where the last
    /// one's bits ended (a sender's telegram and then its filler) starts where they end in
    /// node time too, as one segment carrying both would (the fast path's implied filler).
    #[cold]
    #[inline(never)]
    pub(crate) fn map_in(&mut self, start: Instant, seg: &LineSegment) -> Instant {
        let clock = &self.clock;
        follow(&mut self.contig.input, start, seg, |t| clock.to_local(t))
    }

    /// A node whose clock starts to drift (its times so far the simulation's): the bits it
    /// received and sent last end at the same instant in both times, and a segment that
    /// follows them at once (their filler, after a telegram under way when the drift began)
    /// goes on from there ([`follow`]; 410B §1, spec-notes "Own clocks"), as the fast path's
    /// telegram carrying its filler does.
    /// Mapped alone by the clock it started up to the telegram's length × the clock error
    /// apart (a slave 684 ppm fast from the middle of the MST: the master's filler after it
    /// 14 ns late, and slave 1's AT then from the other level on the reference path only).
    #[cold]
    #[inline(never)]
    pub(crate) fn start_contiguity(&mut self) {
        self.contig.input = self.chip.last_input_bits_end().map(|e| (e, e));
        self.contig.output = Some((self.chip_out_end, self.chip_out_end));
    }

    /// A filler (node time) that starts where the bits this node received last end: the
    /// sender resumed it right after its telegram (410B §1; the fast path's telegram carrying
    /// its filler, split where a fibre's faults or traces take them apart), so it goes on from
    /// the level those bits left, as the sender's line does. `Simulation::deliver` may have
    /// handed the bits over inverted (taken from the level the receiver is at); the filler,
    /// split from them before, still started from their level as sent: the receiver then saw
    /// no edge at its first bit (a slave's AT and its filler at a repeater 684 ppm fast whose
    /// AT began 4.4 ns before an edge of the filler it repeated: the master's INT_FIBBR, 410B
    /// §4.1 2H.13, on the reference path only after a 16 µs break further on).
    #[cold]
    #[inline(never)]
    pub(crate) fn continue_filler(&self, seg: &mut LineSegment) {
        if self.chip.last_input_bits_end() == Some(seg.start)
            && let Some(level) = self.chip.received_level_at(seg.start)
        {
            seg.level_before = level;
        }
    }

    /// Simulation time of an output segment starting at `start` (node time), as
    /// [`Node::map_in`]: one that starts where the last one's bits ended follows them.
    #[cold]
    #[inline(never)]
    pub(crate) fn map_out(&mut self, start: Instant, seg: &LineSegment) -> Instant {
        let clock = &self.clock;
        follow(&mut self.contig.output, start, seg, |t| clock.to_global(t))
    }

    /// `seg`, released by the chip (node time), in simulation time: on the simulation's
    /// clock its start as it is, else as [`Node::map_out_after`] maps it after `floor`.
    #[inline]
    pub(crate) fn map_released(&mut self, seg: &mut LineSegment, floor: Instant) {
        if self.clock.is_identity() {
            seg.start = self.clock.to_global(seg.start);
        } else {
            self.map_out_after(seg, floor);
        }
    }

    /// `seg`, released by the chip (node time), in simulation time ([`Node::map_out`]),
    /// with the output line taken up to `floor`. A segment that starts where or after the
    /// chip's last output ended in node time starts no earlier than that output's end in
    /// simulation time: bits keep the line's bit time in both (spec-notes "Own clocks"), so
    /// a segment's end maps up to its length × the clock error later than the clock maps the
    /// instant, and what follows it in the chip's time could otherwise overlap it in the
    /// simulation's. Only a segment that starts before that end in node time cuts what the
    /// line carries (the chip's own telegram over what it repeats, 410B §1).
    #[cold]
    #[inline(never)]
    pub(crate) fn map_out_after(&mut self, seg: &mut LineSegment, floor: Instant) {
        let local = seg.start;
        let local_end = seg.end().unwrap_or(local);
        seg.start = self.map_out(local, seg);
        if local >= self.out_local_end
            && seg.start < floor
            && !matches!(seg.signal, LineSignal::Dark | LineSignal::Light)
        {
            seg.start = floor;
        }
        self.out_local_end = self.out_local_end.max(local_end);
    }

    pub(crate) fn new(
        cfg: NodeConfig,
        chip: Chip,
        host: Box<dyn HostProgram>,
        clock: NodeClock,
    ) -> Self {
        Node {
            cfg,
            chip,
            host,
            clock,
            powered: true,
            off_windows: Vec::new(),
            host_deadline: None,
            ints: (false, false),
            rewake: false,
            rewaking: false,
            changed_while_busy: false,
            expect: std::collections::VecDeque::new(),
            resume: None,
            last_out: None,
            track_levels: true,
            chip_out_end: Instant::ZERO,
            out_local_end: Instant::ZERO,
            in_floor: Instant::ZERO,
            contig: Contiguity::default(),
            repeating: false,
            wake: None,
            ran_past: false,
            parked: false,
            park_unqueued: false,
            is_touched: false,
            is_rewake: false,
            vcd: None,
            host_run: None,
            host_idle: true,
        }
    }

    /// Whether the node is powered at simulation time `t` as far as the schedule says.
    pub(crate) fn powered_at(&self, t: Instant) -> bool {
        self.powered && !self.off_windows.iter().any(|(a, b)| *a <= t && t < *b)
    }

    /// Runs the host for `why` at the chip's time.
    pub(crate) fn run_host(&mut self, why: Wake) {
        let now = self.chip.now();
        let mut bus = NodeBus::new(&mut self.chip, self.cfg.bus_access);
        self.host_deadline = self.host.wake(&mut bus, now, why);
        self.woke(why);
        self.repeating = repeats(&self.chip);
    }

    /// Why the host is to be woken now (an interrupt pin changed, its deadline passed),
    /// taking the wake: `None` when nothing is due.
    pub(crate) fn host_due(&mut self) -> Option<Wake> {
        let ints = (
            self.chip.pin_level(Pin::Int0),
            self.chip.pin_level(Pin::Int1),
        );
        let changed = std::mem::take(&mut self.changed_while_busy);
        if ints != self.ints || changed {
            self.ints = ints;
            Some(Wake::Interrupt {
                int0: ints.0,
                int1: ints.1,
            })
        } else if self.take_rewake() && self.interrupt_requested() {
            // Looked at once, when the wake has ended: a request that rises later changes a
            // pin from what the host saw (the first case) if the pin shows it at all.
            self.rewaking = true;
            Some(Wake::Interrupt {
                int0: ints.0,
                int1: ints.1,
            })
        } else if self.host_deadline.is_some_and(|d| d <= self.chip.now()) {
            self.host_deadline = None;
            self.note_host();
            Some(Wake::Deadline)
        } else {
            None
        }
    }

    /// Notes a change of INT0 / INT1 from what the host last saw while its wake is under
    /// way (410B §2: the outputs are levels, and a level-triggered host input takes a pulse
    /// that came and went while the host was busy once the host is done; spec-notes
    /// "INT0/INT1 are level-triggered for the host").
    pub(crate) fn note_pins(&mut self) {
        let ints = (
            self.chip.pin_level(Pin::Int0),
            self.chip.pin_level(Pin::Int1),
        );
        if ints != self.ints {
            self.changed_while_busy = true;
        }
    }

    /// Whether serving the node now would do nothing but take its output and empty its
    /// receive log: no pin is traced, no suspended host's access has ended, and
    /// [`Node::host_due`] would find nothing (INT0/INT1
    /// as the host last saw them, no second wake pending, its deadline not passed).
    ///
    /// Short path: an idle host (`host_idle`: nothing traced, no wake under way, no second
    /// wake, no deadline) asks only the pins (410B §2 INT0/INT1).
    pub(crate) fn quiet_host(&self) -> bool {
        debug_assert_eq!(
            self.host_idle,
            self.idle_host_now(),
            "the kept idle host is stale"
        );
        (self.host_idle || self.host_waits_quietly())
            && (
                self.chip.pin_level(Pin::Int0),
                self.chip.pin_level(Pin::Int1),
            ) == self.ints
    }

    /// [`Node::quiet_host`] but for the pins, in full: no pin traced, a wake under way
    /// suspended past the chip's time, no second wake pending, no deadline due.
    #[inline(never)]
    fn host_waits_quietly(&self) -> bool {
        self.vcd.is_none()
            && self
                .host_run
                .as_ref()
                .is_none_or(|r| r.resume_at > self.chip.now())
            && !self.rewake
            && self.host_deadline.is_none_or(|d| d > self.chip.now())
    }

    /// What `host_idle` keeps, found afresh.
    fn idle_host_now(&self) -> bool {
        self.vcd.is_none()
            && self.host_run.is_none()
            && !self.rewake
            && self.host_deadline.is_none()
    }

    /// Takes the second wake pending (`rewake`), `host_idle` kept.
    fn take_rewake(&mut self) -> bool {
        let rewake = std::mem::take(&mut self.rewake);
        if rewake {
            self.note_host();
        }
        rewake
    }

    /// Keeps `host_idle` after `vcd`, `host_run`, `rewake` or `host_deadline` changed.
    pub(crate) fn note_host(&mut self) {
        self.host_idle = self.idle_host_now();
    }

    /// After a wake for `why`: one more wake at most per pin change, in case a flag raised
    /// after the handler's last read of 4H/5H keeps the pin active without a new edge
    /// (level-triggered INT0/INT1; spec-notes "Ring simulation").
    pub(crate) fn woke(&mut self, why: Wake) {
        self.rewake = matches!(why, Wake::Interrupt { .. }) && !self.rewaking;
        self.rewaking = false;
        // Its deadline is set before (`run_host`, `Simulation::end_host_wake`).
        self.note_host();
    }

    /// Whether INT0 or INT1 requests an interrupt now (410B §4.1 3H.0 INTFL0, 3H.3 INTFL1),
    /// whatever the pins' polarity.
    fn interrupt_requested(&self) -> bool {
        let (int0, int1) = self.chip.interrupt_requests();
        int0 || int1
    }

    /// The pins traced for the VCD.
    pub(crate) fn set_traced(&mut self, pins: PinSet) {
        self.chip.set_traced_pins(pins);
    }
}

/// Whether `chip` forwards its input: 410B §4.1 1H.3 REPON = 1 with a TxD pin carrying
/// transmit data (2H.0–6) and no test mode (2H TMODE, pins TM0/TM1).
pub(crate) fn repeats(chip: &Chip) -> bool {
    let r1 = chip.peek_register(1);
    let r2 = chip.peek_register(2);
    let cfg = chip.config();
    r1 & REPON != 0
        && txd_outputs(r2)
            .iter()
            .any(|o| matches!(o, TxdOutput::TransmitData))
        && matches!(test_mode(cfg.variant, &cfg.straps, r2).0, TestMode::Normal)
}

impl Node {
    /// Puts `seg` (simulation time) on the output line, adjusting it in place. Like the
    /// transmitter (410B §1: regenerated signal), a telegram continues from the level the
    /// line is at (NRZI decodes an inverted telegram the same); an own steady signal starts
    /// from that level. A segment starting before the end of what the line carries cuts
    /// it there (410B §1: the chip's transmitter merges its own telegrams over what it
    /// repeats, and what it releases describes its output line from each start on;
    /// spec-notes "Repeater collisions"); returns whether it did so to a telegram's bits.
    /// `out_floor` is how far the node's output line is taken (simulation time; kept by
    /// the simulation in one dense table so that a forwarding hop touches nothing else).
    #[inline]
    pub(crate) fn put_out(
        &mut self,
        out_floor: &mut Instant,
        seg: &mut LineSegment,
        own: bool,
    ) -> bool {
        let cut = seg.start < *out_floor && matches!(seg.signal, LineSignal::Bits(_));
        if !self.track_levels {
            // Fast path: receivers take telegrams from the level they are at (see
            // `Simulation::deliver`), so the output's level need not be followed.
            *out_floor = seg.end().unwrap_or(seg.start);
            return cut;
        }
        self.put_out_tracked(out_floor, seg, own);
        cut
    }

    /// [`Node::put_out`] following the output's level (reference path; out of line).
    #[inline(never)]
    fn put_out_tracked(&mut self, out_floor: &mut Instant, seg: &mut LineSegment, own: bool) {
        if let Some(last) = &self.last_out {
            let level = last.level_at(seg.start);
            match seg.signal {
                LineSignal::Bits(_) if seg.level_before != level => {
                    let dark =
                        LineSegment::steady(seg.start, seg.bit_time, LineSignal::Dark, false);
                    *seg = std::mem::replace(seg, dark).inverted();
                }
                LineSignal::Bits(_) => {}
                _ if own => seg.level_before = level,
                _ => {}
            }
        }
        *out_floor = seg.end().unwrap_or(seg.start);
        self.last_out = Some(seg.clone());
    }
}
