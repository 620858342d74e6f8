//! A host program's wake run so that it can be suspended at each bus access.
//!
//! A [`HostProgram`] is plain code that calls [`SerconBus`] and returns when its work is done.
//! A real host processor's bus cycle takes time (`NodeConfig::bus_access`), during which the
//! ring and the other hosts go on; a program that reads and writes for 18 µs is interleaved
//! with everything else that happens in those 18 µs. To interleave them exactly, each wake
//! runs as a stackful coroutine ([`corosensei`]): every access the program makes is handed
//! to the simulation ([`HostStep::Access`]), which performs it on the chip at the chip's
//! time and resumes the program with its value once the access's bus time has passed, with
//! the events of everybody else in between taken in time order (spec-notes "A host's bus
//! time"). Before, the program ran whole inside the simulation's call and the events
//! meanwhile ran inside its accesses: a host woken within another host's access ran all of
//! its program there, and the outer host's next access came only after it.

use corosensei::stack::DefaultStack;
use corosensei::{Coroutine, CoroutineResult, Yielder};
use sercon_regs::SerconBus;
use sercon_regs::register::read_has_effect;
use sercos_wire::time::Instant;

use crate::host::{HostProgram, Wake};

/// Size of a host program's stack, that of a spawned thread: the drivers need a few KiB; the
/// rest is address space that is never touched (the pages are mapped as they are used).
const STACK_BYTES: usize = 2 << 20;

/// One access of a host program to its chip (the four of [`SerconBus`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Access {
    /// [`SerconBus::read_register`].
    ReadRegister(u8),
    /// [`SerconBus::write_register`].
    WriteRegister(u8, u16),
    /// [`SerconBus::read_ram`].
    ReadRam(u16),
    /// [`SerconBus::write_ram`].
    WriteRam(u16, u16),
}

impl Access {
    /// Performs the access on `bus`: the word read, 0 for a write.
    pub(crate) fn perform(self, bus: &mut dyn SerconBus) -> u16 {
        match self {
            Access::ReadRegister(a) => bus.read_register(a),
            Access::WriteRegister(a, v) => {
                bus.write_register(a, v);
                0
            }
            Access::ReadRam(a) => bus.read_ram(a),
            Access::WriteRam(a, v) => {
                bus.write_ram(a, v);
                0
            }
        }
    }

    /// Whether it writes a control register (which may change whether the chip repeats its
    /// input, 410B §4.1 1H.3 REPON, 2H).
    pub(crate) fn writes_register(self) -> bool {
        matches!(self, Access::WriteRegister(..))
    }

    /// Whether it may change the chip: a write, or a read of RFIFO, which takes a word
    /// from the receive FIFO (410B §4.1 27H). Any other read leaves the chip as it was
    /// (410B §4.1 registers, §4.2 the RAM through the host's port).
    pub(crate) fn changes_chip(self) -> bool {
        match self {
            Access::ReadRegister(a) => read_has_effect(a),
            Access::ReadRam(_) => false,
            Access::WriteRegister(..) | Access::WriteRam(..) => true,
        }
    }
}

/// The program's bus inside the coroutine: every access suspends the program until the
/// simulation resumes it with the access's value.
struct YieldBus<'y> {
    yielder: &'y Yielder<u16, Access>,
}

impl SerconBus for YieldBus<'_> {
    fn read_register(&mut self, address: u8) -> u16 {
        self.yielder.suspend(Access::ReadRegister(address))
    }

    fn write_register(&mut self, address: u8, value: u16) {
        self.yielder.suspend(Access::WriteRegister(address, value));
    }

    fn read_ram(&mut self, address: u16) -> u16 {
        self.yielder.suspend(Access::ReadRam(address))
    }

    fn write_ram(&mut self, address: u16, value: u16) {
        self.yielder.suspend(Access::WriteRam(address, value));
    }
}

/// What a wake hands back when it ends: the program and the deadline it asked for.
type Finished = (Box<dyn HostProgram>, Option<Instant>);

/// What the program did when it was run on ([`HostRun::resume`]).
pub(crate) enum HostStep {
    /// It asks for this access and waits for it.
    Access(Access),
    /// Its wake ended: the program back, with the deadline it asked for (`None`: only
    /// interrupts wake it).
    Done(Box<dyn HostProgram>, Option<Instant>),
}

/// One wake of a host program, under way.
pub(crate) struct HostRun {
    /// `None` only once it has ended ([`HostRun::into_stack`]).
    co: Option<Coroutine<u16, Access, Finished>>,
    /// Why the program was woken.
    pub(crate) why: Wake,
    /// The access in progress ends here (node time): the program goes on then.
    pub(crate) resume_at: Instant,
    /// What the access in progress returns to the program.
    pub(crate) value: u16,
}

impl std::fmt::Debug for HostRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HostRun")
            .field("why", &self.why)
            .field("resume_at", &self.resume_at)
            .field("value", &self.value)
            .finish_non_exhaustive()
    }
}

