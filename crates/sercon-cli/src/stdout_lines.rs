//! Output on stdout that ends quietly when the reader goes away (`sercon bench | head -1`,
//! `sercon idn list | head`): `println!` panics on a closed pipe.

use std::io::Write;

/// Writes `text` to stdout and flushes it; `false` when stdout is closed or failed (the reader
/// went away: nothing to report, the caller stops printing).
pub fn write(text: &str) -> bool {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .is_ok()
}

/// [`write`](fn@write) of `line` and a newline.
pub fn line(line: &str) -> bool {
    write(&format!("{line}\n"))
}

/// Prints a formatted line on stdout ([`line`](fn@line)); evaluates to whether it was written.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::stdout_lines::line(&format!($($arg)*))
    };
}
pub(crate) use say;
