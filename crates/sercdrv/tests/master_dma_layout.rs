//! The master's layout for large rings: DMA data through the FIFOs at 27H (410B §4.1, §2
//! DMAREQR/DMAREQT; §4.2.1 DMA) and one MDT transmit container for every record (410B
//! §4.2.2), with the host-run service channel in phases 3-4 (410B §4.2.4 master table run
//! by the host; spec-notes "Master DMA layout").

mod common;
mod master_support;

use master_support::*;
use sercdrv::master::{
    CyclicLayout, MIN_SERVICE_BUFFER_WORDS, Master, MasterConfig, MasterErrorKind, Progress,
};
use sercdrv::ram_layout::{MasterBudget, MdtContainers};
use sercdrv::service_channel::{ErrorKind, Request};
use sercon_regs::Variant;
use sercon_regs::ram::header::Buffering;
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::Idn;
use sercos_wire::service_error::ServiceError;

const VELOCITY_COMMAND: Idn = Idn::from_raw(36);
const POSITION_FEEDBACK: Idn = Idn::from_raw(51);

fn drives(n: usize) -> Vec<DriveAddress> {
    (1..=n)
        .filter_map(|a| u8::try_from(a).ok().and_then(DriveAddress::new))
        .collect()
}

fn drive(a: u8) -> DriveAddress {
    DriveAddress::new(a).expect("1-254")
}

const DMA_SINGLE: CyclicLayout = CyclicLayout {
    buffering: Buffering::Dma,
    mdt: MdtContainers::Single,
};

/// Brings `ring` to phase 4 within `max_cycles` and checks the layout in use.
fn to_phase4(ring: &mut Ring, max_cycles: u64) {
    let took = ring.run_to_phase(4, max_cycles);
    let status = ring.master.borrow().status();
    assert!(took.is_some(), "no phase 4: {:?}", status.last_error);
    assert_eq!(status.progress, Progress::Cyclic);
    assert_eq!(status.restarts, 0, "{:?}", status.last_error);
    let m = ring.master.borrow();
    assert_eq!(m.cyclic_layout(), DMA_SINGLE);
    assert!(m.host_runs_service_channel());
}

/// Commands out through TFIFO, feedback in through RFIFO, every drive: each drive gets its
/// own velocity command (410B §4.2.2: the records follow each other in the one container,
/// S-0-0009 offsets), and each drive's position feedback (S-0-0051, two words) moves at its
/// own speed every cycle, never a value of another drive or half of two cycles.
fn exchange_both_ways(ring: &mut Ring, n: usize, cycles: u64) {
    let addresses = drives(n);
    {
        let mut m = ring.master.borrow_mut();
        for &a in &addresses {
            m.set_control_word(a, 0xE000).expect("cyclic");
            // Drive i: i × 10 rpm (S-0-0036, 4 decimal places).
            let rpm = u64::from(a.get()) * 10;
            m.set_command(a, VELOCITY_COMMAND, rpm * 10_000)
                .expect("configured");
        }
    }
    // Let the axes follow (time constant) before measuring.
    ring.run_cycles(60);
    let mut last: Vec<i64> = Vec::new();
    let mut steps: Vec<Vec<i64>> = vec![Vec::new(); n];
    for c in 0..cycles {
        ring.run_cycles(1);
        let m = ring.master.borrow();
        let now: Vec<i64> = addresses
            .iter()
            .map(|&a| m.feedback(a, POSITION_FEEDBACK).expect("feedback") as u32 as i32 as i64)
            .collect();
        if c > 0 {
            for (i, (p, q)) in last.iter().zip(&now).enumerate() {
                if let Some(s) = steps.get_mut(i) {
                    s.push((q - p).rem_euclid(1 << 32));
                }
            }
        }
        last = now;
    }
    let status = ring.master.borrow().status();
    for d in &status.drives {
        assert!(d.ats_received > 60, "{d:?}");
    }
    // The MDT path: every drive holds the command the master sent it.
    for (node, &a) in ring.drives.iter().zip(&addresses) {
        let node = node.borrow();
        let words = node
            .drive()
            .database()
            .get(VELOCITY_COMMAND)
            .map(|p| p.words().to_vec());
        let rpm = u32::from(a.get()) * 10 * 10_000;
        assert_eq!(
            words,
            Some(vec![rpm as u16, (rpm >> 16) as u16]),
            "drive {a}"
        );
    }
    // The AT path: position steps per cycle proportional to the drive's own speed
    // (degrees per cycle = rpm × 360 / 60 × cycle; S-0-0051 has 4 decimal places). A
    // value torn between two cycles or taken from another drive breaks the ratio.
    let cycle_s = ring.cycle.as_picos() as f64 * 1e-12;
    for (i, s) in steps.iter().enumerate() {
        let rpm = (i as f64 + 1.0) * 10.0;
        let expected = rpm * 6.0 * cycle_s * 10_000.0;
        for step in s {
            let err = (*step as f64 - expected).abs();
            assert!(
                err <= expected * 0.02 + 2.0,
                "drive {}: step {step}, expected {expected:.1}: {s:?}",
                i + 1
            );
        }
    }
}

