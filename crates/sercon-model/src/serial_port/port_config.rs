//! The serial port's view of the registers 1H and 2H, decoded once per register write with the
//! pure functions of [`crate::serial_settings`].

use sercon_regs::Variant;
use sercos_wire::time::Duration;

use crate::config::Straps;
use crate::serial_settings::{
    LErrnMode, RxdCoding, TestMode, TxdOutput, bit_clock, lerrn_mode, rxd_coding, test_mode,
    txd_outputs,
};

/// 410B §4.1 1H.3 REPON.
const REPON: u16 = 1 << 3;
/// 410B §4.1 1H.7 POLRXD.
const POLRXD: u16 = 1 << 7;
/// 410B §4.1 1H.8 PRESYNC.
const PRESYNC: u16 = 1 << 8;
/// 410B §4.1 1H.9 POLTXD.
const POLTXD: u16 = 1 << 9;

/// What the transmitter puts on the line when it sends no telegram of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TxMode {
    /// No TxD pin carries transmit data: the line is dark.
    Off,
    /// Test signal continuous light (410B §2 TM0; §4.1 2H TMODE 4, 6).
    ContinuousLight,
    /// Test signal zero bit stream (410B §2 TM1; §4.1 2H TMODE 5).
    ZeroBitStream,
    /// Normal operation, repeater off: idle filler between own telegrams.
    Filler,
    /// Normal operation, repeater on (1H.3 REPON): the received signal is forwarded.
    Repeat,
}

/// Decoded serial-port settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PortConfig {
    /// The chip's own bit time; `None` with an external bit clock (410B SREGEN = 0) or an
    /// SCLK that gives no whole number of picoseconds.
    pub(crate) bit_time: Option<Duration>,
    /// What the transmitter sends between own telegrams.
    pub(crate) tx_mode: TxMode,
    /// 1H.8 PRESYNC: a pre-frame sync word precedes each own telegram.
    pub(crate) presync: bool,
    /// 1H.7 POLRXD = 1: light on when RxD = 1.
    pub(crate) polrxd: bool,
    /// 1H.9 POLTXD = 1: light on when TxD = 1.
    pub(crate) poltxd: bool,
    /// 1H.12 RXDNRZ (ERRATA).
    pub(crate) rx_coding: RxdCoding,
    /// 2H.14–15 LMODE.
    pub(crate) lmode: LErrnMode,
}

impl PortConfig {
    /// Decodes the stored words of 1H and 2H.
    pub(crate) fn decode(
        variant: Variant,
        straps: &Straps,
        sclk_hz: u64,
        reg1: u16,
        reg2: u16,
    ) -> Self {
        // 410B §2 TxD1, TxD6-2 and §4.1 2H.0–6: the transmitter drives the line when at least
        // one TxD pin outputs transmit data (spec-notes "Serial port").
        let tx_on = txd_outputs(reg2)
            .iter()
            .any(|o| matches!(o, TxdOutput::TransmitData));
        let tx_mode = if !tx_on {
            TxMode::Off
        } else {
            match test_mode(variant, straps, reg2).0 {
                TestMode::ContinuousLight => TxMode::ContinuousLight,
                TestMode::ZeroBitStream => TxMode::ZeroBitStream,
                // 410B §4.1 1H.3 REPON: 1 = repeater turned on.
                TestMode::Normal if reg1 & REPON != 0 => TxMode::Repeat,
                TestMode::Normal => TxMode::Filler,
            }
        };
        PortConfig {
            bit_time: bit_clock(variant, straps, sclk_hz, reg1).bit_time().ok(),
            tx_mode,
            presync: reg1 & PRESYNC != 0,
            polrxd: reg1 & POLRXD != 0,
            poltxd: reg1 & POLTXD != 0,
            rx_coding: rxd_coding(reg1),
            lmode: lerrn_mode(reg2),
        }
    }

    /// Whether own telegrams are sent (normal operation with a TxD pin enabled).
    pub(crate) fn sends_telegrams(&self) -> bool {
        matches!(self.tx_mode, TxMode::Filler | TxMode::Repeat)
    }
}
