//! The control registers as an enum of word addresses (410B §4.1, 816 §2.11).
//!
//! The address is the word address input on A6-1 (410B §4.1: "To calculate the byte
//! address, the value has to be multiplied by two"). Where the datasheet names a register
//! its name is the doc alias; registers the datasheet leaves unnamed (1H, 2H, 3H, 0CH,
//! 4H–9H) are named after their address or content, with their bit names as aliases.

use crate::variant::Variant;

/// Number of word addresses the register space decodes (A6-1: 00H–3FH).
// 410B §2 (A15-0): "A6-1 the control registers".
pub const REGISTER_SPACE_WORDS: usize = 64;

/// Mask applied to a register word address: only A6-1 are decoded.
pub const REGISTER_ADDRESS_MASK: u8 = 0x3F;

macro_rules! registers {
    ($( $(#[$meta:meta])* $name:ident = $addr:literal, $dsname:literal; )*) => {
        /// A control register, by word address (410B §4.1 00H–27H, 816 §2.11.2 28H–2AH).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[repr(u8)]
        pub enum Register {
            $( $(#[$meta])* $name = $addr, )*
        }

        impl Register {
            /// Every register of both variants, in address order.
            pub const ALL: [Register; 43] = [ $( Register::$name, )* ];

            /// The register at word address `address` (00H–2AH), whichever variant has
            /// it; `None` for the unused addresses 2BH–3FH and anything above.
            pub const fn from_address(address: u8) -> Option<Register> {
                match address {
                    $( $addr => Some(Register::$name), )*
                    _ => None,
                }
            }

            /// The datasheet's name (or names) for this register, e.g. `"TSCYC0"` or
            /// `"RFIFO/TFIFO"`; unnamed registers give their address, e.g. `"1H"`.
            pub const fn datasheet_name(self) -> &'static str {
                match self {
                    $( Register::$name => $dsname, )*
                }
            }
        }
    };
}

registers! {
    /// 00H VERSION: circuit code (410B §4.1; 816 §2.11.1.1).
    #[doc(alias = "VERSION")]
    Version = 0x00, "VERSION";
    /// 1H: reset flag, software reset, repeater, serial line options and baud rate
    /// selection (RSTFL … DMAMODE, SWBAUD16).
    #[doc(alias("1H", "RSTFL", "SWRST", "REPON", "REGMODE", "ENTSBAUD", "SWBAUD16"))]
    Ctrl1 = 0x01, "1H";
    /// 2H: transmit pins, test modes, line error (ENTXD1-6, TXDMODE, TMODE, TM0-1, RDIST,
    /// FIBBR, LMODE).
    #[doc(alias("2H", "ENTXD", "TXDMODE", "TMODE", "LMODE", "RDIST", "FIBBR"))]
    Ctrl2 = 0x02, "2H";
    /// 3H: interrupt outputs and telegram-processing status (INTFL0 … REACTN).
    #[doc(alias("3H", "INTFL0", "ENINT0", "POLINT0", "ENTMT", "COMACT", "FLREC"))]
    Ctrl3 = 0x03, "3H";
    /// 4H: interrupt flags INT_RDIST … INT_RERR (read) / CLR_INT_n (write 1 to clear).
    #[doc(alias("4H", "INT_n", "CLR_INT_n"))]
    IntFlagsLo = 0x04, "INT_n/CLR_INT_n (4H)";
    /// 5H: interrupt flags INT_SC_0 … INT_NEWADR (read) / CLR_INT_n (write 1 to clear).
    #[doc(alias("5H", "INT_n", "CLR_INT_n"))]
    IntFlagsHi = 0x05, "INT_n/CLR_INT_n (5H)";
    /// 6H: EN0_INT_n, which flags of 4H activate INT0.
    #[doc(alias("6H", "EN0_INT_n", "ENO_INT_n"))]
    En0IntLo = 0x06, "EN0_INT_n (6H)";
    /// 7H: EN0_INT_n, which flags of 5H activate INT0.
    #[doc(alias("7H", "EN0_INT_n", "ENO_INT_n"))]
    En0IntHi = 0x07, "EN0_INT_n (7H)";
    /// 8H: EN1_INT_n, which flags of 4H activate INT1.
    #[doc(alias("8H", "EN1_INT_n"))]
    En1IntLo = 0x08, "EN1_INT_n (8H)";
    /// 9H: EN1_INT_n, which flags of 5H activate INT1.
    #[doc(alias("9H", "EN1_INT_n"))]
    En1IntHi = 0x09, "EN1_INT_n (9H)";
    /// 0AH: PHAS0, PHAS1 (printed "OAH", ERRATA).
    #[doc(alias("0AH", "OAH", "PHAS0", "PHAS1"))]
    Phas = 0x0A, "PHAS0/PHAS1";
    /// 0BH: PHASREC, RECADR.
    #[doc(alias("0BH", "PHASREC", "RECADR"))]
    PhasRec = 0x0B, "PHASREC/RECADR";
    /// 0CH: MST and cycle control (MSTEN … NCYC).
    #[doc(alias("0CH", "MSTEN", "MSTMASTER", "COMBLK0", "CYCSTART", "RDCNT", "NCYC"))]
    Ctrl0C = 0x0C, "0CH";
    /// 0DH: HS_TIMEOUT, BUSY_TIMEOUT.
    #[doc(alias("0DH", "HS_TIMEOUT", "BUSY_TIMEOUT"))]
    ScTimeout = 0x0D, "HS_TIMEOUT/BUSY_TIMEOUT";
    /// 0EH: MCLKDIV, MCLKST.
    #[doc(alias("0EH", "MCLKDIV", "MCLKST"))]
    MclkDiv = 0x0E, "MCLKDIV/MCLKST";
    /// 0FH TSCYC0: cycle time of transmission block 0 in µs.
    #[doc(alias = "TSCYC0")]
    Tscyc0 = 0x0F, "TSCYC0";
    /// 10H TSCYC1: cycle time of transmission block 1 in µs.
    #[doc(alias = "TSCYC1")]
    Tscyc1 = 0x10, "TSCYC1";
    /// 11H TCYCDEL: time at which MST is received, ring delay (master).
    #[doc(alias = "TCYCDEL")]
    Tcycdel = 0x11, "TCYCDEL";
    /// 12H TCNTLT: stored value of time counter TCNT.
    #[doc(alias = "TCNTLT")]
    Tcntlt = 0x12, "TCNTLT";
    /// 13H TCNTST: initial value of time counter TCNT.
    #[doc(alias = "TCNTST")]
    Tcntst = 0x13, "TCNTST";
    /// 14H TCYCSTART: delay in triggering timing control.
    #[doc(alias = "TCYCSTART")]
    Tcycstart = 0x14, "TCYCSTART";
    /// 15H JTSCYC1: receive time window for MST 1.
    #[doc(alias = "JTSCYC1")]
    Jtscyc1 = 0x15, "JTSCYC1";
    /// 16H JTSCYC2: receive time window for MST 2.
    #[doc(alias = "JTSCYC2")]
    Jtscyc2 = 0x16, "JTSCYC2";
    /// 17H PROGERR_FL (read) / CLR_PROGERR_FL (write 1 to clear).
    #[doc(alias("PROGERR_FL", "CLR_PROGERR_FL"))]
    ProgerrFl = 0x17, "PROGERR_FL/CLR_PROGERR_FL";
    /// 18H JTRDEL1: receive time window for data telegram 1.
    #[doc(alias = "JTRDEL1")]
    Jtrdel1 = 0x18, "JTRDEL1";
    /// 19H JTRDEL2: receive time window for data telegram 2.
    #[doc(alias = "JTRDEL2")]
    Jtrdel2 = 0x19, "JTRDEL2";
    /// 1AH TINT0: time interrupt 0 and first edge of CON_CLK.
    #[doc(alias = "TINT0")]
    Tint0 = 0x1A, "TINT0";
    /// 1BH TINT1: time interrupt 1 and second edge of CON_CLK.
    #[doc(alias = "TINT1")]
    Tint1 = 0x1B, "TINT1";
    /// 1CH TINT2: time interrupt 2.
    #[doc(alias = "TINT2")]
    Tint2 = 0x1C, "TINT2";
    /// 1DH TINT3: time interrupt 3.
    #[doc(alias = "TINT3")]
    Tint3 = 0x1D, "TINT3";
    /// 1EH TDIVCLK: time of the first DIV_CLK pulse.
    #[doc(alias = "TDIVCLK")]
    Tdivclk = 0x1E, "TDIVCLK";
    /// 1FH DTDIVCLK: DIV_CLK pulse distance.
    #[doc(alias = "DTDIVCLK")]
    Dtdivclk = 0x1F, "DTDIVCLK";
    /// 20H: NDIVCLK, POLDIVCLK, DIVCLKMODE (816).
    #[doc(alias("20H", "NDIVCLK", "POLDIVCLK", "DIVCLKMODE"))]
    Ndivclk = 0x20, "NDIVCLK/POLDIVCLK/DIVCLKMODE";
    /// 21H THTPT: RAM address of the header of the transmitted telegram.
    #[doc(alias = "THTPT")]
    Thtpt = 0x21, "THTPT";
    /// 22H THT: word 0 of the header of the transmitted telegram.
    #[doc(alias = "THT")]
    Tht = 0x22, "THT";
    /// 23H THWPT: RAM address of the header of the telegram expected.
    #[doc(alias = "THWPT")]
    Thwpt = 0x23, "THWPT";
    /// 24H THW: word 0 of the header of the telegram expected.
    #[doc(alias = "THW")]
    Thw = 0x24, "THW";
    /// 25H: THRPT, MSTTCHK, PHAS12, FLMDTADR.
    #[doc(alias("25H", "THRPT", "MSTTCHK", "PHAS12", "FLMDTADR"))]
    Thrpt = 0x25, "THRPT/MSTTCHK/PHAS12/FLMDTADR";
    /// 26H THR: word 0 of the header of the received telegram.
    #[doc(alias = "THR")]
    Thr = 0x26, "THR";
    /// 27H RFIFO (read, pops) / TFIFO (write, pushes).
    #[doc(alias("RFIFO", "TFIFO"))]
    Fifo = 0x27, "RFIFO/TFIFO";
    /// 28H (816 only): watchdog and RSCEND control/status.
    #[doc(alias("28H", "WDOG_START", "WDOG_STAT", "INT_WDOG", "CLR_INT_WDOG", "INT_RSCEND"))]
    WdogCtrl = 0x28, "WDOG_START/WDOG_STAT … EN1_INT_RSCEND (28H)";
    /// 29H WDOG_TRIG (816 only): write 42H to trigger the watchdog.
    #[doc(alias = "WDOG_TRIG")]
    WdogTrig = 0x29, "WDOG_TRIG";
    /// 2AH TWDOG (816 only): watchdog time constant.
    #[doc(alias = "TWDOG")]
    Twdog = 0x2A, "TWDOG";
}

/// Whether a bus read of the register at word address `address` (A6-1 decoded) changes the
/// chip: only a read of RFIFO (27H), which takes the oldest word of the receive FIFO (410B
/// §4.1 27H). Every other read changes nothing (R/W bits read back, status bits show the
/// chip's state, interrupt flags are cleared by writes, 4H–5H).
pub const fn read_has_effect(address: u8) -> bool {
    address & REGISTER_ADDRESS_MASK == Register::Fifo as u8
}

impl Register {
    /// The register's word address (A6-1).
    pub const fn address(self) -> u8 {
        self as u8
    }

    /// The register's byte address on the host bus (word address × 2, 410B §4.1).
    pub const fn byte_address(self) -> u8 {
        (self as u8) << 1
    }

    /// Whether `variant` has this register (28H–2AH exist only on the 816).
    // 816 §2.11.2: 28H–2AH are new in the SERCON816.
    pub const fn exists_on(self, variant: Variant) -> bool {
        self.address() <= variant.last_register_address()
    }
}
