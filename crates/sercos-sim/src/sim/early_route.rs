//! The slaves' ATs sent on right after the master's telegram that let every slave run past
//! its own output (`Simulation::run_ahead`), rather than at one wake per slave.
//!
//! After the master's last telegram of a cycle each slave of a ring of inert hosts runs up
//! to the master's next telegram, through its own AT. Its AT then only waits in the chip for
//! the simulation's time to reach its start; nothing can change it (the chip is past its
//! start, an own telegram is cut only by a reset or a power-off, and no fault comes before
//! the run's limit). Taken at once, in ring order, it meets what it would meet at its time
//! when:
//!
//! * every slave ran past its output in this same telegram's pass and has exactly that one
//!   telegram queued (its filler implied): no other slave output falls between;
//! * the slaves' ATs follow one another around the ring (each starts after the one before
//!   has passed its repeater, 410B §4.2.1 TRT): at every repeater the copies and its own AT
//!   come in the order of their times, as they would one wake after the other;
//! * every slave repeats plainly and every fibre after the first slave is untraced, clean
//!   and keeps nothing (`static_plain`, `plain_hop`): the ATs go to the master only, by sums
//!   of delays (`Simulation::propagate`), and the master, on the simulation's clock, is
//!   handed them in the order of their arrival, ahead of its own time, after the master's
//!   telegram itself came back round;
//! * every AT starts before the master's next telegram can start (the promise the slaves ran
//!   to): at its time it would have been sent before that telegram's pass put its copies
//!   out at the repeaters, as it is now (after the MDT's pass that holds for every AT; after
//!   the MST's only for ATs a slave's list puts before the MDT's receive header).
//!
//! Otherwise each AT goes at its slave's wake, as before.
//!
//! On a plain ring's fast path (`plain_ring`, no replay) with the short paths on, each AT
//! taken so goes its way to the master directly (`send_on_plain`: what `route_output` and
//! `propagate` do with it there, without the checks that cannot hold on that way; debug
//! builds compare its arrival with a hop-by-hop walk). Without faults the ATs of one pass go
//! so one after the other (`send_all_plain`): the output floors' uniform run
//! (`OutFloors::open_through`) is kept between them rather than looked up, checked and
//! written back for each, as each AT leaves it one offset above the hops behind its slave
//! (`sim/out_floors.rs` module notes).

use sercon_model::serial_port::{LineSegment, LineSignal, REPEATER_LATENCY_BITS};
use sercos_wire::time::{Duration, Instant};

use super::{Delivery, Simulation};

impl Simulation {
    /// Sends on the ATs of the slaves that ran past them in the pass just made
    /// (`deferred`), when every condition of the module's holds; forgets them otherwise
    /// (each then goes at its slave's wake).
    pub(super) fn route_deferred(&mut self) {
        let mut deferred = std::mem::take(&mut self.deferred);
        if self.deferred_may_go(&deferred) {
            let mut out = std::mem::take(&mut self.buf);
            // A plain ring on the fast path: each AT by its own short way to the master.
            let plain = self.short_paths
                && self.plain_ring
                && self.delivery == Delivery::Fast
                && self.replay_to.is_none()
                && !self.replay_copy;
            if plain && !self.faulty {
                self.send_all_plain(&deferred, &mut out);
            } else {
                for &j in &deferred {
                    let Some(node) = self.nodes.get_mut(j) else {
                        continue;
                    };
                    let until = node.chip.now();
                    super::chip_calls::take(j, &mut node.chip, until, &mut out);
                    if plain
                        && let [seg] = out.as_slice()
                        && matches!(seg.signal, LineSignal::Bits(_))
                        && let Some(seg) = out.pop()
                    {
                        self.send_on_plain(j, seg);
                    } else {
                        self.route_taken(j, &mut out);
                    }
                }
            }
            self.put_buf(out);
            self.stats.ats_sent_on += deferred.len() as u64;
            if self.short_paths {
                self.unserve_sent_on(&deferred, plain);
            }
        }
        deferred.clear();
        self.deferred = deferred;
    }

