//! Spec tests of the RAM layout builder (`sercdrv::ram_layout`, 410B §4.2): layouts for 1, 4,
//! 8, 32 drives on both variants, the 254-drive ring on the 816, slaves, buffering, refusals,
//! and a property test that structures never overlap and every chain ends in an end marker.

mod common;

use common::ring_timing::{plan_alike, request};
use proptest::prelude::*;
use sercdrv::ram_layout::{
    PhaseGroup, RamLayout, RamLayoutError, RamLayoutRequest, RegionKind, Role, build,
};
use sercdrv::timing::{CycleTiming, DriveParameters, plan_cycle};
use sercon_regs::Variant;
use sercon_regs::ram::container::{ContainerControl, RxContainer};
use sercon_regs::ram::header::{Buffering, Header, HeaderKind};
use sercon_regs::ram::{COMPT0, COMPT1, scpt};
use sercos_wire::time::BitRate;

fn plan(rate: BitRate, cycle: u32, n: u8, at_data: u16, mdt_data: u16) -> CycleTiming {
    plan_alike(rate, cycle, n, at_data, mdt_data).expect("timing fits")
}

/// The RAM after the layout's writes.
fn ram_of(layout: &RamLayout) -> Vec<u16> {
    let mut ram = vec![0xDEADu16; usize::from(layout.variant.ram_words())];
    for w in &layout.writes {
        ram[usize::from(w.address)] = w.word;
    }
    ram
}

/// Walks the header chain from COMPTn the way the chip does (410B §4.2.1-4.2.3) and returns
/// (header address, kind, container count) per telegram; fails on a loop, a bad marker or a
/// container run that does not end where PT points.
fn walk(
    layout: &RamLayout,
    ram: &[u16],
    compt: u16,
) -> Result<Vec<(u16, HeaderKind, usize)>, String> {
    let mut at = ram[usize::from(compt)];
    let mut out = Vec::new();
    for _ in 0..=ram.len() {
        let words = ram.get(usize::from(at)..).ok_or("pointer outside RAM")?;
        let header = Header::decode(layout.variant, words).map_err(|e| e.to_string())?;
        let (kind, pt, buffering) = match header {
            Header::End(_) => return Ok(out),
            Header::Receive(h) => (HeaderKind::Receive, h.pt, h.buffering()),
            Header::Transmit(h) => (HeaderKind::Transmit, h.pt, h.buffering()),
        };
        // ERRATA "data containers": containers follow the header until LASTDC = 1.
        let mut c = u32::from(at) + kind.words() as u32;
        let mut count = 0;
        loop {
            let w0 = *ram.get(c as usize).ok_or("container outside RAM")?;
            let control = ContainerControl::from_word(w0);
            let control_words = if kind == HeaderKind::Receive { 2 } else { 1 };
            c += control_words + control.data_words(buffering);
            count += 1;
            if control.lastdc {
                break;
            }
            if count > ram.len() {
                return Err("no LASTDC".into());
            }
        }
        if c != u32::from(pt) {
            return Err(format!("PT {pt} but containers end at {c}"));
        }
        out.push((at, kind, count));
        at = pt;
    }
    Err("header chain loops".into())
}

/// The invariants every layout keeps.
fn check_layout(layout: &RamLayout) -> Result<(), String> {
    let size = u32::from(layout.variant.ram_words());
    let mut regions = layout.regions.clone();
    regions.sort_by_key(|r| r.start);
    for pair in regions.windows(2) {
        if pair[0].start + pair[0].words > pair[1].start {
            return Err(format!("{:?} overlaps {:?}", pair[0], pair[1]));
        }
    }
    if let Some(last) = regions.last() {
        if last.start + last.words > size || last.start + last.words != layout.words_used {
            return Err(format!(
                "last region {last:?} vs {} used of {size}",
                layout.words_used
            ));
        }
    }
    // Every write lands in a placed structure.
    for w in &layout.writes {
        let a = u32::from(w.address);
        if !regions
            .iter()
            .any(|r| r.start <= a && a < r.start + r.words)
        {
            return Err(format!("write to {a} outside every structure"));
        }
    }
    let ram = ram_of(layout);
    for compt in [COMPT0, COMPT1] {
        let chain = walk(layout, &ram, compt)?;
        // The chain visits exactly the headers the map lists for this block.
        let start = ram[usize::from(compt)];
        if let Some(block) = layout
            .map
            .blocks
            .iter()
            .find(|b| b.telegrams.first().map(|t| t.header) == Some(start))
        {
            let listed: Vec<(u16, HeaderKind, usize)> = block
                .telegrams
                .iter()
                .map(|t| (t.header, t.kind, t.containers.len()))
                .collect();
            if listed != chain {
                return Err(format!("map {listed:?} vs chain {chain:?}"));
            }
        }
    }
    // SCPTn point at the service containers the map lists.
    for s in &layout.map.service_containers {
        let pointer = scpt(s.nsv).ok_or("NSV above 7")?;
        if ram[usize::from(pointer)] != s.address {
            return Err(format!("SCPT{} does not point at {}", s.nsv, s.address));
        }
    }
    Ok(())
}

