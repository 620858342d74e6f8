//! Hosts inside the ring. A host's bus accesses cost time (`NodeConfig::bus_access`), and
//! the ring runs along with them: before an access moves its chip's clock on, every other
//! node's events up to then are run and the chip's own output is put on the line, so that
//! every line segment reaches a chip before the chip's clock passes its start (the contract
//! of `Chip::line_input`). Without this a host that works for a while (the master's driver
//! handles a cycle in ≈ 18 µs at 100 ns per access) ran its chip past the signal still on
//! its way, and the receiver saw no edges: a false FIBBR (410B §4.1 2H.13) on an intact
//! ring (`docs/spec-notes.md`, "Ring simulation").

use sercon_model::Chip;
use sercon_regs::SerconBus;
use sercos_wire::time::{Duration, Instant};

use super::Simulation;
use crate::error::SimError;
use crate::host::{HostProgram, IdleHost, Wake};
use crate::node::{MAX_HOST_WAKES, repeats};

/// Hosts woken inside other hosts' bus time at most this deep; deeper ones move only their
/// own chip on ([`crate::host::NodeBus`]), so a long chain of busy hosts cannot exhaust the stack.
const MAX_HOST_NESTING: usize = 16;

/// A host's access to its chip inside a running simulation (see the module notes).
struct RingBus<'a> {
    sim: &'a mut Simulation,
    node: usize,
    cost: Duration,
}

impl RingBus<'_> {
    fn chip(&mut self) -> Option<&mut Chip> {
        self.sim.nodes.get_mut(self.node).map(|n| &mut n.chip)
    }

    fn spend(&mut self) {
        if let Err(e) = self.sim.spend_host_time(self.node, self.cost) {
            self.sim.held_error.get_or_insert(e);
        }
    }
}

impl SerconBus for RingBus<'_> {
    fn read_register(&mut self, address: u8) -> u16 {
        let v = self.chip().map_or(0, |c| c.read_register(address));
        self.spend();
        v
    }

    fn write_register(&mut self, address: u8, value: u16) {
        if let Some(c) = self.chip() {
            c.write_register(address, value);
        }
        self.spend();
    }

    fn read_ram(&mut self, address: u16) -> u16 {
        let v = self.chip().map_or(0, |c| c.read_ram(address));
        self.spend();
        v
    }

    fn write_ram(&mut self, address: u16, value: u16) {
        if let Some(c) = self.chip() {
            c.write_ram(address, value);
        }
        self.spend();
    }
}

impl Simulation {
    /// Wakes node `j`'s host for interrupt changes and a due deadline, as often as they come
    /// (`Node::serve_host`), with the ring running along (a busy host is not woken again).
    pub(super) fn serve_host(&mut self, j: usize) {
        if self.host_nesting >= MAX_HOST_NESTING {
            if let Some(node) = self.nodes.get_mut(j)
                && !node.host_busy
            {
                node.serve_host();
            }
            return;
        }
        for _ in 0..MAX_HOST_WAKES {
            let Some(node) = self.nodes.get_mut(j) else {
                return;
            };
            if node.host_busy || !node.powered {
                return;
            }
            let Some(why) = node.host_due() else {
                return;
            };
            self.host_wake(j, why);
        }
    }

    /// Runs node `j`'s host once for `why`, its accesses through a [`RingBus`].
    pub(super) fn host_wake(&mut self, j: usize, why: Wake) {
        let Some(node) = self.nodes.get_mut(j) else {
            return;
        };
        let busy = std::mem::replace(&mut node.host_busy, true);
        let mut host: Box<dyn HostProgram> = std::mem::replace(&mut node.host, Box::new(IdleHost));
        let now = node.chip.now();
        let cost = node.cfg.bus_access;
        self.host_nesting += 1;
        let deadline = host.wake(
            &mut RingBus {
                sim: self,
                node: j,
                cost,
            },
            now,
            why,
        );
        self.host_nesting -= 1;
        if let Some(node) = self.nodes.get_mut(j) {
            node.host = host;
            node.host_busy = busy;
            node.host_deadline = deadline;
            node.repeating = repeats(&mut node.chip);
            node.woke(why);
        }
        self.touch(j);
    }

