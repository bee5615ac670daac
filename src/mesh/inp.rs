//! CalculiX/Abaqus deck (`.inp`) reader and writer. (Placeholder until the reader lands.)

use std::path::Path;

use crate::fem::model::Model;

pub struct DeckWarning {
    pub line: usize,
    pub message: String,
}

pub struct Deck {
    pub model: Model,
    pub warnings: Vec<DeckWarning>,
    pub title: Option<String>,
}

pub fn read_deck(path: &Path) -> crate::Result<Deck> {
    Err(crate::FlankError::Parse {
        file: path.to_path_buf(),
        line: 0,
        message: "deck reader not yet available".into(),
    })
}