fn master(variant: Variant, timing: &CycleTiming) -> Result<RamLayout, RamLayoutError> {
    build(&RamLayoutRequest::new(variant, Role::Master, timing))
}

#[test]
fn master_layouts_for_1_4_8_32_drives_on_both_variants() {
    for variant in Variant::ALL {
        for n in [1u8, 4, 8, 32] {
            // The captures' telegram type 7: 8 bytes of AT data, 4 of MDT data.
            let timing = plan(BitRate::Mbit4, 4000, n, 8, 4);
            let layout = master(variant, &timing).expect("fits");
            check_layout(&layout).expect("consistent");
            assert_eq!(layout.map.drives.len(), usize::from(n));
            assert_eq!(layout.map.service_containers.len(), usize::from(n.min(8)));
            // Drives past the eighth have no service container (SVFL = 0).
            let last = layout.map.drive(n).expect("mapped");
            assert_eq!(last.command.nsv.is_some(), n <= 8);
            // The cyclic block holds one AT header per drive and one MDT header.
            let cyclic = &layout.map.blocks[1];
            assert_eq!(cyclic.group, PhaseGroup::Cyclic);
            assert_eq!(cyclic.telegrams.len(), usize::from(n) + 1);
            assert_eq!(cyclic.telegrams[usize::from(n)].adr, 255);
            println!(
                "{variant:?}, {n} drives: {} of {} words",
                layout.words_used,
                variant.ram_words()
            );
        }
    }
}

#[test]
fn the_layout_words_decode_to_the_timing() {
    let timing = plan(BitRate::Mbit2, 2000, 4, 8, 4);
    let layout = master(Variant::Sercon410b, &timing).expect("fits");
    let ram = ram_of(&layout);
    let cyclic = &layout.map.blocks[1];
    for (tel, drive) in cyclic.telegrams.iter().zip(&timing.drives) {
        let h =
            Header::decode(Variant::Sercon410b, &ram[usize::from(tel.header)..]).expect("header");
        let Header::Receive(h) = h else {
            panic!("AT header must be a receive header")
        };
        // 410B §4.2.1: TRT = t1 (µs after end of MST), TLEN = record words, ADR = drive.
        assert_eq!(u32::from(h.trt), drive.t1_us());
        assert_eq!(h.tlen, 6);
        assert_eq!(h.adr, drive.address);
        assert!(h.achk);
        let c =
            RxContainer::decode(&ram[usize::from(tel.containers[0].control)..]).expect("container");
        assert_eq!(c.control.len, 6);
        assert!(c.control.svfl && c.control.scmaster && c.control.lastdc);
        assert_eq!(c.pos, 0);
    }
    let mdt = &cyclic.telegrams[4];
    let Header::Transmit(h) =
        Header::decode(Variant::Sercon410b, &ram[usize::from(mdt.header)..]).expect("header")
    else {
        panic!("MDT header must be a transmit header")
    };
    assert_eq!(u32::from(h.trt), timing.t2_us());
    assert_eq!(h.tlen, 16); // S-0-0010 = 32 bytes
    // 410B §4.2.3: TEND = end of the last telegram.
    let end =
        Header::decode(Variant::Sercon410b, &ram[usize::from(cyclic.end_marker)..]).expect("end");
    assert_eq!(
        end,
        Header::End(sercon_regs::ram::header::EndMarker {
            reserved: 0,
            tend: timing.tend_us() as u16
        })
    );
    // MDT containers in S-0-0009 order, NSV 0-3.
    let nsv: Vec<Option<u8>> = mdt.containers.iter().map(|c| c.nsv).collect();
    assert_eq!(nsv, [Some(0), Some(1), Some(2), Some(3)]);
}

