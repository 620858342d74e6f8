//! `sercon idn read` on a default ring (SERCON816, 16 Mbit/s, 1 ms, drives 1-4).

mod idn_support;

use idn_support::{fails, ok};

// sercos-facts.md, "Timing parameters": S-0-0002 tScyc in µs; the master writes it in
// phase 2, so the drive reads back the ring's cycle.
#[test]
fn read_decodes_the_value_by_the_drives_attribute() {
    let out = ok(&["read", "--drive", "2", "S-0-0002"]);
    assert_eq!(out, "S-0-0002 communication cycle time tScyc = 1000 µs\n");
    // The value comes from the drive, not a fixed text: another cycle, another value.
    let out = ok(&["read", "--drive", "2", "--cycle-us", "2000", "S-0-0002"]);
    assert_eq!(out, "S-0-0002 communication cycle time tScyc = 2000 µs\n");
}

// sercos-facts.md, attribute bits 27-24 (decimal places) and 22-20 (display format).
#[test]
fn read_shows_decimals_binary_and_lists() {
    let out = ok(&["read", "--drive", "1", "S-0-0036"]);
    assert_eq!(out, "S-0-0036 velocity command value = 0.0000 rpm\n");
    let out = ok(&["read", "--drive", "1", "S-0-0032"]);
    assert!(
        out.starts_with("S-0-0032 primary operation mode = 0b"),
        "{out}"
    );
    // S-0-0016 as the master configured it in phase 2 (MasterConfig::new).
    let out = ok(&["read", "--drive", "3", "S-0-0016"]);
    assert_eq!(
        out,
        "S-0-0016 configuration list of the AT = [S-0-0011, S-0-0051, P-0-0019]\n"
    );
}

// sercos-facts.md, "Data block": elements 2 name, 3 attribute, 4 unit, 5 min, 6 max.
#[test]
fn read_each_element() {
    let read = |element: &str| ok(&["read", "--drive", "2", "S-0-0080", "--element", element]);
    assert_eq!(
        read("name"),
        "S-0-0080 torque command value name = torque command value\n"
    );
    assert_eq!(read("unit"), "S-0-0080 torque command value unit = %\n");
    assert_eq!(
        read("min"),
        "S-0-0080 torque command value minimum = -500.0 %\n"
    );
    assert_eq!(
        read("max"),
        "S-0-0080 torque command value maximum = 500.0 %\n"
    );
    let attribute = read("attribute");
    assert!(
        attribute.contains("attribute = ")
            && attribute.contains("2 bytes, signed decimal, 1 decimal places"),
        "{attribute}"
    );
    assert_eq!(read("data"), "S-0-0080 torque command value = 0.0 %\n");
}

// sercos-facts.md, "Service channel errors": 1001H IDN not present.
#[test]
fn unknown_idn_gives_1001h() {
    let (code, line) = fails(&["read", "--drive", "2", "S-0-1234"]);
    assert_eq!(code, 1);
    assert!(
        line.contains("drive 2") && line.contains("S-0-1234"),
        "{line}"
    );
    assert!(line.contains("1001H IDN not present"), "{line}");
}

#[test]
fn bad_idn_text_names_the_argument() {
    for bad in ["X-0-0002", "S-9-0001", "S-0-99999", "S-0-00x1", ""] {
        let (code, line) = fails(&["read", "--drive", "2", bad]);
        assert_eq!(code, 2, "{bad:?}");
        assert!(
            line.contains("<IDN>") && line.contains("is not an IDN"),
            "{line}"
        );
    }
}

#[test]
fn drive_not_on_the_ring() {
    let (code, line) = fails(&["read", "--drive", "9", "S-0-0002"]);
    assert_eq!(code, 1);
    assert!(
        line.contains("--drive 9") && line.contains("no drive 9 on the ring (drives 1, 2, 3, 4)"),
        "{line}"
    );
    let (_, line) = fails(&["read", "--drives", "2", "--drive", "3", "S-0-0002"]);
    assert!(line.contains("(drives 1, 2)"), "{line}");
    let (code, line) = fails(&["read", "--drive", "0", "S-0-0002"]);
    assert_eq!(code, 2);
    assert!(line.contains("--drive"), "{line}");
}

#[test]
fn read_as_json() {
    let out = ok(&["read", "--drive", "4", "S-0-0002", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).expect("one JSON object");
    assert_eq!(v["drive"], 4);
    assert_eq!(v["phase"], 4);
    assert_eq!(v["idn"], "S-0-0002");
    assert_eq!(v["value"], "1000 µs");
    assert_eq!(v["words"], serde_json::json!([1000]));
}
