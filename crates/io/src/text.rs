//! Small helpers shared by the text formats: whole-input reading, a line
//! iterator over bytes with 1-based line numbers, number parsing.

use std::io::Read;

/// Reads the whole input. Every reader works on the complete byte slice,
/// which makes it fast and lets counts from headers be checked against the
/// real length before anything is allocated.
pub(crate) fn read_all<R: Read>(mut reader: R) -> std::io::Result<Vec<u8>> {
    let mut data = Vec::new();
    reader.read_to_end(&mut data)?;
    Ok(data)
}

/// Lines of a byte slice (`\n`, `\r\n` or lone `\r` endings), numbered from 1.
#[derive(Debug)]
pub(crate) struct Lines<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(data: &'a [u8]) -> Self {
        Lines {
            data,
            pos: 0,
            line: 0,
        }
    }
}

impl Lines<'_> {
    /// Byte offset of the start of the next line.
    pub(crate) fn offset(&self) -> usize {
        self.pos
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);
    fn next(&mut self) -> Option<Self::Item> {
        if self.pos >= self.data.len() {
            return None;
        }
        let rest = &self.data[self.pos..];
        let end = rest
            .iter()
            .position(|&b| b == b'\n' || b == b'\r')
            .unwrap_or(rest.len());
        let line = &rest[..end];
        let mut skip = end;
        if skip < rest.len() {
            skip += if rest[skip] == b'\r' && rest.get(skip + 1) == Some(&b'\n') {
                2
            } else {
                1
            };
        }
        self.pos += skip;
        self.line += 1;
        Some((self.line, line))
    }
}

/// Whether the input holds nothing but whitespace.
pub(crate) fn is_blank(data: &[u8]) -> bool {
    data.iter().all(|b| b.is_ascii_whitespace())
}

/// Parses a real number (accepts what Rust accepts, including `nan` and
/// `inf`, which the core's validation then rejects with the vertex index).
#[inline]
pub(crate) fn parse_real(token: &str) -> Option<f64> {
    token.parse::<f64>().ok()
}

/// Shortens a token for an error message.
pub(crate) fn excerpt(token: &str) -> String {
    const MAX: usize = 40;
    if token.chars().count() <= MAX {
        token.to_string()
    } else {
        let mut s: String = token.chars().take(MAX).collect();
        s.push('…');
        s
    }
}
