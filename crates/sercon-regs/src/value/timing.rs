//! Phase, service-channel timeout, clock divider, DIV_CLK and the 16-bit time
//! registers (410B §4.1; 816 §2.7, §2.11.1.2, §2.11.1.3).

use crate::Variant;
use crate::bitfield::{bool_bits, field, with_field};
use crate::error::FieldError;
use crate::value::word_register;

word_register!(
    /// 0AH: PHAS0 (bits 7-0) and PHAS1 (bits 15-8), both reset 0FFH (410B §4.1, ERRATA).
    #[doc(alias("PHAS0", "PHAS1"))]
    Phas,
    Phas
);

impl Phas {
    /// Reset value: PHAS0 = PHAS1 = 0FFH (410B §4.1 0AH).
    pub const RESET: Phas = Phas(0xFFFF);

    /// A value with the given phases.
    pub const fn new(phas0: u8, phas1: u8) -> Self {
        Phas(((phas1 as u16) << 8) | phas0 as u16)
    }

    /// PHAS0: phase for MST transmit (master) or MST receive (slave).
    pub const fn phas0(self) -> u8 {
        self.0 as u8
    }

    /// PHAS1: phase for MST receive (slave).
    pub const fn phas1(self) -> u8 {
        (self.0 >> 8) as u8
    }
}

word_register!(
    /// 0BH (R): PHASREC (bits 7-0, phase of the received MST) and RECADR (bits 15-8,
    /// address of the receive telegram) (410B §4.1).
    #[doc(alias("PHASREC", "RECADR"))]
    PhasRec,
    PhasRec
);

impl PhasRec {
    /// PHASREC: phase information of the received MST.
    pub const fn phasrec(self) -> u8 {
        self.0 as u8
    }

    /// RECADR: address of the receive telegram.
    pub const fn recadr(self) -> u8 {
        (self.0 >> 8) as u8
    }
}

word_register!(
    /// 0DH: HS_TIMEOUT (bits 7-0) and BUSY_TIMEOUT (bits 15-8) of the service channel
    /// (410B §4.1).
    #[doc(alias("HS_TIMEOUT", "BUSY_TIMEOUT"))]
    ScTimeout,
    ScTimeout
);

impl ScTimeout {
    /// A value with the given timeouts.
    pub const fn new(hs_timeout: u8, busy_timeout: u8) -> Self {
        ScTimeout(((busy_timeout as u16) << 8) | hs_timeout as u16)
    }

    /// HS_TIMEOUT: handshake timeout for the service channel.
    pub const fn hs_timeout(self) -> u8 {
        self.0 as u8
    }

    /// BUSY_TIMEOUT: BUSY timeout for the service channel.
    pub const fn busy_timeout(self) -> u8 {
        (self.0 >> 8) as u8
    }
}

word_register!(
    /// 0EH: MCLKDIV (predivider, f_MCLK/1 MHz − 1, reset 19) and MCLKST (its initial
    /// value); 5 bits each on the 410B (4-0, 12-8), 6 on the 816 (5-0, 13-8)
    /// (410B §4.1; 816 §2.11.1.2).
    #[doc(alias("MCLKDIV", "MCLKST"))]
    MclkDiv,
    MclkDiv
);

impl MclkDiv {
    /// Reset value: MCLKDIV = 19, MCLKST = 0 (410B §4.1 0EH; MCLKST: spec-notes).
    pub const RESET: MclkDiv = MclkDiv(19);

    /// MCLKDIV, bits 5-0 (bit 5 is unused and reads 0 on the 410B).
    pub const fn mclkdiv(self) -> u8 {
        field(self.0, 0, 6) as u8
    }

    /// MCLKST, bits 13-8 (bit 13 is unused and reads 0 on the 410B).
    pub const fn mclkst(self) -> u8 {
        field(self.0, 8, 6) as u8
    }

    /// This value with MCLKDIV = `value`, which must fit the variant's width.
    pub const fn with_mclkdiv(self, variant: Variant, value: u8) -> Result<Self, FieldError> {
        match FieldError::check("MCLKDIV", value as u16, variant.mclkdiv_bits()) {
            Ok(v) => Ok(MclkDiv(with_field(self.0, 0, 6, v))),
            Err(e) => Err(e),
        }
    }

    /// This value with MCLKST = `value`, which must fit the variant's width.
    pub const fn with_mclkst(self, variant: Variant, value: u8) -> Result<Self, FieldError> {
        match FieldError::check("MCLKST", value as u16, variant.mclkdiv_bits()) {
            Ok(v) => Ok(MclkDiv(with_field(self.0, 8, 6, v))),
            Err(e) => Err(e),
        }
    }

