//! Loading the database from TOML: the shipped example and clear errors naming file,
//! line/column and entry.

use std::path::{Path, PathBuf};

use sercos_drive::config_file::{load, parse};
use sercos_wire::idn::{Element, Idn};

fn idn(text: &str) -> Idn {
    text.parse().unwrap_or(Idn::from_raw(0xFFFF))
}

#[test]
fn shipped_example_loads() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/tc2000r-axis.toml");
    let db = load(&path);
    assert!(db.is_ok(), "{db:?}");
    let db = db.unwrap_or_default();
    assert_eq!(
        db.read(idn("P-0-0001"), Element::OperationData),
        Ok(vec![30])
    );
    assert_eq!(
        db.read(idn("P-0-0100"), Element::OperationData),
        Ok(vec![25])
    );
    assert_eq!(
        db.read(idn("P-0-0100"), Element::Minimum),
        Ok(vec![(-40i16) as u16])
    );
    let firmware = db.get(idn("P-0-0101")).map(|p| p.words()[0]);
    assert_eq!(firmware, Some(16));
    // Standard IDNs are there too.
    assert!(db.get(idn("S-0-0127")).is_some());
}

fn error_of(text: &str) -> String {
    match parse(text, Path::new("drive.toml")) {
        Ok(_) => String::from("loaded"),
        Err(error) => error.to_string(),
    }
}

#[test]
fn syntax_error_has_line_and_column() {
    let text = "[[parameter]]\nidn = \"S-0-0001\"\nvalue = = 3\n";
    let message = error_of(text);
    assert!(message.starts_with("drive.toml:3:"), "{message}");
}

#[test]
fn bad_entries_are_named() {
    let text = "[[parameter]]\nidn = \"S-0-0001\"\nvalue = 2000\n\n[[parameter]]\nidn = \"S-0-0002\"\nvalue = 65500\n";
    let message = error_of(text);
    assert!(
        message.starts_with("drive.toml:7:9: parameter S-0-0002:"),
        "{message}"
    );
    assert!(message.contains("maximum"), "{message}");

    let message = error_of("[[parameter]]\nidn = \"X-0-0001\"\n");
    assert!(
        message.starts_with("drive.toml:2:7: parameter X-0-0001: bad IDN"),
        "{message}"
    );

    let message = error_of("[[parameter]]\nidn = \"P-0-0500\"\nvalue = 1\n");
    assert!(
        message.contains("P-0-0500: unknown IDN: give its attribute"),
        "{message}"
    );

    let message = error_of("[[parameter]]\nidn = \"S-0-0016\"\nvalue = [\"S-0-0051\", 7]\n");
    assert!(
        message.contains("drive.toml:3:9: parameter S-0-0016: IDN list item"),
        "{message}"
    );

    let message = error_of("[[parameter]]\nidn = \"S-0-0095\"\nvalue = 5\n");
    assert!(
        message.contains("S-0-0095: a integer does not fit"),
        "{message}"
    );

    let message = error_of("[[parameter]]\nidn = \"S-0-0001\"\ncolour = 5\n");
    assert!(message.starts_with("drive.toml:3:1:"), "{message}");
}

#[test]
fn missing_file_is_named() {
    let error = load(Path::new("/nonexistent/drive.toml"))
        .err()
        .map(|e| e.to_string());
    assert!(error.is_some_and(|e| e.starts_with("/nonexistent/drive.toml:0:0:")));
}
