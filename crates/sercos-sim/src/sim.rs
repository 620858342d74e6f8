//! The simulation loop: nodes woken in time order by a deterministic event queue, line
//! segments carried along fibres (or the bus) with their delays, faults applied on the way.
//!
//! Fast path (`Delivery::Fast`): when a node sends a segment, its arrival at every node
//! down the ring is computed at once as a sum of fibre delays and repeater latencies
//! (`REPEATER_LATENCY_BITS` bit times per repeater, 410B §1: "The slaves regenerate and
//! repeat their received data"), so a repeater that only forwards costs no event; the
//! chip's own forwarded copy is recognised and dropped. Reference path
//! (`Delivery::Exact`): every repeater's output is taken from its chip, hop by hop.

use sercon_model::pins::{PinEvent, PinSet};
use sercon_model::serial_port::{LineSegment, LineSignal, REPEATER_LATENCY_BITS};
use sercon_model::vcd_trace::TracedChip;
use sercon_model::{Chip, ChipConfig};
use sercos_wire::telegram::Origin;
use sercos_wire::time::{Duration, Instant};

use crate::clock::NodeClock;
use crate::config::{Delivery, MAX_SLAVES, SimConfig};
use crate::error::SimError;
use crate::fault::{Fault, FaultKind, SegmentFaults, ppm_to_ppb};
use crate::host::{HostProgram, Wake};
use crate::node::{Contiguity, Node, repeats};
use crate::recorder::{Recorder, TraceOutput};
use crate::topology::Topology;

mod bus;
mod chip_calls;
mod early_route;
mod host_run;
mod join_wake;
#[cfg(test)]
mod light_wake_tests;
mod out_floors;
mod plain_pass;
#[cfg(test)]
mod run_ahead_tests;
#[cfg(test)]
mod short_path_tests;
mod swept;
#[cfg(test)]
mod test_lcg;
#[cfg(test)]
mod test_state;
mod wake_queue;

use out_floors::{Crossing, OutFloors};
use plain_pass::PlainPass;
use wake_queue::WakeQueue;

/// `Simulation::plain_hop` of a node a slave telegram does not pass by delays alone.
const NOT_PLAIN: u64 = u64::MAX;

/// `Simulation::rewake_done` without a node.
const NO_NODE: usize = usize::MAX;

/// Rounds of "serve the nodes an event touched" per event before giving up on quiet.
const MAX_SETTLE_ROUNDS: usize = 1024;

/// How long after the instant asked for [`Simulation::run_until`] waits for every host to be
/// between wakes: 100 ms, a million accesses at 100 ns without a break.
pub const HOST_BREAK_LIMIT: Duration = Duration::from_millis(100);

/// What the queue holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ev {
    /// Wake node `n`.
    Node(usize),
    /// Fault `i` starts.
    FaultStart(usize),
    /// Fault `i` ends (repair, power-on).
    FaultEnd(usize),
}

/// Counters of one run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SimStats {
    /// Events processed.
    pub events: u64,
    /// Segments handed to a controller's receiver.
    pub deliveries: u64,
    /// Segments that reached a node after a later one (cut at the later one's start).
    pub out_of_order: u64,
    /// Overlapping transmissions on the bus.
    pub collisions: u64,
    /// Segments that reached a receiver whose chip had already passed their start.
    pub late: u64,
    /// Times a slave's chip ran ahead after a telegram of the master reached it
    /// ([`HostProgram::inert`] hosts only; the run is the same without).
    pub run_aheads: u64,
    /// Of those, the runs up to the master's next telegram, through the slave's own output
    /// (taken at its time), rather than to the end of the one it received.
    pub runs_past_output: u64,
    /// Slave telegrams sent on right after the master's telegram that let every slave run
    /// past them, not at a wake of their own (`early_route`).
    pub ats_sent_on: u64,
    /// Wakes set to a placeholder at the chip's time after a run past its output, rather
    /// than found (`Simulation::park`).
    pub parked_wakes: u64,
    /// Fast path only (0 on the reference path): telegrams that met another at a repeater's
    /// output where the fast path put the repeated one out itself, ahead of the repeater's
    /// chip (410B §1: the chip merges its own telegrams over what it repeats, cutting or
    /// shadowing the repeated one; spec-notes "Repeater collisions"). The fast path then
    /// held the repeated telegram behind the other, or the chip's output cut it with no
    /// rest after; a run with any may differ from the reference path's
    /// ([`Delivery::Exact`]), which should be run instead (`sercon ring` does so by itself).
    /// Every segment the fast path handed to a receiver behind a later one
    /// ([`SimStats::out_of_order`]) counts too (spec-notes "Fast path = reference path",
    /// order at every receiver). A ring whose telegrams keep clear of each other at every
    /// repeater has none.
    pub fast_path_collisions: u64,
    /// Wakes of the master taken at once in the wake before, which sent its telegram round
    /// the ring, rather than as events of their own (`sim/join_wake.rs`): each is one event
    /// fewer in [`SimStats::events`].
    pub joined_wakes: u64,
    /// Host bus accesses during which the ring ran along (the host's program waited for
    /// the access's end while other events were taken), not quiet ones that only moved the
    /// host's chip on (spec-notes "A host's bus time").
    pub host_suspensions: u64,
}

/// One segment (fibre, or the bus) as the simulation sees it.
struct Segment {
    delay: Duration,
    faults: SegmentFaults,
    /// The last segments that entered it (simulation time) and their origins, oldest
    /// first, at most [`KEPT_ENTERED`]: a power-on downstream replays every one that
    /// reaches the fresh receiver from its power-on on, a repair the one in effect.
    last_entered: std::collections::VecDeque<(LineSegment, usize)>,
    /// Keep `last_entered` (a break's repair or a power-on downstream replays it).
    keep_last: bool,
    /// Nothing to do as a segment enters: no fault in the whole run, nothing kept, not
    /// traced (all fixed when the simulation is made).
    plain: bool,
}

/// How many segments that entered a fibre it keeps (`Segment::last_entered`): more than
/// can enter within a fibre's delay (a telegram and its filler, split where the fibre is
/// kept, `splits_filler`; a fibre of 2 km is 10 µs long, a telegram at 16 Mbit/s and its
/// filler at least about 3 µs).
const KEPT_ENTERED: usize = 16;

impl Segment {
    /// Keeps `seg` (entering now, origin `origin`) as the last that entered: one entered
    /// again (a replay) replaces those from its start on.
    fn keep_entered(&mut self, seg: &LineSegment, origin: usize) {
        while self
            .last_entered
            .back()
            .is_some_and(|(s, _)| s.start >= seg.start)
        {
            self.last_entered.pop_back();
        }
        if self.last_entered.len() >= KEPT_ENTERED {
            self.last_entered.pop_front();
        }
        self.last_entered.push_back((seg.clone(), origin));
    }
}

/// A running simulation.
pub struct Simulation {
    topology: Topology,
    delivery: Delivery,
    nodes: Vec<Node>,
    segments: Vec<Segment>,
    faults: Vec<Fault>,
    queue: WakeQueue,
    recorder: Recorder,
    stats: SimStats,
    /// Nodes an event touched, each once (marked `Node::is_touched`).
    touched: Vec<usize>,
    /// Nodes a delivery ahead of their chip left with nothing to serve: only their wake
    /// is set again, after the touched ones are served (each once, marked
    /// `Node::is_rewake`).
    rewake: Vec<usize>,
    /// A node taken out of `rewake` (still marked `Node::is_rewake`) because its own wake set
    /// its wake after its input (`wake_node`): `set_rewakes` would find the same wake
    /// again. An input after that puts it back (`deliver`).
    rewake_done: usize,
    buf: Vec<LineSegment>,
    pins: Vec<PinEvent>,
    bus_busy_until: Instant,
    /// The bus's line since its current transmission began (`bus`).
    bus_line: Option<bus::BusLine>,
    now: Instant,
    lookahead: Lookahead,
    /// How far each node's output line is taken (simulation time), dense for the hop loop.
    out_floors: OutFloors,
    /// Delay of each fibre (dense copy of `segments[k].delay`).
    seg_delays: Vec<Duration>,
    /// A ring whose every fibre is `Segment::plain` and no node has power windows (fixed
    /// when the simulation is made): `propagate` skips the checks of fibre faults, traces,
    /// splits and power windows per hop.
    plain_ring: bool,
    /// The shortest fibre's delay, if not zero (`host_run`: no signal gets from one node to
    /// another faster).
    min_fibre_delay: Option<Duration>,
    /// Hop into node k cannot change a passing slave telegram apart from its delay: the
    /// fibre into k has no fault, is not traced and keeps nothing; k has no power windows.
    static_plain: Vec<bool>,
    /// `static_plain` and, now, k is a powered repeating slave whose clock is the
    /// simulation's: a slave's telegram passes k by a sum of delays (fast path). Then the
    /// delay of the fibre into k in ps, so that the hop loop reads one dense table;
    /// [`NOT_PLAIN`] otherwise (a fibre that long is taken hop by hop, to the same result).
    plain_hop: Vec<u64>,
    /// For each node, the first node from it on that is not plain (`plain_hop`), or the
    /// node count: where a run of plain repeaters starting there ends.
    run_end: Vec<usize>,
    /// Stacks for the hosts' wakes (`host_run`, `crate::host_coroutine`).
    stacks: crate::host_coroutine::Stacks,
    /// Hosts waiting in a bus access: when it ends (simulation time) and the node, earliest
    /// first (`host_run`); an entry whose node no longer waits then is passed over.
    resumes: std::collections::BinaryHeap<std::cmp::Reverse<(Instant, usize)>>,
    /// The last pass through plain repeaters, while the output floors it wrote stand.
    plain_pass: Option<PlainPass>,
    /// Quiet wakes skip the touched list ([`Simulation::wake_node`]); off only in tests
    /// that compare both ways.
    light_wakes: bool,
    /// The short paths of `wake_node` (`rewake_done`) and `early_route`
    /// (`unserve_sent_on`); off only in tests that compare both ways.
    short_paths: bool,
    /// A ring whose hosts are all inert ([`HostProgram::inert`]): a slave's chip may run
    /// ahead to the end of the master's telegram it was just given ([`Simulation::run_ahead`]).
    run_ahead_ok: bool,
    /// The end of the current `run_until` (a chip never runs ahead past it: after the run it
    /// is read at that instant).
    run_to: Instant,
    /// The latest instant a [`Simulation::run_until`] asked for: where the traces end
    /// ([`Simulation::finish`]).
    ran_to: Instant,
    /// The fibres' delay from the master's transmitter to each node's receiver (without the
    /// repeaters' latency).
    from_master: Vec<Duration>,
    /// The first slave whose clock is not the simulation's (the node count if none): the
    /// master's telegrams pass the repeaters before it by their latency exactly.
    first_drifting: usize,
    /// Slaves run past their own output in the pass being made (`early_route`).
    deferred: Vec<usize>,
    /// The node a replay of what enters a fibre is for (`fault_end`): on the fast path it
    /// gets a slave's signal too (see `propagate`).
    replay_to: Option<usize>,
    /// A repeater's chip is putting out its copy of a replay (`deliver_chip_forwards`,
    /// [`ExpectedCopy::replayed`](crate::node::ExpectedCopy)): every receiver behind gets it, as it gets the replay itself.
    replay_copy: bool,
    /// The run has faults (`propagate`: repeaters forward their copies themselves).
    faulty: bool,
    /// For each fibre, the instants at which a fault cuts what enters it (a break's start
    /// and repair, its node's power-off), sorted: a filler split from its telegram
    /// (`splits_filler`) waits for these (`held_fillers`).
    cuts: Vec<Vec<Instant>>,
    /// Fillers split from their telegram held back at their fibre's entrance until a
    /// fault that cuts the telegram has come (`Simulation::hold_filler`): the fibre, the
    /// filler, its origin and the replay marks it was sent with (`replay_to`,
    /// `replay_copy`).
    held_fillers: Vec<HeldFiller>,
    /// The master's next output for any input (`Chip::next_output_for_any_input`), found
    /// once per pass of a telegram of the master (nothing reaches the master before the
    /// pass's last hop).
    master_next: Option<Option<Instant>>,
    /// A repeater latency and, for each node, the fibres' delay from the master's output and
    /// that latency for each slave before it (`Simulation::master_horizon`'s sum, 410B §1):
    /// made for the latency of a sweep of the master's segment (`sim/swept.rs`), kept while
    /// the next has the same.
    master_reach: (Duration, Vec<Duration>),
    /// A wake was joined in this event and some slave's parked wake may not be in the
    /// queue yet (`Node::park_unqueued`, `sim/join_wake.rs`).
    joined_parks: bool,
}

