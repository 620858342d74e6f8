//! Property tests of the timing planner: it never panics, and every plan it returns keeps the
//! relations a master checks (sercos-facts.md, "Timing parameters") and fits the cycle.

use proptest::prelude::*;
use sercdrv::timing::{
    DriveParameters, MdtPlacement, RECORD_HEADER_BYTES, TimingRequest, TimingRules, plan_cycle,
    worst_case_line_bits,
};
use sercos_wire::line::frame_bit_len;
use sercos_wire::time::BitRate;

fn rate() -> impl Strategy<Value = BitRate> {
    prop::sample::select(BitRate::ALL.to_vec())
}

/// Mostly whole words, sometimes an odd byte count (refused).
fn data_bytes() -> impl Strategy<Value = u16> {
    prop_oneof![400 => (0u16..20).prop_map(|w| w * 2), 1 => 0u16..40]
}

fn drive_params() -> impl Strategy<Value = DriveParameters> {
    (
        1u8..=254,
        0u16..400,
        0u16..200,
        0u16..1000,
        0u16..100,
        0u16..200,
        data_bytes(),
        data_bytes(),
    )
        .prop_map(
            |(address, t1min, atmt, t5, mtsy, mtsg, at, mdt)| DriveParameters {
                address,
                t1min_us: t1min,
                t_atmt_us: atmt,
                t5_us: t5,
                t_mtsy_us: mtsy,
                t_mtsg_us: mtsg,
                at_data_bytes: at,
                mdt_data_bytes: mdt,
            },
        )
}

fn request() -> impl Strategy<Value = TimingRequest> {
    (
        rate(),
        prop_oneof![1 => 0u32..70_000, 6 => 60u32..8000],
        1u32..4,
        prop::collection::vec(drive_params(), 0..24),
        0u16..20,
        any::<bool>(),
        prop::bool::weighted(0.9),
    )
        .prop_map(|(bit_rate, cycle, nc, mut drives, gap, late, unique)| {
            // Mostly distinct addresses (random ones collide often and test only one refusal).
            if unique {
                for (i, d) in drives.iter_mut().enumerate() {
                    d.address = u8::try_from(i + 1).unwrap_or(254);
                }
            }
            TimingRequest {
                bit_rate,
                cycle_time_us: cycle,
                nc_cycle_time_us: cycle.saturating_mul(nc),
                drives,
                rules: TimingRules {
                    min_gap_us: gap,
                    mdt_placement: if late {
                        MdtPlacement::EndOfCycle
                    } else {
                        MdtPlacement::AfterAts
                    },
                },
            }
        })
}

/// Every relation a returned plan must keep (sercos-facts.md, "Timing parameters").
fn check_relations(req: &TimingRequest) -> Result<(), TestCaseError> {
    let Ok(plan) = plan_cycle(req) else {
        return Ok(());
    };
    let cycle = req.cycle_time_us;
    let window = cycle - plan.mst_duration_us;
    prop_assert_eq!(plan.drives.len(), req.drives.len());
    let t2 = plan.t2_us();
    let mut previous_end = 0u32;
    let mut offset = 1u32;
    for (p, d) in plan.drives.iter().zip(&req.drives) {
        prop_assert_eq!(p.address, d.address);
        // sercos-facts.md: t1min ≤ t1 < t2 − tATMT.
        prop_assert!(u32::from(d.t1min_us) <= p.t1_us());
        prop_assert!(p.t1_us() + u32::from(d.t_atmt_us) < t2);
        prop_assert!(p.at.end_us() + u32::from(d.t_atmt_us) <= t2);
        // ATs don't overlap each other or the MST, and keep the gap.
        prop_assert!(p.t1_us() >= previous_end + plan.gap_us);
        previous_end = p.at.end_us();
        // S-0-0009 counts from ADR, records back to back.
        prop_assert_eq!(u32::from(p.mdt_offset), offset);
        prop_assert_eq!(
            u32::from(p.mdt_record_bytes),
            RECORD_HEADER_BYTES + u32::from(d.mdt_data_bytes)
        );
        offset += u32::from(p.mdt_record_bytes);
        // The AT's reserved time covers any content's real length on the line.
        let worst = worst_case_line_bits(u64::from(p.at.bytes));
        prop_assert!(
            req.bit_rate.duration_of_bits(worst).as_picos()
                <= u64::from(p.at.duration_us) * 1_000_000
        );
        // sercos-facts.md: t4 ≤ tScyc − t5.
        prop_assert!(plan.t4_us + u32::from(d.t5_us) <= cycle);
        // sercos-facts.md: t2 + MDT duration + S-0-0090 < t3 ≤ tScyc.
        prop_assert!(t2 + plan.mdt.duration_us + u32::from(d.t_mtsg_us) < plan.t3_us);
        // S-0-0088: the MDT ends tMTSY before the next MST.
        prop_assert!(plan.mdt.end_us() + u32::from(d.t_mtsy_us) <= window);
    }
    prop_assert!(previous_end + plan.gap_us <= t2);
    prop_assert!(plan.t3_us <= cycle);
    prop_assert_eq!(u32::from(plan.mdt_length) + 1, offset);
    prop_assert_eq!(plan.mdt.bytes, offset);
    // Every telegram ends before the cycle ends.
    prop_assert!(plan.tend_us() <= window);
    prop_assert!(plan.noncyclic.at.start_us >= plan.gap_us);
    prop_assert!(plan.noncyclic.at.end_us() + plan.gap_us <= plan.noncyclic.mdt.start_us);
    prop_assert!(plan.noncyclic.mdt.end_us() <= window);
    Ok(())
}

fn any_drive() -> impl Strategy<Value = DriveParameters> {
    (any::<u8>(), any::<[u16; 7]>()).prop_map(|(address, v)| DriveParameters {
        address,
        t1min_us: v[0],
        t_atmt_us: v[1],
        t5_us: v[2],
        t_mtsy_us: v[3],
        t_mtsg_us: v[4],
        at_data_bytes: v[5],
        mdt_data_bytes: v[6],
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(1000)))]

    #[test]
    fn every_plan_keeps_every_relation(req in request()) {
        check_relations(&req)?;
    }

    #[test]
    fn arbitrary_values_never_panic(
        bit_rate in rate(),
        cycle in any::<u32>(),
        nc in any::<u32>(),
        drives in prop::collection::vec(any_drive(), 0..300),
        gap in any::<u16>(),
        late in any::<bool>(),
    ) {
        let req = TimingRequest {
            bit_rate,
            cycle_time_us: cycle,
            nc_cycle_time_us: nc,
            drives,
            rules: TimingRules {
                min_gap_us: gap,
                mdt_placement: if late { MdtPlacement::EndOfCycle } else { MdtPlacement::AfterAts },
            },
        };
        check_relations(&req)?;
    }

    #[test]
    fn worst_case_bound_covers_every_frame(bytes in prop::collection::vec(any::<u8>(), 1..80)) {
        // ERRATA "Telegrams": at most one inserted 0 per five bits between the flags.
        prop_assert!(frame_bit_len(&bytes) <= worst_case_line_bits(bytes.len() as u64));
    }
}

#[test]
fn the_property_sees_many_plans() {
    // Guards the property above against being vacuous: a good share of the generated
    // requests must be plannable.
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strategy = request();
    let mut planned = 0;
    for _ in 0..500 {
        let Ok(tree) = strategy.new_tree(&mut runner) else {
            continue;
        };
        if plan_cycle(&tree.current()).is_ok() {
            planned += 1;
        }
    }
    assert!(planned >= 50, "only {planned} of 500 requests planned");
}