/// Service requests of a tool to `a` in phase 4 through the host-run channel
/// (sercos-facts.md service channel): a read (S-0-0002 = the cycle time), a read of an IDN
/// the drive does not have (its error answer 1001H) and a write refused by the drive
/// (S-0-0002 is write-protected from phase 3 on).
fn service_channel_beyond_the_first_eight(ring: &mut Ring, a: DriveAddress, cycle_us: u32) {
    let (read, write, missing) = {
        let mut m = ring.master.borrow_mut();
        let read = m
            .submit_service(a, Request::read_value(Idn::COMMUNICATION_CYCLE_TIME))
            .expect("configured drive");
        // P-0-0100 is not in the standard database: "IDN not present".
        let missing = m
            .submit_service(a, Request::read_value(Idn::from_raw(0x8064)))
            .expect("configured drive");
        let write = m
            .submit_service(
                a,
                Request::write_value(Idn::COMMUNICATION_CYCLE_TIME, vec![1000]),
            )
            .expect("configured drive");
        (read, write, missing)
    };
    let mut done = Vec::new();
    for _ in 0..400 {
        ring.run_cycles(1);
        done.extend(ring.master.borrow_mut().take_service_completions());
        if done.len() == 3 {
            break;
        }
    }
    assert_eq!(done.len(), 3, "{done:?}");
    let by = |t| done.iter().find(|c| c.ticket == t).expect("completed");
    let r = by(read).result.clone().expect("S-0-0002 read");
    assert_eq!(r.words, vec![cycle_us as u16], "S-0-0002 of drive {a}");
    let e = by(missing).result.clone().expect_err("no such IDN");
    assert_eq!(e.drive, a);
    assert_eq!(e.kind, ErrorKind::Drive(ServiceError::IdnNotPresent));
    // sercos-facts.md: S-0-0002 is write-protected from phase 3 on.
    let w = by(write).result.clone().expect_err("protected in phase 4");
    assert!(matches!(w.kind, ErrorKind::Drive(_)), "{w:?}");
    let status = ring.master.borrow().status();
    assert_eq!(status.progress, Progress::Cyclic, "{:?}", status.last_error);
}

// 410B §4.2.1 DMA, §4.2.2, §4.1 27H: a small ring asking for the DMA layout with one MDT
// container: phase 4, data both ways through the FIFOs, host-run service channel.
#[test]
fn twelve_drives_with_dma_and_one_mdt_container() {
    let n = 12;
    let mut cfg = MasterConfig::new(Variant::Sercon816, rate(16), 1000, drives(n));
    cfg.buffering = Buffering::Dma;
    cfg.mdt_containers = MdtContainers::Single;
    let mut ring = ring(cfg, standard_drives(n), Vec::new());
    to_phase4(&mut ring, 8000);
    exchange_both_ways(&mut ring, n, 20);
    service_channel_beyond_the_first_eight(&mut ring, drive(11), 1000);
}

#[test]
fn a_ring_that_fits_no_layout_is_refused_with_its_words() {
    // 410B §4.2: 1024 words; 254 drives need at least 7 words each for their AT.
    let cfg = MasterConfig::new(Variant::Sercon410b, rate(4), 65_000, drives(254));
    let e = Master::new(cfg).expect_err("does not fit");
    match e.kind {
        MasterErrorKind::RingDoesNotFit {
            drives,
            needed,
            available,
        } => {
            assert_eq!((drives, available), (254, 1024));
            assert!(needed > 1024, "{needed}");
        }
        other => panic!("{other:?}"),
    }
}

