//! Registers 1H, 2H, 3H and 0CH (410B §4.1).

use crate::bitfield::{bool_bits, field, with_field};
use crate::error::FieldError;
use crate::value::{flags_register, word_register};

bitflags::bitflags! {
    /// Register 1H (410B §4.1; 816 §2.3.1 for SWBAUD16).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct Ctrl1: u16 {
        /// Reset has taken place (R/W, reset 1).
        const RSTFL = 1 << 0;
        /// Reset by software (W, action).
        const SWRST = 1 << 1;
        /// Repeater turned on (R/W, reset 1; 816 §2.3.3: reset value from TM0-1).
        const REPON = 1 << 3;
        /// Level at pin SREGEN (R; pin 28 is SBAUD16 on the 816).
        const SREGEN = 1 << 4;
        /// Sampling according to the SERCOS interface specification (R/W, reset 1).
        const REGMODE = 1 << 5;
        /// Baud rate f_SCLK/32 instead of /16 when ENTSBAUD = 1 (ERRATA "410B 1H.6").
        const SWBAUD = 1 << 6;
        /// "Light on" when RxD = 1.
        const POLRXD = 1 << 7;
        /// Pre-frame sync word.
        const PRESYNC = 1 << 8;
        /// "Light on" when TxD = 1.
        const POLTXD = 1 << 9;
        /// Baud rate from control bits SWBAUD/SWBAUD16 instead of pins (ERRATA).
        const ENTSBAUD = 1 << 10;
        /// Level at pin SBAUD (R).
        const SBAUD = 1 << 11;
        /// Receive data is NRZ-coded (ERRATA "410B 1H.12").
        const RXDNRZ = 1 << 12;
        /// RAM write access internally synchronized (ERRATA "410B 1H.13").
        const WRSYNC = 1 << 13;
        /// DMAREQR/DMAREQT are pulses.
        const DMAMODE = 1 << 14;
        /// SERCON816 only: 2/4 instead of 8/16 Mbit/s when ENTSBAUD = 1 (816 §2.3.1).
        const SWBAUD16 = 1 << 15;
    }
}
flags_register!(Ctrl1, Ctrl1);

bitflags::bitflags! {
    /// ENTXD1-6 (2H.5-0): which pins TxD1–TxD6 output transmit data (1) rather than
    /// high impedance (0).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct TxdPins: u8 {
        /// TxD1.
        const TXD1 = 1 << 0;
        /// TxD2.
        const TXD2 = 1 << 1;
        /// TxD3.
        const TXD3 = 1 << 2;
        /// TxD4.
        const TXD4 = 1 << 3;
        /// TxD5.
        const TXD5 = 1 << 4;
        /// TxD6.
        const TXD6 = 1 << 5;
    }
}

/// TMODE0-2 (2H.9-7): test function (410B §4.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[doc(alias = "TMODE")]
pub enum TestMode {
    /// Codes 0–3 (reset): test functions are controlled via pins TM0-1.
    PinControlled,
    /// Codes 4 and 6: continuous signal light.
    ContinuousLight,
    /// Code 5: zero bit stream.
    ZeroBitStream,
    /// Code 7: normal operation.
    Normal,
}

impl TestMode {
    /// The test mode of a 3-bit TMODE code (bits above 2 are ignored).
    pub const fn from_code(code: u8) -> TestMode {
        match code & 7 {
            0..=3 => TestMode::PinControlled,
            4 | 6 => TestMode::ContinuousLight,
            5 => TestMode::ZeroBitStream,
            _ => TestMode::Normal,
        }
    }

    /// The canonical code written for this mode (0, 4, 5, 7).
    pub const fn code(self) -> u8 {
        match self {
            TestMode::PinControlled => 0,
            TestMode::ContinuousLight => 4,
            TestMode::ZeroBitStream => 5,
            TestMode::Normal => 7,
        }
    }
}

