//! Hosts inside the ring. A host's bus accesses cost time (`NodeConfig::bus_access`), and
//! the ring runs along with them, other hosts included: each wake of a host program runs as
//! a coroutine (`crate::host_coroutine`) that is suspended at every access. The access is
//! performed on the chip at the chip's time; then, unless nothing can reach or leave the
//! chip before the access ends (the quiet access: the chip is only moved on), the program
//! waits in the simulation's heap of access ends (`Simulation::resumes`) while every other
//! event up to then is taken in time order, and goes on there (`resume_host`). Every line
//! segment so reaches a chip
//! before the chip's clock passes its start (the contract of `Chip::line_input`), and
//! every host's accesses come one access time apart, whoever else is busy meanwhile
//! (spec-notes "A host's bus time").

use sercos_wire::time::{Duration, Instant};

use super::Simulation;
use crate::host::{IdleHost, Wake};
use crate::host_coroutine::{HostRun, HostStep};
use crate::node::{MAX_HOST_WAKES, repeats};
use crate::topology::Topology;

impl Simulation {
    /// Serves node `j`'s host: goes on with its wake under way once the access it waits
    /// for has ended, and wakes it for interrupt changes and a due deadline, as often as
    /// they come (`Node::host_due`, [`MAX_HOST_WAKES`] at most per call), until it waits in
    /// an access or has nothing due. A host whose wake is under way is not woken again.
    pub(super) fn serve_host(&mut self, j: usize) {
        let mut wakes = 0;
        loop {
            let Some(node) = self.nodes.get_mut(j) else {
                return;
            };
            if !node.powered {
                return;
            }
            if let Some(run) = node.host_run.take() {
                if run.resume_at > node.chip.now() {
                    node.host_run = Some(run);
                    node.note_pins();
                    return;
                }
                if !self.drive_host(j, run) {
                    return;
                }
                continue;
            }
            if wakes >= MAX_HOST_WAKES {
                return;
            }
            let Some(why) = node.host_due() else {
                return;
            };
            wakes += 1;
            let host = std::mem::replace(&mut node.host, Box::new(IdleHost));
            let Some(stack) = self.stacks.take() else {
                // No stack to be had: the wake runs whole on its chip alone, as at the start
                // (`start_hosts`).
                if let Some(node) = self.nodes.get_mut(j) {
                    node.host = host;
                    node.run_host(why);
                }
                self.touch(j);
                continue;
            };
            let now = node.chip.now();
            let run = Box::new(HostRun::start(stack, host, now, why));
            if !self.drive_host(j, run) {
                return;
            }
        }
    }

