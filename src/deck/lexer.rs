//! Lines and tokens of a deck.
//!
//! The line loop ([`Parser::run`]): blank lines and `**` comments are
//! skipped, a line starting with `*` is a keyword line (upper-cased, blanks
//! normalized; a trailing comma continues it on the next line when that line
//! holds parameters, as in Abaqus), anything else is a data line of the
//! current keyword. `*INCLUDE, INPUT=file` is followed here, transparently
//! (paths relative to the including file, at most 16 deep). Keyword
//! parameters (`KEY=value`, flags), labels, DOF numbers, reals (Fortran `D`
//! exponents) and set names are read here too; every error and warning
//! carries the file and 1-based line it is about ([`Loc`]).

use std::path::Path;

use super::parser::Parser;
use super::records::{Card, DeckWarning, Loc, Target};
use crate::error::{FlankError, Result};

pub(super) fn read_text(path: &Path) -> std::io::Result<String> {
    let bytes = std::fs::read(path)?;
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "the file is UTF-16 text (byte-order mark); save it as UTF-8",
        ));
    }
    Ok(match String::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => String::from_utf8_lossy(e.as_bytes()).into_owned(),
    })
}

/// Nesting limit for `*INCLUDE` (also stops include cycles).
const MAX_INCLUDE_DEPTH: usize = 16;

/// Upper-case name without surrounding blanks or quotes.
pub(super) fn norm_name(raw: &str) -> String {
    raw.trim().trim_matches('"').trim().to_ascii_uppercase()
}

/// Keyword names compare upper-case with single blanks ("END  STEP" = "END STEP").
pub(super) fn norm_keyword(raw: &str) -> String {
    raw.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_ascii_uppercase()
}

/// Whether a token is meant as a number (labels and set names are told apart
/// by their first character; set names start with a letter).
pub(super) fn looks_numeric(tok: &str) -> bool {
    tok.starts_with(|c: char| c.is_ascii_digit() || matches!(c, '+' | '-' | '.'))
}

/// Parameters that may stand without `=value` on a continuation line.
const FLAG_PARAMETERS: &[&str] = &["GENERATE", "UNSORTED", "NLGEOM", "PERTURBATION"];

/// Whether a line continues a keyword line: its first field is `KEY=VALUE`
/// or a flag parameter (data lines are numbers or set names).
fn looks_like_parameters(line: &str) -> bool {
    let first = line.split(',').next().unwrap_or("").trim();
    !line.starts_with('*')
        && (first.contains('=') || FLAG_PARAMETERS.contains(&norm_keyword(first).as_str()))
}

/// Comma-separated fields, trimmed, without trailing empty fields.
pub(super) fn split_fields(text: &str) -> Vec<&str> {
    let mut f: Vec<&str> = text.split(',').map(str::trim).collect();
    while f.last().is_some_and(|s| s.is_empty()) {
        f.pop();
    }
    f
}

impl Parser {
    pub(super) fn err(&self, loc: Loc, message: impl Into<String>) -> FlankError {
        FlankError::Parse {
            file: self.files[loc.file].clone(),
            line: loc.line,
            message: message.into(),
        }
    }

    pub(super) fn warn(&mut self, loc: Loc, message: impl Into<String>) {
        let mut message = message.into();
        if loc.file != 0 {
            message = format!("{message} (in {})", self.files[loc.file].display());
        }
        self.warnings.push(DeckWarning {
            line: loc.line,
            message,
        });
    }

