//! Property tests: decoding any words never panics, and whatever decodes encodes back
//! to the same words (410B §4.2 structures, §4.1 register values).

mod common;

use common::MemBus;
use proptest::prelude::*;
use sercon_regs::ram::container::{ContainerControl, RxContainer, TxContainer};
use sercon_regs::ram::header::{EndMarker, Header, HeaderKind, RxHeader, TxHeader};
use sercon_regs::ram::service::{ScMaster, ScSlave, ServiceContainer};
use sercon_regs::*;

fn variant() -> impl Strategy<Value = Variant> {
    prop_oneof![Just(Variant::Sercon410b), Just(Variant::Sercon816)]
}

proptest! {
    #[test]
    fn headers_round_trip(v in variant(), words in prop::array::uniform5(any::<u16>())) {
        // ERRATA marker bits: exactly one kind decodes, or 10 is rejected.
        match HeaderKind::classify(words[0]) {
            Ok(HeaderKind::Receive) => {
                let h = RxHeader::from_words(v, words);
                prop_assert_eq!(h.map(|h| h.to_words(v)), Ok(words));
            }
            Ok(HeaderKind::Transmit) => {
                let w = [words[0], words[1], words[2], words[3]];
                let h = TxHeader::from_words(v, w);
                prop_assert_eq!(h.map(|h| h.to_words(v)), Ok(w));
            }
            Ok(HeaderKind::EndMarker) => {
                let w = [words[0], words[1]];
                prop_assert_eq!(EndMarker::from_words(w).map(|h| h.to_words()), Ok(w));
            }
            Err(_) => prop_assert_eq!(words[0] >> 14, 0b10),
        }
        let decoded = Header::decode(v, &words);
        if let Ok(h) = decoded {
            let mut out = [0u16; 5];
            let n = h.encode(v, &mut out);
            prop_assert_eq!(n, Ok(h.kind().words()));
            prop_assert_eq!(&out[..h.kind().words()], &words[..h.kind().words()]);
        }
    }

    #[test]
    fn decoding_short_slices_never_panics(v in variant(), words in prop::collection::vec(any::<u16>(), 0..6)) {
        let _ = Header::decode(v, &words);
        let _ = RxHeader::decode(v, &words);
        let _ = TxHeader::decode(v, &words);
        let _ = EndMarker::decode(&words);
        let _ = RxContainer::decode(&words);
        let _ = TxContainer::decode(&words);
        let _ = ScMaster::decode(&words);
        let _ = ScSlave::decode(&words);
    }

    #[test]
    fn containers_round_trip(w0 in any::<u16>(), w1 in any::<u16>()) {
        // 410B §4.2.2: all 16 bits of control word 0 are used.
        prop_assert_eq!(ContainerControl::from_word(w0).to_word(), w0);
        prop_assert_eq!(RxContainer::from_words([w0, w1]).to_words(), [w0, w1]);
        prop_assert_eq!(TxContainer::from_words([w0]).to_words(), [w0]);
    }

    #[test]
    fn service_containers_round_trip(scmaster in any::<bool>(), words in prop::array::uniform5(any::<u16>())) {
        prop_assert_eq!(ScMaster::from_words(words).to_words(), words);
        prop_assert_eq!(ScSlave::from_words(words).to_words(), words);
        prop_assert_eq!(ServiceContainer::from_words(scmaster, words).to_words(), words);
    }

    #[test]
    fn register_values_are_lossless(bits in any::<u16>()) {
        fn check<R: RegisterValue + PartialEq + core::fmt::Debug>(bits: u16) -> bool {
            R::from_bits(bits).bits() == bits
        }
        prop_assert!(check::<Ctrl1>(bits) && check::<Ctrl2>(bits) && check::<Ctrl3>(bits));
        prop_assert!(check::<Ctrl0C>(bits) && check::<IntFlagsLo>(bits) && check::<IntFlagsHi>(bits));
        prop_assert!(check::<En0IntLo>(bits) && check::<En1IntHi>(bits) && check::<Phas>(bits));
        prop_assert!(check::<MclkDiv>(bits) && check::<Ndivclk>(bits) && check::<Thrpt>(bits));
        prop_assert!(check::<WdogStatus>(bits) && check::<WdogCommand>(bits) && check::<WdogTrig>(bits));
        // Getters of every typed value accept any word.
        let c2 = Ctrl2(bits);
        let _ = (c2.tmode(), c2.lmode(), c2.entxd(), c2.tm());
        let _ = (MclkDiv(bits).mclkdiv(), Thr(bits).kind(), Ctrl0C(bits).ncyc());
    }

    #[test]
    fn register_specs_never_panic(v in variant(), address in any::<u8>(), stored in any::<u16>(), written in any::<u16>()) {
        let s = register_spec(v, address);
        let after = s.stored_after_write(stored, written);
        // 410B §4.1: only R/W bits take the written value.
        prop_assert_eq!(after & s.rw, written & s.rw);
        prop_assert_eq!(after & !s.rw, stored & !s.rw);
        prop_assert_eq!(s.read_value(after, 0xFFFF) & s.unused(), 0);
    }

    #[test]
    fn byte_bus_word_access_equals_direct(
        high_first in any::<bool>(),
        ops in prop::collection::vec((any::<bool>(), any::<u16>(), any::<u16>()), 1..40),
    ) {
        let dir = if high_first { ByteDir::HighFirst } else { ByteDir::LowFirst };
        let mut direct = MemBus::new(Variant::Sercon816);
        let mut bytes = ByteBus::new(MemBus::new(Variant::Sercon816), dir);
        for (ram, address, value) in ops {
            if ram {
                direct.write_ram(address, value);
                bytes.write_ram(address, value);
                prop_assert_eq!(bytes.read_ram(address), direct.read_ram(address));
            } else {
                let a = address as u8;
                direct.write_register(a, value);
                bytes.write_register(a, value);
                prop_assert_eq!(bytes.read_register(a), direct.read_register(a));
            }
        }
        prop_assert_eq!(&bytes.inner().ram, &direct.ram);
        prop_assert_eq!(bytes.inner().regs, direct.regs);
    }
}
