//! The program on a node's host processor, as a simulator or a real board runs it.
//!
//! A host program reaches its SERCON only through [`SerconBus`] (410B §2: the processor
//! interface) and is event-driven: it is woken when one of the chip's interrupt outputs becomes
//! active (410B §2 INT0/INT1) or when a deadline it asked for arrives, does its work without
//! blocking, and says when it next wants to run. It never reads a clock: the current instant is
//! passed in (DESIGN.md, "Time is injected, never read").
//!
//! The ring simulator (`sercos-sim`) drives programs through this trait; the driver (`sercdrv`)
//! and the emulated drive implement it, so neither depends on the other.

use sercos_wire::time::Instant;

use crate::bus::SerconBus;

/// Why a host program is woken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Wake {
    /// The simulation (or the board) starts: first call.
    Start,
    /// The node was powered on again after a power-off; the chip is fresh out of reset (the
    /// host processor restarted too: a program starts over).
    PowerOn,
    /// An interrupt output of the chip changed level (410B §2 INT0 / INT1); the levels now.
    Interrupt {
        /// Level of pin INT0.
        int0: bool,
        /// Level of pin INT1.
        int1: bool,
    },
    /// The deadline the program asked for has arrived.
    Deadline,
}

/// A program on a node's host processor.
pub trait HostProgram {
    /// Does the work for `why` at `now` through `bus`, and returns the next instant at which the
    /// program wants to be woken even without an interrupt (`None`: only by interrupts).
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant>;

    /// Whether the program only acts at [`Wake::Start`] and [`Wake::PowerOn`]: it never
    /// touches the bus when woken by an interrupt and never asks for a deadline. A
    /// simulation whose hosts are all inert may run a chip ahead of the others between its
    /// inputs (nothing reads it or changes its transmitter meanwhile). `false` unless a
    /// program says otherwise.
    fn inert(&self) -> bool {
        false
    }
}