// 410B §4.2: the 410B's 1024 words hold 24 drives with the default layout (double buffer,
// one MDT container per drive, the captures' telegram type); 30 drives make the master fall
// back to DMA with one MDT container by itself (MasterConfig::layout_fallback), reach phase
// 4 at 4 Mbit/s and exchange data both ways, the service channel of drive 29 host-run.
#[test]
fn thirty_drives_on_the_410b_fall_back_to_the_dma_layout() {
    let n = 30;
    let cfg = MasterConfig::new(Variant::Sercon410b, rate(4), 4000, drives(n));
    assert_eq!(cfg.buffering, Buffering::Double);
    let default = MasterBudget::master_default(Variant::Sercon410b, 8, 4);
    assert!(!default.fits(n as u32));
    let mut ring = ring(cfg, standard_drives(n), Vec::new());
    to_phase4(&mut ring, 30_000);
    exchange_both_ways(&mut ring, n, 10);
    service_channel_beyond_the_first_eight(&mut ring, drive(29), 4000);
}

// 410B §4.2 (1024 words) with DMA and one MDT container (410B §4.2.2): per drive only the
// AT receive header and container (5 + 2 words); the master shrinks the service buffers to
// 8 words (MIN_SERVICE_BUFFER_WORDS) for the largest ring, 126 drives; 127 fit no layout.
#[test]
fn the_410b_holds_126_drives_with_the_dma_layout() {
    let m = Master::new(MasterConfig::new(
        Variant::Sercon410b,
        rate(4),
        65_000,
        drives(126),
    ))
    .expect("fits");
    assert_eq!(m.service_buffer_words(), MIN_SERVICE_BUFFER_WORDS);
    let fitting = MasterBudget {
        service_buffer_words: MIN_SERVICE_BUFFER_WORDS,
        ..MasterBudget::master_default(Variant::Sercon410b, 8, 4)
    };
    let dma = MasterBudget {
        buffering: Buffering::Dma,
        mdt: MdtContainers::Single,
        ..fitting
    };
    assert_eq!(dma.largest_ring(), 126);
    // 98 drives still fit with the configured 32-word buffers.
    let m = Master::new(MasterConfig::new(
        Variant::Sercon410b,
        rate(4),
        65_000,
        drives(98),
    ))
    .expect("fits");
    assert_eq!(m.service_buffer_words(), 32);
    let e = Master::new(MasterConfig::new(
        Variant::Sercon410b,
        rate(4),
        65_000,
        drives(127),
    ))
    .expect_err("does not fit");
    assert!(
        matches!(
            e.kind,
            MasterErrorKind::RingDoesNotFit {
                drives: 127,
                available: 1024,
                ..
            }
        ),
        "{e}"
    );
}

// 410B §4.2 / 816 §2.3: 2048 words. 254 drives (sercos-telegrams.md ADR 1-254) with the
// captures' telegram type: the layout with DMA and one MDT container (410B §4.2.2) builds,
// fits, gives every drive its AT header and its record in the one MDT container, and names
// no service container in phases 3-4; the master keeps 24-word service buffers for it.
#[test]
fn the_254_drive_layout_builds_and_fits_the_816() {
    use sercdrv::ram_layout::{PhaseGroup, RamLayoutRequest, Role, build_with};
    use sercos_wire::time::BitRate;
    let m = Master::new(MasterConfig::new(
        Variant::Sercon816,
        rate(16),
        4000,
        drives(254),
    ))
    .expect("fits");
    assert_eq!(m.service_buffer_words(), 24);
    let timing = common::ring_timing::plan_alike(BitRate::Mbit16, 5000, 254, 8, 4)
        .expect("254 drives fit 5 ms at 16 Mbit/s");
    let mut req = RamLayoutRequest::new(Variant::Sercon816, Role::Master, &timing);
    req.buffering = Buffering::Dma;
    req.service_buffer_words = 24;
    let layout = build_with(&req, MdtContainers::Single).expect("fits");
    assert!(layout.words_used <= 2048, "{}", layout.words_used);
    assert_eq!(layout.map.drives.len(), 254);
    let cyclic = layout
        .map
        .blocks
        .iter()
        .find(|b| b.group == PhaseGroup::Cyclic)
        .expect("phase 3-4 block");
    let mdt: Vec<_> = cyclic
        .telegrams
        .iter()
        .filter(|t| t.kind == sercon_regs::ram::header::HeaderKind::Transmit)
        .collect();
    assert_eq!(mdt.len(), 1);
    assert_eq!(mdt[0].containers.len(), 1, "one MDT container");
    // Record words: control word, service info, S-0-0036 (2 words) = 4 per drive.
    assert_eq!(mdt[0].containers[0].len, 254 * 4);
    assert!(
        layout
            .map
            .drives
            .iter()
            .all(|d| d.command.nsv.is_none() && d.feedback.nsv.is_none())
    );
    assert_eq!(cyclic.telegrams.len(), 255);
}
