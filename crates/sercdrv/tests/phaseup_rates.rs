//! The master brings emulated drives to phase 4 at every bit rate of the SERCON816, with
//! eight drives at 16 Mbit/s / 250 µs, and on the SERCON410B at 4 Mbit/s, then exchanges
//! cyclic data (a velocity command goes out, the drive's feedback comes back).

mod master_support;

use master_support::*;
use sercdrv::master::{MasterConfig, Progress};
use sercon_regs::Variant;
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::Idn;

fn drives(n: u8) -> Vec<DriveAddress> {
    (1..=n).filter_map(DriveAddress::new).collect()
}

/// Runs `cfg` with `n` standard drives to phase 4, sends a velocity command to the last
/// drive and checks that the drives follow and report back; returns the cycles to phase 4.
fn phase_up_and_exchange(cfg: MasterConfig, n: usize) -> u64 {
    let label = format!(
        "{:?} {:?} {} µs, {n} drives",
        cfg.variant, cfg.bit_rate, cfg.cycle_us
    );
    let mut ring = ring(cfg, standard_drives(n), Vec::new());
    let took = ring.run_to_phase(4, 20_000);
    let status = ring.master.borrow().status();
    let Some(took) = took else {
        panic!("{label}: no phase 4: {status:#?}");
    };
    assert_eq!(status.progress, Progress::Cyclic, "{label}");
    // sercos-telegrams.md MDT control word bits 15-13 = 111: drive on, enable, restart;
    // S-0-0036 velocity command (4 decimal places).
    let last = status.drives.last().map(|d| d.address).expect("drives");
    {
        let mut m = ring.master.borrow_mut();
        m.set_control_word(last, 0xE000).expect("control word");
        m.set_command(last, Idn::from_raw(36), 1_000_000)
            .expect("velocity command");
    }
    ring.run_cycles(400);
    for d in &ring.drives {
        assert_eq!(d.borrow().phase().number(), 4, "{label}: drive follows");
    }
    let m = ring.master.borrow();
    assert_eq!(m.progress(), Progress::Cyclic, "{label}: {:#?}", m.status());
    // AT status word bits 15-14 = 11: ready to operate (the drive follows the command).
    let status_word = m.status_word(last).expect("an AT of the last drive");
    assert_eq!(
        status_word >> 14,
        0b11,
        "{label}: status {status_word:#06X}"
    );
    // S-0-0051 position feedback moves with the velocity command.
    let position = m
        .feedback(last, Idn::from_raw(51))
        .expect("position feedback");
    assert_ne!(position, 0, "{label}");
    for d in m.status().drives {
        assert!(d.ats_received > 300, "{label}: {d:?}");
    }
    took
}

// 816 §2.3.1: 2, 4, 8 and 16 Mbit/s; the cycle shrinks with the rate.
#[test]
fn every_bit_rate_of_the_816_reaches_phase_4() {
    for (mbit, cycle_us) in [(2, 2000), (4, 1000), (8, 500), (16, 250)] {
        let cfg = MasterConfig::new(Variant::Sercon816, rate(mbit), cycle_us, drives(4));
        phase_up_and_exchange(cfg, 4);
    }
}

// Issue acceptance: 8 drives at 16 Mbit/s and 250 µs.
#[test]
fn eight_drives_at_16_mbit_and_250_us() {
    let cfg = MasterConfig::new(Variant::Sercon816, rate(16), 250, drives(8));
    phase_up_and_exchange(cfg, 8);
}

// 410B §1: 2 and 4 Mbit/s; issue acceptance: the 410B variant at 4 Mbit/s.
#[test]
fn the_410b_at_4_mbit() {
    let cfg = MasterConfig::new(Variant::Sercon410b, rate(4), 1000, drives(4));
    phase_up_and_exchange(cfg, 4);
}

// More drives than the eight service containers (410B §4.2 SCPT0-7): the containers are
// routed to one drive at a time (spec-notes "Driver master"); every drive reaches phase 4.
#[test]
fn twelve_drives_share_the_eight_service_containers() {
    let cfg = MasterConfig::new(Variant::Sercon816, rate(16), 500, drives(12));
    phase_up_and_exchange(cfg, 12);
}
