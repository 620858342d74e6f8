//! The master's next wake taken in the wake that sent its telegram round the ring, rather
//! than as an event of its own (`Simulation::wake_node`).
//!
//! On a ring of inert hosts the master's wake that sends a telegram ends with every slave
//! run ahead to just before the master's next telegram reaches it (`Simulation::run_ahead`,
//! up to the promise `Chip::next_output_for_any_input`, 410B §4.2.1 TRT: after the MST up to
//! the MDT, after the MDT through the slave's AT up to the next MST), and with the wakes set:
//! each slave's parked at its chip's time (`Simulation::park`), the master's at its next
//! telegram's start. That wake is then the next event, and nothing happens before it: it is
//! taken at once, in the same event (the simulation's time moved to it; the chip advanced,
//! its output taken and sent round, the nodes served after, as that event would), when:
//!
//! * the ring is plain on the fast path and every host is inert (`plain_ring`,
//!   `run_ahead_ok`): no fibre is traced and the master's telegram went round by
//!   `propagate_master_plain`, so the pass recorded nothing, and no host's access ends
//!   meanwhile (`resumes`: only a host that is not inert makes one);
//! * the wake and its pass touched no node: every node waits only for its wake to be set
//!   (`rewake` holds them all; nothing is left to serve);
//! * the master's wake, as `set_wake` would set it, is its promised next output `m`
//!   (`master_next`, found in the pass just made: only a pass of the master's telegram
//!   gives every slave a segment on the fast path), after now and within the run
//!   (`run_to`);
//! * `park` would park every slave (it ran past its own output in this pass and holds no
//!   output before its chip's time) at its chip's time, after `m`: the master's telegram
//!   reaches it a fibre's delay and the repeaters' latency after its start (410B §1);
//! * no fault event comes at or before `m` (at `m` it would come first).
//!
//! What the master receives before that wake (its MST come back round the ring; after the
//! MDT, the MDT and the slaves' ATs, `early_route`) reached its chip in the pass just made,
//! before the chip is advanced past it, as it did before: every chip is handed the same
//! inputs and advanced to the same instants in the same order. The slaves' wakes are set as
//! `park` sets them, but their queue entries are moved only when the wake is not set again
//! within the event (the next pass does, `queue_joined_parks`): the queue hands out what it
//! would have. Only the counters change: one event fewer for each wake so taken
//! ([`SimStats::joined_wakes`](super::SimStats::joined_wakes)). Debug builds check that the
//! queue as `set_rewakes` would leave it gives the master's wake at `m` next.

use sercos_wire::time::Instant;

/// The earlier of two instants, either missing.
#[inline(always)]
fn earliest(a: Option<Instant>, b: Option<Instant>) -> Option<Instant> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

#[cfg(debug_assertions)]
use super::Ev;
use super::{Delivery, Lookahead, NO_NODE, Simulation};

impl Simulation {
    /// At the end of the master's quiet wake (`wake_node`, its output sent on): the instant
    /// of its next wake when that wake may be taken now (the module's conditions), the
    /// slaves' wakes and the master's pending rewake set as the event's end would set them;
    /// `None` and nothing changed otherwise.
    pub(super) fn join_next_wake(&mut self) -> Option<Instant> {
        let n = self.nodes.len();
        let m = self.master_next??;
        if !self.short_paths
            || !self.run_ahead_ok
            || !self.plain_ring
            || self.delivery != Delivery::Fast
            || self.lookahead != Lookahead::Events
            || m <= self.now
            || m > self.run_to
            || !self.touched.is_empty()
            || self.rewake_done != NO_NODE
            || !self.resumes.is_empty()
            || self.queue.peek_fault_time().is_some_and(|f| f <= m)
            || self.rewake.len() != n
        {
            return None;
        }
        // Each slave's wake as `park` would set it: after `m`.
        for j in 1..n {
            if !self.parks_after(j, m) {
                return None;
            }
        }
        debug_assert!(
            self.deferred.is_empty(),
            "ATs left to send on at a joined wake"
        );
        // The master's, as `set_wake` would set it (`park` leaves it: it never runs ahead).
        // Its output bound is a load here: `master_horizon`'s `next_output_for_any_input`
        // remembered it in the chip, and the master's own telegram coming back round the
        // ring keeps it (`Chip::out_bound`; 410B §4.1 0CH: its block starts with its cycle
        // start, not with an MST it receives).
        if self.nodes.first().is_none_or(|mst| mst.ran_past) || !self.master_wakes_at(m) {
            return None;
        }
        #[cfg(debug_assertions)]
        {
            // The queue as the event's end would leave it hands out the master's wake next.
            let mut queue = self.queue.clone();
            queue.set(0, m);
            for j in (1..n).rev() {
                if let Some(g) = self.parks_at(j) {
                    queue.park(j, g);
                }
            }
            debug_assert_eq!(
                queue.pop_until(self.run_to),
                Some((m, Ev::Node(0))),
                "a joined wake is not the next event"
            );
        }
        // The event's end (`set_rewakes`): the master's wake is the one taken now; each
        // slave is parked at its chip's time as `park` parks it, its queue entry moved only
        // if the wake is not set again before the event's end (`queue_joined_parks`).
        // Every node is in `rewake` (`rewake_done` is none), each once: all are marked.
        debug_assert!(
            self.nodes.iter().all(|n| n.is_rewake),
            "a node in rewake is not marked"
        );
        self.rewake.clear();
        if let Some(master) = self.nodes.first_mut() {
            master.is_rewake = false;
        }
        #[cfg(debug_assertions)]
        let parks: Vec<Option<Instant>> = (0..n).map(|j| self.parks_at(j)).collect();
        for node in self.nodes.iter_mut().skip(1) {
            // It ran past its output (`parks_after`): on the simulation's clock.
            debug_assert!(
                node.clock.is_identity(),
                "a joined park off the simulation's clock"
            );
            node.is_rewake = false;
            node.ran_past = false;
            node.parked = true;
            node.wake = Some(node.chip.now());
            node.park_unqueued = true;
        }
        #[cfg(debug_assertions)]
        for (j, node) in self.nodes.iter().enumerate().skip(1) {
            debug_assert_eq!(parks.get(j).copied().flatten(), node.wake, "a joined park");
        }
        self.joined_parks = true;
        self.stats.parked_wakes += n.saturating_sub(1) as u64;
        self.stats.joined_wakes += 1;
        Some(m)
    }

