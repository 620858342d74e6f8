//! Telegram formats (filled in by the telegram-formats work).