/// LMODE0-1 (2H.15-14): what activates pin L_ERRN (410B §4.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[doc(alias = "LMODE")]
pub enum LineErrorMode {
    /// 0 (reset): L_ERRN active by FIBBR and RDIST.
    FibbrAndRdist = 0,
    /// 1: L_ERRN active by RDIST.
    Rdist = 1,
    /// 2: L_ERRN active by FIBBR.
    Fibbr = 2,
    /// 3: L_ERRN is inactive.
    Inactive = 3,
}

impl LineErrorMode {
    /// The mode of a 2-bit LMODE code (bits above 1 are ignored).
    pub const fn from_code(code: u8) -> LineErrorMode {
        match code & 3 {
            0 => LineErrorMode::FibbrAndRdist,
            1 => LineErrorMode::Rdist,
            2 => LineErrorMode::Fibbr,
            _ => LineErrorMode::Inactive,
        }
    }
}

word_register!(
    /// Register 2H: transmit pins, test modes and line error (410B §4.1).
    #[doc(alias("ENTXD", "TXDMODE", "TMODE", "LMODE"))]
    Ctrl2,
    Ctrl2
);

impl Ctrl2 {
    /// Reset value 003FH: all TxD pins output data, TMODE 0, LMODE 0 (410B §4.1 2H).
    pub const RESET: Ctrl2 = Ctrl2(0x003F);

    /// ENTXD1-6 (2H.5-0).
    pub const fn entxd(self) -> TxdPins {
        TxdPins::from_bits_truncate(self.0 as u8)
    }

    /// This value with ENTXD1-6 set to `pins`.
    #[must_use]
    pub const fn with_entxd(self, pins: TxdPins) -> Self {
        Ctrl2(with_field(self.0, 0, 6, pins.bits() as u16))
    }

    bool_bits! {
        /// TXDMODE (2H.6): 1 = TxD2-6 output the values of ENTXD2-6 as a parallel port,
        /// 0 = they output transmit data (reading chosen, see spec-notes).
        txdmode, with_txdmode, 6;
        /// RDIST (2H.12, R): receive data over the distortion limit.
        rdist, with_rdist, 12;
        /// FIBBR (2H.13, R): no edges on receive data.
        fibbr, with_fibbr, 13;
    }

    /// The raw TMODE0-2 code (2H.9-7).
    pub const fn tmode_code(self) -> u8 {
        field(self.0, 7, 3) as u8
    }

    /// TMODE0-2 (2H.9-7) as a test mode.
    pub const fn tmode(self) -> TestMode {
        TestMode::from_code(self.tmode_code())
    }

    /// This value with TMODE0-2 set to the canonical code of `mode`.
    #[must_use]
    pub const fn with_tmode(self, mode: TestMode) -> Self {
        Ctrl2(with_field(self.0, 7, 3, mode.code() as u16))
    }

    /// This value with TMODE0-2 set to a raw code (0–7).
    pub const fn with_tmode_code(self, code: u8) -> Result<Self, FieldError> {
        match FieldError::check("TMODE", code as u16, 3) {
            Ok(v) => Ok(Ctrl2(with_field(self.0, 7, 3, v))),
            Err(e) => Err(e),
        }
    }

    /// TM0-1 (2H.11-10, R): levels at pins TM0 (bit 0 of the result) and TM1 (bit 1).
    pub const fn tm(self) -> u8 {
        field(self.0, 10, 2) as u8
    }

    /// LMODE0-1 (2H.15-14).
    pub const fn lmode(self) -> LineErrorMode {
        LineErrorMode::from_code(field(self.0, 14, 2) as u8)
    }

    /// This value with LMODE0-1 set to `mode`.
    #[must_use]
    pub const fn with_lmode(self, mode: LineErrorMode) -> Self {
        Ctrl2(with_field(self.0, 14, 2, mode as u16))
    }
}