    /// Whether `set_wake` would set the master's wake to `m` (after now): `next_wake(0) ==
    /// Some(Some(m))`, found in line for a powered master on the simulation's clock (the
    /// join's conditions give the fast path and `Lookahead::Events`): the earliest of its
    /// chip's next possible own output (`Chip::next_output_bound`, 410B §4.2.1 TRT), its
    /// next output the simulation does not carry, its host's deadline and a resume after
    /// its chip's time is `m`, and its pending wake is not. When that earliest lies at or
    /// before now (`next_wake` then moves it to now or a picosecond later) or the master is
    /// off that clock, `next_wake` itself. Debug builds compare with `next_wake`.
    #[inline(always)]
    fn master_wakes_at(&self, m: Instant) -> bool {
        let Some(master) = self.nodes.first() else {
            return false;
        };
        let wakes = if master.powered && master.clock.is_identity() {
            let chip = &master.chip;
            let chip_now = chip.now();
            let next = earliest(
                earliest(chip.next_output_bound(), chip.next_line_output_unexpected()),
                earliest(
                    master.host_deadline,
                    master.resume.filter(|r| *r > chip_now),
                ),
            );
            match next {
                // On the simulation's clock, after now: `next_wake`'s wake as found.
                Some(t) if t > self.now => t == m && master.wake != Some(m),
                Some(_) => self.next_wake(0) == Some(Some(m)),
                None => false,
            }
        } else {
            self.next_wake(0) == Some(Some(m))
        };
        debug_assert_eq!(
            wakes,
            self.next_wake(0) == Some(Some(m)),
            "the join's check of the master's wake"
        );
        wakes
    }

    /// Whether slave `j` parks after `m` (`Simulation::parks_at`) in a join, whose
    /// conditions ask only what can differ there: every node is powered (only a power-off
    /// fault powers one down, and `run_ahead_ok` rules them out), a node that ran past its
    /// output ran ahead on the simulation's clock (`run_ahead_end`: its chip's time is the
    /// simulation's), and an instant after `m` is after now (`m > now`, the join's
    /// conditions; 410B §1: the master's telegram reaches a slave after it left). Debug
    /// builds compare with `parks_at`.
    #[inline(always)]
    fn parks_after(&self, j: usize, m: Instant) -> bool {
        let Some(node) = self.nodes.get(j) else {
            return false;
        };
        let at = node.chip.now();
        let parks = node.ran_past
            && node.host_deadline.is_none()
            && at > m
            && at < self.run_to
            // Output it still holds before its time (`parks_at`'s short path first).
            && (node.chip.next_line_output_at().is_none_or(|o| o >= at)
                || node
                    .chip
                    .next_line_output_unexpected()
                    .is_none_or(|o| o >= at));
        debug_assert!(
            !node.ran_past || (node.powered && node.clock.is_identity()),
            "a slave run past its output powered off or off the simulation's clock"
        );
        debug_assert_eq!(
            parks,
            self.parks_at(j).is_some_and(|g| g > m),
            "a joined park's short check"
        );
        parks
    }

    /// At the end of an event that joined a wake: the slaves parked then whose wakes were
    /// not set again are parked in the queue too, where `park` would have put them.
    #[cold]
    #[inline(never)]
    pub(super) fn queue_joined_parks(&mut self) {
        self.joined_parks = false;
        for (j, node) in self.nodes.iter_mut().enumerate() {
            if std::mem::take(&mut node.park_unqueued)
                && let Some(g) = node.wake
            {
                self.queue.park(j, g);
            }
        }
    }
}
