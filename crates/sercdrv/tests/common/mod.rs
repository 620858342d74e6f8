//! Set-ups shared by sercdrv's integration tests (`mod common;`).
#![allow(dead_code)]

use sercdrv::timing;

pub mod ring_timing;