    /// The ATs of `deferred` (every slave once, in ring order: `deferred_may_go`) taken
    /// and sent on, each as `send_on_plain` sends it, on a plain ring's fast path without
    /// faults: the ATs of the slaves with repeaters after them sent through
    /// (`send_through`) with the output floors' uniform run kept here from one to the next
    /// (`OutFloors::open_through`; 410B §1: each AT follows the one before through the
    /// repeaters, 410B §4.2.1 TRT), not looked up, checked and written back for each.
    /// Anything else (a take of more than the AT, an AT of another bit rate, the last
    /// slave's, a sum that could saturate) hands the run back and goes the general way.
    // Out of line: inlined into `route_outputs` it cost ring-8 ≈ 180 instructions a cycle
    // more (code layout).
    #[inline(never)]
    fn send_all_plain(&mut self, deferred: &[usize], out: &mut Vec<LineSegment>) {
        let n = self.nodes.len();
        let Some(&delay) = self.seg_delays.get(n.wrapping_sub(1)) else {
            return;
        };
        let mut run = Run::default();
        for &j in deferred {
            let Some(node) = self.nodes.get_mut(j) else {
                continue;
            };
            let until = node.chip.now();
            super::chip_calls::take(j, &mut node.chip, until, out);
            // The AT is sent through where the take left it, and popped only to go on.
            if let [seg] = out.as_mut_slice()
                && matches!(seg.signal, LineSignal::Bits(_))
            {
                let sent = if j + 1 == n {
                    self.send_last_in_run(&mut run, j, seg, delay)
                } else {
                    self.send_in_run(&mut run, j, seg, delay)
                };
                let Some(seg) = out.pop() else {
                    continue;
                };
                if sent {
                    // The master is on the simulation's clock (`deferred_may_go`).
                    if self.nodes.first().is_some_and(|m| m.powered) {
                        self.deliver_into_master(seg, j);
                    }
                    continue;
                }
                self.close_run(&mut run);
                self.send_on_plain(j, seg);
            } else {
                self.close_run(&mut run);
                self.route_taken(j, out);
            }
        }
        self.close_run(&mut run);
        // Debug builds: the pass kept stands (`plain_pass.rs` module notes: a filler right
        // behind it reaches the end of its run where the pass says and changes no floor).
        if cfg!(debug_assertions)
            && let Some(p) = self.plain_pass
        {
            let (start, out) = (p.start_in, p.start_out);
            self.debug_check_follower(
                p.entry,
                start.saturating_add(p.len),
                p.lat,
                out.saturating_add(p.len),
                p.run,
            );
        }
    }

    /// Slave `j`'s AT `seg` (taken from its chip) sent on as `send_on_plain` and
    /// `send_through` send it, within `run` (opened at the first AT): `seg` left at the
    /// master's input, the caller delivers it. `false`: nothing changed (the run may be
    /// open still; the caller closes it and goes the general way).
    #[inline]
    fn send_in_run(
        &mut self,
        run: &mut Run,
        j: usize,
        seg: &mut LineSegment,
        delay: Duration,
    ) -> bool {
        let lat = seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        if !run.tried {
            run.tried = true;
            run.through = self.out_floors.open_through(j, lat);
        }
        let (Some(t), Some(node), Some(end)) =
            (run.through.as_mut(), self.nodes.get_mut(j), seg.end())
        else {
            return false;
        };
        if t.next != j || t.lat != lat || !node.clock.is_identity() {
            return false;
        }
        let len = end.saturating_duration_since(seg.start);
        #[cfg(debug_assertions)]
        let plain = self.plain_hop.get(j + 1..).unwrap_or(&[]);
        #[cfg(not(debug_assertions))]
        let plain = &[];
        let Some((before, out, held)) = self.out_floors.through_next(t, end, seg.start, len, plain)
        else {
            return false;
        };
        debug_assert!(node.expect.is_empty(), "a copy expected on the fast path");
        debug_assert!(!node.track_levels, "levels followed on the fast path");
        // `send_on_plain`: the output after the AT.
        node.resume = if seg.then_filler { None } else { Some(end) };
        // `send_through`.
        self.stats.fast_path_collisions += node.sent_through(seg.start, before, end, held);
        // The floors behind `j` moved: a pass kept from before stands no more. This one is
        // not kept (`plain_pass.rs`): the ATs after it in the pass, the last slave's at
        // least, move floors of its run before any filler of `j`'s could follow it
        // (`send_last_in_run`, `send_on_plain`).
        self.plain_pass = None;
        seg.start = out.saturating_add(delay);
        seg.distorted = false;
        true
    }

