//! Line coding (filled in by the line-coding work).
