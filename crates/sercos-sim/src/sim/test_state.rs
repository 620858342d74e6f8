//! What tests compare of two runs' chips: every chip's registers 0H–1FH (410B §4.1) and
//! the first RAM words.

use sercon_regs::SerconBus;

use super::Simulation;

/// Registers 0H–1FH and RAM words `0..ram_words` of every chip, node after node (accesses
/// through `chip_mut` cost nothing and do not advance the chips).
pub(super) fn chip_words(sim: &mut Simulation, ram_words: u16) -> Vec<u16> {
    let mut words = Vec::new();
    for j in 0..sim.node_count() {
        if let Some(c) = sim.chip_mut(j) {
            words.extend((0u8..0x20).map(|a| c.read_register(a)));
            words.extend((0..ram_words).map(|a| c.read_ram(a)));
        }
    }
    words
}