    /// The MCLKDIV that gives a 1 µs time base from an MCLK of `mclk_hz`
    /// (`f_MCLK / 1 MHz − 1`, 410B §4.1 0EH), if it fits the variant's field.
    pub const fn for_mclk(variant: Variant, mclk_hz: u32) -> Result<u8, FieldError> {
        let mhz = mclk_hz / 1_000_000;
        let value = if mhz == 0 { 0 } else { mhz - 1 };
        let clamped = if value > 0xFFFF { 0xFFFF } else { value as u16 };
        match FieldError::check("MCLKDIV", clamped, variant.mclkdiv_bits()) {
            Ok(v) => Ok(v as u8),
            Err(e) => Err(e),
        }
    }
}

word_register!(
    /// 20H: NDIVCLK (7-0), POLDIVCLK (8) and, on the 816, DIVCLKMODE (9)
    /// (410B §4.1; 816 §2.7, §2.11.1.3; ERRATA "816 §2.7 NDIVCLK").
    #[doc(alias("NDIVCLK", "POLDIVCLK", "DIVCLKMODE"))]
    Ndivclk,
    Ndivclk
);

impl Ndivclk {
    /// NDIVCLK: pulses per cycle (DIVCLKMODE = 0) or cycles per pulse (DIVCLKMODE = 1).
    pub const fn ndivclk(self) -> u8 {
        self.0 as u8
    }

    /// This value with NDIVCLK = `value`.
    #[must_use]
    pub const fn with_ndivclk(self, value: u8) -> Self {
        Ndivclk(with_field(self.0, 0, 8, value as u16))
    }

    bool_bits! {
        /// POLDIVCLK (20H.8): DIV_CLK pulses are 0-active.
        poldivclk, with_poldivclk, 8;
        /// DIVCLKMODE (20H.9, 816 only, reads 0 on the 410B): one pulse after NDIVCLK
        /// cycles instead of NDIVCLK pulses per cycle.
        divclkmode, with_divclkmode, 9;
    }
}

word_register!(
    /// 0FH TSCYC0: SERCOS interface cycle time in µs for transmission block 0.
    #[doc(alias = "TSCYC0")]
    Tscyc0,
    Tscyc0
);
word_register!(
    /// 10H TSCYC1: SERCOS interface cycle time in µs for transmission block 1.
    #[doc(alias = "TSCYC1")]
    Tscyc1,
    Tscyc1
);
word_register!(
    /// 11H TCYCDEL (R): time at which MST is received, ring delay (master).
    #[doc(alias = "TCYCDEL")]
    Tcycdel,
    Tcycdel
);
word_register!(
    /// 12H TCNTLT (R): stored value of time counter TCNT.
    #[doc(alias = "TCNTLT")]
    Tcntlt,
    Tcntlt
);
word_register!(
    /// 13H TCNTST: initial value of time counter TCNT.
    #[doc(alias = "TCNTST")]
    Tcntst,
    Tcntst
);
word_register!(
    /// 14H TCYCSTART: delay in triggering timing control.
    #[doc(alias = "TCYCSTART")]
    Tcycstart,
    Tcycstart
);
word_register!(
    /// 15H JTSCYC1: receive time window for MST 1.
    #[doc(alias = "JTSCYC1")]
    Jtscyc1,
    Jtscyc1
);
word_register!(
    /// 16H JTSCYC2: receive time window for MST 2.
    #[doc(alias = "JTSCYC2")]
    Jtscyc2,
    Jtscyc2
);
word_register!(
    /// 18H JTRDEL1: receive time window for data telegram 1.
    #[doc(alias = "JTRDEL1")]
    Jtrdel1,
    Jtrdel1
);
word_register!(
    /// 19H JTRDEL2: receive time window for data telegram 2.
    #[doc(alias = "JTRDEL2")]
    Jtrdel2,
    Jtrdel2
);
word_register!(
    /// 1AH TINT0: time of time interrupt 0 and of the first edge of CON_CLK.
    #[doc(alias = "TINT0")]
    Tint0,
    Tint0
);
word_register!(
    /// 1BH TINT1: time of time interrupt 1 and of the second edge of CON_CLK.
    #[doc(alias = "TINT1")]
    Tint1,
    Tint1
);
word_register!(
    /// 1CH TINT2: time of time interrupt 2.
    #[doc(alias = "TINT2")]
    Tint2,
    Tint2
);
word_register!(
    /// 1DH TINT3: time of time interrupt 3.
    #[doc(alias = "TINT3")]
    Tint3,
    Tint3
);
word_register!(
    /// 1EH TDIVCLK: time of the first DIV_CLK pulse.
    #[doc(alias = "TDIVCLK")]
    Tdivclk,
    Tdivclk
);
word_register!(
    /// 1FH DTDIVCLK: DIV_CLK pulse distance.
    #[doc(alias = "DTDIVCLK")]
    Dtdivclk,
    Dtdivclk
);
