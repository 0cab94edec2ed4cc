//! The journal of a run: an append-only file of JSON lines in the output directory, one
//! line per finished work item, each written and synced to disk as soon as the item
//! finishes. A crash loses no finished item; a resumed run reads the journal back and runs
//! only the items it lacks.
//!
//! ```text
//! {"journal":2,"run":"9f…","header":{…},"sum":"4c…"}        the run it belongs to
//! {"run":"9f…","index":12,"row":{…},"sum":"b0…"}            a finished item
//! {"run":"9f…","index":3,"row":{…},"sum":"e1…"}             (in the order they finished)
//! ```
//!
//! Every line carries the identity of its run (`run`, a digest of what makes the run:
//! study, inputs, seed, realizations, shard, drystone build; computed by the caller) and
//! its own checksum (`sum`, the SHA-256 of the line without the `sum` member, lower-case
//! hex). Reading checks both before anything is used: a line of another run (copied in
//! from another journal) or a line altered after it was written (a flipped digit, an
//! edited status) is an error naming the journal, the line and the field.
//!
//! Rows keep every number exact (see [`row`](super::row)), so the rows read back are the
//! rows computed, bit for bit. A line is written whole under a lock and synced before the
//! next one; a line that fails in part (a full disk) is cut off again. The only damage a
//! crash can leave is a last line cut short (or filled with NUL bytes), without its line
//! end, which reading drops (and resuming cuts off).

use super::row::RealizationRow;
use crate::files::FileError;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The file name of the journal in a run directory.
pub const FILE_NAME: &str = "journal.jsonl";

/// The version of the journal format (the `journal` key of the first line).
pub const VERSION: u32 = 2;

/// Journal errors.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum JournalError {
    /// Reading or writing the file.
    #[error(transparent)]
    File(#[from] FileError),
    /// A line that is not a sound line of this journal (other than a last line cut short).
    #[error("{path}: line {line}: {field}: {message}")]
    Corrupt {
        /// The journal.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// The member of the line at fault (`sum`, `run`, `index`, `journal`, or `line`
        /// for a line that is not a journal line at all).
        field: &'static str,
        /// What is wrong.
        message: String,
    },
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct HeaderLine<H> {
    journal: u32,
    run: String,
    header: H,
}

/// A row a journal holds: one finished work item of a study, whatever its protocol's rows
/// (the ensemble's [`RealizationRow`], the in-plane study's), keeping every number exact.
pub trait JournalRow: Serialize + DeserializeOwned {
    /// The item it is the row of (unique in a run).
    fn item_index(&self) -> u64;
}

impl JournalRow for RealizationRow {
    fn item_index(&self) -> u64 {
        self.index
    }
}

#[derive(Serialize)]
struct RowLineRef<'a, R> {
    run: &'a str,
    index: u64,
    row: &'a R,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[serde(bound = "R: DeserializeOwned")]
struct RowLine<R> {
    run: String,
    index: u64,
    row: R,
}

/// The `sum` member closing every line: `,"sum":"` + 64 hex digits + `"}`.
const SUM_OPEN: &str = ",\"sum\":\"";
const SUM_LEN: usize = SUM_OPEN.len() + 64 + 2;

use crate::files::sha256_hex;

/// A JSON object with its checksum appended as the last member `sum`: the SHA-256 of the
/// object as given.
fn seal(body: &str) -> String {
    let sum = sha256_hex(body.as_bytes());
    format!("{}{SUM_OPEN}{sum}\"}}", &body[..body.len() - 1])
}

/// The object of a sealed line without its `sum`, if the checksum holds.
fn unseal(text: &str) -> Result<String, (&'static str, String)> {
    let n = text.len();
    let split = n.checked_sub(SUM_LEN).filter(|&i| text.is_char_boundary(i));
    let Some(i) = split.filter(|&i| text[i..].starts_with(SUM_OPEN) && text.ends_with("\"}")) else {
        return Err(("sum", "no checksum at the end of the line (not a line of this journal format)".into()));
    };
    let recorded = &text[i + SUM_OPEN.len()..n - 2];
    let body = format!("{}}}", &text[..i]);
    let actual = sha256_hex(body.as_bytes());
    if actual != recorded {
        return Err((
            "sum",
            format!(
                "the line was altered after it was written: its checksum is {recorded}, its contents hash to {actual}"
            ),
        ));
    }
    Ok(body)
}

/// What a journal on disk holds.
#[derive(Debug, Clone)]
pub struct Contents<H, R = RealizationRow> {
    /// The identity of the run that wrote it (the `run` of every line).
    pub run: String,
    /// The header of the run.
    pub header: H,
    /// The finished rows, in the order they were written.
    pub rows: Vec<R>,
    /// The 1-based line of each row in the file.
    pub lines: Vec<usize>,
    /// The length in bytes of the complete lines (a torn last line starts there).
    pub complete_len: u64,
}

/// An open journal, appended to from any thread.
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    run: String,
    file: Mutex<File>,
}

