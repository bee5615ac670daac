//! Reading a text input file (scene, measured profile, measurement grid,
//! blank inputs) as UTF-8, with an error that says where the text stops
//! being UTF-8 and what to do, instead of the bare "stream did not contain
//! valid UTF-8" of `std::fs::read_to_string`.

use std::path::Path;

use crate::error::{FlankError, Result};

/// The file's text; not UTF-8 is a [`FlankError::Parse`] at the line of the
/// first bad byte (UTF-16 files, recognised by their byte-order mark, at
/// line 1).
pub fn read_utf8(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| FlankError::io(path, e))?;
    utf8(bytes, path)
}

/// [`read_utf8`] on bytes already read; `path` names them in the error.
pub fn utf8(bytes: Vec<u8>, path: &Path) -> Result<String> {
    let err = |line: usize, message: String| FlankError::Parse {
        file: path.to_path_buf(),
        line,
        message,
    };
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        return Err(err(
            1,
            "the file is UTF-16 text (byte-order mark); save it as UTF-8".into(),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
        let column = 1 + good.iter().rev().take_while(|&&b| b != b'\n').count();
        let byte = e.as_bytes()[good.len()];
        err(
            line,
            format!(
                "not UTF-8 text (byte 0x{byte:02X} at column {column}): a binary file, or another encoding (Latin-1?); save it as UTF-8"
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_bytes_are_located() {
        let p = Path::new("s.toml");
        let e = utf8(b"a = 1\nb = \"Ma\xDFe\"\n".to_vec(), p).unwrap_err();
        assert_eq!(
            e.to_string(),
            "s.toml:2: not UTF-8 text (byte 0xDF at column 8): a binary file, or another encoding (Latin-1?); save it as UTF-8"
        );
        let e = utf8(vec![0xFF, 0xFE, b'a', 0], p).unwrap_err();
        assert!(
            e.to_string().starts_with("s.toml:1: the file is UTF-16"),
            "{e}"
        );
        assert_eq!(utf8("ä\n".as_bytes().to_vec(), p).unwrap(), "ä\n");
    }
}
