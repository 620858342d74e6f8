//! An emulated SERCOS servo drive: IDN database, procedure commands and motion model.
