//! Property: a chip whose quiet events (a receive window's opening, a transmit telegram's
//! end, the end marker) are events of their own, because an enabled interrupt output
//! carries their flags, and one that applies them with its next event or bus access read
//! the same registers and RAM, whatever the RAM holds and whatever frames arrive, and
//! whenever the host looks (spec-notes "Events nobody sees at once"; 410B §4.1 3H, 4H, 5H,
//! 17H, 21H–26H; §4.2.1–§4.2.3).

mod common;

use proptest::prelude::*;
use sercon_model::Chip;
use sercon_regs::{Register, SerconBus, SerconBusExt};
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 3H.1 ENINT0, 3H.8 ENTMT.
const ENINT0: u16 = 1 << 1;
const ENTMT: u16 = 1 << 8;
/// 410B §4.1 4H.4 INT_COMEND, 4H.11 INT_TEND, 4H.12 INT_RWAIT.
const QUIET_FLAGS: u16 = (1 << 4) | (1 << 11) | (1 << 12);
/// 410B §4.1 3H.6 COMACT, 3H.7 COMBLK, 3H.9 FLTMT, 3H.10 FLRWAIT, 3H.11 FLREC.
const STATUS_3H: u16 = (1 << 6) | (1 << 7) | (1 << 9) | (1 << 10) | (1 << 11);

/// Everything a host can read that those events change, and a digest of the RAM.
fn host_view(c: &mut Chip) -> (Vec<u16>, u64) {
    let regs = vec![
        c.read(Register::Ctrl3) & STATUS_3H,
        c.read(Register::IntFlagsLo),
        c.read(Register::IntFlagsHi),
        c.read(Register::ProgerrFl),
        c.read(Register::Thtpt),
        c.read(Register::Tht),
        c.read(Register::Thwpt),
        c.read(Register::Thw),
        c.read(Register::Thrpt),
        c.read(Register::Thr),
    ];
    let digest = (0..2048u16).fold(0u64, |h, a| {
        h.wrapping_mul(0x100_0000_01b3)
            .wrapping_add(u64::from(c.read_ram(a)))
    });
    (regs, digest)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(40)))]

    #[test]
    fn quiet_events_read_the_same_as_events(
        ram in proptest::collection::vec(any::<u16>(), 64),
        fill in any::<u16>(),
        master in any::<bool>(),
        frames in proptest::collection::vec(
            (0u64..300, proptest::collection::vec(any::<u8>(), 1..24)),
            0..12,
        ),
        looks in any::<u64>(),
    ) {
        let mut event = common::arbitrary_chip(&ram, fill, master, None);
        let mut folded = common::arbitrary_chip(&ram, fill, master, None);
        // INT0 carries the three flags: their events are events of their own.
        event.write(Register::En0IntLo, QUIET_FLAGS);
        event.write(Register::Ctrl3, ENTMT | ENINT0);
        let mut frames = frames;
        frames.sort_by_key(|f| f.0);
        for (start, bytes) in frames {
            // 1 to 23 bytes: always a telegram the line layer carries.
            let seg = common::hinted_frame(Instant::ZERO + Duration::from_micros(start), &bytes);
            event.line_input(seg.clone());
            folded.line_input(seg);
        }
        // 400 µs in 10 µs hops; the host looks after the hops `looks` marks, and at the end.
        for t in 1..=40u64 {
            let at = Instant::ZERO + Duration::from_micros(10 * t);
            event.advance_to(at);
            folded.advance_to(at);
            if looks & (1 << t) != 0 {
                prop_assert_eq!(host_view(&mut event), host_view(&mut folded), "at {} µs", 10 * t);
            }
        }
        prop_assert_eq!(host_view(&mut event), host_view(&mut folded));
    }
}