impl HostRun {
    /// `host`'s wake for `why` at `now`, on `stack`; nothing runs before the first
    /// [`HostRun::resume`].
    pub(crate) fn start(
        stack: DefaultStack,
        host: Box<dyn HostProgram>,
        now: Instant,
        why: Wake,
    ) -> HostRun {
        let co = Coroutine::with_stack(stack, move |yielder: &Yielder<u16, Access>, _: u16| {
            let mut host = host;
            let deadline = host.wake(&mut YieldBus { yielder }, now, why);
            (host, deadline)
        });
        HostRun {
            co: Some(co),
            why,
            resume_at: now,
            value: 0,
        }
    }

    /// Runs the program on, with [`HostRun::value`] as what its last access returned,
    /// until its next access or its end. A panic of the program goes on in the caller.
    pub(crate) fn resume(&mut self) -> HostStep {
        let Some(co) = self.co.as_mut() else {
            // Ended before: nothing more to run (the program is no longer here).
            return HostStep::Done(Box::new(crate::host::IdleHost), None);
        };
        match co.resume(self.value) {
            CoroutineResult::Yield(a) => HostStep::Access(a),
            CoroutineResult::Return((host, deadline)) => HostStep::Done(host, deadline),
        }
    }

    /// The stack of a run that has ended, for the next one; a run still under way is
    /// dropped (unwound, [`Drop`]) and gives none.
    pub(crate) fn into_stack(mut self) -> Option<DefaultStack> {
        match self.co.take() {
            Some(co) if co.done() => Some(co.into_stack()),
            other => {
                self.co = other;
                None
            }
        }
    }
}

impl Drop for HostRun {
    /// A run still suspended is unwound (its program's frames dropped). A build that
    /// aborts on panic cannot unwind one: its stack is left mapped instead (a simulation
    /// dropped with a host in the middle of an access).
    fn drop(&mut self) {
        if cfg!(panic = "abort")
            && let Some(co) = self.co.take()
            && co.started()
            && !co.done()
        {
            std::mem::forget(co);
        }
    }
}

/// Stacks of ended runs, kept for the next ones (mapping a stack costs system calls).
#[derive(Default)]
pub(crate) struct Stacks {
    free: Vec<DefaultStack>,
}

impl std::fmt::Debug for Stacks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stacks")
            .field("free", &self.free.len())
            .finish()
    }
}

impl Stacks {
    /// A stack for a run: a kept one, or a new one (`None` when none can be mapped).
    pub(crate) fn take(&mut self) -> Option<DefaultStack> {
        match self.free.pop() {
            Some(s) => Some(s),
            None => DefaultStack::new(STACK_BYTES).ok(),
        }
    }

    /// Keeps `stack` for a later run.
    pub(crate) fn give(&mut self, stack: DefaultStack) {
        self.free.push(stack);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::host::IdleHost;

    /// Reads register 3 and writes what it read plus one to RAM word 7, then asks for a
    /// deadline one picosecond after `now`.
    struct Echo;

    impl HostProgram for Echo {
        fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, _why: Wake) -> Option<Instant> {
            let v = bus.read_register(3);
            bus.write_ram(7, v.wrapping_add(1));
            Some(Instant::from_picos(now.as_picos() + 1))
        }
    }

    #[test]
    fn a_run_hands_out_each_access_and_takes_its_value() {
        let mut stacks = Stacks::default();
        let stack = stacks.take().expect("a stack");
        let now = Instant::from_picos(40);
        let mut run = HostRun::start(stack, Box::new(Echo), now, Wake::Deadline);
        assert!(matches!(
            run.resume(),
            HostStep::Access(Access::ReadRegister(3))
        ));
        run.value = 41;
        assert!(matches!(
            run.resume(),
            HostStep::Access(Access::WriteRam(7, 42))
        ));
        run.value = 0;
        let HostStep::Done(_, deadline) = run.resume() else {
            panic!("the wake did not end");
        };
        assert_eq!(deadline, Some(Instant::from_picos(41)));
        let stack = run.into_stack().expect("an ended run gives its stack back");
        stacks.give(stack);
        // The stack serves the next run.
        let mut again = HostRun::start(
            stacks.take().expect("kept"),
            Box::new(IdleHost),
            now,
            Wake::Start,
        );
        assert!(matches!(again.resume(), HostStep::Done(_, None)));
        assert!(again.into_stack().is_some());
    }

    #[test]
    fn a_run_dropped_while_suspended_unwinds_its_program() {
        struct Guarded(std::rc::Rc<std::cell::Cell<bool>>);
        impl Drop for Guarded {
            fn drop(&mut self) {
                self.0.set(true);
            }
        }
        struct Waits(std::rc::Rc<std::cell::Cell<bool>>);
        impl HostProgram for Waits {
            fn wake(&mut self, bus: &mut dyn SerconBus, _: Instant, _: Wake) -> Option<Instant> {
                let _g = Guarded(self.0.clone());
                bus.read_register(0);
                None
            }
        }
        let dropped = std::rc::Rc::new(std::cell::Cell::new(false));
        let mut run = HostRun::start(
            DefaultStack::new(STACK_BYTES).expect("a stack"),
            Box::new(Waits(dropped.clone())),
            Instant::ZERO,
            Wake::Start,
        );
        assert!(matches!(run.resume(), HostStep::Access(_)));
        assert!(
            run.into_stack().is_none(),
            "a suspended run keeps its stack"
        );
        // `into_stack` gave the run back whole; dropping it unwinds the program's frames.
        assert!(dropped.get(), "the program's frame was dropped");
    }
}