bitflags::bitflags! {
    /// Register 3H: interrupt outputs and telegram-processing status (410B §4.1).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct Ctrl3: u16 {
        /// Interrupt INT0 active (R).
        #[doc(alias = "INTFLO")]
        const INTFL0 = 1 << 0;
        /// Interrupt INT0 enabled (R/W; ERRATA "410B 3H.1").
        const ENINT0 = 1 << 1;
        /// INT0 is 0-active (R/W; ERRATA "410B 3H.2/3H.5").
        const POLINT0 = 1 << 2;
        /// Interrupt INT1 active (R).
        const INTFL1 = 1 << 3;
        /// Interrupt INT1 enabled (R/W).
        const ENINT1 = 1 << 4;
        /// INT1 is 0-active (R/W).
        const POLINT1 = 1 << 5;
        /// A transmission block is processed (R).
        const COMACT = 1 << 6;
        /// Transmission block 1 (not 0) is processed (R).
        const COMBLK = 1 << 7;
        /// Send data telegrams (R/W).
        const ENTMT = 1 << 8;
        /// Data telegram is sent (R).
        const FLTMT = 1 << 9;
        /// Data telegram is expected (R).
        const FLRWAIT = 1 << 10;
        /// Data telegram is received (R).
        const FLREC = 1 << 11;
        /// DMA request of the transmit FIFO active (R).
        const DMAREQT = 1 << 12;
        /// DMA request of the receive FIFO active (R).
        const DMAREQR = 1 << 13;
        /// Level at pin IDLE (R; active low).
        const IDLE = 1 << 14;
        /// Level at pin REACTN (R; active low).
        const REACTN = 1 << 15;
    }
}
flags_register!(Ctrl3, Ctrl3);

word_register!(
    /// Register 0CH: MST and cycle control (410B §4.1).
    #[doc(alias("MSTEN", "MSTMASTER", "NCYC", "CYCSTART", "RDCNT"))]
    Ctrl0C,
    Ctrl0C
);

impl Ctrl0C {
    bool_bits! {
        /// MSTEN (0CH.0): MST is transmitted or received (SERCOS interface mode).
        msten, with_msten, 0;
        /// MSTMASTER (0CH.1): transmit and receive MST (master) rather than receive (slave).
        mstmaster, with_mstmaster, 1;
        /// COMBLK0 (0CH.2): when phase = PHAS0, transmission block 1 (not 0) is processed.
        comblk0, with_comblk0, 2;
        /// COMBLK1 (0CH.3): when phase = PHAS1, transmission block 1 (not 0) is processed.
        comblk1, with_comblk1, 3;
        /// CON_CLK (0CH.4, R): level at pin CON_CLK.
        con_clk, with_con_clk, 4;
        /// ENCONCLK (0CH.5): CON_CLK becomes active from TINT0 to TINT1.
        enconclk, with_enconclk, 5;
        /// POLCONCLK (0CH.6): CON_CLK is 0-active.
        polconclk, with_polconclk, 6;
        /// CYC_CLK (0CH.7, R): level at pin CYC_CLK.
        cyc_clk, with_cyc_clk, 7;
        /// ENCYCCLK (0CH.8): CYC_CLK triggers timing control after TCYCSTART.
        encycclk, with_encycclk, 8;
        /// POLCYCCLK (0CH.9): timing control triggered by the falling edge of CYC_CLK.
        polcycclk, with_polcycclk, 9;
        /// CYCSTART (0CH.10, W action): trigger timing control after TCYCSTART (master).
        cycstart, with_cycstart, 10;
        /// RDCNT (0CH.11, W action): load TCNT to TCNTLT.
        rdcnt, with_rdcnt, 11;
    }

    /// NCYC (0CH.15-12): number of communication cycles triggered by CYC_CLK or CYCSTART.
    pub const fn ncyc(self) -> u8 {
        field(self.0, 12, 4) as u8
    }

    /// This value with NCYC set to `ncyc` (0–15).
    pub const fn with_ncyc(self, ncyc: u8) -> Result<Self, FieldError> {
        match FieldError::check("NCYC", ncyc as u16, 4) {
            Ok(v) => Ok(Ctrl0C(with_field(self.0, 12, 4, v))),
            Err(e) => Err(e),
        }
    }
}
