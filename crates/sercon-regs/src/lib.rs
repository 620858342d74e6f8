//! The SERCON410B / SERCON816 register map, dual-port RAM structures and the
//! [`SerconBus`](crate) host-bus trait. Data only: no behaviour lives here.
#![no_std]
