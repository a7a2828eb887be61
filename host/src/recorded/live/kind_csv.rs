//! `record`'s CSV files, one per record kind (`DIR/KIND.csv`), each the CSV that
//! `stickslip decode --kind KIND` prints for the same stream: decode's columns
//! ([`extend_kind_columns`]), header and rows ([`kind_header`], [`kind_row`], [`csv_line`]).
//! One line is written per record, straight to the file (no buffer of ours): what was written
//! is in the file when the process dies.
//!
//! decode's columns are the union of a kind's fields in order of appearance, so a record with
//! a field its kind's earlier records lack (the positional lines of kind `log`; never the
//! firmware's records, whose keys are fixed) appends columns: the file is then rewritten
//! once with the longer header and the earlier rows padded with empty cells (decode's cell
//! for a field a record does not have), through a new file renamed over the old one.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{HostError, Result};
use crate::recorded::decode::{csv_line, extend_kind_columns, kind_header, kind_row, KindColumn, Record};

/// One kind's file.
struct KindFile {
    kind: String,
    path: PathBuf,
    file: File,
    cols: Vec<KindColumn>,
    rows: u64,
}

/// The open CSV files of a recording, in the order their kinds first appeared.
pub struct KindFiles {
    dir: PathBuf,
    files: Vec<KindFile>,
}

/// A kind, its file and the rows written to it.
#[derive(Debug)]
pub struct KindCount {
    pub kind: String,
    pub path: PathBuf,
    pub rows: u64,
}

fn write_err(path: &Path, e: impl std::fmt::Display) -> HostError {
    HostError::Output(format!("{}: cannot write: {e}", path.display()))
}

impl KindFiles {
    pub fn new(dir: &Path) -> Self {
        KindFiles { dir: dir.to_path_buf(), files: Vec::new() }
    }

    /// Writes `r`'s row to its kind's file (created, with its header, at the kind's first record).
    pub fn write(&mut self, r: &Record) -> Result<()> {
        let i = match self.files.iter().position(|f| f.kind == r.kind) {
            Some(i) => i,
            None => {
                // kinds are [a-z0-9_]+ or `log` (decode's record layout): safe as file names
                let path = self.dir.join(format!("{}.csv", r.kind));
                let file = OpenOptions::new().write(true).create_new(true).open(&path).map_err(|e| write_err(&path, e))?;
                self.files.push(KindFile { kind: r.kind.clone(), path, file, cols: Vec::new(), rows: 0 });
                self.files.len() - 1
            }
        };
        let f = &mut self.files[i];
        let old_cols = f.cols.len();
        let grew = extend_kind_columns(&mut f.cols, r);
        if f.rows == 0 {
            f.file.write_all(csv_line(&kind_header(&f.cols)).as_bytes()).map_err(|e| write_err(&f.path, e))?;
        } else if grew {
            f.rewrite_with_columns(old_cols)?;
        }
        f.file.write_all(csv_line(&kind_row(r, &f.cols)).as_bytes()).map_err(|e| write_err(&f.path, e))?;
        f.rows += 1;
        Ok(())
    }

    /// The kinds written so far, with their files and row counts.
    pub fn counts(&self) -> Vec<KindCount> {
        self.files.iter().map(|f| KindCount { kind: f.kind.clone(), path: f.path.clone(), rows: f.rows }).collect()
    }
}

impl KindFile {
    /// The file again under the header of `self.cols`, its rows (of `old_cols` columns)
    /// padded with empty cells; reopened for appending.
    fn rewrite_with_columns(&mut self, old_cols: usize) -> Result<()> {
        let rows: Vec<csv::StringRecord> = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_path(&self.path)
            .and_then(|mut rd| rd.records().collect::<std::result::Result<_, _>>())
            .map_err(|e| HostError::Output(format!("{}: cannot read back to add columns: {e}", self.path.display())))?;
        let width = 2 + self.cols.len();
        let mut text = csv_line(&kind_header(&self.cols));
        for row in rows.iter().skip(1) {
            if row.len() != 2 + old_cols {
                return Err(HostError::Output(format!(
                    "{}: a row of {} cells where {} were written: changed while recording",
                    self.path.display(),
                    row.len(),
                    2 + old_cols
                )));
            }
            let mut cells: Vec<String> = row.iter().map(str::to_string).collect();
            cells.resize(width, String::new());
            text.push_str(&csv_line(&cells));
        }
        let tmp = self.path.with_extension("csv.new");
        std::fs::write(&tmp, text.as_bytes()).map_err(|e| write_err(&tmp, e))?;
        std::fs::rename(&tmp, &self.path).map_err(|e| write_err(&self.path, e))?;
        self.file = OpenOptions::new().append(true).open(&self.path).map_err(|e| write_err(&self.path, e))?;
        Ok(())
    }
}