/// A filler held back at a fibre's entrance (`Simulation::held_fillers`).
struct HeldFiller {
    fibre: usize,
    seg: LineSegment,
    origin: usize,
    replay_to: Option<usize>,
    replay_copy: bool,
}

/// How a node's next wake is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Lookahead {
    /// At the chip's next possible own output (`Chip::next_output_bound`, which is its next
    /// internal event when a pin or an interrupt output can be seen) on the fast path, at
    /// its next event (`Chip::next_event_at`) on the exact one: more wakes, each cheap.
    #[default]
    Events,
    /// At the chip's next observable instant (`Chip::next_deadline`): fewer wakes, each
    /// with a look-ahead probe.
    Observable,
}

impl Simulation {
    /// Builds the nodes (chips at reset, time 0), wakes every host program with
    /// [`Wake::Start`] (node order) and schedules the faults.
    pub fn new(cfg: SimConfig, hosts: Vec<Box<dyn HostProgram>>) -> Result<Self, SimError> {
        let n = cfg.nodes.len();
        if n == 0 {
            return Err(SimError::NoNodes);
        }
        if n - 1 > MAX_SLAVES {
            return Err(SimError::TooManySlaves(n - 1));
        }
        if hosts.len() != n {
            return Err(SimError::HostCount {
                hosts: hosts.len(),
                nodes: n,
            });
        }
        let seg_delays: Vec<Duration> = match &cfg.topology {
            Topology::Ring { fibres } => {
                if fibres.len() != n {
                    return Err(SimError::FibreCount {
                        fibres: fibres.len(),
                        nodes: n,
                    });
                }
                fibres.iter().map(|f| f.delay()).collect()
            }
            Topology::Bus { delay } => vec![*delay],
        };
        for f in &cfg.faults {
            check_fault(f, n, seg_delays.len())?;
        }
        let mut recorder = Recorder::new(cfg.traces.clone())?;
        let from_master: Vec<Duration> = (0..n)
            .scan(Duration::ZERO, |d, k| {
                let here = *d;
                *d = d.saturating_add(seg_delays.get(k).copied().unwrap_or(Duration::ZERO));
                Some(here)
            })
            .collect();
        // Not with faults that cut the line (a break, a power-off): their dark can cut a
        // master's telegram a slave was already given whole and ran ahead through (410B §1:
        // a repeater forwards its input as it comes, so the dark follows hop by hop).
        let run_ahead_ok = matches!(cfg.topology, Topology::Ring { .. })
            && cfg.delivery == Delivery::Fast
            && hosts.iter().all(|h| h.inert())
            && !cfg.faults.iter().any(|f| {
                matches!(
                    f.kind,
                    FaultKind::FibreBreak { .. } | FaultKind::PowerOff { .. }
                )
            });
        let mut nodes = Vec::with_capacity(n);
        for (i, (nc, host)) in cfg.nodes.iter().zip(hosts).enumerate() {
            let mut chip =
                Chip::try_new(nc.chip).map_err(|source| SimError::Chip { node: i, source })?;
            // The receive log is for tools; nothing here reads it (every frame still goes
            // to the telegram processor).
            chip.set_rx_log(false);
            // Fast path: a telegram and the filler after it travel as one segment, and the
            // simulation carries what a repeater forwards (`propagate`): the chip's own
            // copies are not released.
            chip.set_implied_filler(cfg.delivery == Delivery::Fast);
            chip.set_forward_output(cfg.delivery == Delivery::Exact);
            let clock = NodeClock::new(ppm_to_ppb(nc.mclk_error_ppm));
            let mut node = Node::new(nc.clone(), chip, host, clock);
            node.track_levels = cfg.delivery == Delivery::Exact;
            for f in &cfg.faults {
                if let FaultKind::PowerOff { node: j, until } = f.kind
                    && j == i
                {
                    node.off_windows.push((f.at, until.unwrap_or(Instant::MAX)));
                }
            }
            nodes.push(node);
        }
        for (i, pins) in &cfg.traces.vcd {
            let node = nodes.get_mut(*i).ok_or(SimError::NoSuchTarget {
                what: "node",
                index: *i,
            })?;
            let pins: PinSet = *pins;
            node.set_traced(pins);
            let chip = &node.chip;
            let traced = TracedChip::new(&node.cfg.name, pins, |p| chip.pin_level(p))?;
            node.vcd = Some(recorder.add_vcd_chip(traced));
            node.note_host();
        }
        let segments: Vec<Segment> = seg_delays
            .iter()
            .enumerate()
            .map(|(k, d)| {
                let faults = SegmentFaults::new(&cfg.faults, k, cfg.seed);
                let downstream = if seg_delays.len() == 1 {
                    None
                } else {
                    Some((k + 1) % n)
                };
                let keep_last = !faults.is_clean()
                    || cfg.faults.iter().any(|f| {
                        matches!(f.kind, FaultKind::PowerOff { node, .. }
                            if downstream.is_none_or(|d| d == node))
                    });
                let plain = !keep_last && faults.is_clean() && !recorder.wants(k);
                Segment {
                    delay: *d,
                    faults,
                    last_entered: std::collections::VecDeque::new(),
                    keep_last,
                    plain,
                }
            })
            .collect();
        let ring = matches!(cfg.topology, Topology::Ring { .. });
        let static_plain: Vec<bool> = (0..n)
            .map(|k| {
                let up = (k + n - 1) % n;
                ring && k != 0
                    && segments.get(up).is_some_and(|s| s.plain)
                    && nodes.get(k).is_some_and(|nd| nd.off_windows.is_empty())
            })
            .collect();
        let mut fault_events = Vec::with_capacity(2 * cfg.faults.len());
        for (i, f) in cfg.faults.iter().enumerate() {
            fault_events.push((f.at, Ev::FaultStart(i)));
            let end = match f.kind {
                FaultKind::FibreBreak { until, .. } | FaultKind::PowerOff { until, .. } => until,
                _ => None,
            };
            if let Some(e) = end {
                fault_events.push((e.max(f.at), Ev::FaultEnd(i)));
            }
        }
        let drifting = first_drifting(&nodes);
        let faulty = !cfg.faults.is_empty();
        let mut cuts = vec![Vec::new(); n];
        if ring {
            for f in &cfg.faults {
                match f.kind {
                    FaultKind::FibreBreak { segment, until } => {
                        if let Some(c) = cuts.get_mut(segment) {
                            c.push(f.at);
                            c.extend(until.map(|u| u.max(f.at)));
                        }
                    }
                    FaultKind::PowerOff { node, .. } => {
                        if let Some(c) = cuts.get_mut(node) {
                            c.push(f.at);
                        }
                    }
                    _ => {}
                }
            }
            for c in &mut cuts {
                c.sort_unstable();
            }
        }
        let mut sim = Simulation {
            out_floors: OutFloors::new(
                n,
                (0..n).map(|k| {
                    seg_delays
                        .get((k + n - 1) % n)
                        .copied()
                        .unwrap_or(Duration::ZERO)
                }),
            ),
            min_fibre_delay: seg_delays
                .iter()
                .copied()
                .min()
                .filter(|d| *d > Duration::ZERO),
            seg_delays: seg_delays.clone(),
            plain_ring: ring
                && segments.iter().all(|s| s.plain)
                && nodes.iter().all(|nd| nd.off_windows.is_empty()),
            plain_hop: vec![NOT_PLAIN; n],
            run_end: (0..n).collect(),
            static_plain,
            topology: cfg.topology,
            delivery: cfg.delivery,
            nodes,
            segments,
            faults: cfg.faults,
            queue: WakeQueue::new(n, fault_events),
            recorder,
            stats: SimStats::default(),
            touched: Vec::new(),
            rewake: Vec::new(),
            rewake_done: NO_NODE,
            buf: Vec::new(),
            pins: Vec::new(),
            bus_busy_until: Instant::ZERO,
            bus_line: None,
            now: Instant::ZERO,
            lookahead: Lookahead::default(),
            stacks: crate::host_coroutine::Stacks::default(),
            resumes: std::collections::BinaryHeap::new(),
            light_wakes: true,
            master_reach: (Duration::ZERO, Vec::new()),
            short_paths: true,
            run_ahead_ok,
            run_to: Instant::ZERO,
            ran_to: Instant::ZERO,
            plain_pass: None,
            from_master,
            first_drifting: drifting,
            deferred: Vec::new(),
            replay_to: None,
            replay_copy: false,
            faulty,
            cuts,
            held_fillers: Vec::new(),
            master_next: None,
            joined_parks: false,
        };
        sim.start_hosts();
        sim.settle();
        Ok(sim)
    }

    /// Chooses how nodes' wakes are found (both give the same traces; a matter of speed).
    pub fn set_lookahead(&mut self, l: Lookahead) {
        self.lookahead = l;
    }

    /// The current simulation time: after [`Simulation::run_until`]`(t)` at least `t`, and
    /// later where a host's bus access ran on past `t` (the events run inside the access
    /// carry it; how far depends on the path, [`Delivery`]). A program that drives a run
    /// step by step schedules its steps from the instants it asked for, not from this
    /// (spec-notes "The runner's schedule").
    pub fn now(&self) -> Instant {
        self.now
    }

    /// Counters so far.
    pub fn stats(&self) -> SimStats {
        self.stats
    }

    /// Number of nodes (master and slaves).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The controller of node `i` (for reading its registers and RAM after a run;
    /// accesses through it cost nothing and do not advance it).
    pub fn chip_mut(&mut self, i: usize) -> Option<&mut Chip> {
        self.nodes.get_mut(i).map(|n| &mut n.chip)
    }

    /// Whether node `i` is powered now.
    pub fn powered(&self, i: usize) -> bool {
        self.nodes.get(i).is_some_and(|n| n.powered)
    }

