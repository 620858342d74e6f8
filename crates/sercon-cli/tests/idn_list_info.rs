//! `sercon idn list` (S-0-0017 with names) and `sercon idn info`.

mod idn_support;

use idn_support::{fails, ok};

// sercos-facts.md: S-0-0017, the IDN list of all operation data.
#[test]
fn list_names_every_idn_of_s_0_0017() {
    let out = ok(&["list", "--drive", "2"]);
    let lines: Vec<&str> = out.lines().collect();
    // The emulated drive's standard database: the catalogue (sercos_wire::idn_catalog).
    assert_eq!(
        lines.len(),
        sercos_wire::idn_catalog::CATALOG.len(),
        "{out}"
    );
    assert!(
        lines.contains(&"S-0-0002 communication cycle time tScyc"),
        "{out}"
    );
    assert!(
        lines.contains(&"S-0-0017 IDN list of all operation data"),
        "{out}"
    );
    assert!(lines.contains(&"P-0-0019 torque feedback value"), "{out}");
    let v: serde_json::Value =
        serde_json::from_str(&ok(&["list", "--drive", "2", "--json"])).expect("JSON");
    assert_eq!(v["idns"].as_array().map(Vec::len), Some(lines.len()));
    assert_eq!(v["idns"][0]["idn"], "S-0-0001");
}

// sercos-facts.md, attribute: length, format, decimals, write protection per phase.
#[test]
fn info_decodes_the_attribute() {
    let out = ok(&["info", "--drive", "2", "S-0-0036"]);
    for part in [
        "S-0-0036 velocity command value\n",
        "length             4 bytes\n",
        "format             signed decimal\n",
        "decimal places     4\n",
        "write protection   phase 2 writable, phase 3 writable, phase 4 writable\n",
        "unit               rpm\n",
        "minimum            -214748.3648 rpm\n",
        "maximum            214748.3647 rpm\n",
        "value              0.0000 rpm\n",
    ] {
        assert!(out.contains(part), "{part:?} in {out}");
    }
    let out = ok(&["info", "--drive", "2", "S-0-0002"]);
    assert!(
        out.contains("write protection   phase 2 writable, phase 3 protected, phase 4 protected"),
        "{out}"
    );
}

// sercos-facts.md, "Service channel errors": 5001H/6001H, no minimum/maximum.
#[test]
fn info_without_limits_and_as_json() {
    let out = ok(&["info", "--drive", "1", "S-0-0016"]);
    assert!(out.contains("minimum            none (5001H"), "{out}");
    assert!(out.contains("maximum            none (6001H"), "{out}");
    assert!(
        out.contains("length             variable, 2-byte elements"),
        "{out}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&ok(&["info", "--drive", "1", "S-0-0127", "--json"])).expect("JSON");
    assert_eq!(v["procedure_command"], true);
    assert_eq!(v["idn"], "S-0-0127");
    let (code, line) = fails(&["info", "--drive", "1", "P-0-0999"]);
    assert_eq!(code, 1);
    assert!(line.contains("1001H"), "{line}");
}
