//! Control word (MDT) and status word (AT): every bit of sercos-telegrams.md round-trips.

use sercos_wire::idn::Element;
use sercos_wire::telegram::{ControlWord, OperationMode, ReadyToOperate, StatusWord};

/// A one-bit flag: its source, its bit, its getter and its setter.
struct Flag<W> {
    source: &'static str,
    bit: u32,
    get: fn(W) -> bool,
    set: fn(W, bool) -> W,
}

fn control_flags() -> Vec<Flag<ControlWord>> {
    vec![
        Flag {
            source: "sercos-telegrams.md, MDT control word bit 15 (drive ON)",
            bit: 15,
            get: ControlWord::drive_on,
            set: ControlWord::with_drive_on,
        },
        Flag {
            source: "sercos-telegrams.md, MDT control word bit 14 (drive enable)",
            bit: 14,
            get: ControlWord::drive_enable,
            set: ControlWord::with_drive_enable,
        },
        Flag {
            source: "sercos-telegrams.md, MDT control word bit 13 (drive halt/restart)",
            bit: 13,
            get: ControlWord::drive_restart,
            set: ControlWord::with_drive_restart,
        },
        Flag {
            source: "sercos-telegrams.md, MDT control word bit 10 (control unit synchronization)",
            bit: 10,
            get: ControlWord::control_unit_sync,
            set: ControlWord::with_control_unit_sync,
        },
        Flag {
            source: "sercos-telegrams.md, MDT control word bit 7 (real-time control bit 2)",
            bit: 7,
            get: ControlWord::real_time_control_bit_2,
            set: ControlWord::with_real_time_control_bit_2,
        },
        Flag {
            source: "sercos-telegrams.md, MDT control word bit 6 (real-time control bit 1)",
            bit: 6,
            get: ControlWord::real_time_control_bit_1,
            set: ControlWord::with_real_time_control_bit_1,
        },
        Flag {
            source: "sercos-telegrams.md, MDT control word bit 2 (last transmission)",
            bit: 2,
            get: ControlWord::last_transmission,
            set: ControlWord::with_last_transmission,
        },
        Flag {
            source: "sercos-telegrams.md, MDT control word bit 1 (read/write service info)",
            bit: 1,
            get: ControlWord::write,
            set: ControlWord::with_write,
        },
        Flag {
            source: "sercos-telegrams.md, MDT control word bit 0 (MHS)",
            bit: 0,
            get: ControlWord::mhs,
            set: ControlWord::with_mhs,
        },
    ]
}

fn status_flags() -> Vec<Flag<StatusWord>> {
    vec![
        Flag {
            source: "sercos-telegrams.md, AT status word bit 13 (drive shutdown error)",
            bit: 13,
            get: StatusWord::shutdown_error,
            set: StatusWord::with_shutdown_error,
        },
        Flag {
            source: "sercos-telegrams.md, AT status word bit 12 (change bit class 2 diags)",
            bit: 12,
            get: StatusWord::change_bit_class_2,
            set: StatusWord::with_change_bit_class_2,
        },
        Flag {
            source: "sercos-telegrams.md, AT status word bit 11 (change bit class 3 diags)",
            bit: 11,
            get: StatusWord::change_bit_class_3,
            set: StatusWord::with_change_bit_class_3,
        },
        Flag {
            source: "sercos-telegrams.md, AT status word bit 7 (real-time status bit 2)",
            bit: 7,
            get: StatusWord::real_time_status_bit_2,
            set: StatusWord::with_real_time_status_bit_2,
        },
        Flag {
            source: "sercos-telegrams.md, AT status word bit 6 (real-time status bit 1)",
            bit: 6,
            get: StatusWord::real_time_status_bit_1,
            set: StatusWord::with_real_time_status_bit_1,
        },
        Flag {
            source: "sercos-telegrams.md, AT status word bit 5 (change bit commands)",
            bit: 5,
            get: StatusWord::command_change,
            set: StatusWord::with_command_change,
        },
        Flag {
            source: "sercos-telegrams.md, AT status word bit 2 (error in service channel)",
            bit: 2,
            get: StatusWord::service_channel_error,
            set: StatusWord::with_service_channel_error,
        },
        Flag {
            source: "sercos-telegrams.md, AT status word bit 1 (busy)",
            bit: 1,
            get: StatusWord::busy,
            set: StatusWord::with_busy,
        },
        Flag {
            source: "sercos-telegrams.md, AT status word bit 0 (AHS)",
            bit: 0,
            get: StatusWord::ahs,
            set: StatusWord::with_ahs,
        },
    ]
}