    /// Moves node `j`'s chip on by one bus access of `cost`, running the ring along: in
    /// steps that end no later than the shortest fibre after the next wake of the others
    /// and after the chip's own next event (no signal gets from one node to another
    /// faster), the chip first (its output goes on the line at once), then every event of
    /// the other nodes up to the step's end, but none within a fibre of the access's end
    /// (what they send cannot arrive before it ends).
    fn spend_host_time(&mut self, j: usize, cost: Duration) -> Result<(), SimError> {
        if cost == Duration::ZERO {
            return Ok(());
        }
        // The queue must hold every node's wake before it is asked below.
        self.set_rewakes();
        let Some(node) = self.nodes.get(j) else {
            return Ok(());
        };
        let target = node.chip.now().saturating_add(cost);
        let until = node.clock.to_global(target);
        // The shortest fibre: nothing a node sends at `e` reaches another before `e + hop`.
        let hop = self.min_fibre_delay;
        // Quiet access: no node waits to be served (its host or output could reach this
        // chip), no fault event up to the access's end, no node wake early enough for what
        // it sends to arrive before the access ends (its arrival is a fibre delay later at
        // the least), and nothing of this chip due before then (no internal event, so no
        // pin or interrupt change; no output segment). Nothing can reach or leave the chip
        // meanwhile, so moving it on is all the steps below would do (they would serve and
        // reschedule the node for nothing).
        let reaches = |e: Instant| hop.map_or(e, |h| e.saturating_add(h)) <= until;
        if self.touched.is_empty()
            && self.queue.peek_fault_time().is_none_or(|e| e > until)
            && !self.queue.peek_wake_time().is_some_and(reaches)
            && node.chip.next_event_at().is_none_or(|e| e > target)
        {
            if let Some(node) = self.nodes.get_mut(j) {
                node.chip.advance_to(target);
            }
            return Ok(());
        }
        let mut first = true;
        loop {
            let Some(node) = self.nodes.get_mut(j) else {
                return Ok(());
            };
            if node.chip.now() >= target {
                return Ok(());
            }
            let from = node.clock.to_global(node.chip.now());
            let own = node.chip.next_event_at();
            let mut step = until;
            match hop {
                // Nothing a node sends at `e` reaches another before `e + hop`: the chip
                // may run up to a fibre past the next wake of the others (what they send
                // then arrives no earlier) and a fibre past its own next event (what it
                // sends then, served at once below, reaches the others no earlier, and
                // anything they send back no earlier still). Faults act at their instant
                // (a node's power or clock), so the step stops there; so do nodes still
                // waiting to be served (what they release may have started before now).
                Some(h) if self.touched.is_empty() => {
                    if let Some(w) = self.queue.peek_wake_time() {
                        step = step.min(w.saturating_add(h));
                    }
                    if let Some(f) = self.queue.peek_fault_time() {
                        step = step.min(f.max(from));
                    }
                    let own = own.map_or(Instant::MAX, |e| node.clock.to_global(e));
                    step = step.min(own.max(from).saturating_add(h));
                }
                _ => {
                    if let Some(h) = hop {
                        step = step.min(from.saturating_add(h));
                    }
                    if let Some(e) = self.queue.peek_time() {
                        step = step.min(e.max(from));
                    }
                }
            }
            let local = node.clock.to_local(step).min(target);
            // Always forward: at least to the next picosecond of the node's own time.
            let local = local.max(node.chip.now().saturating_add(Duration::from_picos(1)));
            // The node is served (pins, output, wake) on the access's first step (the
            // access may have changed what its chip does next: its wake must follow, as
            // hosts woken meanwhile run ahead and the queue alone moves this chip on) and
            // then only when its chip has something due up to the step's end: otherwise
            // moving it on changes nothing anyone can see (no internal event, so no pin
            // or interrupt change; no output segment) and leaves its next event, so its
            // wake, where they were; its host is busy, so it is not woken either.
            let due = first || own.is_some_and(|e| e <= local);
            first = false;
            node.chip.advance_to(local);
            if due {
                self.touch(j);
            }
            self.settle();
            let step = self
                .nodes
                .get(j)
                .map_or(step, |n| n.clock.to_global(n.chip.now()));
            // The others' events only as far as they can reach this chip within the access:
            // one less than a fibre before its end sends nothing that arrives before the
            // access ends, and waits for its turn (the queue keeps the order). So the quiet
            // access above, which runs none of them, is this loop's shortcut, not an
            // approximation. Run up to the access's end, they took in the wake of a node whose
            // host is busy further out (hosts nest, `host_wake`), which moved that chip on
            // under its host: its next access came that much late, not one access time
            // (`NodeConfig::bus_access`) after the last, and only where the inner access was
            // not quiet. With 20 drives at 4 Mbit/s the master read 4H on INT0 (410B §4.1
            // 4H.4 INT_COMEND) and its write clearing the flags (INT0 falls) came 10.95 µs
            // late on the reference path only: there a wake 50 ns before the end kept the last
            // access of drive 15 (the innermost of the 15 slave hosts nested in the master's
            // read) off the quiet shortcut, and it ran the master's wake at the end
            // (spec-notes "Ring simulation", "Events a host's access runs").
            let step = match hop {
                Some(h) => step.min(Instant::from_picos(
                    until.as_picos().saturating_sub(h.as_picos()),
                )),
                None => step,
            };
            self.run_events_until(step)?;
        }
    }

    /// Runs the queued events up to and including `t` (inside a host's bus time).
    fn run_events_until(&mut self, t: Instant) -> Result<(), SimError> {
        while let Some(ev) = self.queue.pop_until(t) {
            self.process(ev)?;
        }
        Ok(())
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
