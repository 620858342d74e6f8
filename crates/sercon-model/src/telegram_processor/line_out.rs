//! Handing telegrams to the line: the telegram processor sends every telegram (MST, MDT,
//! AT) through the serial port ([`crate::serial_port::SerialPort::transmit`]), which encodes
//! it, times it exactly at the selected bit rate and puts it on the line output as a
//! [`crate::serial_port::LineSegment`] with a [`crate::serial_port::FrameHint`].

use sercos_wire::time::Instant;

use crate::chip::Chip;

/// Sends `chip.tp.txbuf` (ADR and data, 410B §4.2.1) starting at `at`; returns the instant
/// after its closing flag, `None` when nothing is sent (transmitter off, a test mode, no bit
/// clock: 410B §2 TxD1–6, TM0/TM1; spec-notes "Serial port").
pub(super) fn send(chip: &mut Chip, at: Instant) -> Option<Instant> {
    chip.serial.transmit(at, &chip.tp.txbuf)
}
