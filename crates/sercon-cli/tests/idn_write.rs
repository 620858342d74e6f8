//! `sercon idn write`: values parsed by the drive's attribute; refusals with the drive's
//! code and meaning and a non-zero exit.

mod idn_support;

use idn_support::{fails, ok};

// sercos-facts.md, "Service channel errors": 7007H above maximum (S-0-0080 max 500.0 %).
#[test]
fn refused_write_names_code_and_meaning() {
    let (code, line) = fails(&["write", "--drive", "2", "S-0-0080", "600.0"]);
    assert_eq!(code, 1);
    assert_eq!(
        line,
        "sercon: drive 2, S-0-0080 operation data: 7007H operation data above maximum"
    );
    let (code, line) = fails(&["write", "--drive", "2", "S-0-0080", "-600"]);
    assert_eq!(code, 1);
    assert!(
        line.ends_with("7006H operation data below minimum"),
        "{line}"
    );
}

// sercos-facts.md, attribute bits 30-28: P-0-0001 is write-protected in phase 4 only
// (7005H), writable in phase 2.
#[test]
fn write_protection_follows_the_phase() {
    let (code, line) = fails(&["write", "--drive", "1", "P-0-0001", "12.5"]);
    assert_eq!(code, 1);
    assert!(
        line.ends_with("7005H operation data write-protected at this time"),
        "{line}"
    );
    let out = ok(&["write", "--drive", "1", "--phase", "2", "P-0-0001", "12.5"]);
    assert_eq!(out, "P-0-0001 velocity loop time constant := 12.5 ms\n");
    // Read only in every phase: 7004H.
    let (_, line) = fails(&["write", "--drive", "1", "--phase", "2", "S-0-0003", "10"]);
    assert!(
        line.ends_with("7004H operation data cannot be changed (read only)"),
        "{line}"
    );
}

// sercos-facts.md, attribute: decimals and sign; the value read back equals the value written.
#[test]
fn write_signed_decimal_and_read_back() {
    let out = ok(&["write", "--drive", "3", "S-0-0080", "-12.5"]);
    assert_eq!(out, "S-0-0080 torque command value := -12.5 %\n");
    let out = ok(&["write", "--drive", "3", "S-0-0080", "0x7D", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(v["written"], "12.5 %");
    assert_eq!(v["read_back"], "12.5 %");
    assert_eq!(v["words"], serde_json::json!([125]));
}

// sercos-telegrams.md, MDT: S-0-0036 is the cyclic command of the default MDT list; the
// master's next MDT overwrites a written value, and the tool says so.
#[test]
fn cyclic_command_is_overwritten_by_the_mdt() {
    let out = ok(&["write", "--drive", "2", "S-0-0036", "1500.0"]);
    assert_eq!(
        out,
        "S-0-0036 velocity command value := 1500.0000 rpm (the drive now reads 0.0000 rpm)\n"
    );
    // In phase 2 there is no MDT data: the value stays.
    let out = ok(&[
        "write", "--drive", "2", "--phase", "2", "S-0-0036", "1500.0",
    ]);
    assert_eq!(out, "S-0-0036 velocity command value := 1500.0000 rpm\n");
}

// sercos-facts.md, "Variable-length data": an IDN list with its lengths, in phase 2.
#[test]
fn write_an_idn_list() {
    let out = ok(&[
        "write",
        "--drive",
        "2",
        "--phase",
        "2",
        "S-0-0016",
        "[S-0-0011,S-0-0051]",
    ]);
    assert_eq!(
        out,
        "S-0-0016 configuration list of the AT := [S-0-0011, S-0-0051]\n"
    );
    let (_, line) = fails(&["write", "--drive", "2", "S-0-0016", "[S-0-0011]"]);
    assert!(line.contains("7005H"), "{line}");
}

#[test]
fn bad_values_name_the_idn_and_the_text() {
    let (code, line) = fails(&["write", "--drive", "2", "S-0-0080", "abc"]);
    assert_eq!(code, 1);
    assert!(
        line.contains("S-0-0080") && line.contains("\"abc\" is not a signed decimal number"),
        "{line}"
    );
    let (_, line) = fails(&["write", "--drive", "2", "S-0-0080", "1.25"]);
    assert!(line.contains("more than 1 decimal places"), "{line}");
    let (_, line) = fails(&["write", "--drive", "2", "S-0-0080", "100000"]);
    assert!(line.contains("does not fit"), "{line}");
    let (_, line) = fails(&[
        "write",
        "--drive",
        "2",
        "--phase",
        "2",
        "S-0-0016",
        "[S-0-0011,Q]",
    ]);
    assert!(line.contains("\"Q\" is not an IDN"), "{line}");
}
