//! Error locations shared by every section: the file and 1-based line of a
//! span of the scene text, the `table.key` a TOML error is about, and the
//! number checks whose errors point at the offending key.

use std::ops::Range;
use std::path::Path;

use toml::Spanned;

use crate::error::FlankError;

pub(super) type Res<T> = Result<T, FlankError>;

/// The scene text and the file it came from: turns byte spans into
/// [`FlankError::Parse`] errors at file:line.
pub(super) struct Cx<'a> {
    pub(super) text: &'a str,
    pub(super) file: &'a Path,
}

impl Cx<'_> {
    /// 1-based line of a byte offset.
    pub(super) fn line(&self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        1 + self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    }

    pub(super) fn err(&self, span: Range<usize>, message: String) -> FlankError {
        FlankError::Parse {
            file: self.file.to_path_buf(),
            line: self.line(span.start),
            message,
        }
    }

    pub(super) fn toml_error(&self, e: &toml::de::Error) -> FlankError {
        let line = e.span().map(|s| self.line(s.start)).unwrap_or(1);
        let mut message = e.message().trim().to_string();
        if let Some(start) = e.span().map(|s| s.start) {
            if message.starts_with("missing field") {
                if let Some(table) = self.table_at(start) {
                    message = format!("[{table}]: {message}");
                }
            } else if message.starts_with("invalid")
                || message.starts_with("unknown variant")
                || message.starts_with("duplicate key")
            {
                // name the key: `table.key`
                if let Some(key) = self.key_at(start) {
                    let full = match self.table_at(start) {
                        Some(t) => format!("{t}.{key}"),
                        None => key,
                    };
                    message = format!("`{full}`: {message}");
                }
            }
        }
        if message.is_empty() {
            message = "invalid TOML".to_string();
        }
        FlankError::Parse {
            file: self.file.to_path_buf(),
            line,
            message,
        }
    }

    /// The key of a `key = value` line that contains a byte offset, if any.
    pub(super) fn key_at(&self, offset: usize) -> Option<String> {
        let end = offset.min(self.text.len());
        let start = self.text.get(..end)?.rfind('\n').map_or(0, |i| i + 1);
        let line = self.text.get(start..)?.lines().next()?;
        let (key, _) = line.split_once('=')?;
        let key = key.trim();
        let simple = !key.is_empty()
            && key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.');
        simple.then(|| key.to_string())
    }

    /// Name of the `[table]` header at or before a byte offset, if any.
    pub(super) fn table_at(&self, offset: usize) -> Option<String> {
        let end = offset.min(self.text.len());
        // the header line that contains the offset, or the last one before it
        let line_end = self
            .text
            .get(end..)
            .and_then(|t| t.find('\n'))
            .map_or(self.text.len(), |i| end + i);
        let upto = self.text.get(..line_end)?;
        upto.lines().rev().find_map(|l| {
            let t = l.trim();
            let name = t.strip_prefix('[')?.split_once(']')?.0.trim();
            let plain = !t.starts_with("[[")
                && !name.is_empty()
                && name.chars().all(|c| {
                    c.is_alphanumeric() || matches!(c, '_' | '-' | '.' | '"' | '\'' | ' ')
                });
            plain.then(|| name.to_string())
        })
    }

    /// A finite value.
    pub(super) fn finite(&self, v: &Spanned<f64>, key: &str) -> Res<f64> {
        let x = *v.get_ref();
        if !x.is_finite() {
            return Err(self.err(v.span(), format!("`{key}` = {x}: must be a finite number")));
        }
        Ok(x)
    }

    /// A finite value > 0.
    pub(super) fn positive(&self, v: &Spanned<f64>, key: &str) -> Res<f64> {
        let x = self.finite(v, key)?;
        if !(x > 0.0) {
            return Err(self.err(v.span(), format!("`{key}` = {x}: must be positive")));
        }
        Ok(x)
    }

    /// A finite value ≥ 0.
    pub(super) fn non_negative(&self, v: &Spanned<f64>, key: &str) -> Res<f64> {
        let x = self.finite(v, key)?;
        if !(x >= 0.0) {
            return Err(self.err(v.span(), format!("`{key}` = {x}: must not be negative")));
        }
        Ok(x)
    }
}

pub(super) fn toml_message(e: &toml::de::Error) -> String {
    e.message().trim().to_string()
}

#[cfg(test)]
mod tests {
    use crate::error::FlankError;
    use crate::scene::test_support::*;

    #[test]
    fn wrong_type_names_key() {
        let t = edit(SPUR, "teeth = 13", "teeth = 13.0");
        expect_err(
            &t,
            line_of(&t, "teeth = 13.0"),
            &["`pinion.teeth`", "invalid type"],
        );
        let t = edit(SPUR, "kind = \"spur\"", "kind = \"bevel\"");
        expect_err(
            &t,
            line_of(&t, "bevel"),
            &["`pair.kind`", "bevel", "helical"],
        );
    }

    #[test]
    fn malformed_toml_reports_line() {
        let t = edit(
            SPUR,
            "face_width_mm = 13.3\nprofile_shift = 0.3",
            "face_width_mm = 13.3\nprofile_shift = = 0.3",
        );
        let err = parse(&t).unwrap_err();
        match err {
            FlankError::Parse { line, .. } => assert_eq!(line, line_of(&t, "= = 0.3")),
            e => panic!("{e}"),
        }
        let t = edit(SPUR, "[load]", "[load");
        match parse(&t).unwrap_err() {
            FlankError::Parse { line, .. } => assert_eq!(line, line_of(&t, "[load")),
            e => panic!("{e}"),
        }
    }
}