    /// The last slave's AT `seg` (no repeater after it) as `send_on_plain` sends it, within
    /// `run`, which it ends: its floor set, then straight over the last fibre into the
    /// master (`seg` left at the master's input, the caller delivers it). `false`: nothing
    /// changed (the caller closes the run and goes the general way).
    #[inline]
    fn send_last_in_run(
        &mut self,
        run: &mut Run,
        j: usize,
        seg: &mut LineSegment,
        delay: Duration,
    ) -> bool {
        let (Some(t), Some(node), Some(end)) =
            (run.through.as_mut(), self.nodes.get_mut(j), seg.end())
        else {
            return false;
        };
        if t.next != j || !node.clock.is_identity() {
            return false;
        }
        let Some(before) = self.out_floors.through_last(t, end) else {
            return false;
        };
        debug_assert!(node.expect.is_empty(), "a copy expected on the fast path");
        debug_assert!(!node.track_levels, "levels followed on the fast path");
        node.resume = if seg.then_filler { None } else { Some(end) };
        self.stats.fast_path_collisions += node.sent_through(seg.start, before, end, false);
        self.close_run(run);
        // `send_on_plain`'s `set` of this floor: the last pass no longer stands if it
        // covered it.
        self.floor_written(j);
        seg.start = seg.start.saturating_add(delay);
        true
    }

    /// Hands the floors' run of `run` back (`OutFloors::close_through`).
    fn close_run(&mut self, run: &mut Run) {
        if let Some(t) = run.through.take() {
            self.out_floors.close_through(t);
        }
    }

    /// Slave `j`'s AT `seg` (its chip's time), taken from its chip, to the master, as
    /// `route_output` and `propagate` carry it on a plain ring's fast path (no fibre fault,
    /// trace or power window: `plain_ring`; no replay): nothing is expected at the slave's
    /// output (only the reference path and a faulty ring's chip forwards expect copies), so
    /// the AT is the slave's own; it goes through the plain repeaters after the slave
    /// (`pass_plain`: `deferred_may_go` found them plain up to the master, 410B §1 "The
    /// slaves regenerate and repeat their received data") and over the fibre into the
    /// master, which takes it (fast path: a slave's telegram goes to no slave).
    fn send_on_plain(&mut self, j: usize, mut seg: LineSegment) {
        let n = self.nodes.len();
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        debug_assert!(node.expect.is_empty(), "a copy expected on the fast path");
        // `route_output`: the output after the AT, its start in simulation time, the floor.
        node.resume = if seg.then_filler { None } else { seg.end() };
        // `Node::put_out` on the fast path (no levels followed): the line taken to its end.
        debug_assert!(!node.track_levels, "levels followed on the fast path");
        // On the simulation's clock `map_released` keeps the start (and the end). A faulty
        // ring looks for steady receivers before the pass (`count_steady_receivers`): the
        // general way.
        if !self.faulty
            && node.clock.is_identity()
            && let Some(end) = seg.end()
            && self.send_through(j, &mut seg, end)
        {
            if self.nodes.first().is_some_and(|m| m.powered) {
                self.deliver(0, seg, j, false);
            }
            return;
        }
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        let Some(mut floor) = self.out_floors.get(j) else {
            return;
        };
        node.map_released(&mut seg, floor);
        let end = seg.end();
        let before = floor;
        let cut = seg.start < floor;
        floor = end.unwrap_or(seg.start);
        if cut && before > node.chip_out_end {
            // It cut a telegram the fast path put out ahead of the chip (`route_output`).
            self.stats.fast_path_collisions += 1;
        }
        node.chip_out_end = floor;
        self.out_floors.set(j, floor);
        self.floor_written(j);
        // `propagate`: through the plain repeaters, then into the master.
        debug_assert!(j != 0, "the master's telegram sent on as a slave's");
        #[cfg(debug_assertions)]
        let walked = self.walk_to_master(j, &seg);
        let mut cur = j;
        if self.faulty {
            self.count_steady_receivers(cur);
        }
        self.pass_plain_ending(&mut cur, &mut seg, end);
        debug_assert_eq!(cur + 1, n, "the plain repeaters end before the master");
        let Some(delay) = self.seg_delays.get(cur) else {
            return;
        };
        seg.start = seg.start.saturating_add(*delay);
        #[cfg(debug_assertions)]
        debug_assert_eq!(Some(seg.start), walked, "an AT's way to the master");
        if self.nodes.first().is_some_and(|m| m.powered) {
            self.deliver(0, seg, j, false);
        }
    }

