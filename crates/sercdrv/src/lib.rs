//! SERCDRV: host driver for SERCOS masters and slaves, written against `SerconBus` only.
pub mod idn_store;
pub mod master;
pub mod ram_layout;
pub mod service_channel;
pub mod slave;
pub mod timing;
