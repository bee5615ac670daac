//! `table.parquet`: the collected table (`table.csv`'s columns and rows)
//! for pandas/polars users, written with the `parquet` crate's low-level
//! column writers (no Arrow, no compression codecs: the pages are stored
//! uncompressed, PLAIN/dictionary encoded).
//!
//! Columns, in `table.csv`'s order: `index` (INT64), `id`, `analysis`,
//! `status` (UTF-8 strings), the inputs (INT64 when every value is an
//! integer, DOUBLE when every value is a number, else the CSV's text as
//! UTF-8), the figures and `seconds` (DOUBLE, `seconds` rounded to the
//! CSV's milliseconds). Inputs, figures and seconds are nullable: null where
//! the CSV field is empty (a failed or pending job, a figure a job lacks).

use std::path::Path;
use std::sync::Arc;

use parquet::basic::{LogicalType, Repetition, Type as PhysicalType};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::reader::FileReader;
use parquet::file::serialized_reader::SerializedFileReader;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;
use serde_json::Value;

use crate::error::{FlankError, Result};

use super::table::{Row, Table};

/// One column's values, `None` for null.
enum Column {
    Int(Vec<Option<i64>>),
    Double(Vec<Option<f64>>),
    Text(Vec<Option<String>>),
}

/// A cell read back from a Parquet file ([`read_table`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    Null,
    Int(i64),
    Double(f64),
    Text(String),
}

fn err(path: &Path, e: impl std::fmt::Display) -> FlankError {
    FlankError::Campaign(format!("{}: Parquet: {e}", path.display()))
}

/// An input column: integers, numbers or text (as in the CSV).
fn input_column(table: &Table, key: &str) -> Column {
    let values: Vec<Option<&Value>> = table
        .rows
        .iter()
        .map(|r| r.inputs.iter().find(|(k, _)| k == key).map(|(_, v)| v))
        .collect();
    let present = || values.iter().flatten();
    if present().all(|v| v.is_i64()) {
        Column::Int(values.iter().map(|v| v.and_then(Value::as_i64)).collect())
    } else if present().all(|v| v.is_number()) {
        Column::Double(values.iter().map(|v| v.and_then(Value::as_f64)).collect())
    } else {
        Column::Text(
            values
                .iter()
                .map(|v| {
                    v.map(|v| match v {
                        Value::String(s) => s.clone(),
                        v => v.to_string(),
                    })
                })
                .collect(),
        )
    }
}

/// The table's columns, named as in `table.csv`.
fn columns(table: &Table) -> Vec<(String, Column, bool)> {
    let text = |f: fn(&Row) -> &String| {
        Column::Text(table.rows.iter().map(|r| Some(f(r).clone())).collect())
    };
    let mut cols = vec![
        (
            "index".to_string(),
            Column::Int(table.rows.iter().map(|r| Some(r.index as i64)).collect()),
            false,
        ),
        ("id".into(), text(|r| &r.id), false),
        ("analysis".into(), text(|r| &r.analysis), false),
        ("status".into(), text(|r| &r.status), false),
    ];
    for k in &table.input_keys {
        cols.push((k.clone(), input_column(table, k), true));
    }
    for k in &table.figure_keys {
        let v = table.rows.iter().map(|r| Table::figure(r, k)).collect();
        cols.push((k.clone(), Column::Double(v), true));
    }
    // the CSV's milliseconds
    let seconds = table
        .rows
        .iter()
        .map(|r| r.seconds.and_then(|s| format!("{s:.3}").parse().ok()))
        .collect();
    cols.push(("seconds".into(), Column::Double(seconds), true));
    cols
}

/// Values and definition levels (1 present, 0 null) of a nullable column.
fn levels<T: Clone>(v: &[Option<T>]) -> (Vec<T>, Vec<i16>) {
    let values = v.iter().flatten().cloned().collect();
    let defs = v.iter().map(|x| i16::from(x.is_some())).collect();
    (values, defs)
}