    /// The total delay from node `from`'s transmitter to node `to`'s receiver along the
    /// ring for a signal at `bit_time`: fibres plus the repeater latency of every node in
    /// between (`None` on a bus or for unknown nodes).
    pub fn ring_delay(&self, from: usize, to: usize, bit_time: Duration) -> Option<Duration> {
        let Topology::Ring { fibres } = &self.topology else {
            return None;
        };
        let n = fibres.len();
        if from >= n || to >= n {
            return None;
        }
        let mut d = Duration::ZERO;
        let mut k = from;
        loop {
            d += fibres.get(k)?.delay();
            k = (k + 1) % n;
            if k == to {
                return Some(d);
            }
            d += bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        }
    }

    /// Runs every event up to and including `t`, then brings every powered chip to `t`.
    /// A host program that is part way through its work then (waiting in a bus access,
    /// `host_run`) is run to its end, the ring running along in time order (hosts woken
    /// meanwhile too), until no host is in the middle of a wake, so whoever shares a
    /// program's state may look at it when this returns. [`Simulation::now`] may so lie
    /// past `t`. A host that is still at work [`HOST_BREAK_LIMIT`] after `t` gives
    /// [`SimError::HostNeverIdle`].
    pub fn run_until(&mut self, t: Instant) -> Result<(), SimError> {
        self.run_to = t;
        self.ran_to = self.ran_to.max(t);
        self.run_events(t)?;
        self.now = self.now.max(t);
        for j in 0..self.nodes.len() {
            self.advance_node(j, t);
        }
        self.settle();
        let limit = t.saturating_add(HOST_BREAK_LIMIT);
        while let Some(&std::cmp::Reverse((r, j))) = self.resumes.peek() {
            if r > limit {
                return Err(SimError::HostNeverIdle {
                    node: j,
                    from: t,
                    to: limit,
                });
            }
            self.run_events(r)?;
        }
        self.recorder.flush_before(self.now)?;
        Ok(())
    }

    /// Runs the queued events and the hosts' accesses that end (`resumes`) up to and
    /// including `t`, in time order; at one instant the queue's events first (a fault
    /// applies before what the nodes do then, and a node's own events before its host
    /// goes on).
    fn run_events(&mut self, t: Instant) -> Result<(), SimError> {
        loop {
            let resume = self.resumes.peek().map(|std::cmp::Reverse(r)| *r);
            let bound = resume.map_or(t, |(r, _)| r.min(t));
            if let Some(ev) = self.queue.pop_until(bound) {
                self.process(ev)?;
                continue;
            }
            match resume {
                Some((r, j)) if r <= t => {
                    self.resumes.pop();
                    self.resume_host(j, r);
                    self.recorder.flush_before(self.now)?;
                }
                _ => return Ok(()),
            }
        }
    }

    /// Runs one event of the queue and serves the nodes it touched.
    fn process(&mut self, (time, ev): (Instant, Ev)) -> Result<(), SimError> {
        self.now = self.now.max(time);
        self.stats.events += 1;
        // Passes of an earlier event are sent on or forgotten (`early_route`).
        self.deferred.clear();
        match ev {
            Ev::Node(j) => {
                if let Some(node) = self.nodes.get_mut(j) {
                    node.wake = None;
                    node.parked = false;
                }
                if self.wake_node(j, time)? {
                    // Served and rescheduled: one settle round is spent.
                    self.settle_rounds(1);
                    return self.end_event();
                }
            }
            Ev::FaultStart(i) => self.fault_start(i, time)?,
            Ev::FaultEnd(i) => self.fault_end(i, time)?,
        }
        self.settle();
        self.end_event()
    }

    /// The end of an event, its nodes served: the slaves a joined wake parked without their
    /// queue entries are queued (`sim/join_wake.rs`), the traces flushed up to now.
    fn end_event(&mut self) -> Result<(), SimError> {
        if self.joined_parks {
            self.queue_joined_parks();
        }
        self.recorder.flush_before(self.now)
    }

    /// Ends the traces at the latest instant [`Simulation::run_until`] ran to and hands them
    /// over (the simulation can still be inspected; it records nothing more). Not at
    /// [`Simulation::now`]: a host's bus access can carry that past the instant asked for, by
    /// as much as the path's events take (the reference path runs more of them), and a
    /// trace ending there ended elsewhere on the two paths (a VCD's last timestamp, found by
    /// `scripts/reference-random.py` comparing VCDs, session 17).
    pub fn finish(&mut self) -> Result<TraceOutput, SimError> {
        let rec = std::mem::replace(
            &mut self.recorder,
            Recorder::new(crate::config::TraceConfig::default())?,
        );
        rec.finish(self.ran_to)
    }

    fn touch(&mut self, j: usize) {
        if let Some(node) = self.nodes.get_mut(j)
            && !node.is_touched
        {
            node.is_touched = true;
            self.touched.push(j);
        }
    }

    /// Node `j`'s own wake at simulation time `t`: advances it (if powered) and serves it.
    /// Most wakes are for an internal event of the chip (telegram processor windows, frame
    /// starts and ends, transmit starts, timing control) after which its host has nothing
    /// due and no pin events are traced: such a wake only empties the receive log, takes the
    /// chip's output and sets its next wake, as `serve` would, without going through the
    /// touched list (nothing else waits to be served then, so the order is the same).
    /// The master's next wake is taken in the same call when it is the next event
    /// (`sim/join_wake.rs`). Returns whether it did so (`false`: the node is touched or not
    /// powered).
    fn wake_node(&mut self, j: usize, mut t: Instant) -> Result<bool, SimError> {
        let quiet = self.light_wakes && self.touched.is_empty();
        loop {
            let Some(node) = self.nodes.get_mut(j) else {
                return Ok(false);
            };
            if !node.powered {
                return Ok(false);
            }
            let local = node.clock.to_local(t);
            chip_calls::advance(j, &mut node.chip, local);
            if !quiet || !node.quiet_host() {
                self.touch(j);
                return Ok(false);
            }
            // `serve_node` with nothing due but the output; `refresh_hop` would find what it
            // found last (only hosts, power and clock faults change it, and they serve the
            // node).
            self.route_outputs(j);
            // The master's next wake, when it is the next event (`sim/join_wake.rs`).
            match j {
                0 => match self.join_next_wake() {
                    Some(m) => {
                        self.now = m;
                        t = m;
                    }
                    None => break,
                },
                _ => break,
            }
        }
        self.set_wake(j);
        // Its own output came back to it (the master's telegram round the ring), the last
        // node so left: its wake was just set after that input, so `set_rewakes` would
        // find the same one unless more comes (`deliver` then puts it back). Not for a
        // parked node (that wake gives way to the one found).
        if self.short_paths
            && self.rewake.last() == Some(&j)
            && self.rewake_done == NO_NODE
            && self.nodes.get(j).is_some_and(|n| !n.parked)
        {
            self.rewake.pop();
            self.rewake_done = j;
        }
        Ok(true)
    }

    /// Advances node `j` to simulation time `t` (if powered) and serves it.
    fn advance_node(&mut self, j: usize, t: Instant) {
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        if !node.powered {
            return;
        }
        let local = node.clock.to_local(t);
        chip_calls::advance(j, &mut node.chip, local);
        self.touch(j);
    }

    /// Serves the nodes an event touched (pins, hosts, outputs) until quiet, then
    /// reschedules them.
    fn settle(&mut self) {
        self.settle_rounds(0);
    }

    /// [`Simulation::settle`] after `used` rounds of the event's budget.
    fn settle_rounds(&mut self, used: usize) {
        for _ in used..MAX_SETTLE_ROUNDS {
            let Some(j) = self.touched.pop() else {
                self.set_rewakes();
                return;
            };
            if let Some(node) = self.nodes.get_mut(j) {
                node.is_touched = false;
            }
            self.serve(j);
            self.set_wake(j);
        }
        // Left over: reschedule without serving (nothing is lost; they run at their time).
        while let Some(j) = self.touched.pop() {
            if let Some(node) = self.nodes.get_mut(j) {
                node.is_touched = false;
            }
            self.set_wake(j);
        }
        self.set_rewakes();
    }

    /// Sets the wakes of the nodes deliveries left to be rescheduled only (`rewake_done`'s
    /// was set after them).
    fn set_rewakes(&mut self) {
        while let Some(j) = self.rewake.pop() {
            if let Some(node) = self.nodes.get_mut(j) {
                node.is_rewake = false;
            }
            self.set_wake(j);
        }
        let j = std::mem::replace(&mut self.rewake_done, NO_NODE);
        if j != NO_NODE {
            if let Some(node) = self.nodes.get_mut(j) {
                node.is_rewake = false;
            }
            debug_assert!(
                self.next_wake(j)
                    .is_none_or(|w| Some(w) == self.nodes.get(j).map(|n| n.wake)),
                "a node's wake set at its own wake moved before the event's end"
            );
        }
    }

    /// Pin events to the VCD, host wakes, outputs to the line; then whether slave
    /// telegrams may pass node `j` by delays alone (its host may have changed REPON).
    fn serve(&mut self, j: usize) {
        self.serve_node(j);
        self.refresh_hop(j);
    }

    fn serve_node(&mut self, j: usize) {
        if !self.nodes.get(j).is_some_and(|n| n.powered) {
            return;
        }
        // Hosts run with the ring running along (`host_run`).
        self.serve_host(j);
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        if !node.powered {
            return;
        }
        if let Some(v) = node.vcd {
            node.chip.drain_pin_events(&mut self.pins);
            for mut e in self.pins.drain(..) {
                e.at = node.clock.to_global(e.at);
                self.recorder.pin_event(v, e);
            }
        }
        self.route_outputs(j);
    }

    /// Takes what node `j`'s chip released to its output line and sends it on its way.
    fn route_outputs(&mut self, j: usize) {
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        let mut out = std::mem::take(&mut self.buf);
        // A chip run past its output (`run_ahead`) keeps what starts later until then.
        let until = node.clock.to_local(self.now);
        chip_calls::take(j, &mut node.chip, until, &mut out);
        self.route_taken(j, &mut out);
        self.put_buf(out);
        if !self.deferred.is_empty() {
            self.route_deferred();
        }
    }

    /// Puts `out` back as the take buffer (`buf`). What was left there meanwhile is
    /// usually the empty vector `mem::take` put in its place: without an allocation it
    /// holds nothing to drop (a segment is no zero-sized type) and is let go without the
    /// drop glue's call; a buffer a nested take left there is dropped.
    #[inline(always)]
    pub(super) fn put_buf(&mut self, out: Vec<LineSegment>) {
        let left = std::mem::replace(&mut self.buf, out);
        if left.capacity() == 0 {
            // Letting it go frees nothing: no allocation, and so no segment.
            debug_assert!(
                left.capacity() == 0 && left.is_empty(),
                "a take buffer let go with an allocation"
            );
            std::mem::forget(left);
        } else {
            drop(left);
        }
    }

    /// Sends on, in order, the segments taken from node `j`'s chip into `out`, leaving it
    /// empty. A take is usually one segment (a telegram with its filler implied): popped,
    /// without setting up and dropping a drain.
    #[inline]
    pub(super) fn route_taken(&mut self, j: usize, out: &mut Vec<LineSegment>) {
        if out.len() <= 1 {
            if let Some(seg) = out.pop() {
                self.route_output(j, seg);
            }
            debug_assert!(out.is_empty(), "a taken segment was not sent on");
            return;
        }
        for seg in out.drain(..) {
            self.route_output(j, seg);
        }
    }