    /// Reads the lines of one file. `*INCLUDE` is handled here, transparently:
    /// the included lines continue the current keyword block (Abaqus allows
    /// data-only include files).
    pub(super) fn run(&mut self, text: &str, file: usize, depth: usize) -> Result<()> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text.lines().enumerate().peekable();
        while let Some((i, raw)) = lines.next() {
            let loc = Loc { file, line: i + 1 };
            let t = raw.trim();
            if t.is_empty() || t.starts_with("**") {
                continue;
            }
            let Some(kw) = t.strip_prefix('*') else {
                self.data(t, loc)?;
                continue;
            };
            // A keyword line ending with a comma continues on the next line
            // if that line holds parameters (Abaqus); otherwise the comma is
            // a harmless trailing one and the next line is data (ccx).
            let mut kw = kw.to_string();
            while kw.trim_end().ends_with(',') {
                let Some(&(_, next)) = lines.peek() else {
                    break;
                };
                let n = next.trim();
                if n.starts_with("**") {
                    lines.next();
                    continue;
                }
                if !looks_like_parameters(n) {
                    break;
                }
                kw.push_str(n);
                lines.next();
            }
            let card = self.parse_card(&kw, loc)?;
            if card.name == "INCLUDE" {
                self.include(&card, depth)?;
            } else {
                self.keyword(card)?;
            }
        }
        Ok(())
    }

    pub(super) fn parse_card(&self, kw: &str, loc: Loc) -> Result<Card> {
        let mut parts = kw.split(',');
        let name = norm_keyword(parts.next().unwrap_or(""));
        if name.is_empty() {
            return Err(self.err(loc, "empty keyword ('*' without a name)"));
        }
        let mut params = Vec::new();
        for p in parts {
            let p = p.trim();
            if p.is_empty() {
                continue;
            }
            let (key, value) = match p.split_once('=') {
                Some((k, v)) => (norm_keyword(k), Some(v.trim().to_string())),
                None => (norm_keyword(p), None),
            };
            if key.is_empty() {
                return Err(self.err(loc, format!("malformed parameter '{p}' on *{name}")));
            }
            params.push((key, value));
        }
        Ok(Card { name, params, loc })
    }

    /// Rejects parameters not in `allowed` (an unknown parameter might change
    /// the meaning of the data).
    pub(super) fn check_params(&self, card: &Card, allowed: &[&str]) -> Result<()> {
        for (k, _) in &card.params {
            if !allowed.contains(&k.as_str()) {
                return Err(self.err(
                    card.loc,
                    format!("parameter {k} on *{} is not supported", card.name),
                ));
            }
        }
        Ok(())
    }

    /// Value of parameter `key` (raw text); present without `=value` is an error.
    pub(super) fn value(&self, card: &Card, key: &str) -> Result<Option<String>> {
        match card.params.iter().find(|(k, _)| k == key) {
            None => Ok(None),
            Some((_, Some(v))) if !v.is_empty() => Ok(Some(v.clone())),
            Some(_) => Err(self.err(
                card.loc,
                format!(
                    "parameter {key} on *{} needs a value ({key}=...)",
                    card.name
                ),
            )),
        }
    }

    pub(super) fn required(&self, card: &Card, key: &str) -> Result<String> {
        self.value(card, key)?.ok_or_else(|| {
            self.err(
                card.loc,
                format!("*{} needs the parameter {key}=...", card.name),
            )
        })
    }

    pub(super) fn flag(card: &Card, key: &str) -> bool {
        card.params.iter().any(|(k, _)| k == key)
    }

    /// Id of a set name (upper-cased; node and element sets share ids but
    /// not namespaces).
    pub(super) fn intern(&mut self, raw: &str, loc: Loc) -> Result<u32> {
        let name = norm_name(raw);
        if name.is_empty() {
            return Err(self.err(loc, "empty set name"));
        }
        // a control character in a name is corruption (found by
        // tests/fuzz_parsers.rs: it was kept, and the writer renamed the set)
        if let Some(c) = name.chars().find(|c| c.is_control()) {
            return Err(self.err(
                loc,
                format!(
                    "name '{}' contains the control character U+{:04X}",
                    name.escape_debug(),
                    c as u32
                ),
            ));
        }
        if let Some(&id) = self.name_ids.get(&name) {
            return Ok(id);
        }
        let id = self.names.len() as u32;
        self.names.push(name.clone());
        self.name_ids.insert(name, id);
        Ok(id)
    }

    pub(super) fn include(&mut self, card: &Card, depth: usize) -> Result<()> {
        self.check_params(card, &["INPUT"])?;
        let input = self.required(card, "INPUT")?;
        let input = input.trim().trim_matches(|c| c == '"' || c == '\'').trim();
        if depth >= MAX_INCLUDE_DEPTH {
            return Err(self.err(
                card.loc,
                format!("*INCLUDE nested more than {MAX_INCLUDE_DEPTH} deep (include cycle?)"),
            ));
        }
        let rel = Path::new(input);
        let path = match self.files[card.loc.file].parent() {
            Some(dir) if rel.is_relative() => dir.join(rel),
            _ => rel.to_path_buf(),
        };
        let text = read_text(&path).map_err(|e| {
            self.err(
                card.loc,
                format!("cannot read *INCLUDE file '{}': {e}", path.display()),
            )
        })?;
        self.files.push(path);
        let id = self.files.len() - 1;
        self.run(&text, id, depth + 1)
    }

    /// Value of a parameter that ccx also accepts without blanks
    /// (`REF NODE=` or `REFNODE=`).
    pub(super) fn value_either(&self, card: &Card, keys: [&str; 2]) -> Result<Option<String>> {
        match self.value(card, keys[0])? {
            Some(v) => Ok(Some(v)),
            None => self.value(card, keys[1]),
        }
    }

    // -- tokens -------------------------------------------------------------

    /// A positive integer label.
    pub(super) fn parse_label(&self, tok: &str, loc: Loc) -> Result<u64> {
        match tok.trim().parse::<u64>() {
            Ok(0) => Err(self.err(loc, "label 0 is not allowed (labels start at 1)")),
            Ok(v) => Ok(v),
            Err(_) => Err(self.err(
                loc,
                format!("malformed number '{tok}' (expected a positive integer)"),
            )),
        }
    }

    /// A degree of freedom number (1-based).
    pub(super) fn parse_dof(&self, tok: &str, loc: Loc) -> Result<usize> {
        match tok.trim().parse::<usize>() {
            Ok(0) => Err(self.err(loc, "DOF 0 does not exist (DOFs start at 1)")),
            Ok(v) => Ok(v),
            Err(_) => Err(self.err(loc, format!("malformed DOF number '{tok}'"))),
        }
    }

    /// A finite real; Fortran `D` exponents are accepted, `inf`/`nan` are not.
    pub(super) fn parse_real(&self, tok: &str, loc: Loc) -> Result<f64> {
        let t = tok.trim();
        let plausible = !t.is_empty()
            && t.bytes().all(|b| {
                b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E' | b'd' | b'D')
            });
        if plausible {
            let parsed = if t.contains(['d', 'D']) {
                t.replace(['d', 'D'], "e").parse::<f64>()
            } else {
                t.parse::<f64>()
            };
            if let Ok(v) = parsed {
                if v.is_finite() {
                    return Ok(v);
                }
                return Err(self.err(loc, format!("number '{t}' is out of range")));
            }
        }
        Err(self.err(loc, format!("malformed number '{t}'")))
    }

    pub(super) fn parse_target(&mut self, tok: &str, loc: Loc) -> Result<Target> {
        if tok.is_empty() {
            return Err(self.err(loc, "missing label or set name"));
        }
        if looks_numeric(tok) {
            Ok(Target::Label(self.parse_label(tok, loc)?))
        } else {
            Ok(Target::Set(self.intern(tok, loc)?))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::read_deck;
    use crate::deck::test_decks::*;
    use crate::testing::Rng;

    #[test]
    fn trailing_comma_on_keyword_before_data() {
        // ccx ignores the comma; "bottom, 1, 3" stays a data line.
        let d = with(HEX, "*BOUNDARY\nbottom", "*BOUNDARY,\nbottom");
        let d = with(&d, "*nset,nset=TOP,generate", "*nset,nset=TOP,\n GENERATE");
        let m = parse(&d).unwrap().model;
        assert_eq!(m.dirichlet, parse(HEX).unwrap().model.dirichlet);
        assert_eq!(m.mesh.node_sets["TOP"].len(), 8);
    }

    /// A UTF-16 deck (byte-order mark) was read lossily into "data line
    /// before the first keyword"; now the read says what the file is.
    #[test]
    fn utf16_deck_is_named() {
        let dir = std::env::temp_dir().join(format!("flank-inp-utf16-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut bytes = vec![0xFF, 0xFE];
        bytes.extend("*NODE\n".encode_utf16().flat_map(|u| u.to_le_bytes()));
        std::fs::write(dir.join("d.inp"), bytes).unwrap();
        let e = read_deck(&dir.join("d.inp")).unwrap_err();
        assert!(
            format!("{e:#}").contains("d.inp")
                && std::error::Error::source(&e)
                    .unwrap()
                    .to_string()
                    .contains("UTF-16"),
            "{e:?}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn include_is_followed_relative_to_including_file() {
        let dir = std::env::temp_dir().join(format!("flank-inp-test-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let node_start = HEX.find("1, 0, 0, 0").unwrap();
        let node_end = HEX.find("*Element").unwrap();
        // Data-only include: the node lines continue the *NODE block.
        std::fs::write(dir.join("sub/nodes.inc"), &HEX[node_start..node_end]).unwrap();
        let main = format!(
            "{}*INCLUDE, INPUT=sub/nodes.inc\n{}",
            &HEX[..node_start],
            &HEX[node_end..]
        );
        std::fs::write(dir.join("main.inp"), &main).unwrap();
        let deck = read_deck(&dir.join("main.inp")).unwrap();
        assert_eq!(deck.model.mesh.node_count(), 20);
        assert_eq!(deck.model.mesh.node_sets["NALL"].len(), 20);

        // Errors inside an included file name that file and its line.
        let bad = HEX[node_start..node_end].replace("6, 1, 0, 1", "6, 1, x, 1");
        std::fs::write(dir.join("sub/nodes.inc"), &bad).unwrap();
        match read_deck(&dir.join("main.inp")) {
            Err(FlankError::Parse { file, line, .. }) => {
                assert!(file.ends_with("sub/nodes.inc"));
                assert_eq!(line, line_of(&bad, "6, 1, x"));
            }
            other => panic!("{other:?}"),
        }

        // A file including itself stops with an error, and a missing file too.
        std::fs::write(dir.join("loop.inp"), "*INCLUDE, INPUT=loop.inp\n").unwrap();
        assert!(matches!(
            read_deck(&dir.join("loop.inp")),
            Err(FlankError::Parse { line: 1, .. })
        ));
        std::fs::write(dir.join("missing.inp"), "**\n*INCLUDE, INPUT=nope.inp\n").unwrap();
        assert!(matches!(
            read_deck(&dir.join("missing.inp")),
            Err(FlankError::Parse { line: 2, .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn malformed_number() {
        let d = with(HEX, "2, 1., 0., 0.", "2, 1.0.0, 0., 0.");
        expect_err(&d, line_of(&d, "1.0.0"), "malformed number '1.0.0'");
        let d = with(HEX, "7, 1, 100.5", "7, 1, nan");
        expect_err(&d, line_of(&d, "7, 1, nan"), "nan");
        let d = with(HEX, "7, 1, 100.5", "7x, 1, 100.5");
        expect_err(&d, line_of(&d, "7x, 1"), "7x");
    }

    #[test]
    fn garbage_does_not_panic() {
        let bytes: Vec<u8> = (0..=255u8).cycle().take(4096).collect();
        let binary = String::from_utf8_lossy(&bytes).into_owned();
        let cases = [
            binary.as_str(),
            "\0\u{1}\u{2}\u{ff}\u{fe}\u{7f}",
            "*",
            "*,,,=",
            "*=,=",
            "1, 2, 3",
            "*NODE\n1,2,3,4,5,6,7\n*ELEMENT,TYPE=\n",
            "*ELEMENT, TYPE=C3D20\n1,\n",
            "*ELEMENT, TYPE=C3D20\n1,2,3\n*NODE\n1\n",
            "*NSET,NSET=A,GENERATE\n1\n",
            "*NSET,NSET=A,GENERATE\n5, 1\n",
            "*NSET,NSET=A\nA\n",
            "*NODE\n-1, 0, 0, 0",
            "*NODE\n18446744073709551616, 0",
            "*NODE\n1, 1e999",
            "*STEP\n*STEP",
            "*STEP\n*STATIC\n*DLOAD\n1, P99999999999999999999999, 1\n",
            "*BOUNDARY\n1, 3, 1\n",
            "*BOUNDARY\n1, 0\n",
            "*MATERIAL\n*ELASTIC\n1,0.3\n",
            "*ELASTIC\n1, 0.3",
            "*MATERIAL, NAME=\"\"\n",
            "*INCLUDE\n",
            "*INCLUDE, INPUT=\n",
            "*HEADING\n\u{feff}\u{202e}text",
            "\u{feff}*NODE\n1,0,0,0\r\n2,0,0,0\r\n",
        ];
        for c in cases {
            let _ = parse(c);
        }
        // Random decks from keyword and data fragments.
        let fragments = [
            "*NODE",
            "*NODE, NSET=A",
            "*ELEMENT, TYPE=C3D20",
            "*ELEMENT,TYPE=C3D15,ELSET=E",
            "*ELEMENT,TYPE=C3D20R,",
            "*NSET,NSET=A,GENERATE",
            "*ELSET,ELSET=E",
            "*ELSET,ELSET=E,GENERATE",
            "*MATERIAL,NAME=M",
            "*ELASTIC",
            "*SOLID SECTION,ELSET=E,MATERIAL=M",
            "*STEP",
            "*STATIC",
            "*END STEP",
            "*BOUNDARY",
            "*CLOAD",
            "*DLOAD",
            "*HEADING",
            "*FOO",
            "**",
            "",
            "*INCLUDE,INPUT=/nonexistent/x.inp",
            "1, 2, 3",
            "1, 0, 0, 0",
            "2, 1.5, -3e2",
            "a, b",
            ",",
            ",,,",
            "E, P3, 1",
            "E, P6, -1",
            "A, 1, 3",
            "A, 2",
            "1, 1, 3, 0.5",
            "1e999",
            "P0",
            "1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,",
            "16, 17, 18, 19, 20",
            "3, 1",
            "0, 0",
            "18446744073709551615, 1, 1",
            "210000, 0.3",
            "1, 0.5",
            "NALL, 1, 3",
            "EALL, P1, 2",
            "\u{0}\u{1}*",
            "1,,,",
            "  *  node  ,  nset = a  ",
            "7, 1, 1.0",
            "*SURFACE, NAME=S, TYPE=ELEMENT",
            "*SURFACE,NAME=N,TYPE=NODE",
            "*SURFACE, NAME=S",
            "E, S2",
            "1, S9",
            "1, SPOS",
            "*SURFACE INTERACTION, NAME=I",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD",
            "*SURFACE BEHAVIOR",
            "*FRICTION",
            "-0.1",
            "0.2, 1e5",
            "*CONTACT PAIR, INTERACTION=I, TYPE=NODE TO SURFACE",
            "*CONTACT PAIR, INTERACTION=J",
            "S, N",
            "N, S",
            "1e7, 0.1, 1e-3",
            "*CONTACT PRINT",
        ];
        let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
        for _ in 0..3000 {
            let mut deck = String::new();
            for _ in 0..rng.below(40) {
                deck.push_str(fragments[rng.below(fragments.len())]);
                deck.push('\n');
            }
            let _ = parse(&deck);
        }
    }
}
