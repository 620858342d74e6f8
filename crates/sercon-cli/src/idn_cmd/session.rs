//! A simulated ring brought to phase 2 or 4 and one drive's service channel on it: the
//! master's tool requests (`Master::submit_service`) carried out cycle by cycle in
//! simulated time.

use anyhow::{Result, anyhow, bail};
use sercdrv::master::Progress;
use sercdrv::service_channel::{Request, Response, ServiceChannelError};
use sercon_cli::ring::{self, BuiltRing, RingSpec};
use sercos_wire::address::DriveAddress;
use sercos_wire::time::{Duration, Instant};

/// The phase the ring is brought to before the access.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetPhase {
    /// Phase 2, the parameterisation phase: the master configures the drives and stays
    /// there (sercos-facts.md: configuration IDNs are written in phase 2).
    Two,
    /// Phase 4, cyclic operation.
    Four,
}

/// Cycles a tool request may take before the tool gives up: more than the master's own
/// limit for one request (400 cycles, `MasterConfig::service_timeout`), so that the
/// master's timeout, which names the element, comes first.
const REQUEST_CYCLES: u64 = 1000;

/// A ring up in its target phase, with one drive to talk to.
pub struct Session {
    ring: BuiltRing,
    drive: DriveAddress,
    cycle: Duration,
}

impl Session {
    /// Builds the ring of `spec`, checks that `drive` is on it, and runs it until the
    /// master serves tool requests in `phase`.
    pub fn open(spec: &RingSpec, drive: u8, phase: TargetPhase) -> Result<Session> {
        if spec.position_of(drive).is_none() {
            let on: Vec<String> = spec.drives.iter().map(|d| d.address.to_string()).collect();
            bail!(
                "--drive {drive}: there is no drive {drive} on the ring (drives {})",
                on.join(", ")
            );
        }
        let address =
            DriveAddress::new(drive).ok_or_else(|| anyhow!("--drive {drive}: not 1-254"))?;
        let mut ring = ring::build(spec, Vec::new(), false)?;
        ring.master
            .borrow_mut()
            .master
            .set_hold_in_phase2(phase == TargetPhase::Two);
        let cycle = Duration::from_micros(u64::from(spec.cycle_us.max(1)));
        let limit = Instant::ZERO.saturating_add(spec.phase_up_limit);
        loop {
            let (serves, progress, status) = {
                let m = ring.master.borrow();
                (
                    m.master.serves_tools(),
                    m.master.progress(),
                    m.master.status(),
                )
            };
            if serves {
                break;
            }
            let now = ring.sim.now();
            if progress == Progress::Halted || now >= limit {
                let why = status
                    .last_error
                    .map_or_else(|| format!("{progress:?}"), |e| e.to_string());
                bail!(
                    "the ring did not reach phase {} (master in phase {}: {why})",
                    match phase {
                        TargetPhase::Two => 2,
                        TargetPhase::Four => 4,
                    },
                    status.phase
                );
            }
            let next = now.saturating_add(cycle).min(limit);
            ring.sim
                .run_until(next)
                .map_err(|e| anyhow!("simulation: {e}"))?;
        }
        Ok(Session {
            ring,
            drive: address,
            cycle,
        })
    }

    /// The master's phase now.
    pub fn phase(&self) -> u8 {
        self.ring.master.borrow().master.phase()
    }

    /// Carries out `request` on the drive: the response, or the drive's refusal (or the
    /// service channel's failure) naming drive, IDN and element. `Err` only when the
    /// simulation fails or nothing comes back in time.
    pub fn request(
        &mut self,
        request: Request,
    ) -> Result<std::result::Result<Response, ServiceChannelError>> {
        let idn = request.idn();
        let ticket = self
            .ring
            .master
            .borrow_mut()
            .master
            .submit_service(self.drive, request)?;
        let end = self
            .ring
            .sim
            .now()
            .saturating_add(self.cycle.saturating_mul(REQUEST_CYCLES));
        while self.ring.sim.now() < end {
            let next = self.ring.sim.now().saturating_add(self.cycle).min(end);
            self.ring
                .sim
                .run_until(next)
                .map_err(|e| anyhow!("simulation: {e}"))?;
            let done = self
                .ring
                .master
                .borrow_mut()
                .master
                .take_service_completions();
            if let Some(c) = done.into_iter().find(|c| c.ticket == ticket) {
                return Ok(c.result);
            }
        }
        bail!(
            "drive {}, {idn}: no answer within {REQUEST_CYCLES} cycles (master in phase {})",
            self.drive.get(),
            self.phase()
        )
    }
}
