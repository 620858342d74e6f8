//! Fuzz target: the files a user hands `sercon` (docs/fuzzing.md). The first byte picks the
//! kind, the rest is the file: a ring description (`sercon ring --config`, parsed, then the
//! master's configuration and cycle plan built from it as `sercon ring` does before it runs),
//! a drive's IDN file, or a line capture (`sercon capture transcript --force`: decoded, its
//! telegrams fed to the service transcript). Any panic is a finding; so is a refusal that
//! does not name the file's line and column.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use sercon_cli::full_stack::plan_ring;
use sercon_cli::ring::{master_config, parse_config};
use sercos_wire::line::{self, CaptureFile, Coding, LineConfig, OwnedDecoded, Polarity};
use sercos_wire::service_transcript::TranscriptBuilder;

fuzz_target!(|data: &[u8]| {
    let Some((&kind, file)) = data.split_first() else {
        return;
    };
    match kind % 3 {
        0 => {
            let text = String::from_utf8_lossy(file);
            // A path with no folder: IDN files named in the text are looked for in the
            // working directory (almost never there); the plan reads none.
            match parse_config(&text, Path::new("ring.toml")) {
                // A refusal names the line and column (from 1) where the text is wrong.
                Err(e) => assert!(e.line >= 1 && e.column >= 1, "{e}"),
                Ok(spec) => {
                    let _ = master_config(&spec);
                    if spec.drives.iter().all(|d| d.idn_file.is_none()) {
                        let _ = plan_ring(&spec);
                    }
                }
            }
        }
        1 => {
            let text = String::from_utf8_lossy(file);
            if let Err(e) = sercos_drive::config_file::parse(&text, Path::new("drive.toml")) {
                assert!(e.line >= 1 && e.column >= 1, "{e}");
            }
        }
        _ => {
            let Ok(capture) = CaptureFile::parse(file) else {
                return;
            };
            for coding in [Coding::Nrzi, Coding::Nrz] {
                let frames =
                    line::decode_all(capture.bits, LineConfig::new(coding, Polarity::LightOnLow));
                let mut builder = TranscriptBuilder::new();
                for (i, f) in frames.iter().enumerate() {
                    if let OwnedDecoded::Telegram { bytes, .. } = f {
                        builder.master_telegram(bytes, i as u64);
                    }
                }
                for e in builder.finish() {
                    assert!((e.first_telegram as usize) < frames.len());
                }
            }
        }
    }
});
