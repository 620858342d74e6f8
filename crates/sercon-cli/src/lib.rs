//! The library behind the `sercon` command line: what a command does, apart from parsing its
//! arguments, so that other tools (the IDN tool, the full-stack benchmark) and the tests can
//! call it.
//!
//! * [`ring`]: a full-stack simulated ring (a `sercdrv` master and emulated drives on
//!   `sercos-sim`), built from a [`ring::RingSpec`], run with progress callbacks, summed up
//!   in a [`ring::RingReport`].
//! * [`full_stack`]: the full-stack scenarios of `sercon bench` (master driver, emulated
//!   drives, controller models and ring all running), measured in real-time factor.
//! * [`script_format`]: the text format of `sercon script` files (register writes, reads,
//!   checks and waits on one controller model).
//! * [`transcript_json`]: the JSON-lines schema of the master's service-channel transcript,
//!   shared by `sercon capture transcript --json` and `sercon ring --transcript`.

pub mod full_stack;
pub mod ring;
pub mod script_format;
pub mod transcript_json;