    /// [`Simulation::send_on_plain`] of slave `j`'s telegram `seg` (its chip's time; on the
    /// simulation's clock `map_released` keeps its start; ending at `end`) where its own
    /// floor and the plain repeaters after it, up to the master, are one offset above the
    /// hops (`OutFloors::send_through`): the floor set and the pass in one step, without
    /// the floor read, the split of the uniform run and the run's look-ups of each (410B
    /// §1: the slaves repeat it by their hops); the caller delivers it. Returns whether it
    /// was so (`false`: nothing changed, the general way follows). The pass is kept
    /// (`plain_pass`) as `pass_plain_ending` keeps it; its floor needs no
    /// `floor_written`, the new pass replacing the last.
    #[inline]
    fn send_through(&mut self, j: usize, seg: &mut LineSegment, end: Instant) -> bool {
        let n = self.nodes.len();
        let first = j + 1;
        if self.run_end.get(first) != Some(&n) {
            return false;
        }
        let (Some(plain), Some(delay)) = (self.plain_hop.get(first..n), self.seg_delays.get(n - 1))
        else {
            return false;
        };
        let delay = *delay;
        let len = end.saturating_duration_since(seg.start);
        let lat = seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        let crossing = super::out_floors::Crossing {
            start: seg.start,
            len,
            lat,
        };
        #[cfg(debug_assertions)]
        let walked = self.walk_to_master(j, seg);
        let Some((before, out, held)) = self.out_floors.send_through(j, end, plain, n, crossing)
        else {
            return false;
        };
        let Some(node) = self.nodes.get_mut(j) else {
            return false;
        };
        self.stats.fast_path_collisions += node.sent_through(seg.start, before, end, held);
        // `out + len` is below the prefix sums' safe bound (`send_through`): no sum
        // saturated, the pass is kept as `pass_plain_ending` keeps it.
        self.plain_pass = Some(super::plain_pass::PlainPass {
            entry: j,
            start_in: seg.start,
            len,
            lat,
            start_out: out,
            run: n - first,
        });
        seg.start = out.saturating_add(delay);
        seg.distorted = false;
        #[cfg(debug_assertions)]
        debug_assert_eq!(Some(seg.start), walked, "an AT's way to the master");
        true
    }

    /// Debug builds: where `seg`, put out by slave `j`, reaches the master when every hop
    /// after it is taken as `propagate`'s general loop takes it (fibre delay, repeater
    /// latency, the repeater's output floor; 410B §1), the floors left as they are.
    #[cfg(debug_assertions)]
    fn walk_to_master(&self, j: usize, seg: &LineSegment) -> Option<Instant> {
        let lat = seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        let mut at = seg.start;
        for m in j + 1..self.nodes.len() {
            at = at
                .saturating_add(*self.seg_delays.get(m - 1)?)
                .saturating_add(lat)
                .max(self.out_floors.get(m)?);
        }
        Some(at.saturating_add(*self.seg_delays.last()?))
    }

    /// The slaves whose ATs were just sent on, touched by their delivery because that AT
    /// was due in their chips (`deliver`), would now be served for nothing: their host
    /// quiet (INT0/INT1 as it last saw them, 410B §2; no deadline due), nothing traced, no output left up to the simulation's time (the take above
    /// went up to the chip's), and whether a slave's telegram passes them plainly
    /// (`refresh_hop`) unchanged (only hosts, power and clock faults change it). Such a
    /// slave only has its wake set, once the event's nodes are served, as `deliver` leaves
    /// a node with nothing to serve. Debug builds check that the serve would do nothing.
    ///
    /// `plain`: the ATs went on a plain ring's fast path, where a slave's telegram reaches
    /// no slave (`Simulation::propagate`): nothing came into a slave after the take, so no
    /// output is due (debug builds check it).
    fn unserve_sent_on(&mut self, sent: &[usize], plain: bool) {
        let now = self.now;
        let mut removed = 0;
        for &j in sent {
            let Some(node) = self.nodes.get(j) else {
                continue;
            };
            if !node.is_touched
                || node.is_rewake
                || !node.quiet_host()
                || (!plain && node.chip.line_output_due_at(node.clock.to_local(now)))
            {
                continue;
            }
            debug_assert!(
                self.serve_does_nothing(j),
                "a slave whose AT was sent on would be served for something"
            );
            if let Some(node) = self.nodes.get_mut(j) {
                node.is_touched = false;
                node.is_rewake = true;
                self.rewake.push(j);
            }
            removed += 1;
        }
        // `touched` holds each touched node once (`touch`) and `sent` each slave once
        // (`deferred_may_go`): when as many left it as it holds, none is left (the usual
        // case: only the slaves sent on were touched).
        if removed == self.touched.len() {
            debug_assert!(
                self.touched
                    .iter()
                    .all(|&k| !self.nodes.get(k).is_some_and(|n| n.is_touched)),
                "a touched node left out"
            );
            self.touched.clear();
        } else if removed > 0 {
            let nodes = &self.nodes;
            self.touched
                .retain(|&k| nodes.get(k).is_some_and(|n| n.is_touched));
        }
    }