/// Writes `table` to `path` (whole or not at all: temporary name, rename).
pub fn write_table(table: &Table, path: &Path) -> Result<()> {
    let cols = columns(table);
    let mut fields = Vec::with_capacity(cols.len());
    for (name, col, nullable) in &cols {
        let (physical, logical) = match col {
            Column::Int(_) => (PhysicalType::INT64, None),
            Column::Double(_) => (PhysicalType::DOUBLE, None),
            Column::Text(_) => (PhysicalType::BYTE_ARRAY, Some(LogicalType::String)),
        };
        let rep = if *nullable {
            Repetition::OPTIONAL
        } else {
            Repetition::REQUIRED
        };
        let t = Type::primitive_type_builder(name, physical)
            .with_repetition(rep)
            .with_logical_type(logical)
            .build()
            .map_err(|e| err(path, format!("column `{name}`: {e}")))?;
        fields.push(Arc::new(t));
    }
    let schema = Type::group_type_builder("table")
        .with_fields(fields)
        .build()
        .map_err(|e| err(path, e))?;
    let props = Arc::new(WriterProperties::builder().build());
    crate::atomic_file::write_with(path, |tmp| {
        let file = std::fs::File::create(tmp).map_err(|e| FlankError::io(tmp, e))?;
        let mut w =
            SerializedFileWriter::new(file, Arc::new(schema), props).map_err(|e| err(path, e))?;
        let mut rg = w.next_row_group().map_err(|e| err(path, e))?;
        for (name, col, nullable) in &cols {
            let mut cw = rg
                .next_column()
                .map_err(|e| err(path, e))?
                .ok_or_else(|| err(path, format!("no column writer for `{name}`")))?;
            let r = match col {
                Column::Int(v) => {
                    let (values, defs) = levels(v);
                    let defs = nullable.then_some(&defs[..]);
                    cw.typed::<Int64Type>().write_batch(&values, defs, None)
                }
                Column::Double(v) => {
                    let (values, defs) = levels(v);
                    let defs = nullable.then_some(&defs[..]);
                    cw.typed::<DoubleType>().write_batch(&values, defs, None)
                }
                Column::Text(v) => {
                    let (values, defs) = levels(v);
                    let values: Vec<ByteArray> = values
                        .iter()
                        .map(|s| ByteArray::from(s.as_bytes().to_vec()))
                        .collect();
                    let defs = nullable.then_some(&defs[..]);
                    cw.typed::<ByteArrayType>().write_batch(&values, defs, None)
                }
            };
            r.map_err(|e| err(path, format!("column `{name}`: {e}")))?;
            cw.close().map_err(|e| err(path, e))?;
        }
        rg.close().map_err(|e| err(path, e))?;
        let file = w.into_inner().map_err(|e| err(path, e))?;
        file.sync_all().map_err(|e| FlankError::io(tmp, e))
    })
}

/// Reads a table written by [`write_table`] back with the same crate's
/// reader: column names and rows of cells.
pub fn read_table(path: &Path) -> Result<(Vec<String>, Vec<Vec<Cell>>)> {
    let file = std::fs::File::open(path).map_err(|e| FlankError::io(path, e))?;
    let reader = SerializedFileReader::new(file).map_err(|e| err(path, e))?;
    let head: Vec<String> = reader
        .metadata()
        .file_metadata()
        .schema_descr()
        .columns()
        .iter()
        .map(|c| c.name().to_string())
        .collect();
    let mut rows = Vec::new();
    for row in reader {
        let row = row.map_err(|e| err(path, e))?;
        let mut cells = Vec::with_capacity(head.len());
        for (name, f) in row.get_column_iter() {
            use parquet::record::Field;
            cells.push(match f {
                Field::Null => Cell::Null,
                Field::Long(i) => Cell::Int(*i),
                Field::Double(x) => Cell::Double(*x),
                Field::Str(s) => Cell::Text(s.clone()),
                other => {
                    return Err(err(
                        path,
                        format!("column `{name}`: unexpected value {other:?}"),
                    ))
                }
            });
        }
        rows.push(cells);
    }
    Ok((head, rows))
}

