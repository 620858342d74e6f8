//! The files a user hands `sercon` (a ring description, a drive's IDN file, a register
//! script) never make it
//! panic: any text, and above all near-valid text (the shipped examples with random edits,
//! which reach far deeper into the parsers than random text does), is either taken or
//! refused with an error that names the file, line and column (a script: its line). A ring description taken
//! goes on through what `sercon ring` does with it before it runs (the master's
//! configuration and cycle plan), which must not panic either.

use std::path::Path;

use proptest::prelude::*;
use sercon_cli::full_stack::plan_ring;
use sercon_cli::ring::{master_config, parse_config};
use sercon_cli::script_format;
use sercon_regs::Variant;
use sercos_drive::config_file;

const RING_EXAMPLE: &str = include_str!("../../../examples/ring.toml");
/// Where the ring example lies: its drives' IDN files are found relative to it.
const RING_PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/ring.toml");
const DRIVE_EXAMPLE: &str = include_str!("../../sercos-drive/data/tc2000r-axis.toml");
const SCRIPT_EXAMPLE: &str = include_str!("../../../examples/scripts/con_clk_div_clk.scr");

/// Characters the edits insert: what TOML and the files' values are made of, and some that
/// they are not.
const ALPHABET: &[char] = &[
    '0', '1', '2', '5', '9', '-', '+', '.', '_', 'x', 'e', 'S', 'P', 'a', 'z', '"', '\'', '[', ']',
    '{', '}', '=', ',', '#', ' ', '\n', '\t', '\\', 'µ', '°', '\u{0}',
];

/// One edit of a text: delete, insert or replace the character at a position (taken modulo
/// the text's length).
#[derive(Debug, Clone)]
enum Edit {
    Delete(usize),
    Insert(usize, char),
    Replace(usize, char),
}

fn edit() -> impl Strategy<Value = Edit> {
    let c = proptest::sample::select(ALPHABET);
    prop_oneof![
        any::<usize>().prop_map(Edit::Delete),
        (any::<usize>(), c.clone()).prop_map(|(i, c)| Edit::Insert(i, c)),
        (any::<usize>(), c).prop_map(|(i, c)| Edit::Replace(i, c)),
    ]
}

/// `text` with `edits` applied one after the other (on characters: the result stays UTF-8).
fn edited(text: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for e in edits {
        let n = chars.len().max(1);
        match *e {
            Edit::Delete(i) => {
                if !chars.is_empty() {
                    chars.remove(i % n);
                }
            }
            Edit::Insert(i, c) => chars.insert(i % (chars.len() + 1), c),
            Edit::Replace(i, c) => {
                if let Some(slot) = chars.get_mut(i % n) {
                    *slot = c;
                }
            }
        }
    }
    chars.into_iter().collect()
}

/// Whether `message` starts with `file:line:column: ` and a reason, line and column from 1.
fn names_the_place(message: &str, file: &str) -> bool {
    let Some(rest) = message.strip_prefix(file).and_then(|r| r.strip_prefix(':')) else {
        return false;
    };
    let mut parts = rest.splitn(3, ':');
    let number = |p: Option<&str>| {
        p.and_then(|p| p.parse::<usize>().ok())
            .is_some_and(|n| n >= 1)
    };
    number(parts.next())
        && number(parts.next())
        && parts
            .next()
            .is_some_and(|r| r.starts_with(' ') && r.len() > 1)
}

/// Parses `text` as a ring description and, when taken, builds what `sercon ring` builds
/// from it before the run; the error's place when refused.
fn check_ring(text: &str) -> Result<(), TestCaseError> {
    match parse_config(text, Path::new(RING_PATH)) {
        Err(e) => {
            let message = e.to_string();
            prop_assert!(names_the_place(&message, RING_PATH), "{message}");
        }
        Ok(spec) => {
            // The master's configuration and the cycle plan, which reads the drives' IDN
            // files: only the example's own (an edit can name any file, even a device that
            // never ends). Both refuse or take; neither may panic.
            let _ = master_config(&spec);
            let shipped = shipped_idn_files();
            if spec
                .drives
                .iter()
                .all(|d| d.idn_file.as_ref().is_none_or(|f| shipped.contains(f)))
            {
                let _ = plan_ring(&spec);
            }
        }
    }
    Ok(())
}

