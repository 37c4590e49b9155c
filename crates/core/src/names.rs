//! User-given names (bodies, boundaries, node sets, materials, contact pairs, load groups, steps,
//! Gmsh physical names) in messages and their limits.
//!
//! A name is echoed by [`shown`]: control and invisible formatting characters escaped, and cut
//! after [`SHOWN_CHARS`] characters, so that no message carries raw terminal escapes or a
//! megabyte of name. [`listed`] shows a list of names the same way, at most [`LISTED_NAMES`] of
//! them. [`name_problem`] is the rule a name must meet to be accepted at all: at most
//! [`MAX_NAME_BYTES`] bytes, and no such characters.

/// The most characters of a name a message shows; a longer name is cut and its length given.
pub const SHOWN_CHARS: usize = 64;

/// The most names a list in a message shows; the rest are counted.
pub const LISTED_NAMES: usize = 20;

/// The longest name accepted, in bytes of UTF-8.
pub const MAX_NAME_BYTES: usize = 256;

/// Whether `c` is escaped when shown and refused in a name: a control character (C0, DEL, C1)
/// or an invisible formatting one (zero-width characters, bidirectional overrides and isolates,
/// the byte-order mark), which would change or hide what a terminal prints.
pub fn is_hidden(c: char) -> bool {
    c.is_control()
        || matches!(c,
            '\u{200B}'..='\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2060}'..='\u{2069}'
            | '\u{FEFF}')
}

/// `name` as a message shows it: every [`is_hidden`] character escaped as Rust writes it (`\t`,
/// `\n`, `\u{1b}`), and a name of more than [`SHOWN_CHARS`] characters cut there and followed by
/// `…(N bytes)`, N its whole length.
pub fn shown(name: &str) -> String {
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if i == SHOWN_CHARS {
            out += &format!("…({} bytes)", name.len());
            break;
        }
        if is_hidden(c) {
            out.extend(c.escape_debug());
            if c.escape_debug().len() == 1 {
                out.extend(c.escape_unicode());
            }
        } else {
            out.push(c);
        }
    }
    out
}

/// The names `names`, each [`shown`], at most [`LISTED_NAMES`] of them; a longer list ends in
/// `… (N more)`.
pub fn listed<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let mut out = Vec::new();
    let mut more = 0usize;
    for name in names {
        if out.len() < LISTED_NAMES {
            out.push(shown(name));
        } else {
            more += 1;
        }
    }
    if more > 0 {
        out.push(format!("… ({more} more)"));
    }
    out
}

/// Why `name` is not accepted as a name, or `None` if it is: longer than [`MAX_NAME_BYTES`]
/// bytes, or holding an [`is_hidden`] character.
pub fn name_problem(name: &str) -> Option<String> {
    if name.len() > MAX_NAME_BYTES {
        return Some(format!(
            "the name '{}' is {} bytes long; a name has at most {MAX_NAME_BYTES}",
            shown(name),
            name.len()
        ));
    }
    name.chars().find(|&c| is_hidden(c)).map(|c| {
        format!(
            "the name '{}' holds the control or formatting character {}; a name is printable text",
            shown(name),
            c.escape_unicode()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hidden_characters_are_escaped() {
        assert_eq!(shown("lower"), "lower");
        assert_eq!(shown("é ü"), "é ü");
        assert_eq!(shown("a\u{1b}[31mb\u{7}"), "a\\u{1b}[31mb\\u{7}");
        assert_eq!(shown("a\tb\n"), "a\\tb\\n");
        assert_eq!(shown("x\u{202E}y"), "x\\u{202e}y");
        assert_eq!(shown("\u{feff}"), "\\u{feff}");
    }

    #[test]
    fn long_names_are_cut_with_their_length() {
        let long = "é".repeat(1_000_000);
        let s = shown(&long);
        assert_eq!(s, format!("{}…(2000000 bytes)", "é".repeat(SHOWN_CHARS)));
        assert_eq!(shown(&"a".repeat(SHOWN_CHARS)), "a".repeat(SHOWN_CHARS));
    }

    #[test]
    fn lists_are_capped() {
        let names: Vec<String> = (0..25).map(|i| format!("n{i}")).collect();
        let l = listed(names.iter().map(String::as_str));
        assert_eq!(l.len(), LISTED_NAMES + 1);
        assert_eq!(l.last().map(String::as_str), Some("… (5 more)"));
        assert_eq!(listed(["a\u{7}"]), vec!["a\\u{7}".to_string()]);
    }

    #[test]
    fn the_rule() {
        assert_eq!(name_problem("lower-top"), None);
        assert_eq!(name_problem(&"a".repeat(MAX_NAME_BYTES)), None);
        let long = name_problem(&"a".repeat(MAX_NAME_BYTES + 1)).unwrap();
        assert!(long.contains("257 bytes long"), "{long}");
        let bell = name_problem("ding\u{7}").unwrap();
        assert!(
            bell.contains("'ding\\u{7}'") && !bell.contains('\u{7}'),
            "{bell}"
        );
    }
}
