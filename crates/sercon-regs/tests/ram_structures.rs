//! RAM structures of 410B §4.2 with the ERRATA readings: fixed words, headers, marker
//! classification, containers, service containers.

use sercon_regs::RamError;
use sercon_regs::Variant::{Sercon410b, Sercon816};
use sercon_regs::ram::container::{ContainerControl, RxContainer, TxContainer};
use sercon_regs::ram::header::{
    Buffering, EndMarker, Header, HeaderKind, RxHeader, TxEnable, TxHeader,
};
use sercon_regs::ram::service::{
    NInfo, SC_BUFFER_MAX_WORDS, SC_BUFFER_OFFSET, ScMaster, ScPointers, ScSlave, ServiceContainer,
    sc_word_address,
};
use sercon_regs::ram::{self, COMPT0, COMPT1, FIXED_WORDS, NMSTERR, SCPT0, SCPT7};

#[test]
fn fixed_words() {
    // 410B §4.2: 0-1 COMPT0-1, 2-9 SCPT0-7, 10 NMSTERR; the first eleven words are fixed.
    assert_eq!(
        (COMPT0, COMPT1, SCPT0, SCPT7, NMSTERR, FIXED_WORDS),
        (0, 1, 2, 9, 10, 11)
    );
    assert_eq!(ram::compt(1), Some(1));
    assert_eq!(ram::compt(2), None);
    assert_eq!(ram::scpt(5), Some(7));
    assert_eq!(ram::scpt(8), None);
}

#[test]
fn marker_classification() {
    // ERRATA "telegram header marker bits": 00 receive, 01 transmit, 11 end, 10 invalid.
    assert_eq!(HeaderKind::classify(0x0000), Ok(HeaderKind::Receive));
    assert_eq!(HeaderKind::classify(0x3FFF), Ok(HeaderKind::Receive));
    assert_eq!(HeaderKind::classify(0x4000), Ok(HeaderKind::Transmit));
    assert_eq!(HeaderKind::classify(0x7FFF), Ok(HeaderKind::Transmit));
    assert_eq!(HeaderKind::classify(0xC000), Ok(HeaderKind::EndMarker));
    assert_eq!(
        HeaderKind::classify(0x8123),
        Err(RamError::InvalidMarker { word0: 0x8123 })
    );
    // 410B §4.2.1: 5-word receive header, 4-word transmit header; §4.2.3: 2-word end marker.
    assert_eq!(HeaderKind::Receive.words(), 5);
    assert_eq!(HeaderKind::Transmit.words(), 4);
    assert_eq!(HeaderKind::EndMarker.words(), 2);
}

#[test]
fn receive_header_fields() {
    // 410B §4.2.1 receive header: ADR 7-0, DMA 8, DBUF 9, VAL 10, ACHK 11, TCHK 12, RERR 13.
    let words = [0x0A05 | 1 << 13, 100, 12, 0x0123, 7];
    let h = RxHeader::from_words(Sercon410b, words).expect("receive header");
    assert_eq!(h.adr, 5);
    assert!(!h.dma && h.dbuf && !h.val && h.achk && !h.tchk && h.rerr);
    assert_eq!((h.trt, h.tlen, h.pt, h.nerr), (100, 12, 0x123, 7));
    assert_eq!(h.buffering(), Buffering::Double);
    assert_eq!(h.to_words(Sercon410b), words);
}

#[test]
fn pointer_width_differs_between_variants() {
    // ERRATA "word addresses": PT is 10 bits on the 410B, 11 on the 816; bits above are
    // "(Not used)" and kept.
    let words = [0x0000, 0, 0, 0xFD23, 0];
    let a = RxHeader::from_words(Sercon410b, words).expect("rx");
    let b = RxHeader::from_words(Sercon816, words).expect("rx");
    assert_eq!((a.pt, a.pt_reserved), (0x123, 0xFC00));
    assert_eq!((b.pt, b.pt_reserved), (0x523, 0xF800));
    assert_eq!(a.to_words(Sercon410b), words);
    assert_eq!(b.to_words(Sercon816), words);
}

#[test]
fn transmit_header_fields() {
    // 410B §4.2.1 transmit header: EN 12-11 (0 off, 1 once, 2 continuous, 3 on address).
    for (code, en) in [
        (0, TxEnable::Off),
        (1, TxEnable::Once),
        (2, TxEnable::Continuous),
        (3, TxEnable::OnAddress),
    ] {
        let w0 = 0x4000 | code << 11 | 0x0100 | 0x00FF;
        let h = TxHeader::from_words(Sercon816, [w0, 1, 2, 0x7FF]).expect("tx");
        assert_eq!(h.en, en);
        assert!(h.dma);
        assert_eq!(h.adr, 0xFF);
        assert_eq!(h.pt, 0x7FF);
        assert_eq!(h.buffering(), Buffering::Dma);
        assert_eq!(h.to_words(Sercon816), [w0, 1, 2, 0x7FF]);
    }
    // Bit 13 "(Not used)" survives the round trip.
    let h = TxHeader::from_words(Sercon410b, [0x6000, 0, 0, 0]).expect("tx");
    assert!(h.reserved13);
    assert_eq!(h.to_words(Sercon410b)[0], 0x6000);
}