/// The IDN files the ring example names, as the parser resolves them.
fn shipped_idn_files() -> Vec<std::path::PathBuf> {
    parse_config(RING_EXAMPLE, Path::new(RING_PATH))
        .map(|spec| spec.drives.into_iter().filter_map(|d| d.idn_file).collect())
        .unwrap_or_default()
}

fn check_drive(text: &str) -> Result<(), TestCaseError> {
    if let Err(e) = config_file::parse(text, Path::new("drive.toml")) {
        let message = e.to_string();
        prop_assert!(names_the_place(&message, "drive.toml"), "{message}");
    }
    Ok(())
}

/// Parses `text` as a script for both controllers: taken with its lines in order, or refused
/// at a line of the text.
fn check_script(text: &str) -> Result<(), TestCaseError> {
    let lines = text.lines().count();
    for variant in [Variant::Sercon816, Variant::Sercon410b] {
        match script_format::parse(text, variant) {
            Err(e) => {
                prop_assert!((1..=lines).contains(&e.line), "{e} of {lines} lines");
                let place = format!("line {}: ", e.line);
                prop_assert!(e.to_string().starts_with(&place), "{e}");
            }
            Ok(steps) => {
                prop_assert!(steps.windows(2).all(|w| w[0].number < w[1].number));
                prop_assert!(steps.iter().all(|l| (1..=lines).contains(&l.number)));
            }
        }
    }
    Ok(())
}

#[test]
fn the_examples_are_taken_as_shipped() {
    script_format::parse(SCRIPT_EXAMPLE, Variant::Sercon816).expect("con_clk_div_clk.scr");
    parse_config(RING_EXAMPLE, Path::new(RING_PATH)).expect("examples/ring.toml");
    assert!(
        !shipped_idn_files().is_empty(),
        "the example names an IDN file"
    );
    config_file::parse(DRIVE_EXAMPLE, Path::new("drive.toml")).expect("tc2000r-axis.toml");
    assert!(names_the_place(
        "ring.toml:3:14: cycle_us 5 is not 62-65000",
        "ring.toml"
    ));
    assert!(!names_the_place("ring.toml:0:14: x", "ring.toml"));
    assert!(!names_the_place("ring.toml: x", "ring.toml"));
}

// 256 cases each by default; `PROPTEST_CASES=N` for a longer run.
proptest! {
    /// No panic from a ring description: examples/ring.toml with up to 12 random edits.
    #[test]
    fn an_edited_ring_file_is_taken_or_refused_with_its_place(
        edits in proptest::collection::vec(edit(), 1..12)
    ) {
        check_ring(&edited(RING_EXAMPLE, &edits))?;
    }

    /// No panic from a ring description: any text.
    #[test]
    fn any_text_as_a_ring_file_is_taken_or_refused_with_its_place(text in ".{0,400}") {
        check_ring(&text)?;
    }

    /// No panic from a drive's IDN file: the shipped axis with up to 12 random edits.
    #[test]
    fn an_edited_idn_file_is_taken_or_refused_with_its_place(
        edits in proptest::collection::vec(edit(), 1..12)
    ) {
        check_drive(&edited(DRIVE_EXAMPLE, &edits))?;
    }

    /// No panic from a drive's IDN file: any text.
    #[test]
    fn any_text_as_an_idn_file_is_taken_or_refused_with_its_place(text in ".{0,400}") {
        check_drive(&text)?;
    }

    /// No panic from a register script: the shipped example with up to 12 random edits.
    #[test]
    fn an_edited_script_is_taken_or_refused_at_its_line(
        edits in proptest::collection::vec(edit(), 1..12)
    ) {
        check_script(&edited(SCRIPT_EXAMPLE, &edits))?;
    }

    /// No panic from a register script: any text.
    #[test]
    fn any_text_as_a_script_is_taken_or_refused_at_its_line(text in ".{0,400}") {
        check_script(&text)?;
    }
}
