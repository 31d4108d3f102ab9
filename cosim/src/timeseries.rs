//! CSV time series, flushed at least every second of wall time so a killed run keeps its data;
//! [`CsvObserver`] writes one from a run.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Seek, Write};
use std::path::Path;
use std::time::{Duration, Instant};

pub struct TimeSeriesWriter {
    out: BufWriter<File>,
    last_flush: Instant,
    /// Bytes written so far (the checkpoint records it to truncate on resume).
    pub bytes: u64,
    /// FNV-1a 64 of those bytes (the checkpoint records it: a resume checks the prefix it keeps).
    pub check: u64,
    /// One row's text, reused (no allocation per value or row).
    line: String,
}

const FLUSH_EVERY: Duration = Duration::from_secs(1);

impl TimeSeriesWriter {
    /// New file with the header `time [s]`, then `name [unit]` per column.
    pub fn create(path: &Path, columns: &[(String, String)]) -> std::io::Result<Self> {
        let mut w = TimeSeriesWriter {
            out: BufWriter::new(File::create(path)?),
            last_flush: Instant::now(),
            bytes: 0,
            check: crate::checkpoint::FNV_START,
            line: String::new(),
        };
        let mut header = String::from("time [s]");
        for (name, unit) in columns {
            header.push_str(&format!(
                ",{name} [{}]",
                if unit.is_empty() { "1" } else { unit }
            ));
        }
        header.push('\n');
        w.write_raw(header.as_bytes())?;
        w.out.flush()?;
        Ok(w)
    }

    /// Reopens a file for appending after `bytes` whose checksum is `check` (everything later,
    /// from after the checkpoint, is cut).
    pub fn resume(path: &Path, bytes: u64, check: u64) -> std::io::Result<Self> {
        let f = OpenOptions::new().write(true).open(path)?;
        f.set_len(bytes)?;
        let mut f = f;
        f.seek(std::io::SeekFrom::End(0))?;
        Ok(TimeSeriesWriter {
            out: BufWriter::new(f),
            last_flush: Instant::now(),
            bytes,
            check,
            line: String::new(),
        })
    }

    fn write_raw(&mut self, b: &[u8]) -> std::io::Result<()> {
        self.out.write_all(b)?;
        self.bytes += b.len() as u64;
        self.check = crate::checkpoint::checksum_continue(self.check, b);
        Ok(())
    }

    pub fn row(&mut self, t: f64, values: &[f64]) -> std::io::Result<()> {
        let mut line = std::mem::take(&mut self.line);
        line.clear();
        // Ryu: the shortest text that reads back to the same f64 (like `{:?}`, ~5x faster; the
        // rows are most of the master's own work in a run-up).
        let mut buf = ryu::Buffer::new();
        line.push_str(buf.format(t));
        for v in values {
            line.push(',');
            line.push_str(buf.format(*v));
        }
        line.push('\n');
        let r = self.write_raw(line.as_bytes());
        self.line = line;
        r?;
        if self.last_flush.elapsed() >= FLUSH_EVERY {
            self.flush()?;
        }
        Ok(())
    }

    pub fn flush(&mut self) -> std::io::Result<()> {
        self.last_flush = Instant::now();
        self.out.flush()
    }
}

/// The time-series file as an observer: `timeseries.csv` in the run folder, created at the start
/// (or cut back to the checkpoint's byte count on resume), a row per sample, flushed at every
/// checkpoint and at the end.
pub struct CsvObserver {
    path: std::path::PathBuf,
    writer: Option<TimeSeriesWriter>,
}

impl CsvObserver {
    pub fn new(path: impl Into<std::path::PathBuf>) -> Self {
        CsvObserver {
            path: path.into(),
            writer: None,
        }
    }

    fn writer(&mut self) -> Result<&mut TimeSeriesWriter, String> {
        self.writer
            .as_mut()
            .ok_or_else(|| format!("{}: written before the run started", self.path.display()))
    }
}

impl crate::Observer for CsvObserver {
    fn started(&mut self, run: &crate::observer::RunStart<'_>) -> Result<(), String> {
        let w = match run.resumed_from {
            Some(m) => {
                let check =
                    check_resumable(&self.path, m.csv_bytes, m.next_output_index, m.csv_check)?;
                TimeSeriesWriter::resume(&self.path, m.csv_bytes, check)
            }
            None => {
                let columns: Vec<(String, String)> = run
                    .columns
                    .iter()
                    .map(|r| (r.name.clone(), r.unit.clone()))
                    .collect();
                TimeSeriesWriter::create(&self.path, &columns)
            }
        };
        self.writer = Some(w.map_err(|e| format!("{}: {e}", self.path.display()))?);
        Ok(())
    }

    fn sample(&mut self, t_s: f64, values: &[f64]) -> Result<(), String> {
        let path = self.path.display().to_string();
        self.writer()?
            .row(t_s, values)
            .map_err(|e| format!("{path}: {e}"))
    }

    fn checkpoint(&mut self, state: &mut crate::checkpoint::MasterState) -> Result<(), String> {
        let path = self.path.display().to_string();
        let w = self.writer()?;
        w.flush().map_err(|e| format!("{path}: {e}"))?;
        state.csv_bytes = w.bytes;
        state.csv_check = Some(w.check);
        Ok(())
    }

    fn finished(
        &mut self,
        _cosim: &crate::CoSim,
        _report: &crate::RunReport,
    ) -> Result<(), String> {
        let path = self.path.display().to_string();
        match self.writer.as_mut() {
            Some(w) => w.flush().map_err(|e| format!("{path}: {e}")),
            None => Ok(()),
        }
    }
}

