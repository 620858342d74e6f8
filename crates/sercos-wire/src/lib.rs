//! SERCOS II telegrams on the line.
//!
//! Two layers, both independent of the controller chip:
//!
//! * telegram formats (MST, MDT, AT, data records, control and status words, IDNs,
//!   addresses) as zero-copy views over byte buffers plus owned representations with
//!   `parse` / `emit`, in the manner of smoltcp's `wire` module;
//! * line coding (SERCON410B datasheet §1, §2): FCS, flags, zero insertion, NRZI/NRZ,
//!   light polarity, with a fast encoder/decoder and a bit-serial reference beside it.
//!
//! The crate is `no_std`; the `alloc` and `std` features add owned buffers and the
//! capture-file reader.
#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(feature = "alloc")]
extern crate alloc;

pub mod address;
pub mod attribute;
pub mod idn;
pub mod idn_catalog;
pub mod line;
pub mod service_error;
pub mod telegram;
pub mod time;

#[cfg(feature = "alloc")]
pub mod service_transcript;
