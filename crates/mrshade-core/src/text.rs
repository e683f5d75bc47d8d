//! Text from files, made safe to print.
//!
//! Names in a glTF, lines of a TOML file and paths come from anywhere. Printed raw, a carriage
//! return or an escape sequence rewrites the user's terminal, and a newline breaks the
//! promise of one line per error. Everything mrshade prints goes through [`printable`].

use std::borrow::Cow;

/// `s` with every control character (C0, DEL, C1) and every bidirectional override shown as a
/// Rust-style escape (`\r`, `\u{1b}`, `\u{202e}`); other text, accents included, unchanged.
pub fn printable(s: &str) -> Cow<'_, str> {
    if !s.chars().any(needs_escape) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if needs_escape(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// A number for a message: plain when it reads well (`0.96`, `1500`), in exponent form when
/// it would print dozens of digits (`3e38`, `1e-12`).
pub fn number(v: f32) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e6).contains(&v.abs()) { format!("{v:e}") } else { format!("{v}") }
}

/// What a panic said, and where: for reporting it as one line instead of a backtrace.
pub fn panic_message(info: &std::panic::PanicHookInfo) -> String {
    let payload = info.payload();
    let text = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_default();
    let at = info.location().map(|l| format!(" at {}:{}", l.file(), l.line())).unwrap_or_default();
    format!("{text}{at}")
}

fn needs_escape(c: char) -> bool {
    c.is_control() || matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped_and_the_rest_kept() {
        assert_eq!(printable("desk"), "desk");
        assert_eq!(printable("Schreibtisch über"), "Schreibtisch über");
        assert_eq!(printable("a\r\u{1b}[31mb\nc\td"), "a\\r\\u{1b}[31mb\\nc\\td");
        assert_eq!(printable("x\u{202e}y\u{9b}"), "x\\u{202e}y\\u{9b}");
        assert!(!printable("\u{7f}").contains('\u{7f}'));
    }

    #[test]
    fn numbers_read_well() {
        assert_eq!(number(0.96), "0.96");
        assert_eq!(number(3e38), "3e38");
        assert_eq!(number(-2.5e-7), "-2.5e-7");
        assert_eq!(number(0.0), "0");
    }
}