/// A resume cuts the file back to `bytes`: that prefix must be the header and exactly `rows`
/// whole rows with the checksum `check` the checkpoint recorded (None: unchecked, older
/// checkpoints), so a truncated, edited or zero-filled file is refused instead of being continued
/// into a series with holes. Returns the prefix's checksum.
fn check_resumable(path: &Path, bytes: u64, rows: u64, check: Option<u64>) -> Result<u64, String> {
    let damaged = |what: String| {
        format!(
            "{}: {what}; the run folder is damaged, start the run afresh",
            path.display()
        )
    };
    let len = std::fs::metadata(path)
        .map_err(|e| format!("{}: {e}", path.display()))?
        .len();
    if len < bytes {
        return Err(damaged(format!(
            "{len} bytes, but the checkpoint was taken at {bytes}"
        )));
    }
    let mut prefix = vec![0u8; bytes as usize];
    use std::io::Read;
    File::open(path)
        .and_then(|mut f| f.read_exact(&mut prefix))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if prefix.contains(&0) {
        return Err(damaged("it holds NUL bytes".into()));
    }
    if prefix.last() != Some(&b'\n') {
        return Err(damaged(format!("byte {bytes} does not end a row")));
    }
    let lines = prefix.iter().filter(|b| **b == b'\n').count() as u64;
    if lines != rows + 1 {
        return Err(damaged(format!(
            "{} rows before the checkpoint, which recorded {rows}",
            lines.saturating_sub(1)
        )));
    }
    let sum = crate::checkpoint::checksum(&prefix);
    if check.is_some_and(|c| c != sum) {
        return Err(damaged(format!(
            "its first {bytes} bytes are not the ones the checkpoint recorded (checksum differs)"
        )));
    }
    Ok(sum)
}

/// Reads a time series back: (column names, rows of time + values).
pub fn read(path: &Path) -> std::io::Result<(Vec<String>, Vec<Vec<f64>>)> {
    let text = std::fs::read_to_string(path)?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(|s| s.to_string())
        .collect();
    let rows = lines
        .filter(|l| !l.is_empty())
        .map(|l| {
            l.split(',')
                .map(|x| x.parse::<f64>().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    Ok((header, rows))
}

#[cfg(test)]
mod resume_tests {
    use super::*;

    #[test]
    fn a_damaged_series_is_not_resumed() {
        let dir = std::env::temp_dir().join(format!("cosim-ts-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("s.csv");
        let mut w = TimeSeriesWriter::create(&p, &[("a.x".into(), "m".into())]).unwrap();
        for k in 0..10 {
            w.row(k as f64, &[1.0]).unwrap();
        }
        w.flush().unwrap();
        let (bytes, rows, check) = (w.bytes, 10, w.check);
        drop(w);
        assert_eq!(check_resumable(&p, bytes, rows, Some(check)), Ok(check));
        // (Checkpoints of earlier versions carry no checksum.)
        assert_eq!(check_resumable(&p, bytes, rows, None), Ok(check));
        // Rows after the checkpoint are fine (the resume cuts them).
        std::fs::write(
            &p,
            [std::fs::read(&p).unwrap(), b"10,1\n".to_vec()].concat(),
        )
        .unwrap();
        assert!(check_resumable(&p, bytes, rows, Some(check)).is_ok());
        for (what, edit) in [
            ("truncated", 0usize),
            ("NUL-filled", 1),
            ("mid-row offset", 2),
            ("other row count", 3),
            ("a digit edited", 4),
        ] {
            let good = std::fs::read(&p).unwrap();
            let (file, b, r) = match edit {
                0 => (good[..good.len() / 2].to_vec(), bytes, rows),
                1 => {
                    let mut f = good.clone();
                    f[20..30].fill(0);
                    (f, bytes, rows)
                }
                2 => (good.clone(), bytes - 1, rows),
                3 => (good.clone(), bytes, rows + 1),
                _ => {
                    // Same length, same rows, one value changed: only the checksum sees it.
                    let mut f = good.clone();
                    let k = f.len() / 2 + f[f.len() / 2..].iter().position(|c| *c == b'1').unwrap();
                    f[k] = b'2';
                    (f, bytes, rows)
                }
            };
            std::fs::write(dir.join("bad.csv"), &file).unwrap();
            let e = check_resumable(&dir.join("bad.csv"), b, r, Some(check)).unwrap_err();
            assert!(e.contains("damaged"), "{what}: {e}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every value reads back to the same bits (NaN as NaN): the series is the exact record.
    #[test]
    fn values_round_trip_exactly() {
        let dir = std::env::temp_dir().join(format!("airring-ts-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("ts.csv");
        let cols = [
            ("a".to_string(), "m".to_string()),
            ("b".to_string(), "".to_string()),
        ];
        let values = [
            [1.0, -0.0],
            [1e-300, -2.5e17],
            [0.1 + 0.2, f64::MIN_POSITIVE / 3.0],
            [f64::INFINITY, f64::NEG_INFINITY],
            [f64::NAN, 123456.789],
        ];
        let mut w = TimeSeriesWriter::create(&path, &cols).unwrap();
        for (k, v) in values.iter().enumerate() {
            w.row(k as f64 * 2e-5, v).unwrap();
        }
        w.flush().unwrap();
        let (header, rows) = read(&path).unwrap();
        assert_eq!(header, ["time [s]", "a [m]", "b [1]"]);
        assert_eq!(rows.len(), values.len());
        for (k, (row, v)) in rows.iter().zip(&values).enumerate() {
            assert_eq!(row[0].to_bits(), (k as f64 * 2e-5).to_bits());
            for (x, y) in row[1..].iter().zip(v) {
                assert!(
                    x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()),
                    "{x} vs {y}"
                );
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
