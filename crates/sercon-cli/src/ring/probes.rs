//! Host programs that run the master and the drives and note what happened to them: phase
//! changes, errors, missed command records, and every command value a drive applied.

use std::cell::RefCell;
use std::collections::HashSet;
use std::rc::Rc;

use sercdrv::master::{Master, MasterError, Progress};
use sercdrv::slave::SlaveDriverEvent;
use sercon_regs::SerconBus;
use sercon_regs::host::{HostProgram, Wake};
use sercos_drive::node::DriveNode;
use sercos_wire::idn::Idn;
use sercos_wire::time::Instant;

/// S-0-0036, velocity command (sercos-facts.md), the command of the default MDT list.
pub const VELOCITY_COMMAND: Idn = Idn::from_raw(36);

/// Runs a shared program as a simulator host program.
pub struct Shared<P>(pub Rc<RefCell<P>>);

impl<P: HostProgram> HostProgram for Shared<P> {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        self.0.borrow_mut().wake(bus, now, why)
    }
}

/// The master with its history.
#[derive(Debug)]
pub struct MasterProbe {
    /// The driver.
    pub master: Master,
    /// (time, phase, progress) at every change, the first at the first wake.
    pub timeline: Vec<(Instant, u8, Progress)>,
    /// Errors the master reported, with their time.
    pub errors: Vec<(Instant, MasterError)>,
}

impl MasterProbe {
    /// A probe around `master`.
    pub fn new(master: Master) -> MasterProbe {
        MasterProbe {
            master,
            timeline: Vec::new(),
            errors: Vec::new(),
        }
    }
}

impl HostProgram for MasterProbe {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        let next = self.master.wake(bus, now, why);
        let state = (self.master.phase(), self.master.progress());
        if self.timeline.last().map(|(_, p, g)| (*p, *g)) != Some(state) {
            self.timeline.push((now, state.0, state.1));
        }
        for e in self.master.take_errors() {
            self.errors.push((now, e));
        }
        next
    }
}

/// A drive node with its history.
#[derive(Debug)]
pub struct DriveProbe {
    /// The node.
    pub node: DriveNode,
    /// (time, phase) at every change.
    pub phases: Vec<(Instant, u8)>,
    /// Phase 3-4 cycles without a valid MDT record (slave driver `CommandMissing`).
    pub commands_missing: u64,
    /// Changes of the applied velocity command.
    pub commands_applied: u64,
    /// Applied velocity commands the master never sent, with their time.
    pub corrupted: Vec<(Instant, i128)>,
    /// Every velocity command the master sent to this drive (filled by the runner).
    pub sent: Rc<RefCell<HashSet<i128>>>,
    /// Refusals and failures the slave driver reported, as text, with their time.
    pub problems: Vec<(Instant, String)>,
    last_applied: Option<i128>,
}

impl DriveProbe {
    /// A probe around `node`; its current velocity command counts as sent.
    pub fn new(node: DriveNode) -> DriveProbe {
        let initial = node.drive().database().number(VELOCITY_COMMAND);
        let sent: HashSet<i128> = initial.into_iter().collect();
        DriveProbe {
            node,
            phases: Vec::new(),
            commands_missing: 0,
            commands_applied: 0,
            corrupted: Vec::new(),
            sent: Rc::new(RefCell::new(sent)),
            problems: Vec::new(),
            last_applied: initial,
        }
    }
}

impl HostProgram for DriveProbe {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        let next = self.node.wake(bus, now, why);
        for e in self.node.take_events() {
            match e {
                SlaveDriverEvent::CommandMissing => self.commands_missing += 1,
                SlaveDriverEvent::Failed(err) | SlaveDriverEvent::CyclicSetUpFailed(err) => {
                    self.problems.push((now, err.to_string()));
                }
                SlaveDriverEvent::DeviceRefused(r) => self.problems.push((now, r.0)),
                SlaveDriverEvent::PhaseRefused {
                    requested, reason, ..
                } => self
                    .problems
                    .push((now, format!("refused phase {requested}: {reason:?}"))),
                _ => {}
            }
        }
        let phase = self.node.phase().number();
        if self.phases.last().map(|(_, p)| *p) != Some(phase) {
            self.phases.push((now, phase));
        }
        // What the drive applied: its S-0-0036 after the slave driver handed it the record.
        let applied = self.node.drive().database().number(VELOCITY_COMMAND);
        if applied != self.last_applied {
            self.last_applied = applied;
            if let Some(v) = applied {
                self.commands_applied += 1;
                if !self.sent.borrow().contains(&v) {
                    self.corrupted.push((now, v));
                }
            }
        }
        next
    }
}