/// Checks one flag against a few background words: setting it sets exactly its bit, clearing
/// clears exactly its bit, and the getter reads the raw bit.
fn check_flags<W: Copy + std::fmt::Debug>(
    flags: &[Flag<W>],
    from_raw: fn(u16) -> W,
    raw: fn(W) -> u16,
) {
    for flag in flags {
        let mask = 1u16 << flag.bit;
        for background in [0x0000u16, 0xFFFF, 0xA5A5, 0x5A5A] {
            let word = from_raw(background);
            assert_eq!((flag.get)(word), background & mask != 0, "{}", flag.source);
            let on = (flag.set)(word, true);
            assert_eq!(raw(on), background | mask, "{}: set", flag.source);
            assert!((flag.get)(on), "{}: get after set", flag.source);
            let off = (flag.set)(word, false);
            assert_eq!(raw(off), background & !mask, "{}: clear", flag.source);
            assert!(!(flag.get)(off), "{}: get after clear", flag.source);
        }
    }
}

#[test]
fn control_word_flags_round_trip() {
    check_flags(&control_flags(), ControlWord::from_raw, ControlWord::raw);
}

#[test]
fn status_word_flags_round_trip() {
    check_flags(&status_flags(), StatusWord::from_raw, StatusWord::raw);
}

#[test]
fn control_word_operation_mode_bits_9_8() {
    // sercos-telegrams.md, MDT control word bits 9, 8: 00 primary, 01/10/11 secondary 1/2/3.
    for (bits, mode) in OperationMode::ALL.into_iter().enumerate() {
        for background in [0x0000u16, 0xFFFF] {
            let word = ControlWord::from_raw(background).with_operation_mode(mode);
            assert_eq!(word.raw() & 0x0300, (bits as u16) << 8);
            assert_eq!(word.raw() & !0x0300, background & !0x0300);
            assert_eq!(word.operation_mode(), mode);
        }
    }
}

#[test]
fn control_word_element_bits_5_3() {
    // sercos-telegrams.md, MDT control word bits 5, 4, 3: data block element 000–111.
    for element in Element::ALL {
        for background in [0x0000u16, 0xFFFF] {
            let word = ControlWord::from_raw(background).with_data_block_element(element);
            assert_eq!(word.raw() & 0x0038, u16::from(element.bits()) << 3);
            assert_eq!(word.raw() & !0x0038, background & !0x0038);
            assert_eq!(word.data_block_element(), element);
        }
    }
    assert_eq!(
        ControlWord::from_raw(0b111 << 3).data_block_element(),
        Element::OperationData
    );
    assert_eq!(
        ControlWord::from_raw(0b001 << 3).data_block_element(),
        Element::Idn
    );
}

#[test]
fn status_word_ready_to_operate_bits_15_14() {
    // sercos-telegrams.md, AT status word bits 15, 14: 00 not ready for power-up, 01 ready
    // for power-up, 10 power ready, 11 ready to operate.
    for (bits, state) in ReadyToOperate::ALL.into_iter().enumerate() {
        for background in [0x0000u16, 0xFFFF] {
            let word = StatusWord::from_raw(background).with_ready_to_operate(state);
            assert_eq!(word.raw() & 0xC000, (bits as u16) << 14);
            assert_eq!(word.raw() & !0xC000, background & !0xC000);
            assert_eq!(word.ready_to_operate(), state);
        }
    }
    assert_eq!(
        StatusWord::from_raw(0xC000).ready_to_operate(),
        ReadyToOperate::ReadyToOperate
    );
}

