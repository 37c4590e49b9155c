//! The white-space separated tokens of a `.msh` file, with their line numbers for errors.

use crate::error::GmshError;
use crate::names::shown;

/// A cursor over the white-space separated tokens of the file, tracking line numbers.
pub(super) struct Tokens<'a> {
    lines: Vec<&'a str>,
    /// 0-based index of the current line.
    line: usize,
    /// Byte offset in the current line.
    pos: usize,
    /// Name of the section being read, for end-of-file messages.
    pub(super) section: &'static str,
    /// Length of the text, bytes.
    bytes: usize,
}

impl<'a> Tokens<'a> {
    /// A cursor at the start of `text`.
    pub(super) fn new(text: &'a str) -> Self {
        Tokens {
            lines: text.lines().collect(),
            line: 0,
            pos: 0,
            section: "",
            bytes: text.len(),
        }
    }

    /// The most items of `min_bytes` bytes each (separators included) the file can hold: a
    /// bound on a count the file announces, before memory is reserved for it.
    pub(super) fn room_for(&self, count: usize, min_bytes: usize) -> usize {
        count.min(self.bytes / min_bytes.max(1))
    }

    /// Number of lines of the file.
    pub(super) fn num_lines(&self) -> usize {
        self.lines.len()
    }

    /// A parse error at 1-based line `line`.
    pub(super) fn error(&self, line: usize, message: impl Into<String>) -> GmshError {
        GmshError::Parse {
            line,
            message: message.into(),
        }
    }

    /// The next token and its 1-based line, or `None` at the end of the file.
    pub(super) fn next_opt(&mut self) -> Option<(usize, &'a str)> {
        while let Some(&text) = self.lines.get(self.line) {
            let rest = text.get(self.pos..).unwrap_or("");
            // ASCII text (all of a usual file) byte by byte; a line with other characters from
            // here on by characters, where Unicode white space separates too.
            if let Some((start, len)) = ascii_token(rest.as_bytes()) {
                if len == 0 {
                    self.line += 1;
                    self.pos = 0;
                    continue;
                }
                let start = self.pos + start;
                self.pos = start + len;
                return Some((self.line + 1, &text[start..start + len]));
            }
            let trimmed = rest.trim_start();
            if trimmed.is_empty() {
                self.line += 1;
                self.pos = 0;
                continue;
            }
            let start = self.pos + (rest.len() - trimmed.len());
            let len = trimmed.find(char::is_whitespace).unwrap_or(trimmed.len());
            self.pos = start + len;
            return Some((self.line + 1, &trimmed[..len]));
        }
        None
    }

    /// The next token; the end of the file is an error.
    pub(super) fn next(&mut self) -> Result<(usize, &'a str), GmshError> {
        match self.next_opt() {
            Some(t) => Ok(t),
            None => {
                let message = if self.section.is_empty() {
                    "unexpected end of file".to_string()
                } else {
                    format!(
                        "unexpected end of file in section ${0} (missing $End{0}?)",
                        self.section
                    )
                };
                Err(self.error(self.lines.len() + 1, message))
            }
        }
    }

    /// The rest of the current line (trimmed), moving to the next line.
    pub(super) fn rest_of_line(&mut self) -> &'a str {
        let rest = match self.lines.get(self.line) {
            Some(text) => text.get(self.pos..).unwrap_or(""),
            None => "",
        };
        self.line += 1;
        self.pos = 0;
        rest.trim()
    }

    /// Parses the next token as `T`, naming `what` in the error message.
    pub(super) fn parse<T: std::str::FromStr>(&mut self, what: &str) -> Result<T, GmshError> {
        Ok(self.parse_at(what)?.1)
    }

    /// Parses the next token as `T`, and returns it with its 1-based line number.
    pub(super) fn parse_at<T: std::str::FromStr>(
        &mut self,
        what: &str,
    ) -> Result<(usize, T), GmshError> {
        let (line, token) = self.next()?;
        match token.parse() {
            Ok(value) => Ok((line, value)),
            Err(_) => Err(self.error(line, format!("expected {what}, found '{}'", shown(token)))),
        }
    }

    /// Parses the next token as a count or tag (a non-negative integer).
    pub(super) fn usize(&mut self, what: &str) -> Result<usize, GmshError> {
        self.parse(what)
    }

    /// Parses the next token as a finite coordinate.
    pub(super) fn coordinate(&mut self) -> Result<f64, GmshError> {
        Ok(self.coordinate_at()?.1)
    }

    /// Parses the next token as a finite coordinate, and returns it with its 1-based line number.
    pub(super) fn coordinate_at(&mut self) -> Result<(usize, f64), GmshError> {
        let (line, token) = self.next()?;
        match token.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok((line, x)),
            Ok(_) => Err(self.error(line, format!("non-finite coordinate '{}'", shown(token)))),
            Err(_) => Err(self.error(
                line,
                format!("expected a coordinate, found '{}'", shown(token)),
            )),
        }
    }

    /// Expects the token `$End<section>`.
    pub(super) fn expect_end(&mut self) -> Result<(), GmshError> {
        let section = self.section;
        let (line, token) = self.next()?;
        if token.strip_prefix("$End") == Some(section) {
            self.section = "";
            Ok(())
        } else {
            Err(self.error(
                line,
                format!("expected $End{section}, found '{}'", shown(token)),
            ))
        }
    }
}

/// The white space of ASCII, as [`char::is_whitespace`] sees it (with the vertical tab, which
/// [`u8::is_ascii_whitespace`] leaves out).
fn is_space(b: u8) -> bool {
    matches!(b, b'\t' | b'\n' | b'\x0b' | b'\x0c' | b'\r' | b' ')
}

/// The start and length of the first token of `bytes` (length 0: none), when the bytes up to
/// the end of that token are ASCII; `None` if a non-ASCII byte comes first.
fn ascii_token(bytes: &[u8]) -> Option<(usize, usize)> {
    let start = bytes
        .iter()
        .position(|&b| !is_space(b))
        .unwrap_or(bytes.len());
    let len = bytes[start..]
        .iter()
        .position(|&b| is_space(b) || !b.is_ascii())
        .unwrap_or(bytes.len() - start);
    let ascii = |b: Option<&u8>| b.map_or(true, u8::is_ascii);
    (ascii(bytes.get(start)) && ascii(bytes.get(start + len))).then_some((start, len))
}

/// Reads an entity dimension (0 to 3).
pub(super) fn read_dim(tokens: &mut Tokens<'_>) -> Result<u8, GmshError> {
    let (line, token) = tokens.next()?;
    match token.parse::<u8>() {
        Ok(dim) if dim <= 3 => Ok(dim),
        _ => Err(tokens.error(
            line,
            format!("expected a dimension (0 to 3), found '{}'", shown(token)),
        )),
    }
}

/// Skips an unknown section up to its `$End` line.
pub(super) fn skip_section(
    tokens: &mut Tokens<'_>,
    start: usize,
    name: &str,
) -> Result<(), GmshError> {
    let end = format!("$End{name}");
    // Skip whole lines: unknown sections may hold quoted strings.
    loop {
        if tokens.line >= tokens.lines.len() {
            return Err(tokens.error(
                start,
                format!("section ${} is not closed by {}", shown(name), shown(&end)),
            ));
        }
        if tokens.rest_of_line() == end {
            return Ok(());
        }
    }
}