/// Whether a Parquet cell holds what a `table.csv` field says: the same
/// text, the same number (the CSV's shortest round-trip text parsed), or
/// null for an empty field.
pub fn cell_matches_csv(cell: &Cell, csv: &str) -> bool {
    match cell {
        Cell::Null => csv.is_empty(),
        Cell::Int(i) => csv.parse::<i64>().ok() == Some(*i),
        Cell::Double(x) => csv
            .parse::<f64>()
            .is_ok_and(|y| y.to_bits() == x.to_bits() || (x.is_nan() && y.is_nan())),
        Cell::Text(s) => s == csv,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::campaign::collect::read_csv;

    fn table() -> Table {
        let row = |index: usize, status: &str, figures: Vec<(String, f64)>, seconds| Row {
            index,
            id: format!("{index:016x}"),
            analysis: "ltca".into(),
            status: status.into(),
            inputs: vec![
                (
                    "load.torque_nm".into(),
                    serde_json::json!(150.5 + index as f64),
                ),
                ("mesh.teeth_in_sector".into(), serde_json::json!(3 + index)),
                ("mesh.element".into(), serde_json::json!("hex20")),
            ],
            figures,
            seconds,
        };
        Table {
            input_keys: vec![
                "load.torque_nm".into(),
                "mesh.teeth_in_sector".into(),
                "mesh.element".into(),
            ],
            figure_keys: vec!["te_urad".into(), "steps.0.force, \"n\"".into()],
            rows: vec![
                row(
                    0,
                    "done",
                    vec![
                        ("te_urad".into(), 0.1 + 0.2),
                        ("steps.0.force, \"n\"".into(), -1.5e-300),
                    ],
                    Some(1.23456),
                ),
                row(1, "failed", vec![], None),
                row(2, "done", vec![("te_urad".into(), 42.0)], Some(0.5)),
            ],
        }
    }

    /// Written and read back, every cell equals the CSV's field: numbers
    /// bit for bit, nulls where the CSV is empty (a failed job, a figure a
    /// job lacks), strings with commas and quotes intact; the column types
    /// follow the values.
    #[test]
    fn parquet_reads_back_as_the_csv() {
        let dir = std::env::temp_dir().join(format!("flank-parquet-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let t = table();
        let csv = dir.join("table.csv");
        std::fs::write(&csv, t.csv()).unwrap();
        let pq = dir.join("table.parquet");
        write_table(&t, &pq).unwrap();
        let (csv_head, csv_rows) = read_csv(&csv).unwrap();
        let (head, rows) = read_table(&pq).unwrap();
        assert_eq!(head, csv_head);
        assert_eq!(rows.len(), 3);
        for (r, c) in rows.iter().zip(&csv_rows) {
            assert_eq!(r.len(), c.len());
            for ((cell, field), name) in r.iter().zip(c).zip(&head) {
                assert!(
                    cell_matches_csv(cell, field),
                    "{name}: {cell:?} vs `{field}`"
                );
            }
        }
        assert_eq!(rows[0][0], Cell::Int(0));
        assert_eq!(rows[0][5], Cell::Int(3));
        assert_eq!(rows[0][6], Cell::Text("hex20".into()));
        assert_eq!(rows[0][7], Cell::Double(0.1 + 0.2));
        assert_eq!(rows[1][7], Cell::Null);
        assert_eq!(rows[2][8], Cell::Null);
        assert_eq!(rows[0][9], Cell::Double(1.235));
        // no temporary left beside it
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        // a file that is not Parquet is an error naming it
        std::fs::write(&pq, b"not parquet").unwrap();
        let e = read_table(&pq).unwrap_err().to_string();
        assert!(e.contains("table.parquet") && e.contains("Parquet"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn matching_rules() {
        assert!(cell_matches_csv(&Cell::Null, ""));
        assert!(!cell_matches_csv(&Cell::Null, "0"));
        assert!(cell_matches_csv(&Cell::Double(0.0), "0"));
        assert!(!cell_matches_csv(&Cell::Double(0.1), "0.10000000000000002"));
        assert!(cell_matches_csv(&Cell::Int(7), "7"));
        assert!(!cell_matches_csv(&Cell::Int(7), "7.5"));
    }
}
