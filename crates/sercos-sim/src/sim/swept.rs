//! A slave's delivery of the master's segment in a sweep (`Simulation::sweep_master_plain`):
//! what `Simulation::deliver` decides the same way for every slave of the sweep, found once.
//!
//! In a sweep every slave is a plain repeater (`run_end`: powered, repeating, on the
//! simulation's clock; 410B §1 "The slaves regenerate and repeat their received data"), the
//! ring is plain on the fast path and no replay runs (`propagate_master_plain`). So at each
//! slave's delivery:
//!
//! * its clock maps the segment's instants as they are (no `Node::map_in`);
//! * no copy is expected back (the fast path's chips release none,
//!   `Chip::set_forward_output`), no replay is counted (the segment is the master's);
//! * it runs ahead after the segment (`Simulation::run_ahead`) when slaves do
//!   (`Simulation::runs_ahead`) and the segment is the master's telegram: to the telegram's
//!   end, its length the same at every hop (only its start moves, by fibre delay and
//!   repeater latency);
//! * the run-ahead's limit (the end of the current run, the next fault event) is the one
//!   found at the sweep's start: nothing in the sweep moves either;
//! * the master's promise (`Simulation::master_horizon`, 410B §4.2.1 TRT) holds for every
//!   slave that runs ahead when the master is powered and on the simulation's clock (found
//!   once): a slave whose pins are traced has no quiet host and runs not ahead. The fibres'
//!   delay and repeater latency up to each slave are a table (`master_reach`), made again
//!   only when a sweep's latency differs from the last one's.
//!
//! The master's deliveries of what comes back round such a ring (its own telegram at the
//! sweep's end, the slaves' ATs sent on, `early_route`) share the same facts when the master
//! is on the simulation's clock ([`Swept::INTO_MASTER`]): the instants as they are, no copy
//! expected (the master repeats nothing, 410B §1), no run-ahead and no replay counted
//! (`run_ahead_end` and the replay count are for slaves only).
//!
//! A segment that reaches a receiver out of order (cut at its floor, `out_of_order`) or that
//! is not bits (a filler continued from the bits before, `Node::continue_filler`) takes
//! `deliver` itself. Debug builds compare every decision taken here with `deliver`'s own
//! computation.

#[cfg(debug_assertions)]
use sercon_model::serial_port::REPEATER_LATENCY_BITS;
use sercon_model::serial_port::{LineSegment, LineSignal};
use sercos_wire::time::{Duration, Instant};

#[cfg(debug_assertions)]
use super::Delivery;
use super::{SimStats, Simulation};
use crate::node::Node;

/// What every slave's delivery in one sweep of the master's segment shares (module notes).
#[derive(Debug, Clone, Copy)]
pub(super) struct Swept {
    /// The telegram's length (its end less its start) when the slaves run ahead after it
    /// (`Simulation::runs_ahead`, the master's bits); `None`: none runs ahead.
    run_len: Option<Duration>,
    /// The segment's bit time when it carries its filler (`deliver`'s `past`).
    past: Option<Duration>,
    /// `Simulation::run_ahead_limit` at the sweep's start.
    limit: Instant,
    /// The segment carries its filler and the master is powered and on the simulation's
    /// clock: its promise holds for every slave that runs ahead (`Simulation::master_horizon`;
    /// a slave whose pins are traced runs not ahead: no quiet host, `Node::quiet_host`).
    promised: bool,
}

impl Swept {
    /// What the master's deliveries of the segments coming back round a plain ring share
    /// (the slaves' ATs sent on, `early_route`; its own telegram, `sweep_into_master`): the
    /// master never runs ahead (`run_ahead_end`: slaves only), expects no copy (it repeats
    /// nothing, 410B §1) and is no replay's fresh receiver (slaves only). Taken only for
    /// the master on the simulation's clock (the caller's condition; debug builds check it).
    pub(super) const INTO_MASTER: Swept = Swept {
        run_len: None,
        past: None,
        limit: Instant::ZERO,
        promised: false,
    };
}

/// `deliver`'s first part for the master's bits `local` (simulation time), in order at
/// slave `node`'s receiver in the sweep `sw`: the receiver's floor raised to its start, a
/// late start counted. Whether it starts ahead of the chip's time, its start and where the
/// slave runs ahead to.
#[inline(always)]
pub(super) fn take_swept(
    node: &mut Node,
    stats: &mut SimStats,
    local: &LineSegment,
    sw: &Swept,
) -> (bool, Instant, Option<Instant>) {
    // On the simulation's clock: the instants as they are.
    let start = local.start;
    node.in_floor = start;
    let now = node.chip.now();
    if start < now {
        stats.late += 1;
    }
    (
        start > now,
        start,
        sw.run_len.map(|len| start.saturating_add(len)),
    )
}

