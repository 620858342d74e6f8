//! Container walks kept under the layout proof (`telegram_processor::walk_memo`): a host
//! write to a container's control words between two cycles (410B §4.2.2 LEN, POS) is what
//! the telegrams stored and sent from then on follow, as in a run that never made the proof
//! (debug builds also compare every kept walk with a fresh one).

#[path = "../benches/support/pair_setup.rs"]
mod pair_setup;

use pair_setup::{Shape, chips};
use sercon_model::Chip;
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::{SerconBus, SerconBusExt};
use sercos_wire::time::{Duration, Instant};

/// Control word 0 of a container of `len` words, LASTDC = 1 (410B §4.2.2).
fn control(len: u16) -> u16 {
    ContainerControl::new(len, false, 0, false, true).map_or(0, |c| c.to_word())
}

/// Runs the bench pair to `until` in steps of half the fibre delay, asking each chip's
/// output bound before every step when `ask` (which makes the layout proof the kept walks
/// rest on), with `write` done by the hosts at `at`. Returns the RAM's first 1024 words of
/// both chips, then their registers 04H, 05H (interrupt flags, 410B §4.1) and 17H
/// (PROGERR_FL).
fn run(ask: bool, at: Instant, until: Instant, write: fn(&mut [Chip; 2])) -> [Vec<u16>; 2] {
    let shape = Shape::BENCH;
    let mut pair = chips(shape);
    let delay = Duration::from_nanos(shape.delay_ns);
    let step = Duration::from_picos((delay.as_picos() / 2).max(1));
    let mut now = Instant::ZERO;
    let mut written = false;
    let mut buf = Vec::new();
    while now < until {
        now = (now + step).min(until);
        if !written && now >= at {
            write(&mut pair);
            written = true;
        }
        for i in 0..2 {
            if ask {
                let _ = pair[i].next_output_bound();
            }
            pair[i].advance_to(now);
            pair[i].take_line_output(&mut buf);
            for seg in buf.drain(..) {
                pair[1 - i].line_input(seg.delayed(delay));
            }
        }
    }
    pair.map(|mut c| {
        let mut out: Vec<u16> = (0..1024).map(|a| c.read_ram(a)).collect();
        out.extend([0x04, 0x05, 0x17].map(|r| c.read_register(r)));
        out
    })
}

/// Runs the pair with `write` applied at 300 µs, up to 700 µs, with the layout proof asked for
/// and without (the general paths): both leave the same RAM and registers; returns them.
fn kept_as_plain(write: fn(&mut [Chip; 2])) -> [Vec<u16>; 2] {
    let at = Instant::ZERO + Duration::from_micros(300);
    let until = Instant::ZERO + Duration::from_micros(700);
    let kept = run(true, at, until, write);
    let plain = run(false, at, until, write);
    assert_eq!(kept, plain);
    kept
}

/// Makes the container whose control word is RAM word `word` of chip `s` service container 0
/// (410B §4.2.2 SVFL; its words from 256 on: SCPT0, RAM word 2, clear of the headers and
/// containers the layout proof reads).
fn service_container_at(s: &mut Chip, word: u16) {
    s.write_ram(2, 256);
    let svc = ContainerControl::new(8, true, 0, false, true).map_or(0, |c| c.to_word());
    s.write_ram(word, svc);
}

// 410B §4.2.2 LEN, POS: the slave's MDT container (control words 21, 22) and the master's
// AT container (34, 35) move within their telegrams, the slave's AT container (35) gets
// shorter (the rest of its telegram is sent as 0, 410B §4.2.1 TLEN), after several cycles
// stored and sent with the walks kept.
#[test]
fn a_host_write_to_the_containers_is_followed_by_the_kept_walks() {
    let write = |pair: &mut [Chip; 2]| {
        let [m, s] = pair;
        s.write_ram_words(21, &[control(4), 2]);
        s.write_ram(35, control(4));
        m.write_ram_words(34, &[control(5), 3]);
    };
    let kept = kept_as_plain(write);
    let [m, s] = &kept;
    // The slave stored MDT words 2..6 (the master sends 0xF000 + i) from word 23 on.
    assert_eq!(s[23..27], [0xF002, 0xF003, 0xF004, 0xF005]);
    // The master stored AT words 3..8 (0x1003, then the zeros past the slave's 4 words)
    // from word 36 on.
    assert_eq!(m[36..41], [0x1003, 0, 0, 0, 0]);
}

/// The slave's AT header (word 0 at 31, `pair_setup::tx_block`) as `tx_block` writes it but
/// with DMA = `dma` (410B §4.2.1 DMA).
fn slave_at_word0(dma: bool) -> u16 {
    use sercon_regs::Variant;
    use sercon_regs::ram::header::{TxEnable, TxHeader};
    let h = TxHeader {
        adr: 1,
        dma,
        en: TxEnable::Continuous,
        trt: pair_setup::Shape::BENCH.at_trt,
        tlen: 8,
        pt: 44,
        ..TxHeader::default()
    };
    h.to_words(Variant::Sercon816)[0]
}

