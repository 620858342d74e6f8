//! The SERCON410B / SERCON816 register map, dual-port RAM structures and the
//! [`SerconBus`] host-bus trait. Data only: no behaviour lives here.
//!
//! * [`Variant`]: the two controllers and their differences as data.
//! * [`Register`]: every control register by word address (410B §4.1 00H–27H, 816
//!   §2.11.2 28H–2AH), with [`Register::spec`] giving per variant whether it exists, its
//!   reset value and which bits are R/W, read-only, write actions, write-1-to-clear or
//!   unused ([`RegisterSpec`]).
//! * [`value`]: one typed value per register ([`RegisterValue`]), bitflags for flag
//!   registers and getters/setters for multi-bit fields.
//! * [`ram`]: the fixed words of the dual-port RAM and the structures of 410B §4.2
//!   (headers, end marker, data containers, service containers) with lossless
//!   `from_words` / `to_words`.
//! * [`SerconBus`], [`SerconBusExt`], [`ByteBus`]: the host interface of 410B §2 as a
//!   driver sees it, typed accessors over it, and the 8-bit bus with BYTEDIR.
#![no_std]

mod bitfield;

pub mod access;
pub mod bus;
pub mod byte_bus;
pub mod error;
pub mod host;
pub mod ram;
pub mod register;
pub mod value;
pub mod variant;

pub use access::{RegisterSpec, register_spec, reset_values};
pub use bus::{Modifiable, SerconBus, SerconBusExt};
pub use byte_bus::{ByteBus, ByteDir};
pub use error::{FieldError, RamError};
pub use register::Register;
pub use value::RegisterValue;
pub use value::control::{Ctrl0C, Ctrl1, Ctrl2, Ctrl3, LineErrorMode, TestMode, TxdPins};
pub use value::interrupt::{En0IntHi, En0IntLo, En1IntHi, En1IntLo, IntFlagsHi, IntFlagsLo};
pub use value::pointer::{Thr, Thrpt, Tht, Thtpt, Thw, Thwpt};
pub use value::timing::{
    Dtdivclk, Jtrdel1, Jtrdel2, Jtscyc1, Jtscyc2, MclkDiv, Ndivclk, Phas, PhasRec, ScTimeout,
    Tcntlt, Tcntst, Tcycdel, Tcycstart, Tdivclk, Tint0, Tint1, Tint2, Tint3, Tscyc0, Tscyc1,
};
pub use value::watchdog::{Twdog, WdogCommand, WdogStatus, WdogTrig};
pub use value::{Fifo, ProgerrFl, Version};
pub use variant::Variant;