    /// Recomputes whether a slave telegram passes node `k` by its delays alone.
    fn refresh_hop(&mut self, k: usize) {
        let plain = self.static_plain.get(k).copied().unwrap_or(false)
            && self
                .nodes
                .get(k)
                .is_some_and(|n| n.powered && n.repeating && n.clock.is_identity());
        let up = k
            .checked_sub(1)
            .unwrap_or(self.seg_delays.len().saturating_sub(1));
        let delay = self
            .seg_delays
            .get(up)
            .filter(|_| plain)
            .map_or(NOT_PLAIN, |d| d.as_picos());
        if let Some(p) = self.plain_hop.get_mut(k)
            && *p != delay
        {
            *p = delay;
            // A run of plain repeaters may end elsewhere now.
            self.plain_pass = None;
            let mut end = self.plain_hop.len();
            for (i, (r, p)) in self
                .run_end
                .iter_mut()
                .zip(&self.plain_hop)
                .enumerate()
                .rev()
            {
                if *p == NOT_PLAIN {
                    end = i;
                }
                *r = end;
            }
        }
    }

    /// A segment node `j`'s chip released (local time).
    fn route_output(&mut self, j: usize, mut seg: LineSegment) {
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        while node.expect.front().is_some_and(|e| e.at < seg.start) {
            node.expect.pop_front();
        }
        let mut origin = j;
        // Exact path: a repeater's copy of what it received keeps its origin (the fast
        // path carries received segments itself, `propagate`; the chips release no copies).
        let mut replayed = false;
        // A copy is what starts where it is expected; a telegram is the copy of a telegram
        // expected there (a steady signal's copy due at the same instant, the dark before a
        // repair's replay say, is passed over), and with none it is the chip's own, which
        // shadows a filler's copy due then (410B §1): its origin is this node (the log named
        // it after the filler's origin: a slave's AT logged as the master's MDT on the
        // reference path, found by the mixed property test with moved ATs, no fault).
        let bits = matches!(seg.signal, LineSignal::Bits(_));
        if let Some(i) = node
            .expect
            .iter()
            .take_while(|e| e.at == seg.start)
            .position(|e| e.bits || !bits)
            && let Some(e) = node.expect.remove(i)
        {
            origin = e.origin;
            replayed = e.replayed;
        }
        if matches!(seg.signal, LineSignal::Bits(_)) {
            // The chip's output after its own telegram is taken at the end of it, unless
            // the telegram carries it (an implied filler: any other output then is the
            // chip's next own output, `Chip::next_line_output_except`).
            node.resume = seg.end().filter(|_| !seg.then_filler);
        }
        let Some(mut floor) = self.out_floors.get(j) else {
            return;
        };
        node.map_released(&mut seg, floor);
        let before = floor;
        if node.put_out(&mut floor, &mut seg, origin == j) && before > node.chip_out_end {
            // The chip's output cut a telegram the fast path put out ahead of it (`repeat_out`,
            // `pass_plain`): the chip knew nothing of it and sends no rest after its own.
            self.stats.fast_path_collisions += 1;
        }
        node.chip_out_end = floor;
        self.out_floors.set(j, floor);
        self.floor_written(j);
        if replayed {
            let replay_to = self.replay_to;
            self.propagate_marked(j, seg, origin, (replay_to, true));
        } else {
            self.propagate(j, seg, origin, true);
        }
    }

