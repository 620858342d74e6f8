//! Communication-cycle timing through the bus: CYCSTART, TCYCSTART, NCYC, TSCYC0/1,
//! COMACT/COMBLK and INT_COMBLK0/1, INT_COMEND (410B §4.1 3H, 4H, 0CH, 0FH–14H).

mod common;

use common::*;
use sercon_model::pins::Pin;
use sercon_regs::{Register, SerconBusExt};

#[test]
fn smoke_trace() {
    let mut chip = chip816();
    chip.set_traced_pins(sercon_model::pins::PinSet::ALL);
    chip.write(Register::Tscyc0, 100);
    chip.write(Register::Tint0, 10);
    chip.write(Register::Tint1, 30);
    chip.write(Register::Tdivclk, 5);
    chip.write(Register::Dtdivclk, 20);
    chip.write(Register::Ndivclk, 4);
    chip.write(Register::Ctrl0C, CTRL0C_ENCONCLK | CTRL0C_CYCSTART);
    chip.advance_to(us(250));
    let ev = drain(&mut chip);
    for e in &ev {
        eprintln!("{} {} {}", e.at, e.pin, e.level);
    }
    assert!(ev.iter().any(|e| e.pin == Pin::DivClk));
}