#[test]
fn status_word_actual_operation_mode_bits_9_8() {
    // sercos-telegrams.md, AT status word bits 9, 8: actual operation mode.
    for (bits, mode) in OperationMode::ALL.into_iter().enumerate() {
        let word = StatusWord::new().with_actual_operation_mode(mode);
        assert_eq!(word.raw(), (bits as u16) << 8);
        assert_eq!(word.actual_operation_mode(), mode);
    }
}

#[test]
fn reserved_bits_are_kept() {
    // sercos-telegrams.md, MDT control word bits 12, 11 "Reserved"; AT status word bits 4, 3
    // "Reserved" and bit 10 (not in the table): raw conversions keep them.
    for raw in 0..=u16::MAX {
        assert_eq!(ControlWord::from(raw).raw(), raw);
        assert_eq!(u16::from(StatusWord::from(raw)), raw);
    }
    assert_eq!(ControlWord::from_raw(0xFFFF).reserved_bits(), 0x1800);
    assert_eq!(StatusWord::from_raw(0xFFFF).reserved_bits(), 0x0418);
    assert_eq!(
        ControlWord::new().with_reserved_bits(0xFFFF).raw(),
        0x1800,
        "with_reserved_bits touches only bits 12-11"
    );
    assert_eq!(StatusWord::new().with_reserved_bits(0xFFFF).raw(), 0x0418);
}

#[test]
fn every_control_bit_is_named_by_some_field() {
    // Together the flags, the two multi-bit fields and the reserved mask cover all 16 bits once.
    let mut covered = ControlWord::OPERATION_MODE | ControlWord::DATA_BLOCK_ELEMENT;
    assert_eq!(covered & ControlWord::RESERVED, 0);
    covered |= ControlWord::RESERVED;
    for flag in control_flags() {
        let mask = 1u16 << flag.bit;
        assert_eq!(covered & mask, 0, "{} overlaps", flag.source);
        covered |= mask;
    }
    assert_eq!(covered, 0xFFFF);
}

#[test]
fn every_status_bit_is_named_by_some_field() {
    let mut covered = StatusWord::READY_TO_OPERATE | StatusWord::ACTUAL_OPERATION_MODE;
    assert_eq!(covered & StatusWord::RESERVED, 0);
    covered |= StatusWord::RESERVED;
    for flag in status_flags() {
        let mask = 1u16 << flag.bit;
        assert_eq!(covered & mask, 0, "{} overlaps", flag.source);
        covered |= mask;
    }
    assert_eq!(covered, 0xFFFF);
}

#[test]
fn handshake_toggles() {
    // sercos-telegrams.md, MDT control word bit 0 and AT status word bit 0: "A toggle bit".
    let word = ControlWord::from_raw(0xE008);
    assert!(word.with_mhs_toggled().mhs());
    assert_eq!(word.with_mhs_toggled().with_mhs_toggled(), word);
    let status = StatusWord::from_raw(0xC000);
    assert!(status.with_ahs_toggled().ahs());
    assert_eq!(status.with_ahs_toggled().raw(), 0xC001);
}

#[test]
fn display_names_the_set_bits() {
    let word = ControlWord::new()
        .with_drive_on(true)
        .with_drive_enable(true)
        .with_drive_restart(true)
        .with_operation_mode(OperationMode::Secondary2)
        .with_data_block_element(Element::OperationData)
        .with_write(true)
        .with_mhs(true);
    assert_eq!(
        word.to_string(),
        "E23BH (drive on, drive enable, drive restart, mode secondary 2, \
         element operation data, write, MHS)"
    );
    assert_eq!(
        format!("{:?}", ControlWord::new()),
        "ControlWord(0000H (none))"
    );
    assert_eq!(
        ControlWord::from_raw(0x1800).to_string(),
        "1800H (reserved 1800H)"
    );
    let status = StatusWord::new()
        .with_ready_to_operate(ReadyToOperate::ReadyToOperate)
        .with_busy(true)
        .with_service_channel_error(true);
    assert_eq!(
        status.to_string(),
        "C006H (ready to operate, service channel error, busy)"
    );
    assert_eq!(
        format!("{:?}", StatusWord::from_raw(0x2021)),
        "StatusWord(2021H (shutdown error, command change, AHS))"
    );
}