    /// Carries `seg` (simulation time, at the entrance of segment `from`) down the line.
    /// `enter`: apply the segment's break and faults (false for a break's own darkness).
    fn propagate(&mut self, from: usize, mut seg: LineSegment, origin: usize, enter: bool) {
        if matches!(self.topology, Topology::Bus { .. }) {
            self.propagate_bus(seg, origin);
            return;
        }
        let n = self.nodes.len();
        let fast = self.delivery == Delivery::Fast;
        if origin == 0 {
            self.master_next = None;
            if fast && self.plain_ring && self.short_paths {
                self.propagate_master_plain(from, seg);
                return;
            }
        }
        let mut cur = from;
        let mut enter = enter;
        // Fast path: a slave's telegram or filler goes to no slave (see below), so through
        // a run of plain repeaters (410B §1: "The slaves regenerate and repeat their received
        // data") it only moves by fibre delay plus repeater latency, hop after hop, without
        // touching the nodes.
        // The repeaters' latency, 410B §1 (found at the first repeater).
        let mut lat: Option<Duration> = None;
        // Not a replay (a repair, a power-on): every receiver behind the fresh one gets it
        // (see `deliver` below), plain repeaters too.
        let passes = fast
            && origin != 0
            && enter
            && matches!(seg.signal, LineSignal::Bits(_) | LineSignal::Filler)
            && self.replay_to.is_none()
            && !self.replay_copy;
        for _ in 0..n {
            if passes {
                if self.faulty {
                    self.count_steady_receivers(cur);
                }
                self.pass_plain(&mut cur, &mut seg);
            }
            // The next node round the ring (no division: this runs at every hop).
            let next = if cur + 1 >= n { 0 } else { cur + 1 };
            if seg.then_filler && enter && !self.plain_ring && self.splits_filler(cur) {
                // The fibre's faults or traces take the telegram and its filler apart.
                let (bits, filler) = seg.split_filler();
                self.propagate(cur, bits, origin, true);
                if let Some(f) = filler {
                    if self.faulty && self.cut_before(cur, f.start) {
                        self.hold_filler(cur, f, origin);
                    } else {
                        self.propagate(cur, f, origin, true);
                    }
                }
                return;
            }
            if !self.plain_ring {
                let Some(s) = self.segments.get_mut(cur) else {
                    return;
                };
                if enter && !s.plain {
                    if s.keep_last {
                        s.keep_entered(&seg, origin);
                    }
                    // A clean fibre (the usual case) leaves the segment as it is.
                    if !s.faults.is_clean() {
                        if s.faults.broken_at(seg.start) {
                            return;
                        }
                        seg = s.faults.apply(seg);
                    }
                    // A replay (a repair, a power-on downstream) sends again what already
                    // entered fibre `from` and was traced there: the trace shows each
                    // telegram where it enters the segment, once (spec-notes "Trace times";
                    // 410B §1 a fibre carries one signal). Further fibres get it anew.
                    if self.recorder.wants(cur) && !(self.replay_to.is_some() && cur == from) {
                        self.recorder.observe(cur, &seg, origin_of(origin));
                    }
                }
            }
            debug_assert!(
                !self.plain_ring
                    || self.segments.get(cur).is_some_and(|s| s.plain)
                        && self
                            .nodes
                            .get(next)
                            .is_some_and(|n| n.off_windows.is_empty()),
                "a plain ring's fibre or node is not plain"
            );
            enter = true;
            let Some(delay) = self.seg_delays.get(cur) else {
                return;
            };
            seg.start = seg.start.saturating_add(*delay);
            let Some(node) = self.nodes.get(next) else {
                return;
            };
            // A plain ring's nodes have no power windows (`plain_ring`).
            if !(if self.plain_ring {
                node.powered
            } else {
                node.powered_at(seg.start)
            }) {
                return;
            }
            // Fast path: slaves ignore other slaves' telegrams (410B §1: "Only transmission
            // data which is intended for the particular interface user is processed"), so
            // a slave's ATs and filler go only to the master. A slave's receiver then follows
            // the master's filler, which never ends between the master's telegrams; a fresh
            // receiver (a node powered on, a fibre repaired) has none and gets the replay of
            // what enters its fibre whatever its origin, or it would see no edges until the
            // master's next telegram (410B §4.1 2H.13 FIBBR).
            let deliver = !fast
                || next == 0
                || origin == 0
                || !matches!(seg.signal, LineSignal::Bits(_) | LineSignal::Filler)
                // Every receiver down the ring from a repaired fibre or a node powered on
                // was dark (the darkness was repeated, 410B §1), not only the first one:
                // each gets the replay (else FIBBR stayed set behind the first until the
                // master's next telegram, 410B §4.1 2H.13, where the exact path clears it).
                || self.replay_to.is_some()
                || self.replay_copy;
            let repeating = node.repeating && next != 0;
            if !fast || !repeating {
                // The last hop: the segment itself goes to the receiver.
                if deliver {
                    self.deliver(next, seg, origin, repeating);
                }
                return;
            }
            // The segment's bit time is the same at every hop.
            let lat =
                *lat.get_or_insert_with(|| seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS));
            // A run with faults: an own output of the repeater may come first or cut the
            // copy (410B §1 "or send their own telegrams": the transmitter shadows or cuts
            // the forwarded signal), brought on by the input itself (a slave that lost its
            // MST sends its AT as the MDT comes in). Put out here, ahead of the chip, the
            // copy would hold that output back and reach the nodes further on whole; the
            // chip forwards it instead, as on the exact path, and it goes on from there at
            // its time. Whether an own output comes is known only once the chip has taken
            // the input, and a chip not run ahead has not: so every copy, not only those
            // found in the way (the run is the same with slaves run ahead or not). A replay
            // (a repair, a power-on) too: its copies put out ahead of the chip went out
            // before the chip's own copies of what came just before (the dark of a
            // power-off at the same instant), which then followed and cut them (INT_FIBBR
            // at the master on the fast path only); its chip's copies reach every node
            // behind as the replay does (`ExpectedCopy::replayed`, `deliver` above). A fault-free run
            // keeps every own output clear of the copies; so does a plain ring (no fibre
            // fault, no power window: clock drifts only, whose master's telegrams take
            // `propagate_master_plain`).
            if self.faulty && !self.plain_ring {
                self.deliver_chip_forwards(next, seg, origin);
                return;
            }
            if deliver {
                self.deliver(next, seg.clone(), origin, repeating);
            }
            if !self.repeat_out(next, &mut seg, lat) {
                return;
            }
            cur = next;
        }
    }

    /// A slave's segment at the entrance of fibre `cur` is about to pass the run of plain
    /// repeaters after it without their chips (`pass_plain`) in a run with faults: counted as
    /// a collision the fast path cannot follow when one of them hears a steady line, its last
    /// input a telegram with no filler after it (`Chip::line_steady_after_last_input`). The
    /// fast path gives a slave's telegrams to no slave because its receiver follows the
    /// master's filler (see above); with faults the chips forward the master's telegrams and
    /// their filler hop by hop, and a slave's own telegram starting where a repeated one ends
    /// cuts the filler after that to nothing, so that the slaves behind get the master's
    /// telegram and then nothing but other slaves' telegrams and filler (410B §1): without
    /// them their receivers see no edge (FIBBR, 410B §4.1 2H.13) and their transmitters resume
    /// no filler after their own ATs, which the master then sees end in a steady line (its
    /// FIBBR set on the fast path only; 3 slaves at 2 Mbit/s, slave 1's AT 12 µs early, found
    /// by a property test with one fibre logged).
    #[cold]
    #[inline(never)]
    fn count_steady_receivers(&mut self, cur: usize) {
        let first = cur + 1;
        let stop = self.run_end.get(first).copied().unwrap_or(first);
        let steady = self
            .nodes
            .get(first..stop)
            .is_some_and(|run| run.iter().any(|n| n.chip.line_steady_after_last_input()));
        if steady {
            self.stats.fast_path_collisions += 1;
        }
    }

    /// Hands `seg` to repeater `k` with its chip releasing the copy itself (as on the exact
    /// path, `Chip::set_forward_output`): the copy is expected back with its origin
    /// (`route_output`) when the chip puts it out, unless an own output shadows or cuts it.
    #[cold]
    #[inline(never)]
    fn deliver_chip_forwards(&mut self, k: usize, seg: LineSegment, origin: usize) {
        let lat = seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        let bits = matches!(seg.signal, LineSignal::Bits(_));
        if let Some(node) = self.nodes.get_mut(k) {
            node.chip.set_forward_output(true);
        }
        self.deliver(k, seg, origin, true);
        let replayed = self.replay_to.is_some() || self.replay_copy;
        if let Some(node) = self.nodes.get_mut(k) {
            node.chip.set_forward_output(false);
            let at = node.in_floor.saturating_add(lat);
            node.expect.push_back(crate::node::ExpectedCopy {
                at,
                origin,
                replayed,
                bits,
            });
        }
        self.touch(k);
    }

    /// [`Simulation::propagate`] of a master's segment on a plain ring (`plain_ring`) on the
    /// fast path: the same hops with what is the same at every hop found once (no fibre
    /// to split, fault or trace, no power window; every node gets the master's segment;
    /// the repeater latency from the one bit time, 410B §1).
    fn propagate_master_plain(&mut self, from: usize, mut seg: LineSegment) {
        let n = self.nodes.len();
        let lat = seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        if from == 0 && self.run_end.get(1) == Some(&n) {
            self.sweep_master_plain(seg, lat);
            return;
        }
        let mut cur = from;
        for _ in 0..n {
            let next = if cur + 1 >= n { 0 } else { cur + 1 };
            let Some(delay) = self.seg_delays.get(cur) else {
                return;
            };
            seg.start = seg.start.saturating_add(*delay);
            debug_assert!(
                self.segments.get(cur).is_some_and(|s| s.plain)
                    && self
                        .nodes
                        .get(next)
                        .is_some_and(|n| n.off_windows.is_empty()),
                "a plain ring's fibre or node is not plain"
            );
            let Some(node) = self.nodes.get(next) else {
                return;
            };
            // A plain ring's nodes have no power windows (`plain_ring`).
            if !node.powered {
                return;
            }
            if !node.repeating || next == 0 {
                // The last hop: the segment itself goes to the receiver.
                self.deliver(next, seg, 0, false);
                return;
            }
            self.deliver(next, seg.clone(), 0, true);
            if !self.repeat_out(next, &mut seg, lat) {
                return;
            }
            cur = next;
        }
    }

    /// [`Simulation::propagate_master_plain`] of the master's segment when every slave is a
    /// plain repeater (`run_end`: powered, repeating, on the simulation's clock; 410B §1:
    /// "The slaves regenerate and repeat their received data"): each gets it and puts it
    /// out `lat` later, not before its output floor, and the master gets it back. The
    /// floors are a sweep (`OutFloors::open_sweep`): read and written as they are, and kept
    /// as one run after it where the segment was held up at none but the first slave's
    /// (then each is one offset above the hops, `OutFloors` module notes), so that the
    /// slaves' ATs after it pass in constant time (`sim/plain_pass.rs`). A segment entering
    /// at or above every floor's offset over the hops is held up at none
    /// (`OutFloors::free_sweep`): the floors are kept as that run at once, none read or
    /// written hop by hop.
    fn sweep_master_plain(&mut self, mut seg: LineSegment, lat: Duration) {
        let n = self.nodes.len();
        // What each slave's delivery shares (`sim/swept.rs`).
        let sw = self.swept(&seg, lat);
        // Every slave's floor is written below (nothing reads the last plain pass before).
        self.floors_written(1..n);
        let crossing = Crossing {
            start: seg.start,
            len: seg
                .end()
                .map_or(Duration::ZERO, |e| e.saturating_duration_since(seg.start)),
            lat,
        };
        if self.out_floors.free_sweep(1..n, crossing) {
            // Held up at no floor (`OutFloors::free_sweep`; `repeat_out` on the simulation's
            // clock): only the hops and the latency.
            for next in 1..n {
                let Some(delay) = self.seg_delays.get(next - 1) else {
                    return;
                };
                seg.start = seg.start.saturating_add(*delay);
                debug_assert!(
                    self.nodes.get(next).is_some_and(|n| !n.track_levels),
                    "levels followed on the fast path"
                );
                self.deliver_swept(next, seg.clone(), &sw);
                seg.start = seg.start.saturating_add(lat);
                seg.distorted = false;
            }
            self.sweep_into_master(seg);
            return;
        }
        self.out_floors.open_sweep(lat);
        let mut uniform = true;
        for next in 1..n {
            let Some(delay) = self.seg_delays.get(next - 1) else {
                return;
            };
            seg.start = seg.start.saturating_add(*delay);
            debug_assert!(
                self.segments.get(next - 1).is_some_and(|s| s.plain)
                    && self
                        .nodes
                        .get(next)
                        .is_some_and(|n| n.off_windows.is_empty()
                            && n.powered
                            && n.repeating
                            && n.clock.is_identity()),
                "a plain ring's fibre or slave is not plain"
            );
            self.deliver_swept(next, seg.clone(), &sw);
            // `repeat_out` on the simulation's clock.
            seg.start = seg.start.saturating_add(lat);
            seg.distorted = false;
            let (Some(node), Some(mut floor)) =
                (self.nodes.get_mut(next), self.out_floors.swept(next))
            else {
                return;
            };
            if seg.start < floor && !matches!(seg.signal, LineSignal::Dark | LineSignal::Light) {
                if matches!(seg.signal, LineSignal::Bits(_)) {
                    self.stats.fast_path_collisions += 1;
                }
                seg.start = floor;
                // Held at the first floor, the others are above it by the hops alone.
                uniform &= next == 1;
            }
            node.put_out(&mut floor, &mut seg, false);
            self.out_floors.sweep_set(next, floor);
        }
        self.out_floors.close_sweep(1..n, uniform);
        self.sweep_into_master(seg);
    }

    /// The master's segment of a sweep, put out by the last slave, over the last fibre into
    /// the master (`propagate_master_plain`'s last hop).
    #[inline]
    fn sweep_into_master(&mut self, mut seg: LineSegment) {
        let Some(delay) = self.seg_delays.last() else {
            return;
        };
        seg.start = seg.start.saturating_add(*delay);
        match self.nodes.first() {
            Some(m) if m.powered && m.clock.is_identity() => self.deliver_into_master(seg, 0),
            Some(m) if m.powered => self.deliver(0, seg, 0, false),
            _ => {}
        }
    }

    /// Repeater `next` puts out its copy of `seg` (410B §1: the slaves regenerate and repeat
    /// their received data), `lat` after it came in by the node's clock, not before the end
    /// of what it put out last (its output floor, raised to the copy's end). `false`: no
    /// such node.
    #[inline(always)]
    fn repeat_out(&mut self, next: usize, seg: &mut LineSegment, lat: Duration) -> bool {
        let Some(node) = self.nodes.get_mut(next) else {
            return false;
        };
        let l_out = node.clock.to_local(seg.start).saturating_add(lat);
        seg.start = node.clock.to_global(l_out);
        seg.distorted = false;
        let Some(mut floor) = self.out_floors.get(next) else {
            return false;
        };
        // The fast path's copy, put out ahead of the repeater's chip, waits behind what its
        // output carries (410B §1: the chip would cut or shadow one of the two; the run may
        // differ from the reference path's: counted). A filler waits as the chip's resume
        // after its own telegram would send it.
        if seg.start < floor && !matches!(seg.signal, LineSignal::Dark | LineSignal::Light) {
            if matches!(seg.signal, LineSignal::Bits(_)) {
                self.stats.fast_path_collisions += 1;
            }
            seg.start = floor;
        }
        node.put_out(&mut floor, seg, false);
        self.out_floors.set(next, floor);
        self.floor_written(next);
        true
    }

    /// Whether a segment entering fibre `k` is taken as its bits and their filler: the
    /// fibre has faults, keeps what entered it or is traced.
    fn splits_filler(&self, k: usize) -> bool {
        self.segments.get(k).is_none_or(|s| !s.plain)
    }

    /// Whether a fault cuts what enters fibre `k` after now and before `end`
    /// (`Simulation::cuts`).
    fn cut_before(&self, k: usize, end: Instant) -> bool {
        self.cuts
            .get(k)
            .is_some_and(|c| c.iter().any(|t| *t > self.now && *t < end))
    }

    /// Holds back a filler split from its telegram at the entrance of fibre `k` while a
    /// fault that cuts the telegram is still to come (410B §1: each fibre carries one
    /// signal, which a repeater regenerates and repeats; a break or a dark transmitter
    /// ends it there, whole or not). Handed to the receiver ahead, the filler raised its
    /// input floor to the telegram's end, so the dark of a break or a power-off inside the
    /// telegram reached the receiver only from that end, and a repair's replay of the
    /// telegram's rest not at all: the telegram got through whole, where the reference path
    /// (whose chips put the filler out as its own segment at the telegram's end) cuts it.
    /// It enters after that fault (`release_fillers`). Runs with faults only.
    #[cold]
    #[inline(never)]
    fn hold_filler(&mut self, k: usize, seg: LineSegment, origin: usize) {
        self.held_fillers.push(HeldFiller {
            fibre: k,
            seg,
            origin,
            replay_to: self.replay_to,
            replay_copy: self.replay_copy,
        });
    }

    /// After a fault on fibre `k` at the current instant: the fillers held back there
    /// (`hold_filler`) enter it unless another cut comes before them; `dropped` (a
    /// power-off of the node sending them): they never leave it.
    fn release_fillers(&mut self, k: usize, dropped: bool) {
        if !self.held_fillers.iter().any(|h| h.fibre == k) {
            return;
        }
        let (mine, rest): (Vec<_>, Vec<_>) = std::mem::take(&mut self.held_fillers)
            .into_iter()
            .partition(|h| h.fibre == k);
        self.held_fillers = rest;
        if dropped {
            return;
        }
        for h in mine {
            if self.cut_before(k, h.seg.start) {
                self.held_fillers.push(h);
                continue;
            }
            self.propagate_marked(k, h.seg, h.origin, (h.replay_to, h.replay_copy));
        }
    }

    /// [`Simulation::propagate`] of `seg` with the replay marks `(replay_to, replay_copy)`
    /// in force (a replay's copy, a held filler of a replay), the marks before restored.
    #[cold]
    #[inline(never)]
    fn propagate_marked(
        &mut self,
        k: usize,
        seg: LineSegment,
        origin: usize,
        marks: (Option<usize>, bool),
    ) {
        let before = (self.replay_to, self.replay_copy);
        (self.replay_to, self.replay_copy) = marks;
        self.propagate(k, seg, origin, true);
        (self.replay_to, self.replay_copy) = before;
    }

    /// Hands `local` (given in simulation time, taken to the node's time here) to node `j`'s
    /// receiver.
    #[inline(always)]
    fn deliver(&mut self, j: usize, local: LineSegment, origin: usize, repeating: bool) {
        self.deliver_in(j, local, origin, repeating, None);
    }

    /// [`Simulation::deliver`]; `swept`: a slave's delivery of the master's segment in a
    /// sweep, with what every slave's delivery of it shares found once (`sim/swept.rs`), or
    /// the master's of a segment back round a plain ring (`Swept::INTO_MASTER`), taken as
    /// found when the segment comes in order and is bits; otherwise the general way
    /// (`take_general`, out of line).
    fn deliver_in(
        &mut self,
        j: usize,
        mut local: LineSegment,
        origin: usize,
        repeating: bool,
        swept: Option<&swept::Swept>,
    ) {
        #[cfg(debug_assertions)]
        if let Some(sw) = swept {
            self.check_swept(j, &local, sw);
        }
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        let swept = swept.filter(|_| {
            local.start >= node.in_floor && matches!(local.signal, LineSignal::Bits(_))
        });
        let (ahead, start, ahead_to, past);
        if let Some(sw) = swept {
            (ahead, start, ahead_to) = swept::take_swept(node, &mut self.stats, &local, sw);
            debug_assert_eq!(
                ahead_to,
                run_ahead_end(
                    self.run_ahead_ok && self.lookahead == Lookahead::Events,
                    origin,
                    j,
                    node,
                    &local
                ),
                "a swept delivery's run-ahead end"
            );
            // `run_ahead` takes the sweep's promise (`swept_run_bounds`), not `past`.
            past = None;
        } else {
            let marks = GeneralMarks {
                delivery: self.delivery,
                runs: self.run_ahead_ok && self.lookahead == Lookahead::Events,
                replay: self.replay_to.is_some() || self.replay_copy,
            };
            match take_general(
                node,
                &mut self.stats,
                marks,
                (j, origin, repeating),
                &mut local,
            ) {
                Some(g) => (ahead, start, ahead_to, past) = g,
                None => return,
            }
        }
        chip_calls::input(j, &mut node.chip, local);
        self.stats.deliveries += 1;
        // A segment that starts after the chip's time adds events from its start on only
        // (`Chip::line_input`; it may also put a pending event off, such as the FIBBR
        // timeout, 410B §4.1 2H.13): a node whose pending wake comes no later, with nothing
        // for its host, would be served for nothing now (no output, no pin change; the
        // frames are taken at that wake) and would get a wake no earlier. It keeps its
        // wake; if nothing is due then, that wake only sets the next one. Debug builds check
        // that the wake it would get is not earlier.
        if ahead && node.quiet_host() && !node.is_touched {
            if node.is_rewake {
                // Its wake is set once the event's nodes are served, after this input too
                // (found again even when its own wake set it meanwhile, `set_rewakes`).
                if self.rewake_done == j {
                    self.rewake_done = NO_NODE;
                    self.rewake.push(j);
                }
                return;
            }
            // A parked node's wake is no wake of its own (`Simulation::park`). The input may
            // still bring an event before that wake: a receiver decodes the end of the bits
            // before it (an abort, a frame's end) once it sees how the line goes on, which
            // may be an earlier segment's rest cut or resumed at a repeater (410B §1): then
            // the wake found is taken.
            if !node.parked
                && node.wake.is_some_and(|w| w <= start)
                && self.next_wake(j).is_none_or(|w| {
                    w.is_none_or(|w| self.nodes.get(j).and_then(|n| n.wake) <= Some(w))
                })
            {
                return;
            }
            if let Some(end) = ahead_to
                && self.run_ahead(j, end, past, swept)
            {
                self.deferred.push(j);
            }
            let Some(node) = self.nodes.get_mut(j) else {
                return;
            };
            if !node.chip.line_output_due_at(node.clock.to_local(self.now)) {
                // Serving it would find nothing to do but its next wake (no host due, no
                // output, nothing traced): only that is set, once the event's nodes are
                // served (its wake may only come earlier: the input adds frames and
                // changes). After them, so that a node woken now sets its own wake
                // first, where the queue keeps it (`WakeQueue` module notes).
                if !node.is_rewake {
                    node.is_rewake = true;
                    self.rewake.push(j);
                }
                return;
            }
        }
        self.touch(j);
    }

    /// Runs slave `j`'s chip ahead, right after the master's telegram ending at `end`
    /// (simulation time) reached it, to just before the earliest of that end, the node's next
    /// wake and the next fault event, and no further than the end of the current run (where
    /// every chip is brought and may be read): its frames are processed while its state is at hand
    /// (the telegram processor's work for the MST and the MDT then runs for one slave after
    /// the other, not inside each slave's own wake; docs/performance.md, session 7).
    ///
    /// Nothing can reach the chip or read it before then, so the run is the one its next
    /// wake would do. Every host is inert ([`HostProgram::inert`]): no bus access, no
    /// deadline, no transmitter mode changed after the start. On a ring the master's next
    /// segment starts after this one ends (an own telegram is never cut but by a reset or a
    /// power-off; the output floors keep the order at every repeater), and a slave's own
    /// telegrams and filler reach no slave on the fast path (`Simulation::propagate`); only a
    /// fault could bring anything else, and none happens before the limit. The node's next
    /// wake bounds it too: the chip's next output, and its next internal event when an
    /// interrupt output or a pin can be seen (`Chip::next_output_bound`), come no earlier.
    /// The caller gives only slaves on the simulation's clock (`deliver`): then an instant
    /// before the limit is one before every later input in the chip's time too.
    ///
    /// When the telegram `past` carries its filler (its bit time given) and the master
    /// promises its next output whatever it receives ([`Simulation::master_horizon`]), the
    /// limit is that output's arrival here instead of the telegram's end and the node's
    /// wake: the chip runs through its own output too, which waits in it until the
    /// simulation's time reaches it (`route_outputs`) or is sent on with the other slaves'
    /// (`early_route`). Returns whether it ran so.
    ///
    /// `swept`: in a sweep of the master's segment, whose limit and master's promise are the
    /// sweep's (`sim/swept.rs`).
    #[inline(always)]
    fn run_ahead(
        &mut self,
        j: usize,
        end: Instant,
        past: Option<Duration>,
        swept: Option<&swept::Swept>,
    ) -> bool {
        let (mut limit, horizon) = match swept {
            Some(sw) => self.swept_run_bounds(j, sw),
            None => (
                self.run_ahead_limit(),
                past.and_then(|bit_time| self.master_horizon(j, bit_time)),
            ),
        };
        if let Some(h) = horizon {
            // Through the node's own output too (taken at its wake, `route_outputs`, or
            // right after this pass, `early_route`).
            return self.run_ahead_to(j, limit.min(h), true);
        }
        let wake = match self.next_wake(j) {
            Some(w) => w,
            None => self.nodes.get(j).and_then(|n| n.wake),
        };
        limit = limit.min(end);
        if let Some(w) = wake {
            limit = limit.min(w);
        }
        self.run_ahead_to(j, limit, false);
        false
    }

    /// How far a run-ahead may go at most (`run_ahead`): just before the end of the current
    /// run and the next fault event.
    fn run_ahead_limit(&self) -> Instant {
        let limit = self.run_to.saturating_add(Duration::from_picos(1));
        match self.queue.peek_fault_time() {
            Some(f) => limit.min(f),
            None => limit,
        }
    }

    /// When the master's next output can reach node `j` at the earliest, whatever the
    /// master receives meanwhile (`Chip::next_output_for_any_input`, plus the fibres' delay
    /// and the repeater latency of the nodes in between at `bit_time`, the master's; 410B
    /// §1); `None` unless both are on the simulation's clock and `j`'s pins are not traced
    /// (its pin events would come ahead of the simulation's time).
    fn master_horizon(&mut self, j: usize, bit_time: Duration) -> Option<Instant> {
        let master = self.nodes.first()?;
        let node = self.nodes.get(j)?;
        if !master.powered
            || !master.clock.is_identity()
            || node.vcd.is_some()
            || j > self.first_drifting
        {
            return None;
        }
        let out = self.master_out()?;
        let repeaters = u64::try_from(j.saturating_sub(1)).ok()?;
        let latency = bit_time
            .saturating_mul(REPEATER_LATENCY_BITS)
            .saturating_mul(repeaters);
        Some(
            out.saturating_add(self.from_master.get(j).copied()?)
                .saturating_add(latency),
        )
    }

    /// The master's next output for any input (`Chip::next_output_for_any_input`, 410B
    /// §4.2.1 TRT), found once per pass of its telegram (`master_next`).
    #[inline(always)]
    fn master_out(&mut self) -> Option<Instant> {
        let out = match self.master_next {
            Some(out) => out,
            None => {
                let out = self.nodes.first()?.chip.next_output_for_any_input();
                self.master_next = Some(out);
                out
            }
        };
        debug_assert_eq!(
            out,
            self.nodes
                .first()
                .and_then(|m| m.chip.next_output_for_any_input()),
            "the master changed within a pass of its telegram"
        );
        out
    }

    /// Whether slaves run ahead after a telegram of the master (`run_ahead_ok`, woken at
    /// their next possible output: `Lookahead::Events`).
    fn runs_ahead(&self) -> bool {
        self.run_ahead_ok && self.lookahead == Lookahead::Events
    }

    /// [`Simulation::run_ahead`] to just before `limit`; `past_output`: through the node's
    /// own output (a plain advance), else before it (the bound kept). Whether it ran past.
    #[inline(always)]
    fn run_ahead_to(&mut self, j: usize, limit: Instant, past_output: bool) -> bool {
        // Just before: an input or an event at the limit itself keeps its order within the
        // instant (a segment's changes before the MCLK tick at the same instant).
        let Some(to) = limit.as_picos().checked_sub(1).map(Instant::from_picos) else {
            return false;
        };
        let Some(node) = self.nodes.get_mut(j) else {
            return false;
        };
        // Only slaves on the simulation's clock run ahead (`run_ahead_end`, `sim/swept.rs`):
        // `to` is the node's time too.
        debug_assert!(
            node.clock.is_identity(),
            "a run-ahead off the simulation's clock"
        );
        if to > node.chip.now() {
            self.stats.run_aheads += 1;
            if past_output {
                chip_calls::advance(j, &mut node.chip, to);
                node.ran_past = true;
                self.stats.runs_past_output += 1;
                return true;
            }
            node.chip.advance_before_output(to);
        }
        false
    }

    /// Sets node `j`'s wake to [`Simulation::next_wake`], or parks it
    /// ([`Simulation::park`]).
    fn set_wake(&mut self, j: usize) {
        if !self.park(j) {
            self.set_found_wake(j);
        }
    }

    /// [`Simulation::set_wake`] when not parked: the wake found. Not inlined: the parked
    /// case (most slaves' wakes on a ring, `Simulation::park`) then keeps a short frame.
    #[inline(never)]
    fn set_found_wake(&mut self, j: usize) {
        let Some(wake) = self.next_wake(j) else {
            return;
        };
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        node.wake = wake;
        node.park_unqueued = false;
        match wake {
            Some(g) => self.queue.set(j, g),
            None => self.queue.remove(j),
        }
    }

    /// Parks node `j` when its chip ran past its own output since its wake was last set
    /// (`Simulation::run_ahead`) and has nothing left to put out before its own time: its
    /// wake is set to that time instead of being found (which walks the chip's headers,
    /// `Chip::next_output_bound`). The chip is past every event up to its time, so any wake
    /// it has comes no earlier: a wake there is early at worst, and only sets the next one.
    /// It ran up to just before the master's next telegram can reach it, so on a ring that
    /// runs as promised that telegram's delivery comes first, during the master's wake, and
    /// runs the chip on (`deliver` takes a parked node's wake as none); then the wake is set
    /// again, parked or found. Returns whether it parked the node.
    fn park(&mut self, j: usize) -> bool {
        let at = self.parks_at(j);
        let Some(node) = self.nodes.get_mut(j) else {
            return false;
        };
        node.parked = false;
        node.ran_past = false;
        let Some(g) = at else {
            return false;
        };
        node.wake = Some(g);
        node.parked = true;
        node.park_unqueued = false;
        self.queue.park(j, g);
        self.stats.parked_wakes += 1;
        true
    }

    /// Where [`Simulation::park`] would set node `j`'s wake (simulation time); `None` when it
    /// would not park it.
    fn parks_at(&self, j: usize) -> Option<Instant> {
        let node = self.nodes.get(j)?;
        if !node.ran_past || !node.powered || node.host_deadline.is_some() {
            return None;
        }
        let at = node.chip.now();
        // Output it still holds (its own telegram when not sent on with the others'): its
        // wake is that output's start, which may lie before the chip's time. Short path:
        // nothing queued starts before `at` (`Chip::next_line_output_at`, the earliest
        // queued segment or resume, kept by the transmitter: no earlier than any start
        // `next_line_output_except` finds, 410B §1); then the walk of the queue is skipped
        // (debug builds walk it too and compare).
        let held = |chip: &Chip| chip.next_line_output_unexpected().is_some_and(|o| o < at);
        let nothing_before =
            self.short_paths && node.chip.next_line_output_at().is_none_or(|o| o >= at);
        debug_assert!(
            !nothing_before || !held(&node.chip),
            "the park short path missed output held before the chip's time"
        );
        if !nothing_before && held(&node.chip) {
            return None;
        }
        let g = node.clock.to_global(at);
        // A run cut by the end of `run_until` (not by the master's telegram): its wake would
        // be served at that end for nothing.
        if g <= self.now || g >= self.run_to {
            return None;
        }
        Some(g)
    }

    /// Node `j`'s next wake as [`Simulation::set_wake`] sets it; `None` when the pending
    /// one stays as it is.
    fn next_wake(&self, j: usize) -> Option<Option<Instant>> {
        let now = self.now;
        let exact = self.delivery == Delivery::Exact;
        let lookahead = self.lookahead;
        let node = self.nodes.get(j)?;
        let mut next: Option<Instant> = None;
        if node.powered {
            let chip_now = node.chip.now();
            let mut cand = |t: Option<Instant>| {
                if let Some(t) = t {
                    next = Some(next.map_or(t, |n: Instant| n.min(t)));
                }
            };
            // Fast path: the chip's next possible own output (`Chip::next_output_bound`:
            // its next transmit telegram or cycle start, 410B §4.2.1 TRT, unless a pin or
            // an interrupt output can be seen; then its next internal event). Receive
            // events before it are processed at the next advance, with the same results.
            if lookahead == Lookahead::Events && !exact {
                // Fast path: the chip releases no copies of what it repeats (the simulation
                // carried them down the ring when they arrived, 410B §1 "The slaves
                // regenerate and repeat their received data"; `Chip::set_forward_output`):
                // its own output and anything else it releases wake it.
                cand(node.chip.next_output_bound());
                cand(node.chip.next_line_output_unexpected());
            } else {
                cand(general_wake(node, lookahead, exact));
            }
            cand(node.host_deadline);
            cand(node.resume.filter(|r| *r > chip_now));
        }
        let global = next.map(|l| node.clock.to_global(l).max(now));
        if node.wake == global {
            return None;
        }
        let Some(g) = global else {
            return Some(None);
        };
        // A deadline that does not move on would be served again at once: one picosecond
        // later at least, so that time always advances.
        let g = if g <= node.clock.to_global(node.chip.now()) && g <= now {
            now.saturating_add(Duration::from_picos(1))
        } else {
            g
        };
        Some(Some(g))
    }

    fn fault_start(&mut self, i: usize, t: Instant) -> Result<(), SimError> {
        let Some(f) = self.faults.get(i).copied() else {
            return Ok(());
        };
        match f.kind {
            FaultKind::FibreBreak { segment, .. } => {
                // The fibre goes dark at its far end after the delay.
                let dark = LineSegment::steady(t, Duration::ZERO, LineSignal::Dark, false);
                let dark = LineSegment {
                    bit_time: self.bit_time_hint(segment),
                    ..dark
                };
                self.propagate(segment, dark, segment, false);
                self.release_fillers(segment, false);
            }
            FaultKind::PowerOff { node, .. } => {
                // A node is off while any of its power-off windows lasts (`Node::powered_at`):
                // one that starts while it is off already changes nothing.
                if self.nodes.get(node).is_some_and(|n| !n.powered) {
                    return Ok(());
                }
                // The others run up to `t` and put out what they send then; the node itself
                // is brought to `t` (its frozen state the same on both paths) but sends
                // nothing from `t` on: the power-off applies before its output at `t` (the
                // queue gives faults first at an instant; spec-notes "Faults: exact
                // accounting", same-instant rule).
                for k in 0..self.nodes.len() {
                    if k != node {
                        self.advance_node(k, t);
                    }
                }
                if let Some(n) = self.nodes.get_mut(node)
                    && n.powered
                {
                    let local = n.clock.to_local(t);
                    n.chip.advance_to(local);
                }
                self.settle();
                // Its host's wake under way ends on the chip alone (what it does reaches
                // nobody now; at power-on the program starts over, `Wake::PowerOn`).
                self.finish_host_alone(node);
                if let Some(n) = self.nodes.get_mut(node) {
                    n.powered = false;
                    n.parked = false;
                    if n.wake.take().is_some() {
                        self.queue.remove(node);
                    }
                    n.expect.clear();
                }
                // Its output ends at `t` (the dark below cuts what it put out there): the
                // floor is `t`, not the end of that output. Kept at the output's end, it put
                // the fresh chip's first output (a power-on at `t`, or soon after) behind a
                // telegram that never left: a slave powered off and on at its AT's start
                // (zero length) sent its dark 18.5 µs late, and on the fast path the
                // replay's copies behind it too (spec-notes "Faults: exact accounting").
                self.out_floors.set(node, t);
                self.floor_written(node);
                self.refresh_hop(node);
                // Its transmitter goes dark.
                let dark =
                    LineSegment::steady(t, self.bit_time_hint(node), LineSignal::Dark, false);
                self.propagate(node, dark, node, true);
                self.release_fillers(node, true);
            }
            FaultKind::ClockDrift { node, ppm } => {
                self.advance_node(node, t);
                if let Some(n) = self.nodes.get_mut(node) {
                    if n.clock.is_identity() {
                        n.start_contiguity();
                    }
                    n.clock.set_error_ppb(t, ppm_to_ppb(ppm));
                }
                self.first_drifting = first_drifting(&self.nodes);
                self.refresh_hop(node);
                self.touch(node);
            }
            FaultKind::BitErrors { .. }
            | FaultKind::BitErrorBurst { .. }
            | FaultKind::Distortion { .. } => {}
        }
        Ok(())
    }

    fn fault_end(&mut self, i: usize, t: Instant) -> Result<(), SimError> {
        let Some(f) = self.faults.get(i).copied() else {
            return Ok(());
        };
        match f.kind {
            FaultKind::FibreBreak { segment, .. } => {
                let downstream = (segment + 1) % self.nodes.len().max(1);
                for (seg, origin) in self.current_entering(segment, t, false) {
                    self.replay(segment, seg, origin, downstream);
                }
                self.release_fillers(segment, false);
            }
            FaultKind::PowerOff { node, .. } => {
                let n_nodes = self.nodes.len();
                let Some(n) = self.nodes.get_mut(node) else {
                    return Ok(());
                };
                // On already, or another of its power-off windows still lasts: it stays off
                // until that one ends (the windows are half-open, `Node::powered_at`).
                if n.powered || n.off_windows.iter().any(|(a, b)| *a <= t && t < *b) {
                    return Ok(());
                }
                // A fresh chip out of reset; its host configures it again.
                let cfg: ChipConfig = n.cfg.chip;
                n.chip = Chip::new(cfg);
                // The receive log is for tools; nothing here reads it.
                n.chip.set_rx_log(false);
                n.chip.set_implied_filler(self.delivery == Delivery::Fast);
                n.chip.set_forward_output(self.delivery == Delivery::Exact);
                let local = n.clock.to_local(t);
                n.chip.advance_to(local);
                if let Some(v) = n.vcd {
                    let _ = v;
                }
                n.powered = true;
                n.contig = Contiguity::default();
                n.expect.clear();
                n.resume = None;
                n.in_floor = local;
                n.last_out = None;
                n.host_deadline = None;
                n.note_host();
                n.ints = (
                    n.chip.pin_level(sercon_model::pins::Pin::Int0),
                    n.chip.pin_level(sercon_model::pins::Pin::Int1),
                );
                debug_assert!(n.host_run.is_none(), "a host's wake left at power-on");
                n.run_host(Wake::PowerOn);
                n.repeating = repeats(&n.chip);
                self.touch(node);
                // The fresh chip's first output (dark from its reset on) goes out now,
                // before the replay below: on the fast path the replay puts the repeated
                // copies out itself (`repeat_out`) and raises the output floor, so the dark,
                // taken only when the node is served, went out after them and darkened the
                // line behind the node from the end of the last copy (the master saw RDIST
                // and FIBBR until its next telegram; the exact path's chip forwards the
                // copies after its dark). At power-on time t the chip is powered from t on
                // (spec-notes "Faults: exact accounting", same-instant rule).
                self.route_power_on_output(node, local);
                // What the line upstream carries now reaches the fresh receiver.
                let up = (node + n_nodes - 1) % n_nodes;
                let up = if matches!(self.topology, Topology::Bus { .. }) {
                    0
                } else {
                    up
                };
                let delay = self.segments.get(up).map_or(Duration::ZERO, |s| s.delay);
                let at = Instant::from_picos(t.as_picos().saturating_sub(delay.as_picos()));
                if !matches!(self.topology, Topology::Bus { .. }) {
                    for (seg, origin) in self.current_entering(up, at, true) {
                        self.replay(up, seg, origin, node);
                    }
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// [`Simulation::route_outputs`] of node `node`'s fresh chip at its power-on instant
    /// `local` (node time): the chip starts out of reset at time zero, so its first output
    /// (dark, the transmitter off) is dated from then; it is the line from the power-on on
    /// (the node was unpowered before, its output dark from its power-off). Dated from zero,
    /// it reached the next receiver behind what that receiver had been given since (out of
    /// order, cut to its input floor).
    fn route_power_on_output(&mut self, node: usize, local: Instant) {
        let mut out = std::mem::take(&mut self.buf);
        if let Some(n) = self.nodes.get_mut(node) {
            let until = n.clock.to_local(self.now);
            n.chip.take_line_output_until(until, &mut out);
        }
        out.retain_mut(|seg| {
            if seg.start >= local {
                return true;
            }
            match seg.from_instant(local) {
                Some(from) => {
                    *seg = from;
                    true
                }
                None => false,
            }
        });
        self.route_taken(node, &mut out);
        self.buf = out;
        // No slave runs ahead in a run with power-offs (`run_ahead_ok`): nothing deferred.
        debug_assert!(self.deferred.is_empty(), "an AT deferred at a power-on");
    }

    /// Sends what enters fibre `k` again (at a repair or a power-on), for the fresh
    /// receiver of node `to` (`propagate`: it gets it whatever its origin).
    fn replay(&mut self, k: usize, seg: LineSegment, origin: usize, to: usize) {
        self.replay_to = Some(to);
        self.propagate(k, seg, origin, true);
        self.replay_to = None;
    }

    /// The signal entering segment `k` from `t` on, to be sent again. A repair (`later`
    /// false): the last segment that entered, from `t` on, if it started before `t` (one
    /// entering at `t` or later passed the whole fibre). A power-on (`later`): the segment in effect before `t`, from `t` on, and
    /// every one that entered from `t` on, all of which reached the unpowered receiver: a
    /// telegram and its filler entered within a fibre's delay before the power-on, on the
    /// fast path two segments (`splits_filler`), must all reach the fresh receiver (it got
    /// the filler only, not the telegram, when only the last was kept).
    fn current_entering(&self, k: usize, t: Instant, later: bool) -> Vec<(LineSegment, usize)> {
        let Some(kept) = self.segments.get(k).map(|s| &s.last_entered) else {
            return Vec::new();
        };
        if !later {
            // A segment entering at the repair's instant or later finds the fibre whole
            // (`SegmentFaults::broken_at`: a break lasts from its start up to, not
            // including, its repair) and goes on by itself: sent again it reached the nodes
            // behind twice, and on the fast path the second pass put its copy ahead of the
            // chip's own (spec-notes "Faults: exact accounting", same-instant rule). Only
            // the one in effect before the repair, dark at the far end, is sent again from
            // then on: the last that started before it, unless one started at its instant.
            // A segment the fast path entered ahead (a filler split from its telegram,
            // `splits_filler`) does not hide it: both paths replay the same (the bit
            // errors' random stream is drawn the same).
            if kept.iter().any(|(s, _)| s.start == t) {
                return Vec::new();
            }
            return kept
                .iter()
                .rev()
                .find(|(s, _)| s.start < t)
                .map(|(last, origin)| (Self::entering_from(last, t), *origin))
                .into_iter()
                .collect();
        }
        // The last one that started before `t`, if kept.
        let first = kept.iter().rposition(|(s, _)| s.start < t);
        let mut out = Vec::new();
        if let Some(i) = first
            && let Some((last, origin)) = kept.get(i)
        {
            out.push((Self::entering_from(last, t), *origin));
        }
        out.extend(kept.iter().skip(first.map_or(0, |i| i + 1)).cloned());
        out
    }

    /// `last` (entered at or before `t`) from `t` on.
    fn entering_from(last: &LineSegment, t: Instant) -> LineSegment {
        match last.from_instant(t) {
            Some(s) => s,
            None => {
                let signal = if last.level_at(t) {
                    LineSignal::Light
                } else {
                    LineSignal::Dark
                };
                LineSegment::steady(t, last.bit_time, signal, last.level_at(t))
            }
        }
    }

    /// The bit time last seen entering segment `k` (for steady segments the fault makes).
    fn bit_time_hint(&self, k: usize) -> Duration {
        self.segments
            .get(k)
            .and_then(|s| s.last_entered.back())
            .map_or(Duration::ZERO, |(s, _)| s.bit_time)
    }
}

/// A segment for `node` that starts before the last one handed to it (`Node::in_floor`):
/// counted, and cut to start there (`None`: nothing of it is left). On the fast path
/// (`fast`), when it is a telegram or a filler, or a telegram was handed over last, it also
/// counts as a collision the fast path cannot follow ([`SimStats::fast_path_collisions`]): the fast path carried the later one
/// ahead of what comes first on the line (a slave's telegram through plain repeaters ahead
/// of the filler still in their chips; a filler split off ahead of the repeater's own
/// telegram that cuts what it repeats, 410B §1), and the receiver cannot take it in its
/// place, so the run may differ from the reference path's (a filler handed over late: the
/// master's filler overtaken by a slave's AT and its filler, its copy lost behind them).
/// Dark after dark, as every chip's first output reaches the next at the start, changes
/// nothing; a node whose clock drifts
/// maps segments that follow one another on the line onto its own time out of order by up
/// to length × error, on both paths alike (spec-notes "Own clocks"): neither is counted.
#[cold]
#[inline(never)]
fn out_of_order(
    stats: &mut SimStats,
    fast: bool,
    node: &Node,
    local: LineSegment,
) -> Option<LineSegment> {
    stats.out_of_order += 1;
    if fast
        && node.clock.is_identity()
        && (matches!(local.signal, LineSignal::Bits(_) | LineSignal::Filler)
            || node.chip.last_input_is_bits())
    {
        stats.fast_path_collisions += 1;
    }
    local.from_instant(node.in_floor)
}

/// What [`Simulation::deliver`] reads of the simulation's settings on its general way
/// (`take_general`).
#[derive(Debug, Clone, Copy)]
struct GeneralMarks {
    delivery: Delivery,
    /// Slaves run ahead after the master's telegrams (`Simulation::runs_ahead`).
    runs: bool,
    /// A replay runs (`replay_to` or `replay_copy`).
    replay: bool,
}

/// `deliver`'s first part on its general way (not a swept delivery, `sim/swept.rs`): `local`
/// (simulation time) taken to node `j`'s time, in order at its receiver (its floor raised),
/// from `origin`, `repeating` at `j`. Whether it starts ahead of the chip's time, its start
/// (simulation time), where the slave runs ahead to and `past` (`Simulation::run_ahead`);
/// `None`: nothing to deliver. Out of line: a plain ring's deliveries are all swept.
#[cold]
#[inline(never)]
fn take_general(
    node: &mut Node,
    stats: &mut SimStats,
    marks: GeneralMarks,
    (j, origin, repeating): (usize, usize, bool),
    local: &mut LineSegment,
) -> Option<(bool, Instant, Option<Instant>, Option<Duration>)> {
    if node.clock.is_identity() {
        local.start = node.clock.to_local(local.start);
    } else {
        local.start = node.map_in(local.start, local);
    }
    if local.start < node.in_floor {
        let fast = marks.delivery == Delivery::Fast;
        match out_of_order(stats, fast, node, local.clone()) {
            Some(s) => *local = s,
            None => return None,
        }
    }
    node.in_floor = local.start;
    // The fast path leaves out segments this receiver ignores, so the level it saw
    // last may differ from the sender's: a telegram is taken from the level the
    // receiver is at (NRZI decodes an inverted telegram the same), by the chip
    // (`Chip::line_input_at_level`; the sender's hint has the inverted bits at hand,
    // `FrameHint::coded`). Nothing below reads the bits or the level before that.
    if matches!(local.signal, LineSignal::Filler) {
        node.continue_filler(local);
    }
    // The exact path matches the repeater's copies with what it delivered; on the fast
    // path the chip releases none (`Chip::set_forward_output`).
    if repeating && marks.delivery == Delivery::Exact {
        let lat = local.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        node.expect.push_back(crate::node::ExpectedCopy {
            at: local.start.saturating_add(lat),
            origin,
            replayed: false,
            bits: matches!(local.signal, LineSignal::Bits(_)),
        });
    }
    let ahead = local.start > node.chip.now();
    if local.start < node.chip.now() {
        stats.late += 1;
    }
    let start = node.clock.to_global(local.start);
    // A telegram of the master to a slave (`Simulation::run_ahead`): where it ends
    // (`run_ahead_end`: only on the simulation's clock). The master's next segment is
    // its next telegram only when this one carries the filler after it (unsplit on
    // its way here, `splits_filler`): then a run past it may go up to that telegram
    // (`Simulation::master_horizon`).
    let past = (local.then_filler).then_some(local.bit_time);
    let ahead_to = run_ahead_end(marks.runs, origin, j, node, local);
    if origin != 0
        && j != 0
        && marks.replay
        && marks.delivery == Delivery::Fast
        && matches!(local.signal, LineSignal::Bits(_))
        && !local.then_filler
    {
        // A replay (a repair, a power-on) gives a fresh receiver a slave's telegram
        // without the filler after it, which comes as a slave's segment of its own and,
        // on the fast path, to no slave (see `propagate`): that receiver sees no edge
        // until the master's next telegram (FIBBR, 410B §4.1 2H.13), where the reference
        // path's gets the filler. Counted like the collisions the fast path cannot follow.
        stats.fast_path_collisions += 1;
    }
    Some((ahead, start, ahead_to, past))
}

/// Where slave `j` runs ahead to after `local` from `origin` reached it
/// ([`Simulation::run_ahead`]): the end of a telegram of the master, when slaves run ahead
/// (`runs`, `Simulation::runs_ahead`) and `j` is on the simulation's clock (its local instants
/// are the simulation's: with a clock error they do not map one to one, and a telegram's
/// end, taken back, can lie after the next one's start).
#[inline(always)]
fn run_ahead_end(
    runs: bool,
    origin: usize,
    j: usize,
    node: &Node,
    local: &LineSegment,
) -> Option<Instant> {
    (runs
        && origin == 0
        && j != 0
        && node.clock.is_identity()
        && matches!(local.signal, LineSignal::Bits(_)))
    .then(|| local.end())
    .flatten()
}

/// The chip part of a node's next wake off the fast path (exact delivery, or woken for
/// observable changes only): kept out of line, so that the fast path's reschedule, run
/// for every node many times a cycle, stays small in the instruction cache.
#[cold]
#[inline(never)]
fn general_wake(node: &Node, lookahead: Lookahead, exact: bool) -> Option<Instant> {
    let own = if lookahead == Lookahead::Events {
        node.chip.next_event_at()
    } else {
        node.chip.next_deadline()
    };
    let out = node.chip.next_line_output_at();
    let expected = node.expect.front().map(|e| e.at);
    let out = out.filter(|o| exact || Some(*o) != expected);
    match (own, out) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// The first slave whose clock is not the simulation's, or the node count.
fn first_drifting(nodes: &[Node]) -> usize {
    nodes
        .iter()
        .enumerate()
        .skip(1)
        .find(|(_, n)| !n.clock.is_identity())
        .map_or(nodes.len(), |(j, _)| j)
}

/// Node 0 is the master; everyone else a slave.
fn origin_of(node: usize) -> Origin {
    if node == 0 {
        Origin::Master
    } else {
        Origin::Slave
    }
}

fn check_fault(f: &Fault, nodes: usize, segments: usize) -> Result<(), SimError> {
    let (what, index, limit) = match f.kind {
        FaultKind::FibreBreak { segment, .. }
        | FaultKind::BitErrors { segment, .. }
        | FaultKind::BitErrorBurst { segment, .. }
        | FaultKind::Distortion { segment, .. } => ("segment", segment, segments),
        FaultKind::PowerOff { node, .. } | FaultKind::ClockDrift { node, .. } => {
            ("node", node, nodes)
        }
    };
    if index >= limit {
        return Err(SimError::NoSuchTarget { what, index });
    }
    Ok(())
}
