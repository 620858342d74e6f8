//! The ring options of `sercon idn`: --variant, --baud, --cycle-us, --drives, --config,
//! --phase.

mod idn_support;

use idn_support::{fails, ok};

// 410B §4.1 1H: the SERCON410B runs at 2 or 4 Mbit/s; P-0-0002 is the drive's bit rate.
#[test]
fn variant_and_baud_reach_the_drive() {
    let out = ok(&[
        "read",
        "--drive",
        "1",
        "--variant",
        "410b",
        "--baud",
        "4",
        "P-0-0002",
    ]);
    assert_eq!(out, "P-0-0002 bit rate = 4 Mbit/s\n");
    let (code, line) = fails(&[
        "read",
        "--drive",
        "1",
        "--variant",
        "410b",
        "--baud",
        "16",
        "P-0-0002",
    ]);
    assert_eq!(code, 1);
    assert!(line.contains("SERCON410B runs at 2 or 4 Mbit/s"), "{line}");
    let (code, line) = fails(&["read", "--drive", "1", "--baud", "3", "P-0-0002"]);
    assert_eq!(code, 2);
    assert!(
        line.contains("--baud") && line.contains("not 2, 4, 8 or 16"),
        "{line}"
    );
}

// sercos-telegrams.md: the phase in the MST; --phase brings the ring there first.
#[test]
fn phase_option() {
    let v: serde_json::Value = serde_json::from_str(&ok(&[
        "read", "--drive", "1", "--phase", "2", "S-0-0002", "--json",
    ]))
    .expect("JSON");
    assert_eq!(v["phase"], 2);
    let (code, line) = fails(&["read", "--drive", "1", "--phase", "3", "S-0-0002"]);
    assert_eq!(code, 2);
    assert!(
        line.contains("--phase") && line.contains("not 2 or 4"),
        "{line}"
    );
}

#[test]
fn config_file_gives_the_ring() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("ring.toml");
    std::fs::write(
        &path,
        "baud = 8\ncycle_us = 500\n[[drive]]\naddress = 5\n[[drive]]\naddress = 7\n",
    )
    .expect("write");
    let config = path.to_str().expect("utf-8 path");
    let out = ok(&["read", "--config", config, "--drive", "7", "S-0-0002"]);
    assert_eq!(out, "S-0-0002 communication cycle time tScyc = 500 µs\n");
    // The options override the file.
    let out = ok(&[
        "read",
        "--config",
        config,
        "--drive",
        "5",
        "--cycle-us",
        "1000",
        "S-0-0002",
    ]);
    assert_eq!(out, "S-0-0002 communication cycle time tScyc = 1000 µs\n");
    let (_, line) = fails(&["read", "--config", config, "--drive", "1", "S-0-0002"]);
    assert!(line.contains("(drives 5, 7)"), "{line}");
    std::fs::write(&path, "baud = \"fast\"\n").expect("write");
    let (code, line) = fails(&["read", "--config", config, "--drive", "1", "S-0-0002"]);
    assert_eq!(code, 1);
    assert!(line.contains("ring.toml"), "{line}");
    let (_, line) = fails(&[
        "read",
        "--config",
        "/nonexistent/ring.toml",
        "--drive",
        "1",
        "S-0-0002",
    ]);
    assert!(line.contains("/nonexistent/ring.toml"), "{line}");
}

// The drive's own IDN file: values, names and units come from the drive (elements 2-4),
// not from the catalogue, which knows neither P-0-0100 nor P-0-0101.
#[test]
fn a_drives_own_idns_are_decoded_by_its_attribute() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("ring.toml");
    let axis = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../sercos-drive/data/tc2000r-axis.toml"
    );
    std::fs::write(
        &path,
        format!("[[drive]]\naddress = 1\nidn_file = {axis:?}\n[[drive]]\naddress = 2\n"),
    )
    .expect("write");
    let config = path.to_str().expect("utf-8 path");
    let out = ok(&["read", "--config", config, "--drive", "1", "P-0-0100"]);
    assert_eq!(out, "P-0-0100 motor temperature = 25 °C\n");
    let out = ok(&["read", "--config", config, "--drive", "1", "P-0-0101"]);
    assert_eq!(out, "P-0-0101 firmware version = sercon-drive 0.1\n");
    let out = ok(&["info", "--config", config, "--drive", "1", "P-0-0100"]);
    assert!(out.contains("maximum            200 °C"), "{out}");
    let (_, line) = fails(&[
        "write", "--config", config, "--drive", "1", "P-0-0100", "30",
    ]);
    assert!(line.contains("7004H"), "{line}");
    // Drive 2 has the standard catalogue only.
    let (_, line) = fails(&["read", "--config", config, "--drive", "2", "P-0-0100"]);
    assert!(line.contains("1001H IDN not present"), "{line}");
}