#[test]
fn two_hundred_fifty_four_drives_do_not_fit_the_816_as_master() {
    // 4 bytes of cyclic data each way: AT record 8 bytes (4 words), MDT record 4 words.
    let timing = plan(BitRate::Mbit16, 4000, 254, 4, 4);
    let err = master(Variant::Sercon816, &timing).expect_err("does not fit");
    // 410B §4.2: 11 fixed words; 8 service containers of 5 + 32 words; phases 0-2 block:
    // AT header 5 + container 2 + 2, MDT header 4 + container 1 + 2, end marker 2;
    // phases 3-4 block: per drive AT header 5 + container 2 + 4 and MDT container 1 + 4,
    // one MDT header 4 and an end marker 2.
    let needed = 11 + 8 * 37 + (5 + 2 + 2 + 4 + 1 + 2 + 2) + 254 * (5 + 2 + 4 + 1 + 4) + 4 + 2;
    assert_eq!(
        err,
        RamLayoutError::DoesNotFit {
            variant: Variant::Sercon816,
            needed,
            available: 2048
        }
    );
    assert!(err.to_string().contains("needs 4395 words"), "{err}");
    // Even with DMA (no data words) and only the phase 3-4 block the AT headers alone
    // (254 × 7 words) nearly fill the RAM: still refused.
    let mut req = RamLayoutRequest::new(Variant::Sercon816, Role::Master, &timing);
    req.buffering = Buffering::Dma;
    req.blocks = [None, Some(PhaseGroup::Cyclic)];
    let err = build(&req).expect_err("does not fit with DMA either");
    let needed_dma = 11 + 8 * 37 + 2 + 254 * (5 + 2 + 1) + 4 + 2;
    assert_eq!(
        err,
        RamLayoutError::DoesNotFit {
            variant: Variant::Sercon816,
            needed: needed_dma,
            available: 2048
        }
    );
}

#[test]
fn a_slave_layout_takes_its_own_record() {
    let timing = plan(BitRate::Mbit4, 2000, 4, 8, 4);
    for variant in Variant::ALL {
        let layout = build(&RamLayoutRequest::new(
            variant,
            Role::Slave { address: 3 },
            &timing,
        ))
        .expect("fits");
        check_layout(&layout).expect("consistent");
        assert_eq!(layout.map.service_containers.len(), 1);
        let me = layout.map.drive(3).expect("own record");
        assert_eq!(layout.map.drives.len(), 1);
        let ram = ram_of(&layout);
        let rx = RxContainer::decode(&ram[usize::from(me.command.control)..]).expect("container");
        // 410B §4.2.2 POS in words; S-0-0009 = 17 bytes from ADR → word 8 of the data.
        assert_eq!(rx.pos, 8);
        assert!(!rx.control.scmaster && rx.control.svfl);
        // Phases 0-2: AT only after an MDT with our address (EN = 3, 410B §4.2.1).
        let noncyclic = &layout.map.blocks[0];
        assert_eq!(noncyclic.telegrams[0].kind, HeaderKind::Transmit);
        let w0 = ram[usize::from(noncyclic.telegrams[0].header)];
        assert_eq!((w0 >> 11) & 3, 3);
    }
    let err = build(&RamLayoutRequest::new(
        Variant::Sercon816,
        Role::Slave { address: 9 },
        &timing,
    ));
    assert_eq!(err, Err(RamLayoutError::UnknownDrive { address: 9 }));
}

#[test]
fn buffering_changes_the_container_sizes() {
    let timing = plan(BitRate::Mbit4, 2000, 2, 8, 4);
    let used = |buffering| {
        let mut req = RamLayoutRequest::new(Variant::Sercon816, Role::Master, &timing);
        req.buffering = buffering;
        let layout = build(&req).expect("fits");
        check_layout(&layout).expect("consistent");
        layout.words_used
    };
    // ERRATA "container words": LEN, 2 × LEN or no data words. Records: AT 6, MDT 4 words.
    let per_drive = 6 + 4;
    assert_eq!(
        used(Buffering::Double) - used(Buffering::Single),
        2 * per_drive
    );
    assert_eq!(
        used(Buffering::Single) - used(Buffering::Dma),
        2 * per_drive
    );
}

