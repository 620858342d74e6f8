//! Interrupt flags 4H/5H and their enables 6H–9H (410B §4.1).
//!
//! Reading 4H/5H returns the flags; writing 1 to a bit clears that flag and writing 0
//! leaves it (ERRATA "410B 4H/5H"). 6H/8H enable the flags of 4H onto INT0/INT1, 7H/9H
//! those of 5H, with the same bit assignment.

use crate::register::Register;
use crate::value::{RegisterValue, flags_register};

bitflags::bitflags! {
    /// Interrupt flags of register 4H (INT_n / CLR_INT_n), also the bit assignment of
    /// the enables 6H and 8H (410B §4.1).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct IntFlagsLo: u16 {
        /// Receive data distorted.
        const INT_RDIST = 1 << 0;
        /// No receive data.
        const INT_FIBBR = 1 << 1;
        /// Start of transmission block 0.
        const INT_COMBLK0 = 1 << 2;
        /// Start of transmission block 1.
        const INT_COMBLK1 = 1 << 3;
        /// End of transmission block.
        const INT_COMEND = 1 << 4;
        /// Phase of MST = 0.
        const INT_PHAS0 = 1 << 5;
        /// Phase of MST errored.
        const INT_PHASERR = 1 << 6;
        /// Communication cycle start too early.
        const INT_MSTEARLY = 1 << 7;
        /// Communication cycle start too late.
        const INT_MSTLATE = 1 << 8;
        /// MST missing twice.
        const INT_MSTMIS = 1 << 9;
        /// Start of transmit telegram.
        const INT_TSTART = 1 << 10;
        /// End of transmit telegram.
        const INT_TEND = 1 << 11;
        /// Start waiting for receive telegram.
        const INT_RWAIT = 1 << 12;
        /// Start of receive telegram.
        const INT_RSTART = 1 << 13;
        /// End of receive telegram.
        const INT_REND = 1 << 14;
        /// Error of receive telegram.
        const INT_RERR = 1 << 15;
    }
}
flags_register!(IntFlagsLo, IntFlagsLo);

bitflags::bitflags! {
    /// Interrupt flags of register 5H (INT_n / CLR_INT_n), also the bit assignment of
    /// the enables 7H and 9H (410B §4.1).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct IntFlagsHi: u16 {
        /// Service container 0.
        const INT_SC_0 = 1 << 0;
        /// Service container 1.
        const INT_SC_1 = 1 << 1;
        /// Service container 2.
        const INT_SC_2 = 1 << 2;
        /// Service container 3.
        const INT_SC_3 = 1 << 3;
        /// Service container 4.
        const INT_SC_4 = 1 << 4;
        /// Service container 5.
        const INT_SC_5 = 1 << 5;
        /// Service container 6.
        const INT_SC_6 = 1 << 6;
        /// Service container 7.
        const INT_SC_7 = 1 << 7;
        /// Receive telegram missing twice.
        const INT_RMISS = 1 << 8;
        /// Time TINT0 reached.
        const INT_TIME0 = 1 << 9;
        /// Time TINT1 reached.
        const INT_TIME1 = 1 << 10;
        /// Time TINT2 reached.
        const INT_TIME2 = 1 << 11;
        /// Time TINT3 reached.
        const INT_TIME3 = 1 << 12;
        /// DIV_CLK signal.
        const INT_DIVCLK = 1 << 13;
        /// Programming error.
        const INT_PROGERR = 1 << 14;
        /// Address change.
        const INT_NEWADR = 1 << 15;
    }
}
flags_register!(IntFlagsHi, IntFlagsHi);

impl IntFlagsHi {
    /// INT_SC_n of service container `n` (0–7); `None` for other `n`.
    pub const fn int_sc(n: u8) -> Option<IntFlagsHi> {
        if n < 8 {
            Some(IntFlagsHi::from_bits_retain(1 << n))
        } else {
            None
        }
    }

    /// INT_TIMEn of time interrupt `n` (0–3); `None` for other `n`.
    pub const fn int_time(n: u8) -> Option<IntFlagsHi> {
        if n < 4 {
            Some(IntFlagsHi::from_bits_retain(1 << (9 + n)))
        } else {
            None
        }
    }
}

macro_rules! enable_register {
    ($(#[$meta:meta])* $name:ident, $flags:ty, $reg:ident) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        pub struct $name(pub $flags);

        impl RegisterValue for $name {
            const REGISTER: Register = Register::$reg;
            fn from_bits(bits: u16) -> Self {
                $name(<$flags>::from_bits_retain(bits))
            }
            fn bits(self) -> u16 {
                self.0.bits()
            }
        }
    };
}

enable_register!(
    /// 6H EN0_INT_n: flags of 4H that activate INT0 (410B §4.1).
    #[doc(alias("EN0_INT_n", "ENO_INT_n"))]
    En0IntLo,
    IntFlagsLo,
    En0IntLo
);
enable_register!(
    /// 7H EN0_INT_n: flags of 5H that activate INT0 (410B §4.1).
    #[doc(alias("EN0_INT_n", "ENO_INT_n"))]
    En0IntHi,
    IntFlagsHi,
    En0IntHi
);
enable_register!(
    /// 8H EN1_INT_n: flags of 4H that activate INT1 (410B §4.1).
    #[doc(alias = "EN1_INT_n")]
    En1IntLo,
    IntFlagsLo,
    En1IntLo
);
enable_register!(
    /// 9H EN1_INT_n: flags of 5H that activate INT1 (410B §4.1).
    #[doc(alias = "EN1_INT_n")]
    En1IntHi,
    IntFlagsHi,
    En1IntHi
);