#[test]
fn wrong_kind_is_an_error() {
    assert_eq!(
        RxHeader::from_words(Sercon410b, [0x4000, 0, 0, 0, 0]),
        Err(RamError::WrongKind {
            expected: HeaderKind::Receive,
            found: HeaderKind::Transmit
        })
    );
    assert_eq!(
        TxHeader::from_words(Sercon410b, [0xC000, 0, 0, 0]),
        Err(RamError::WrongKind {
            expected: HeaderKind::Transmit,
            found: HeaderKind::EndMarker
        })
    );
    assert_eq!(
        EndMarker::from_words([0x8000, 0]),
        Err(RamError::InvalidMarker { word0: 0x8000 })
    );
    assert_eq!(
        RxHeader::decode(Sercon410b, &[0, 1, 2]),
        Err(RamError::TooShort { needed: 5, got: 3 })
    );
}

#[test]
fn end_marker() {
    // 410B §4.2.3: bits 14, 15 = 1; TEND in word 1; bits 13-0 not used (kept).
    let e = EndMarker::from_words([0xC00F, 900]).expect("end");
    assert_eq!((e.reserved, e.tend), (0x000F, 900));
    assert_eq!(e.to_words(), [0xC00F, 900]);
}

#[test]
fn header_enum_decodes_by_marker_and_encodes_back() {
    let words = [0x4000 | 9, 10, 4, 0x20, 0xFFFF];
    let h = Header::decode(Sercon410b, &words).expect("tx");
    assert_eq!(h.kind(), HeaderKind::Transmit);
    assert_eq!(h.pt(), Some(0x20));
    let mut out = [0u16; 5];
    assert_eq!(h.encode(Sercon410b, &mut out), Ok(4));
    assert_eq!(out[..4], words[..4]);
    let mut short = [0u16; 1];
    assert_eq!(
        h.encode(Sercon410b, &mut short),
        Err(RamError::TooShort { needed: 4, got: 1 })
    );
    assert_eq!(
        Header::decode(Sercon410b, &[]),
        Err(RamError::TooShort { needed: 1, got: 0 })
    );
    assert_eq!(
        Header::decode(Sercon410b, &[0xC000, 5]).map(|h| h.pt()),
        Ok(None)
    );
}

#[test]
fn container_control_word() {
    // 410B §4.2.2: LEN 9-0, SVFL 10, NSV 13-11, SCMASTER 14, LASTDC 15.
    let c = ContainerControl::from_word(0xFC05);
    assert_eq!(c.len, 5);
    assert!(c.svfl && c.scmaster && c.lastdc);
    assert_eq!(c.nsv, 7);
    assert_eq!(c.to_word(), 0xFC05);
    assert_eq!(
        ContainerControl::new(4, true, 3, false, true).map(|c| c.to_word()),
        Ok(0x9C04)
    );
    assert!(ContainerControl::new(1024, false, 0, false, false).is_err());
    assert!(ContainerControl::new(1, false, 8, false, false).is_err());
}

#[test]
fn container_sizes() {
    // ERRATA "container words": receive 2 control words, transmit 1; data LEN, 2 × LEN or 0.
    let rx = RxContainer::from_words([0x0003, 4]);
    assert_eq!(rx.pos, 4);
    assert_eq!(rx.to_words(), [0x0003, 4]);
    assert_eq!(rx.total_words(Buffering::Single), 5);
    assert_eq!(rx.total_words(Buffering::Double), 8);
    assert_eq!(rx.total_words(Buffering::Dma), 2);
    let tx = TxContainer::from_words([0x8003]);
    assert!(tx.control.lastdc);
    assert_eq!(tx.total_words(Buffering::Double), 7);
    assert_eq!(
        RxContainer::decode(&[1]),
        Err(RamError::TooShort { needed: 2, got: 1 })
    );
    assert_eq!(
        TxContainer::decode(&[]),
        Err(RamError::TooShort { needed: 1, got: 0 })
    );
}