    /// Whether `serve` would do nothing for node `j` but what `set_wake` does (debug
    /// builds): powered, no host due, nothing traced, no output due, its plain hop as
    /// found last.
    fn serve_does_nothing(&self, j: usize) -> bool {
        let Some(node) = self.nodes.get(j) else {
            return false;
        };
        let plain = self.static_plain.get(j).copied().unwrap_or(false)
            && node.powered
            && node.repeating
            && node.clock.is_identity();
        let hop_same = (self.plain_hop.get(j) == Some(&super::NOT_PLAIN)) != plain;
        node.powered
            && node.vcd.is_none()
            && node.quiet_host()
            && !node.chip.line_output_due_at(node.clock.to_local(self.now))
            && self.deferred.is_empty()
            && hop_same
    }

    /// Whether the ATs of `deferred` may go now (the module's conditions).
    fn deferred_may_go(&self, deferred: &[usize]) -> bool {
        // The first slave's telegram is asked for first: after a telegram that lets the
        // slaves run only up to the next one (a ring's MST: the MDT comes before the ATs),
        // none has its AT queued yet, and that ends the checks below at once (every one of
        // them must hold; their order changes nothing).
        let Some(first) = self
            .nodes
            .get(1)
            .and_then(|s| s.chip.sole_queued_telegram())
        else {
            return false;
        };
        let n = self.nodes.len();
        // Every slave, in ring order, each once.
        if n < 2 || deferred.len() != n - 1 || !deferred.iter().copied().eq(1..n) {
            return false;
        }
        // Plain repeaters from the first slave on, and a plain fibre into the master.
        let into_master = n - 1;
        let plain_into_master = self
            .segments
            .get(into_master)
            .is_some_and(|s| s.faults.is_clean() && !s.keep_last)
            && !self.recorder.wants(into_master);
        if self.run_end.get(1) != Some(&n) || !plain_into_master {
            return false;
        }
        let Some(master) = self.nodes.first() else {
            return false;
        };
        if !master.powered || !master.off_windows.is_empty() || !master.clock.is_identity() {
            return false;
        }
        // The master's next output, as the pass promised it (`Simulation::master_horizon`).
        let Some(next_master) = self.master_next else {
            return false;
        };
        let mut after: Option<Instant> = None;
        for j in 1..n {
            let queued = if j == 1 {
                Some(first)
            } else {
                self.nodes
                    .get(j)
                    .and_then(|node| node.chip.sole_queued_telegram())
            };
            let Some((start, end, bit_time)) = queued else {
                return false;
            };
            // Its telegram is ahead of the simulation, and starts after the one before has
            // passed this repeater (fibre delay plus the repeater latency of its bits).
            if start <= self.now
                || after.is_some_and(|a| start < a)
                || next_master.is_none_or(|m| start >= m)
            {
                return false;
            }
            let hop = self.seg_delays.get(j).copied().unwrap_or(Duration::ZERO);
            after = Some(
                end.saturating_add(hop)
                    .saturating_add(bit_time.saturating_mul(REPEATER_LATENCY_BITS)),
            );
        }
        true
    }
}

/// The ATs sent through in one `route_deferred` (`Simulation::send_all_plain`).
#[derive(Debug, Default)]
struct Run {
    /// Whether the floors' run was asked for (at the first AT).
    tried: bool,
    /// The floors' run, while open.
    through: Option<super::out_floors::Through>,
}