    /// Runs node `j`'s host wake `run` on: each access it asks for is performed on the chip
    /// at the chip's time and lasts one `NodeConfig::bus_access`. A quiet access (nothing
    /// can reach or leave the chip before it ends, [`Simulation::access_is_quiet`]) only
    /// moves the chip on and the program goes on at once; any other suspends the program
    /// until the access's end, entered in `resumes` (`resume_host` goes on with it there, or
    /// `serve_host` when the node is served at or after it). Returns whether the wake ended
    /// (`false`: it waits in an access).
    fn drive_host(&mut self, j: usize, mut run: Box<HostRun>) -> bool {
        loop {
            match run.resume() {
                HostStep::Access(access) => {
                    // The queue must hold every node's wake before `access_is_quiet` asks
                    // it.
                    self.set_rewakes();
                    let Some(node) = self.nodes.get_mut(j) else {
                        return true;
                    };
                    run.value = access.perform(&mut node.chip);
                    // Only a register write can change INT0 / INT1 at once (410B §4.1: 3H
                    // ENINT0/1 and POLINT0/1, 4H–5H flags cleared, 6H–9H enables; a read
                    // changes nothing but RFIFO, which moves no interrupt); a change of the
                    // chip's own comes at an event of its own, where the node is served
                    // (`serve_host` notes it there). A write may also have changed whether
                    // the chip repeats its input (410B §4.1 1H.3 REPON): the ring follows it
                    // from now on.
                    if access.writes_register() {
                        node.note_pins();
                        node.repeating = repeats(&node.chip);
                    }
                    let cost = node.cfg.bus_access;
                    if cost == Duration::ZERO {
                        continue;
                    }
                    let target = node.chip.now().saturating_add(cost);
                    if self.access_is_quiet(j, target) {
                        if let Some(node) = self.nodes.get_mut(j) {
                            node.chip.advance_to(target);
                        }
                        continue;
                    }
                    let Some(node) = self.nodes.get_mut(j) else {
                        return true;
                    };
                    run.resume_at = target;
                    node.host_run = Some(run);
                    node.note_host();
                    let until = node.clock.to_global(target);
                    self.resumes.push(std::cmp::Reverse((until, j)));
                    // A read leaves the chip as it was (`Access::changes_chip`); any other
                    // access may have changed what it does next: the node is served again
                    // (its pins, its output, its wake).
                    if access.changes_chip() {
                        self.touch(j);
                    }
                    self.stats.host_suspensions += 1;
                    return false;
                }
                HostStep::Done(host, deadline) => {
                    self.end_host_wake(j, *run, host, deadline);
                    if let Some(node) = self.nodes.get_mut(j) {
                        node.repeating = repeats(&node.chip);
                    }
                    self.touch(j);
                    return true;
                }
            }
        }
    }

    /// Node `j`'s host goes on at `r` (simulation time), the end of the access it waits in
    /// (`resumes`; an entry for a host that no longer waits then is passed over). Its chip is
    /// brought there; with nothing of the chip due before (its own events are its wakes,
    /// taken first) the program goes on at once (`drive_host`), else the node is served as
    /// at a wake of its own, which goes on with it (`serve_host`).
    #[inline(never)]
    pub(super) fn resume_host(&mut self, j: usize, r: Instant) {
        self.now = self.now.max(r);
        self.deferred.clear();
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        let Some(local) = node.host_run.as_ref().map(|run| run.resume_at) else {
            return;
        };
        if !node.powered || node.clock.to_global(local) != r {
            return;
        }
        let due = node.chip.next_event_at().is_some_and(|e| e <= local);
        node.chip.advance_to(local);
        if due {
            self.touch(j);
        } else if let Some(run) = node.host_run.take() {
            self.drive_host(j, run);
        }
        self.settle();
    }

    /// Whether another host's access end (`resumes`) comes early enough for what its node
    /// sends then to reach node `j` by `until`: with a few hosts waiting, each by the fibres
    /// from its node round to `j` ([`Simulation::reach_delay`]); with more, the earliest by
    /// the shortest fibre (a bound no later than any of them, and one look instead of one per
    /// waiting host, which would make a ring of 254 busy drives quadratic).
    fn resume_reaches(&self, j: usize, until: Instant) -> bool {
        const FEW: usize = 8;
        if self.resumes.len() <= FEW {
            self.resumes.iter().any(|std::cmp::Reverse((r, k))| {
                self.reach_delay(*k, j)
                    .is_none_or(|d| r.saturating_add(d) <= until)
            })
        } else {
            self.resumes
                .peek()
                .is_some_and(|std::cmp::Reverse((r, _))| {
                    self.min_fibre_delay.map_or(*r, |h| r.saturating_add(h)) <= until
                })
        }
    }