// 410B §4.2.1 DMA, §2 DMAREQT: a transmit telegram with DMA = 1 takes its words from the
// transmit FIFO, not from the RAM, with its one container's walk kept as well: the slave's
// FIFO is empty, so its AT goes out as zeros (410B §4.2.1 TLEN) and the master stores them.
// The short assembly of a kept container (`transmit::assemble_kept`) is for RAM buffers
// only: allowed for DMA it sends the RAM's words (this test fails, release builds too).
#[test]
fn a_dma_telegram_with_its_walk_kept_is_sent_from_the_fifo() {
    let write = |pair: &mut [Chip; 2]| {
        let [_, s] = pair;
        s.write_ram(31, slave_at_word0(true));
    };
    let kept = kept_as_plain(write);
    let [m, s] = &kept;
    assert_eq!(s[31], slave_at_word0(true), "the header as written");
    // The master stored the AT's 8 words from word 36 on: zeros from the empty FIFO.
    assert_eq!(m[36..44], [0; 8]);
}

// 410B §4.2.2 SVFL: a container with SVFL = 1 is a service container, whose record the
// service channel fills in before it is sent (slave mode: the AT's status word's
// service-channel bits and the info words, 816 §2.10.2), with its walk kept as well. The
// short assembly of a kept container (`transmit::assemble_kept`) is for containers
// without SVFL: allowed for one it sends the RAM's words unfilled and leaves the RAM
// unwritten (debug builds: the comparison with the general assembly fails).
#[test]
fn a_service_container_with_its_walk_kept_is_filled_in() {
    let write = |pair: &mut [Chip; 2]| {
        let [_, s] = pair;
        service_container_at(s, 35);
    };
    kept_as_plain(write);
}

/// The master's AT header (word 0 at 29, `pair_setup::rx_block`) as `rx_block` writes it but
/// with DMA = `dma` (410B §4.2.1 DMA).
fn master_at_word0(dma: bool) -> u16 {
    use sercon_regs::Variant;
    use sercon_regs::ram::header::RxHeader;
    let h = RxHeader {
        adr: 1,
        dma,
        achk: true,
        trt: pair_setup::Shape::BENCH.at_trt,
        tlen: 8,
        pt: 44,
        ..RxHeader::default()
    };
    h.to_words(Variant::Sercon816)[0]
}

// 410B §4.2.1 DMA: a receive telegram with DMA = 1 puts its words into the receive FIFO,
// not into the RAM, with its one container's walk kept as well (the container has its
// control words only, 410B §4.2.2). The short store of a kept container
// (`receive::store_kept`) is for RAM buffers only: allowed for DMA it writes the AT's words
// over the RAM words after the container (this test fails, release builds too).
#[test]
fn a_dma_telegram_received_with_its_walk_kept_goes_to_the_fifo() {
    let write = |pair: &mut [Chip; 2]| {
        let [m, _] = pair;
        m.write_ram(29, master_at_word0(true));
        m.write_ram_words(36, &[0; 8]);
    };
    let kept = kept_as_plain(write);
    let [m, _] = &kept;
    assert_eq!(m[36..44], [0; 8], "no AT word stored in the RAM");
}

// 410B §4.2.2 SVFL, §4.2.4: a received container with SVFL = 1 is a service container, whose
// record the service channel takes (slave mode: the MDT's control word and info words into
// service container 0's words, 816 §2.10.2), with its walk kept as well. The short store of
// a kept container (`receive::store_kept`) is for containers without SVFL: allowed for one
// it stores the data words only and skips the service channel (debug builds: the
// comparison with the general store fails).
#[test]
fn a_service_container_received_with_its_walk_kept_is_taken() {
    let write = |pair: &mut [Chip; 2]| {
        let [_, s] = pair;
        service_container_at(s, 21);
    };
    kept_as_plain(write);
}

// 410B §4.2.2 LEN, POS: an empty container stores nothing wherever its POS points, past the
// telegram's data too (no container overrun, 17H PROGERR_FL), with its walk kept. Mutation
// tried: `store_kept`'s overrun condition `len != 0` made `true` (this test fails through
// PROGERR_FL and INT_PROGERR, release builds too).
#[test]
fn an_empty_container_past_the_data_with_its_walk_kept_is_no_overrun() {
    let write = |pair: &mut [Chip; 2]| {
        let [m, _] = pair;
        m.write_ram_words(34, &[control(0), 20]);
    };
    let kept = kept_as_plain(write);
    let [m, _] = &kept;
    assert_eq!(m[1024 + 2], 0, "PROGERR_FL");
}