impl Journal {
    /// Reads the journal at `path`; `None` if there is none. Every complete line must carry
    /// its checksum and the run identity of the header line; a row appears at most once.
    /// A last line without its line end (a write cut short by a crash) is dropped.
    ///
    /// # Errors
    /// [`JournalError::Corrupt`] naming the file, the line and the field.
    pub fn read<H: DeserializeOwned>(path: &Path) -> Result<Option<Contents<H>>, JournalError> {
        Journal::read_rows(path)
    }

    /// [`Journal::read`] of a journal of rows of type `R`.
    ///
    /// # Errors
    /// As [`Journal::read`].
    pub fn read_rows<H: DeserializeOwned, R: JournalRow>(path: &Path) -> Result<Option<Contents<H, R>>, JournalError> {
        let f = match File::open(path) {
            Ok(f) => f,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(FileError::at(path)(e).into()),
        };
        let mut reader = BufReader::new(f);
        let corrupt = |line: usize, field: &'static str, message: String| JournalError::Corrupt {
            path: path.to_owned(),
            line,
            field,
            message,
        };
        let mut head: Option<(String, H)> = None;
        let (mut rows, mut lines) = (Vec::new(), Vec::new());
        let mut seen = std::collections::BTreeMap::new();
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
            let text = std::str::from_utf8(&buf[..n - 1]).map_err(|e| corrupt(line, "line", e.to_string()))?;
            let body = unseal(text).map_err(|(field, m)| corrupt(line, field, m))?;
            match &head {
                None => {
                    let v: serde_json::Value =
                        serde_json::from_str(&body).map_err(|e| corrupt(line, "line", e.to_string()))?;
                    let version = v.get("journal").and_then(serde_json::Value::as_u64);
                    if version != Some(u64::from(VERSION)) {
                        let found = version.map_or_else(|| "none".to_string(), |v| v.to_string());
                        return Err(corrupt(
                            line,
                            "journal",
                            format!("journal format {found}; this drystone reads format {VERSION}"),
                        ));
                    }
                    let h: HeaderLine<H> =
                        serde_json::from_str(&body).map_err(|e| corrupt(line, "header", e.to_string()))?;
                    head = Some((h.run, h.header));
                }
                Some((run, _)) => {
                    let r: RowLine<R> =
                        serde_json::from_str(&body).map_err(|e| corrupt(line, "line", e.to_string()))?;
                    if &r.run != run {
                        return Err(corrupt(
                            line,
                            "run",
                            format!("a row of another run ({}; this journal's run is {run})", r.run),
                        ));
                    }
                    if r.index != r.row.item_index() {
                        let item = r.row.item_index();
                        return Err(corrupt(line, "index", format!("{} but the row is item {item}", r.index)));
                    }
                    if let Some(first) = seen.insert(r.index, line) {
                        return Err(corrupt(line, "index", format!("item {} is already on line {first}", r.index)));
                    }
                    rows.push(r.row);
                    lines.push(line);
                }
            }
            complete_len += n as u64;
        }
        Ok(head.map(|(run, header)| Contents { run, header, rows, lines, complete_len }))
    }

    /// Starts a new journal at `path` (replacing any) for the run `run` (its identity) with
    /// `header`, synced.
    ///
    /// # Errors
    /// [`JournalError::File`] naming the file.
    pub fn create<H: Serialize>(path: &Path, run: &str, header: &H) -> Result<Journal, JournalError> {
        let body = serde_json::to_string(&HeaderLine { journal: VERSION, run: run.to_string(), header })
            .map_err(|e| FileError::at(path)(std::io::Error::other(e)))?;
        let file = File::create(path).map_err(FileError::at(path))?;
        let j = Journal { path: path.to_owned(), run: run.to_string(), file: Mutex::new(file) };
        j.write_line(seal(&body))?;
        crate::files::sync_dir(path);
        Ok(j)
    }

    /// Continues the journal at `path` of the run `run` whose complete lines end at
    /// `complete_len` (a torn last line is cut off).
    ///
    /// # Errors
    /// [`JournalError::File`] naming the file.
    pub fn resume(path: &Path, run: &str, complete_len: u64) -> Result<Journal, JournalError> {
        let file = OpenOptions::new().append(true).open(path).map_err(FileError::at(path))?;
        file.set_len(complete_len).map_err(FileError::at(path))?;
        file.sync_all().map_err(FileError::at(path))?;
        Ok(Journal { path: path.to_owned(), run: run.to_string(), file: Mutex::new(file) })
    }

    /// Appends a finished row and syncs it to disk.
    ///
    /// # Errors
    /// [`JournalError::File`] naming the file (e.g. `No space left on device`).
    pub fn append<R: JournalRow>(&self, row: &R) -> Result<(), JournalError> {
        let body = serde_json::to_string(&RowLineRef { run: &self.run, index: row.item_index(), row })
            .map_err(|e| FileError::at(&self.path)(std::io::Error::other(e)))?;
        self.write_line(seal(&body))
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
    use crate::ensemble::row::{CollapseColumns, LateralColumns, Status, TiltColumns};

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
            collapse: CollapseColumns {
                collapse_angle_deg: None,
                first_unstable_deg: None,
                collapse_reason: String::new(),
                mechanism: "none".into(),
                joint: String::new(),
                moving_blocks: 0,
                failure_height_fraction: None,
                mechanism_kind: String::new(),
                mechanism_start: String::new(),
                mechanism_extent: None,
            },
            tilt: TiltColumns {
                tilt_deg: vec![0.5, 1.0 / 3.0],
                disp_top_left_cm: vec![f64::NAN, -0.0],
                disp_top_centre_cm: vec![],
                disp_top_right_cm: vec![],
            },
            lateral: LateralColumns {
                lateral_disp_left_cm: None,
                lateral_disp_centre_cm: None,
                lateral_disp_right_cm: None,
                lateral_disp_max_cm: None,
                lateral_drift: None,
            },
            shake: Default::default(),
            pushover: Default::default(),
            in_plane: None,
            compression: None,
            steps: 10,
            iterations: 3,
            dt_s: 1e-4,
            wall_time_s: 0.5,
        }
    }

    fn same(a: &[RealizationRow], b: &[RealizationRow]) -> bool {
        serde_json::to_string(a).unwrap() == serde_json::to_string(b).unwrap()
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("drystone-journal-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn rows_come_back_and_a_torn_last_line_is_dropped_then_cut_off() {
        let dir = scratch("torn");
        let p = dir.join(FILE_NAME);
        assert!(Journal::read::<String>(&p).unwrap().is_none());
        let j = Journal::create(&p, "A", &"run A".to_string()).unwrap();
        j.append(&row(4)).unwrap();
        j.append(&row(1)).unwrap();
        drop(j);
        let good = std::fs::metadata(&p).unwrap().len();
        // A crash in the middle of a line, then one that left NUL bytes.
        for tail in [&b"{\"run\":\"A\",\"index\":7,\"row\":{\"ind"[..], &[0u8; 300][..]] {
            let mut f = OpenOptions::new().append(true).open(&p).unwrap();
            f.write_all(tail).unwrap();
            drop(f);
            let c = Journal::read::<String>(&p).unwrap().unwrap();
            assert_eq!((c.run.as_str(), c.header.as_str()), ("A", "run A"));
            assert!(same(&c.rows, &[row(4), row(1)]));
            assert_eq!(c.lines, [2, 3]);
            assert_eq!(c.complete_len, good);
            drop(Journal::resume(&p, "A", c.complete_len).unwrap());
        }
        let j = Journal::resume(&p, "A", good).unwrap();
        j.append(&row(7)).unwrap();
        let c = Journal::read::<String>(&p).unwrap().unwrap();
        assert!(same(&c.rows, &[row(4), row(1), row(7)]));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The journal at `p` with line `n` (1-based) replaced by `f(line)`.
    fn edit(p: &Path, n: usize, f: impl Fn(&str) -> String) {
        let text = std::fs::read_to_string(p).unwrap();
        let lines: Vec<String> =
            text.lines().enumerate().map(|(i, l)| if i + 1 == n { f(l) } else { l.to_string() }).collect();
        std::fs::write(p, lines.join("\n") + "\n").unwrap();
    }

    fn error_of(p: &Path) -> String {
        Journal::read::<String>(p).unwrap_err().to_string()
    }

    #[test]
    fn altered_foreign_and_repeated_lines_are_refused_naming_line_and_field() {
        let dir = scratch("damaged");
        let p = dir.join(FILE_NAME);
        let other = dir.join("other.jsonl");
        let fresh = || {
            let j = Journal::create(&p, "A", &"run A".to_string()).unwrap();
            j.append(&row(4)).unwrap();
            j.append(&row(1)).unwrap();
            j.append(&row(2)).unwrap();
        };
        // A flipped digit (the number of blocks) and an edited status: the checksum.
        for (from, to) in [("\"blocks\":2", "\"blocks\":3"), ("\"status\":\"stood\"", "\"status\":\"collapsed\"")] {
            fresh();
            edit(&p, 3, |l| l.replacen(from, to, 1));
            assert_ne!(std::fs::read_to_string(&p).unwrap().matches(to).count(), 0, "{to} not in the journal");
            let e = error_of(&p);
            assert!(e.starts_with(&format!("{}: line 3: sum: the line was altered", p.display())), "{e}");
        }
        // A whole row line of another run, checksum intact.
        let j = Journal::create(&other, "B", &"run B".to_string()).unwrap();
        j.append(&row(3)).unwrap();
        let foreign = std::fs::read_to_string(&other).unwrap().lines().nth(1).unwrap().to_string();
        fresh();
        edit(&p, 4, |_| foreign.clone());
        let e = error_of(&p);
        assert!(e.contains("journal.jsonl: line 4: run: a row of another run (B; this journal's run is A)"), "{e}");
        // The same item twice.
        fresh();
        let second = std::fs::read_to_string(&p).unwrap().lines().nth(1).unwrap().to_string();
        edit(&p, 4, |l| format!("{l}\n{second}"));
        assert!(error_of(&p).contains("line 5: index: item 4 is already on line 2"), "{}", error_of(&p));
        // A line without a checksum, and a header of another format.
        fresh();
        edit(&p, 2, |_| "{\"index\":4}".into());
        assert!(error_of(&p).contains("line 2: sum: no checksum"), "{}", error_of(&p));
        fresh();
        edit(&p, 1, |_| seal("{\"journal\":1,\"header\":\"run A\"}"));
        assert!(error_of(&p).contains("line 1: journal: journal format 1; this drystone reads format 2"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_full_disk_is_reported_with_the_journal_file() {
        let full = Path::new("/dev/full");
        if !full.exists() {
            return;
        }
        let j = Journal {
            path: full.to_owned(),
            run: "A".into(),
            file: Mutex::new(OpenOptions::new().write(true).open(full).unwrap()),
        };
        let e = j.append(&row(0)).unwrap_err().to_string();
        assert!(e.starts_with("/dev/full: No space left on device"), "{e}");
    }
}