    /// The least time a signal takes from node `k` to node `j`: on a ring the fibres from
    /// `k` round to `j` (410B §1 Fig. 3: the line runs one way; the repeaters' latency left
    /// out, a lower bound), on the bus its delay (Fig. 4); `None` for no time at all.
    fn reach_delay(&self, k: usize, j: usize) -> Option<Duration> {
        let d = match self.topology {
            Topology::Bus { delay } => delay,
            Topology::Ring { .. } => {
                let at = |i: usize| self.from_master.get(i).copied().unwrap_or(Duration::ZERO);
                if j > k {
                    at(j).saturating_sub(at(k))
                } else {
                    let round = self
                        .from_master
                        .last()
                        .copied()
                        .unwrap_or(Duration::ZERO)
                        .saturating_add(self.seg_delays.last().copied().unwrap_or(Duration::ZERO));
                    round.saturating_sub(at(k)).saturating_add(at(j))
                }
            }
        };
        (d > Duration::ZERO).then_some(d)
    }

    /// Whether node `j`'s access ending at `target` (node time) is quiet: no node waits to
    /// be served (its host or output could reach this chip), no fault event up to the
    /// access's end, no node wake early enough for what it sends to arrive before the access
    /// ends (its arrival is a fibre delay later at the least; a waiting host's access's end too),
    /// and nothing of this chip due before then (no internal event, so no pin or interrupt
    /// change; no output segment). Nothing can reach or leave the chip meanwhile, so moving
    /// it on is all that waiting for the access's end with the ring running along would do.
    fn access_is_quiet(&mut self, j: usize, target: Instant) -> bool {
        let Some(until) = self.nodes.get(j).map(|n| n.clock.to_global(target)) else {
            return false;
        };
        // The shortest fibre: nothing a node sends at `e` reaches another before `e + hop`.
        let hop = self.min_fibre_delay;
        let reaches = |e: Instant| hop.map_or(e, |h| e.saturating_add(h)) <= until;
        self.touched.is_empty()
            && self.queue.peek_fault_time().is_none_or(|e| e > until)
            && !self.queue.peek_wake_time().is_some_and(reaches)
            && !self.resume_reaches(j, until)
            && self
                .nodes
                .get(j)
                .is_some_and(|n| n.chip.next_event_at().is_none_or(|e| e > target))
    }

    /// Ends node `j`'s host wake under way, if any, on its chip alone (each access moving
    /// the chip on by its bus time, as at the start): the node was powered off, and nothing
    /// it does can reach the ring any more.
    pub(super) fn finish_host_alone(&mut self, j: usize) {
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        let Some(mut run) = node.host_run.take() else {
            return;
        };
        let cost = node.cfg.bus_access;
        loop {
            match run.resume() {
                HostStep::Access(access) => {
                    run.value = access.perform(&mut node.chip);
                    let t = node.chip.now().saturating_add(cost);
                    node.chip.advance_to(t);
                }
                HostStep::Done(host, deadline) => {
                    self.end_host_wake(j, *run, host, deadline);
                    return;
                }
            }
        }
    }

    /// Node `j`'s host wake `run` has ended: the program back in its node with the deadline
    /// it asked for, the wake's stack kept for the next one.
    fn end_host_wake(
        &mut self,
        j: usize,
        run: HostRun,
        host: Box<dyn crate::host::HostProgram>,
        deadline: Option<Instant>,
    ) {
        let why = run.why;
        if let Some(stack) = run.into_stack() {
            self.stacks.give(stack);
        }
        if let Some(node) = self.nodes.get_mut(j) {
            node.host = host;
            node.host_deadline = deadline;
            node.woke(why);
        }
    }

    /// Wakes every host with [`Wake::Start`], in node order, each on its own chip at time
    /// 0 (every chip is still at reset and the line dark: nothing can arrive late that
    /// matters; starting the hosts one after another with the ring running along would
    /// delay every later node's configuration by the earlier hosts' bus time).
    pub(super) fn start_hosts(&mut self) {
        for j in 0..self.nodes.len() {
            if let Some(node) = self.nodes.get_mut(j) {
                node.run_host(Wake::Start);
                node.ints = (
                    node.chip.pin_level(sercon_model::pins::Pin::Int0),
                    node.chip.pin_level(sercon_model::pins::Pin::Int1),
                );
            }
            self.touch(j);
        }
    }
}
