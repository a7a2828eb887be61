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

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::{json, Value};

    fn rec(frame: u64, t: Option<f64>, fields: Vec<(&str, Value)>) -> Record {
        Record {
            frame,
            offset: 0,
            timestamp: None,
            timestamp_s: t,
            level: Some("info"),
            kind: "log".into(),
            message: String::new(),
            fields: fields.into_iter().map(|(k, v)| (k.to_string(), v)).collect(),
        }
    }

    /// Records whose fields grow (as positional log lines do): the file is rewritten with the
    /// longer header, earlier rows padded; after every record it holds decode's CSV of the
    /// records so far, written out here by hand.
    #[test]
    fn new_columns_rewrite_the_file_with_the_rows_padded() {
        let dir = std::env::temp_dir().join(format!("stickslip-kind-csv-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let mut files = KindFiles::new(&dir);
        let steps: [(Record, &str); 4] = [
            (rec(0, Some(0.5), vec![("arg0", json!(1))]), "frame,timestamp_s,arg0\n0,0.5,1\n"),
            (
                rec(2, None, vec![("arg0", json!(2)), ("arg1", json!("x,y"))]),
                "frame,timestamp_s,arg0,arg1\n0,0.5,1,\n2,,2,\"x,y\"\n",
            ),
            (
                rec(3, Some(0.25), vec![("arg0", json!(3)), ("pp", json!([1.5, 2]))]),
                "frame,timestamp_s,arg0,arg1,pp_0,pp_1\n0,0.5,1,,,\n2,,2,\"x,y\",,\n3,0.25,3,,1.5,2\n",
            ),
            (
                rec(4, Some(1.0), vec![("pp", json!([4, 5, 6])), ("arg1", json!(true))]),
                "frame,timestamp_s,arg0,arg1,pp_0,pp_1,pp_2\n0,0.5,1,,,,\n2,,2,\"x,y\",,,\n3,0.25,3,,1.5,2,\n4,1,,true,4,5,6\n",
            ),
        ];
        for (i, (r, want)) in steps.iter().enumerate() {
            files.write(r).unwrap();
            let got = std::fs::read_to_string(dir.join("log.csv")).unwrap();
            assert_eq!(got, *want, "after record {i}");
        }
        let c = files.counts();
        assert_eq!((c.len(), c[0].kind.as_str(), c[0].rows), (1, "log", 4));
        // the rewrite leaves no temporary file
        let names: Vec<String> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
        assert_eq!(names, ["log.csv"]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
