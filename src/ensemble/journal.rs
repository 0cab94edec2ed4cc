//! The journal of a run: an append-only file of JSON lines in the output directory, one
//! line per finished work item, each written and synced to disk as soon as the item
//! finishes. A crash loses no finished item; a resumed run reads the journal back and runs
//! only the items it lacks.
//!
//! ```text
//! {"journal":1,"header":{…}}          the run it belongs to (what must match to resume)
//! {"index":12,"row":{…}}              a finished item: its global index and its row
//! {"index":3,"row":{…}}               (in the order the items finished)
//! ```
//!
//! Rows keep every number exact (see [`row`](super::row)), so the rows read back are the
//! rows computed, bit for bit. A line is written whole under a lock and synced before the
//! next one; a line that fails in part (a full disk) is cut off again. The only damage a
//! crash can leave is a last line cut short, which reading drops (and resuming cuts off).

use super::row::RealizationRow;
use crate::io::FileError;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The file name of the journal in a run directory.
pub const FILE_NAME: &str = "journal.jsonl";

/// The version of the journal format (the `journal` key of the first line).
pub const VERSION: u32 = 1;

/// Journal errors.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum JournalError {
    /// Reading or writing the file.
    #[error(transparent)]
    File(#[from] FileError),
    /// A line that is not a journal line (other than a last line cut short).
    #[error("{path}: line {line}: {message}")]
    Corrupt {
        /// The journal.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

#[derive(Serialize, Deserialize)]
struct HeaderLine<H> {
    journal: u32,
    header: H,
}

#[derive(Serialize, Deserialize)]
struct RowLine {
    index: u64,
    row: RealizationRow,
}

/// What a journal on disk holds.
#[derive(Debug, Clone)]
pub struct Contents<H> {
    /// The header of the run.
    pub header: H,
    /// The finished rows, in the order they were written.
    pub rows: Vec<RealizationRow>,
    /// The length in bytes of the complete lines (a torn last line starts there).
    pub complete_len: u64,
}

/// An open journal, appended to from any thread.
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    file: Mutex<File>,
}

impl Journal {
    /// Reads the journal at `path`; `None` if there is none.
    ///
    /// # Errors
    /// [`JournalError`] naming the file and line.
    pub fn read<H: DeserializeOwned>(path: &Path) -> Result<Option<Contents<H>>, JournalError> {
        let f = match File::open(path) {
            Ok(f) => f,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(FileError::at(path)(e).into()),
        };
        let mut reader = BufReader::new(f);
        let corrupt = |line: usize, message: String| JournalError::Corrupt { path: path.to_owned(), line, message };
        let mut header: Option<H> = None;
        let mut rows = Vec::new();
        let mut complete_len = 0u64;
        let mut buf = Vec::new();
        for line in 1.. {
            buf.clear();
            let n = reader.read_until(b'\n', &mut buf).map_err(FileError::at(path))?;
            if n == 0 {
                break;
            }
            if buf.last() != Some(&b'\n') {
                break; // cut short by a crash: dropped
            }
            let text = std::str::from_utf8(&buf[..n - 1]).map_err(|e| corrupt(line, e.to_string()))?;
            if line == 1 {
                let h: HeaderLine<H> = serde_json::from_str(text).map_err(|e| corrupt(line, e.to_string()))?;
                if h.journal != VERSION {
                    return Err(corrupt(line, format!("journal version {}; this drystone reads {VERSION}", h.journal)));
                }
                header = Some(h.header);
            } else {
                let r: RowLine = serde_json::from_str(text).map_err(|e| corrupt(line, e.to_string()))?;
                if r.index != r.row.index {
                    return Err(corrupt(line, format!("index {} but the row is item {}", r.index, r.row.index)));
                }
                rows.push(r.row);
            }
            complete_len += n as u64;
        }
        Ok(header.map(|header| Contents { header, rows, complete_len }))
    }

    /// Starts a new journal at `path` (replacing any) with `header`, synced.
    ///
    /// # Errors
    /// [`JournalError::File`] naming the file.
    pub fn create<H: Serialize>(path: &Path, header: &H) -> Result<Journal, JournalError> {
        let line = serde_json::to_string(&HeaderLine { journal: VERSION, header })
            .map_err(|e| FileError::at(path)(std::io::Error::other(e)))?;
        let file = File::create(path).map_err(FileError::at(path))?;
        let j = Journal { path: path.to_owned(), file: Mutex::new(file) };
        j.write_line(line)?;
        crate::io::sync_dir(path);
        Ok(j)
    }

    /// Continues the journal at `path` whose complete lines end at `complete_len` (a torn
    /// last line is cut off).
    ///
    /// # Errors
    /// [`JournalError::File`] naming the file.
    pub fn resume(path: &Path, complete_len: u64) -> Result<Journal, JournalError> {
        let file = OpenOptions::new().append(true).open(path).map_err(FileError::at(path))?;
        file.set_len(complete_len).map_err(FileError::at(path))?;
        file.sync_all().map_err(FileError::at(path))?;
        Ok(Journal { path: path.to_owned(), file: Mutex::new(file) })
    }

    /// Appends a finished row and syncs it to disk.
    ///
    /// # Errors
    /// [`JournalError::File`] naming the file (e.g. `No space left on device`).
    pub fn append(&self, row: &RealizationRow) -> Result<(), JournalError> {
        let line = serde_json::to_string(&RowLine { index: row.index, row: row.clone() })
            .map_err(|e| FileError::at(&self.path)(std::io::Error::other(e)))?;
        self.write_line(line)
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn write_line(&self, mut line: String) -> Result<(), JournalError> {
        line.push('\n');
        let mut f = self.file.lock().unwrap_or_else(|p| p.into_inner());
        let len = f.metadata().map_err(FileError::at(&self.path))?.len();
        let written = f.write_all(line.as_bytes()).and_then(|()| f.sync_data());
        if let Err(e) = written {
            // A line written in part (e.g. a full disk) is taken back, so that a later line
            // cannot follow it.
            let _ = f.set_len(len);
            return Err(FileError::at(&self.path)(e).into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ensemble::row::Status;

    fn row(index: u64) -> RealizationRow {
        RealizationRow {
            index,
            study: "s".into(),
            group: "g".into(),
            point: 0,
            sweep: String::new(),
            seed: 1,
            realization: index,
            status: Status::Stood,
            error: String::new(),
            blocks: 2,
            collapse_angle_deg: None,
            first_unstable_deg: None,
            collapse_reason: String::new(),
            mechanism: "none".into(),
            joint: String::new(),
            moving_blocks: 0,
            tilt_deg: vec![0.5, 1.0 / 3.0],
            disp_top_left_cm: vec![f64::NAN, -0.0],
            disp_top_centre_cm: vec![],
            disp_top_right_cm: vec![],
            lateral_disp_left_cm: None,
            lateral_disp_centre_cm: None,
            lateral_disp_right_cm: None,
            lateral_disp_max_cm: None,
            lateral_drift: None,
            steps: 10,
            iterations: 3,
            dt_s: 1e-4,
            wall_time_s: 0.5,
        }
    }

    fn same(a: &[RealizationRow], b: &[RealizationRow]) -> bool {
        serde_json::to_string(a).unwrap() == serde_json::to_string(b).unwrap()
    }

    #[test]
    fn rows_come_back_and_a_torn_last_line_is_dropped_then_cut_off() {
        let dir = std::env::temp_dir().join(format!("drystone-journal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(FILE_NAME);
        assert!(Journal::read::<String>(&p).unwrap().is_none());
        let j = Journal::create(&p, &"run A".to_string()).unwrap();
        j.append(&row(4)).unwrap();
        j.append(&row(1)).unwrap();
        drop(j);
        let good = std::fs::metadata(&p).unwrap().len();
        // A crash in the middle of a line.
        let mut f = OpenOptions::new().append(true).open(&p).unwrap();
        f.write_all(b"{\"index\":7,\"row\":{\"ind").unwrap();
        drop(f);
        let c = Journal::read::<String>(&p).unwrap().unwrap();
        assert_eq!(c.header, "run A");
        assert!(same(&c.rows, &[row(4), row(1)]));
        assert_eq!(c.complete_len, good);
        let j = Journal::resume(&p, c.complete_len).unwrap();
        j.append(&row(7)).unwrap();
        let c = Journal::read::<String>(&p).unwrap().unwrap();
        assert!(same(&c.rows, &[row(4), row(1), row(7)]));
        // A bad line in the middle is an error naming the line.
        let text = std::fs::read_to_string(&p).unwrap().replacen("\"index\":1,", "\"index\":x,", 1);
        std::fs::write(&p, text).unwrap();
        let e = Journal::read::<String>(&p).unwrap_err().to_string();
        assert!(e.contains("journal.jsonl: line 3:"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_full_disk_is_reported_with_the_journal_file() {
        let full = Path::new("/dev/full");
        if !full.exists() {
            return;
        }
        let j = Journal { path: full.to_owned(), file: Mutex::new(OpenOptions::new().write(true).open(full).unwrap()) };
        let e = j.append(&row(0)).unwrap_err().to_string();
        assert!(e.starts_with("/dev/full: No space left on device"), "{e}");
    }
}