impl Simulation {
    /// The facts of a sweep of the master's `seg` (at the master's output), its repeaters'
    /// latency `lat`; `master_reach` made for `lat`.
    pub(super) fn swept(&mut self, seg: &LineSegment, lat: Duration) -> Swept {
        let n = self.nodes.len();
        if self.master_reach.0 != lat || self.master_reach.1.len() != n {
            self.make_master_reach(lat);
        }
        let run_len = match &seg.signal {
            LineSignal::Bits(b) if self.runs_ahead() => Some(seg.bit_time.saturating_mul(b.len())),
            _ => None,
        };
        let promised = seg.then_filler
            && self
                .nodes
                .first()
                .is_some_and(|m| m.powered && m.clock.is_identity());
        Swept {
            run_len,
            past: seg.then_filler.then_some(seg.bit_time),
            limit: self.run_ahead_limit(),
            promised,
        }
    }

    /// `master_reach` for the repeater latency `lat`.
    #[cold]
    #[inline(never)]
    fn make_master_reach(&mut self, lat: Duration) {
        let reach = self
            .from_master
            .iter()
            .enumerate()
            .map(|(j, d)| {
                let repeaters = u64::try_from(j.saturating_sub(1)).unwrap_or(u64::MAX);
                d.saturating_add(lat.saturating_mul(repeaters))
            })
            .collect();
        self.master_reach = (lat, reach);
    }

    /// [`Simulation::deliver`] of the master's `local` (simulation time) to slave `j` in the
    /// sweep `sw` (module notes): the same, with the sweep's facts taken as found.
    #[inline(always)]
    pub(super) fn deliver_swept(&mut self, j: usize, local: LineSegment, sw: &Swept) {
        self.deliver_in(j, local, 0, true, Some(sw));
    }

    /// [`Simulation::deliver`] of `local` (simulation time), from `origin`, to the master on
    /// the simulation's clock, with [`Swept::INTO_MASTER`]'s facts taken as found.
    #[inline(always)]
    pub(super) fn deliver_into_master(&mut self, local: LineSegment, origin: usize) {
        self.deliver_in(0, local, origin, false, Some(&Swept::INTO_MASTER));
    }

    /// [`Simulation::run_ahead`]'s limit and the master's promise at slave `j` in the sweep
    /// `sw`.
    #[inline(always)]
    pub(super) fn swept_run_bounds(&mut self, j: usize, sw: &Swept) -> (Instant, Option<Instant>) {
        let horizon = if sw.promised {
            let reach = self.master_reach.1.get(j).copied();
            self.master_out()
                .and_then(|out| Some(out.saturating_add(reach?)))
        } else {
            None
        };
        debug_assert_eq!(
            horizon,
            sw.past
                .and_then(|bit_time| self.master_horizon(j, bit_time)),
            "a swept delivery's master horizon"
        );
        (sw.limit, horizon)
    }

    /// Debug builds: the sweep's facts are what `deliver` would find at slave `j`.
    #[cfg(debug_assertions)]
    pub(super) fn check_swept(&self, j: usize, local: &LineSegment, sw: &Swept) {
        let node = self.nodes.get(j);
        if j == 0 {
            // `Swept::INTO_MASTER`: the master on the simulation's clock, no run-ahead.
            debug_assert!(
                node.is_some_and(|n| n.clock.is_identity()) && sw.run_len.is_none(),
                "a delivery into the master taken as swept off the simulation's clock"
            );
            return;
        }
        debug_assert!(
            j != 0
                && self.delivery == Delivery::Fast
                && self.plain_ring
                && self.replay_to.is_none()
                && !self.replay_copy
                && j < self.first_drifting
                && node.is_some_and(|n| n.clock.is_identity() && n.repeating && n.powered),
            "a swept delivery off a plain sweep"
        );
        debug_assert_eq!(
            sw.past,
            local.then_filler.then_some(local.bit_time),
            "a swept delivery's filler"
        );
        debug_assert_eq!(
            sw.limit,
            self.run_ahead_limit(),
            "a swept delivery's run-ahead limit"
        );
        debug_assert_eq!(
            sw.promised,
            local.then_filler
                && self
                    .nodes
                    .first()
                    .is_some_and(|m| m.powered && m.clock.is_identity()),
            "a swept delivery's master"
        );
        debug_assert_eq!(
            self.master_reach.0,
            local.bit_time.saturating_mul(REPEATER_LATENCY_BITS),
            "a swept delivery's repeater latency"
        );
    }
}