#[test]
fn service_container_master_mode_bits() {
    // 410B §4.2.4 master mode; ERRATA: CMD_AT is word 1 bit 3.
    let words = [
        1 | 1 << 1 | 1 << 2 | 5 << 3 | 1 << 6 | 1 << 7 | 3 << 8 | 1 << 12 | 1 << 13 | 1 << 14,
        1 | 1 << 1 | 1 << 2 | 1 << 3 | 1 << 7 | 2 << 8,
        0x0A05,
        0x0B06,
        200 | 1 << 8 | 1 << 9 | 1 << 10 | 1 << 11 | 1 << 12,
    ];
    let m = ScMaster::from_words(words);
    assert!(m.hs_mdt && m.ls_mdt && m.end_mdt && m.setend && m.m_busy);
    assert_eq!(m.elem_mdt, 5);
    assert_eq!(m.ninfo_write.count(), 4);
    assert!(m.int_err && m.int_end_wrbuf && m.int_end_rdbuf);
    assert!(m.hs_at && m.busy_at && m.err_at && m.cmd_at && m.recerr);
    assert_eq!(m.ninfo_read.count(), 3);
    assert_eq!(
        m.pointers,
        ScPointers {
            wrdatpt: 5,
            wrdatlast: 10,
            rddatpt: 6,
            rddatlast: 11
        }
    );
    assert_eq!(m.err_cnt, 200);
    assert!(m.busy_cnt && m.int_sc_err && m.int_hs_timeout && m.int_busy_timeout && m.int_cmd);
    assert_eq!(m.reserved, [0; 5]);
    assert_eq!(m.to_words(), words);
    // CMD_AT alone: word 1 bit 3 and nothing else.
    let only = ScMaster {
        cmd_at: true,
        ..ScMaster::default()
    };
    assert_eq!(only.to_words(), [0, 1 << 3, 0, 0, 0]);
}

#[test]
fn service_container_slave_mode_bits() {
    // 410B §4.2.4 slave mode; ERRATA: slave word 0 bit 3 is the command modification bit.
    let only_cmd = ScSlave {
        cmd_at: true,
        ..ScSlave::default()
    };
    assert_eq!(only_cmd.to_words(), [1 << 3, 0, 0, 0, 0]);
    let words = [
        1 | 1 << 2 | 6 << 4 | 1 << 7 | 1 << 8 | 1 << 12 | 1 << 15,
        1 << 1 | 7 << 3 | 1 << 7,
        0,
        0xFF05,
        1 << 9,
    ];
    let s = ScSlave::from_words(words);
    assert!(s.hs_at && !s.busy_at && s.err_at && !s.cmd_at);
    assert_eq!((s.elem, s.ninfo_write.count()), (6, 2));
    assert!(s.ls && s.int_elem_change && s.int_end_mdt && !s.int_end_wrbuf);
    assert!(!s.hs_mdt && s.ls_mdt && !s.end_mdt && s.recerr);
    assert_eq!(s.elem_mdt, 7);
    assert_eq!((s.pointers.rddatpt, s.pointers.rddatlast), (5, 255));
    assert!(s.int_sc_err);
    assert_eq!(s.to_words(), words);
}

#[test]
fn service_container_reserved_bits_survive() {
    // 410B §4.2.4 "(Not used)" bits are kept through decode/encode.
    let all = [0xFFFF; 5];
    assert_eq!(ScMaster::from_words(all).to_words(), all);
    assert_eq!(ScSlave::from_words(all).to_words(), all);
    assert_eq!(ScMaster::from_words(all).reserved, ScMaster::RESERVED);
    assert_eq!(ScSlave::from_words(all).reserved, ScSlave::RESERVED);
    let sc = ServiceContainer::from_words(true, all);
    assert!(matches!(sc, ServiceContainer::Master(_)));
    assert_eq!(sc.to_words(), all);
    assert_eq!(sc.pointers().wrdatlast, 0xFF);
}

#[test]
fn ninfo_counts_one_to_four() {
    // 410B §4.2.4 NINFO_WRITE/NINFO_READ "1 to 4" in 2 bits: code = count − 1 (spec-notes).
    for count in 1..=4 {
        let n = NInfo::from_count(count).expect("1..=4");
        assert_eq!(n.count(), count);
        assert_eq!(n.code(), count - 1);
    }
    assert!(NInfo::from_count(0).is_err());
    assert!(NInfo::from_count(5).is_err());
    assert_eq!(NInfo::default().count(), 1);
}

#[test]
fn service_buffer_addressing() {
    // Reading chosen (spec-notes): WRDATPT etc. are word offsets from the start of the
    // service container; the buffer starts at offset 5, after the 5 control words.
    assert_eq!(SC_BUFFER_OFFSET, 5);
    assert_eq!(SC_BUFFER_MAX_WORDS, 251);
    assert_eq!(sc_word_address(Sercon410b, 0x100, 5), 0x105);
    // Addresses wrap within the RAM as the chip decodes only A10-1 / A11-1.
    assert_eq!(sc_word_address(Sercon410b, 0x3FF, 5), 0x004);
    assert_eq!(sc_word_address(Sercon816, 0x3FF, 5), 0x404);
}
