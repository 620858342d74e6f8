//! Where a drive's entry is in a list, by its address: one table look-up instead of a scan,
//! so that per-cycle work over 254 drives stays linear in the ring (sercos-telegrams.md ADR:
//! addresses 1-254, so a 256-entry table holds every address).

use sercos_wire::address::DriveAddress;

/// Entry positions by drive address.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct DriveIndex {
    positions: Vec<Option<usize>>,
}

impl Default for DriveIndex {
    fn default() -> Self {
        DriveIndex {
            positions: vec![None; 256],
        }
    }
}

impl DriveIndex {
    /// The index of `drives`: the first position of each address.
    pub(crate) fn new(drives: impl IntoIterator<Item = DriveAddress>) -> DriveIndex {
        let mut index = DriveIndex::default();
        for (i, d) in drives.into_iter().enumerate() {
            if let Some(slot) = index.positions.get_mut(usize::from(d.get())) {
                slot.get_or_insert(i);
            }
        }
        index
    }

    /// The position of `drive`, if listed.
    pub(crate) fn get(&self, drive: DriveAddress) -> Option<usize> {
        self.positions
            .get(usize::from(drive.get()))
            .copied()
            .flatten()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn a(n: u8) -> DriveAddress {
        DriveAddress::new(n).expect("1-254")
    }

    // sercos-telegrams.md ADR 1-254: every address has a place; the first listing counts.
    #[test]
    fn positions_are_found_by_address() {
        let index = DriveIndex::new([a(254), a(1), a(7), a(1)]);
        assert_eq!(index.get(a(254)), Some(0));
        assert_eq!(index.get(a(1)), Some(1));
        assert_eq!(index.get(a(7)), Some(2));
        assert_eq!(index.get(a(2)), None);
    }
}