#[test]
fn refusals_name_the_reason() {
    let timing = plan(BitRate::Mbit16, 1000, 2, 4, 4);
    // 816 §2.3.1: 8 and 16 Mbit/s only on the 816.
    assert_eq!(
        master(Variant::Sercon410b, &timing),
        Err(RamLayoutError::BitRateNotSupported {
            variant: Variant::Sercon410b,
            rate: BitRate::Mbit16
        })
    );
    let mut req = RamLayoutRequest::new(Variant::Sercon816, Role::Master, &timing);
    req.service_buffer_words = 252; // 410B §4.2.4: 8-bit offsets, buffer from offset 5.
    assert!(matches!(
        build(&req),
        Err(RamLayoutError::ServiceBufferSize { words: 252, .. })
    ));
    // A block without a phase group points at an end marker.
    let mut req = RamLayoutRequest::new(Variant::Sercon816, Role::Master, &timing);
    req.blocks = [Some(PhaseGroup::NonCyclic), None];
    let layout = build(&req).expect("fits");
    check_layout(&layout).expect("consistent");
    let idle = layout.map.idle_end_marker.expect("idle end marker");
    assert_eq!(ram_of(&layout)[usize::from(COMPT1)], idle);
    assert!(
        layout
            .regions
            .iter()
            .any(|r| r.kind == RegionKind::EndMarker && r.start == u32::from(idle))
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(300)))]

    #[test]
    fn structures_never_overlap_and_chains_end(
        n in 1u8..=80,
        at_words in 0u16..12,
        mdt_words in 0u16..12,
        variant in prop::sample::select(Variant::ALL.to_vec()),
        buffering in prop::sample::select(vec![Buffering::Single, Buffering::Double, Buffering::Dma]),
        slave in any::<bool>(),
        sc_words in 1u16..=64,
    ) {
        let drives = (1..=n)
            .map(|address| DriveParameters {
                address,
                t1min_us: 0,
                t_atmt_us: 0,
                t5_us: 0,
                t_mtsy_us: 0,
                t_mtsg_us: 0,
                at_data_bytes: at_words * 2,
                mdt_data_bytes: mdt_words * 2,
            })
            .collect();
        let Ok(timing) = plan_cycle(&request(BitRate::Mbit4, 65_000, drives)) else {
            return Ok(());
        };
        let role = if slave { Role::Slave { address: n } } else { Role::Master };
        let mut req = RamLayoutRequest::new(variant, role, &timing);
        req.buffering = buffering;
        req.service_buffer_words = sc_words;
        match build(&req) {
            Ok(layout) => {
                prop_assert!(layout.words_used <= u32::from(variant.ram_words()));
                if let Err(e) = check_layout(&layout) {
                    return Err(TestCaseError::fail(e));
                }
            }
            Err(RamLayoutError::DoesNotFit { needed, available, .. }) => {
                prop_assert!(needed > available);
                prop_assert_eq!(available, u32::from(variant.ram_words()));
            }
            Err(other) => return Err(TestCaseError::fail(other.to_string())),
        }
    }
}

#[test]
fn largest_master_rings_with_the_captures_telegram_type() {
    // Per drive 18 words (AT header 5, AT container 2 + 6, MDT container 1 + 4); fixed part
    // 11 + 8 × 37 + 18 + 4 + 2 = 331. 410B: 331 + 18 × 38 = 1015 ≤ 1024 < 1033 (39 drives);
    // 816: 331 + 18 × 95 = 2041 ≤ 2048 < 2059 (96 drives).
    for (variant, most) in [(Variant::Sercon410b, 38u8), (Variant::Sercon816, 95)] {
        let fits = plan(BitRate::Mbit4, 20_000, most, 8, 4);
        assert!(master(variant, &fits).is_ok(), "{variant:?} {most}");
        let too_many = plan(BitRate::Mbit4, 20_000, most + 1, 8, 4);
        assert!(matches!(
            master(variant, &too_many),
            Err(RamLayoutError::DoesNotFit { .. })
        ));
    }
}
