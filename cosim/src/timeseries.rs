//! CSV time series; [`CsvObserver`] writes one from a run. A writer flushes at least every second
//! of wall time, so a killed run keeps its data up to then, but for the rows the observer still
//! queues (at most [`MAX_QUEUED_ROWS`]: a few milliseconds of a run-up) and its checkpoint cuts
//! the file back to its own rows on resume anyway.

use crate::parallel::{IdleWork, IdleWorkers};
use std::collections::VecDeque;
use std::fs::File;
use std::io::{BufWriter, Seek, Write};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

pub struct TimeSeriesWriter {
    path: std::path::PathBuf,
    out: BufWriter<File>,
    last_flush: Instant,
    /// Bytes written so far (the checkpoint records it to truncate on resume).
    pub bytes: u64,
    /// FNV-1a 64 of the first `checked_bytes` bytes ([`TimeSeriesWriter::check`] extends it).
    check_state: u64,
    checked_bytes: u64,
    /// One row's text, reused (no allocation per value or row).
    line: String,
}

const FLUSH_EVERY: Duration = Duration::from_secs(1);

impl TimeSeriesWriter {
    /// New file with the header `time [s]`, then `name [unit]` per column. An old file or a
    /// symbolic link at `path` is replaced, never written through (files.rs).
    pub fn create(path: &Path, columns: &[(String, String)]) -> std::io::Result<Self> {
        let mut w = TimeSeriesWriter {
            path: path.to_path_buf(),
            out: BufWriter::new(crate::files::create_replacing(path)?),
            last_flush: Instant::now(),
            bytes: 0,
            check_state: crate::checkpoint::FNV_START,
            checked_bytes: 0,
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
    /// from after the checkpoint, is cut). A symbolic link at `path` is refused.
    pub fn resume(path: &Path, bytes: u64, check: u64) -> std::io::Result<Self> {
        let f = crate::files::open_existing_for_writing(path)?;
        f.set_len(bytes)?;
        let mut f = f;
        f.seek(std::io::SeekFrom::End(0))?;
        Ok(TimeSeriesWriter {
            path: path.to_path_buf(),
            out: BufWriter::new(f),
            last_flush: Instant::now(),
            bytes,
            check_state: check,
            checked_bytes: bytes,
            line: String::new(),
        })
    }

    fn write_raw(&mut self, b: &[u8]) -> std::io::Result<()> {
        self.out.write_all(b)?;
        self.bytes += b.len() as u64;
        Ok(())
    }

    /// FNV-1a 64 of the `bytes` written so far (a checkpoint records it: a resume checks the
    /// prefix it keeps). Flushes, then continues the checksum over the bytes written since the
    /// last call, read back from the file (the page cache): FNV-1a takes one multiply per byte
    /// in a chain, ~48 ms of a path-1 run-up's 44 MB if every row went through it on the
    /// master's thread, though only checkpoints (and an interrupted run's last one) read it.
    pub fn check(&mut self) -> std::io::Result<u64> {
        self.flush()?;
        if self.checked_bytes < self.bytes {
            use std::io::{Read, SeekFrom};
            let mut f = File::open(&self.path)?;
            f.seek(SeekFrom::Start(self.checked_bytes))?;
            let mut rest = f.take(self.bytes - self.checked_bytes);
            let mut buf = vec![0u8; 1 << 16];
            let mut h = self.check_state;
            let mut read = 0u64;
            loop {
                let n = rest.read(&mut buf)?;
                if n == 0 {
                    break;
                }
                h = crate::checkpoint::checksum_continue(h, &buf[..n]);
                read += n as u64;
            }
            if read != self.bytes - self.checked_bytes {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::UnexpectedEof,
                    format!(
                        "{} bytes in the file where {} were written",
                        self.checked_bytes + read,
                        self.bytes
                    ),
                ));
            }
            self.check_state = h;
            self.checked_bytes = self.bytes;
        }
        Ok(self.check_state)
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
///
/// A sample's values are queued; the row's text is made and written by whichever thread gets to
/// it first: a thread waiting on the run's parallel pool, one row at a time between its steps
/// ([`IdleWork`]), or this observer itself once [`MAX_QUEUED_ROWS`] rows wait, and at every
/// checkpoint and the end. One lock keeps the rows in order. In a path-1 run-up the rows' text
/// and writes would be ~60-80 ms of the master's own thread, which the pool's worker instead
/// does while it waits for the next film step. Without a pool every row is written at once.
pub struct CsvObserver {
    path: std::path::PathBuf,
    queue: Option<Arc<RowQueue>>,
    /// The pool whose waiting threads take rows (otherwise each row is written as it comes);
    /// the queue is withdrawn from it when the run ends.
    idle_workers: Option<IdleWorkers>,
}

/// Rows a sample leaves for the pool's waiting threads before the observer writes them itself
/// (a worker parked because its films step one after the other takes none).
pub const MAX_QUEUED_ROWS: usize = 64;

struct RowQueue {
    /// Rows waiting (read without the lock by the idle threads).
    pending: AtomicUsize,
    rows: Mutex<QueuedRows>,
}

struct QueuedRows {
    writer: TimeSeriesWriter,
    /// Waiting rows, time first, oldest first; `spare` keeps written rows' buffers.
    waiting: VecDeque<Vec<f64>>,
    spare: Vec<Vec<f64>>,
    /// The first failed write (no row is written after it).
    error: Option<String>,
}

impl RowQueue {
    fn lock(&self) -> Result<MutexGuard<'_, QueuedRows>, String> {
        self.rows
            .lock()
            .map_err(|_| "the time-series writer failed (a panic while writing a row)".to_string())
    }

    /// Writes the oldest waiting row; false if none waited.
    fn write_one(&self, q: &mut QueuedRows) -> bool {
        let Some(row) = q.waiting.pop_front() else {
            return false;
        };
        self.pending.fetch_sub(1, Ordering::Release);
        if q.error.is_none() {
            if let Err(e) = q.writer.row(row[0], &row[1..]) {
                q.error = Some(format!("{}: {e}", q.writer.path.display()));
            }
        }
        q.spare.push(row);
        true
    }

    /// Writes every waiting row; the first write error, if any.
    fn write_all(&self, q: &mut QueuedRows) -> Result<(), String> {
        while self.write_one(q) {}
        match &q.error {
            Some(e) => Err(e.clone()),
            None => Ok(()),
        }
    }
}

impl IdleWork for RowQueue {
    fn run_one(&self) -> bool {
        if self.pending.load(Ordering::Acquire) == 0 {
            return false;
        }
        // The master holds the lock only to queue a row or to write them all: then there is
        // nothing for this thread to do.
        match self.rows.try_lock() {
            Ok(mut q) => self.write_one(&mut q),
            Err(_) => false,
        }
    }
}

impl CsvObserver {
    pub fn new(path: impl Into<std::path::PathBuf>) -> Self {
        CsvObserver {
            path: path.into(),
            queue: None,
            idle_workers: None,
        }
    }

    fn queue(&self) -> Result<&Arc<RowQueue>, String> {
        self.queue
            .as_ref()
            .ok_or_else(|| format!("{}: written before the run started", self.path.display()))
    }
}

impl crate::Observer for CsvObserver {
    fn started(
        &mut self,
        run: &crate::observer::RunStart<'_>,
    ) -> Result<(), crate::observer::ObserverError> {
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
        let writer = w.map_err(|e| crate::observer::ObserverError::io(&self.path, e))?;
        let queue = Arc::new(RowQueue {
            pending: AtomicUsize::new(0),
            rows: Mutex::new(QueuedRows {
                writer,
                waiting: VecDeque::new(),
                spare: Vec::new(),
                error: None,
            }),
        });
        if let Some(idle) = &run.idle_workers {
            idle.offer(queue.clone());
        }
        self.idle_workers = run.idle_workers.clone();
        self.queue = Some(queue);
        Ok(())
    }

    fn sample(&mut self, t_s: f64, values: &[f64]) -> Result<(), crate::observer::ObserverError> {
        let queue = self.queue()?;
        let mut q = queue.lock()?;
        if let Some(e) = &q.error {
            return Err(e.clone().into());
        }
        let mut row = q.spare.pop().unwrap_or_default();
        row.clear();
        row.push(t_s);
        row.extend_from_slice(values);
        q.waiting.push_back(row);
        queue.pending.fetch_add(1, Ordering::Release);
        if self.idle_workers.is_none() || q.waiting.len() > MAX_QUEUED_ROWS {
            queue.write_all(&mut q)?;
        }
        Ok(())
    }

    fn checkpoint(
        &mut self,
        state: &mut crate::checkpoint::MasterState,
    ) -> Result<(), crate::observer::ObserverError> {
        let queue = self.queue()?;
        let mut q = queue.lock()?;
        queue.write_all(&mut q)?;
        let path = self.path.clone();
        state.csv_check = Some(
            q.writer
                .check()
                .map_err(|e| crate::observer::ObserverError::io(&path, e))?,
        );
        state.csv_bytes = q.writer.bytes;
        Ok(())
    }

    fn finished(
        &mut self,
        _cosim: &crate::CoSim,
        _report: &crate::RunReport,
    ) -> Result<(), crate::observer::ObserverError> {
        self.withdraw_queue();
        let Some(queue) = &self.queue else {
            return Ok(());
        };
        let mut q = queue.lock()?;
        queue.write_all(&mut q)?;
        q.writer
            .flush()
            .map_err(|e| crate::observer::ObserverError::io(&self.path, e))
    }
}

impl CsvObserver {
    /// Takes the row queue back from the pool's waiting threads (the run has ended; this
    /// observer writes what is left).
    fn withdraw_queue(&mut self) {
        if let (Some(idle), Some(queue)) = (self.idle_workers.take(), &self.queue) {
            let work: Arc<dyn IdleWork> = queue.clone();
            idle.withdraw(&work);
        }
    }
}

impl Drop for CsvObserver {
    /// Rows still queued are written (a run that ends without `finished` loses none).
    fn drop(&mut self) {
        self.withdraw_queue();
        if let Some(queue) = &self.queue {
            if let Ok(mut q) = queue.rows.lock() {
                let _ = queue.write_all(&mut q);
                let _ = q.writer.flush();
            }
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

    /// The checksum taken in pieces (at checkpoints, after a resume) is the whole file's.
    #[test]
    fn the_checksum_in_pieces_and_after_a_resume_is_the_whole_files() {
        let dir = std::env::temp_dir().join(format!("cosim-ts-check-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("s.csv");
        let whole = |p: &Path| crate::checkpoint::checksum(&std::fs::read(p).unwrap());
        let mut w = TimeSeriesWriter::create(&p, &[("a.x".into(), "m".into())]).unwrap();
        assert_eq!(w.check().unwrap(), whole(&p), "the header alone");
        // More than one read-back buffer between two checks.
        for k in 0..20_000 {
            w.row(k as f64 * 1e-5, &[(k as f64).sqrt()]).unwrap();
        }
        let first = w.check().unwrap();
        assert_eq!(first, whole(&p));
        assert_eq!(w.check().unwrap(), first, "nothing written since");
        let bytes = w.bytes;
        w.row(0.5, &[1.0]).unwrap();
        drop(w);
        // A resume cuts the row after the checkpoint and continues the checksum from it.
        let mut w = TimeSeriesWriter::resume(&p, bytes, first).unwrap();
        for k in 0..100 {
            w.row(1.0 + k as f64, &[-1.0]).unwrap();
        }
        assert_eq!(w.check().unwrap(), whole(&p));
        assert_ne!(w.check().unwrap(), first);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_damaged_series_is_not_resumed() {
        let dir = std::env::temp_dir().join(format!("cosim-ts-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("s.csv");
        let mut w = TimeSeriesWriter::create(&p, &[("a.x".into(), "m".into())]).unwrap();
        for k in 0..10 {
            w.row(k as f64, &[1.0]).unwrap();
        }
        let check = w.check().unwrap();
        let (bytes, rows) = (w.bytes, 10);
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

    struct Sleeper;

    impl crate::parallel::Step for Sleeper {
        fn step(&mut self, _t: f64, _h: f64) -> Result<(), fmi_core::CallError> {
            std::thread::sleep(Duration::from_micros(200));
            Ok(())
        }
    }

    /// Rows queued for a pool's waiting threads reach the file complete and in order, the same
    /// bytes as rows written at once; a checkpoint in between records exactly the rows sampled
    /// before it, with their checksum; the ended run's queue is withdrawn from the pool.
    #[test]
    fn rows_written_by_the_pools_threads_are_the_rows_written_at_once() {
        use crate::Observer;
        let dir = std::env::temp_dir().join(format!("cosim-ts-pool-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let columns: Vec<crate::Recorded> = ["a", "b", "c"]
            .iter()
            .enumerate()
            .map(|(k, n)| crate::Recorded {
                subsystem: 0,
                vr: k as u32,
                name: format!("m.{n}"),
                unit: "m".into(),
            })
            .collect();
        let value = |k: usize, j: usize| ((k * 3 + j) as f64 * 0.37).sin() * 1e-6;
        let pool = crate::parallel::StepPool::new(2);
        let mut m = [Sleeper, Sleeper];
        let mut file = |name: &str, idle: Option<crate::parallel::IdleWorkers>| {
            let path = dir.join(name);
            let mut obs = CsvObserver::new(&path);
            obs.started(&crate::RunStart {
                columns: &columns,
                resumed_from: None,
                stop_time_s: 1.0,
                output_interval_s: 1e-3,
                idle_workers: idle.clone(),
            })
            .unwrap();
            let mut at_checkpoint = None;
            for k in 0..500 {
                let v = [value(k, 0), value(k, 1), value(k, 2)];
                obs.sample(k as f64 * 1e-3, &v).unwrap();
                if idle.is_some() {
                    let mut refs: Vec<&mut Sleeper> = m.iter_mut().collect();
                    pool.step(&mut refs, 0.0, 1.0);
                }
                if k == 299 {
                    let state = crate::algorithm::AlgorithmState {
                        t_s: 0.3,
                        histories: vec![],
                        refine_level: 0,
                    };
                    let mut ms = crate::checkpoint::MasterState::new(&state, 300, 300, 0.0);
                    obs.checkpoint(&mut ms).unwrap();
                    at_checkpoint = Some((ms.csv_bytes, ms.csv_check));
                }
            }
            let queue = Arc::downgrade(obs.queue.as_ref().unwrap());
            drop(obs);
            // The pool, which lives on for other runs, holds the ended run's queue no more.
            assert!(
                queue.upgrade().is_none(),
                "{name}: the queue outlives its run"
            );
            (std::fs::read(&path).unwrap(), at_checkpoint.unwrap())
        };
        let (at_once, _) = file("at_once.csv", None);
        let (pooled, (bytes, check)) = file("pooled.csv", Some(pool.idle_workers()));
        assert_eq!(pooled, at_once);
        let prefix = &pooled[..bytes as usize];
        assert_eq!(prefix.iter().filter(|b| **b == b'\n').count(), 301);
        assert_eq!(check, Some(crate::checkpoint::checksum(prefix)));
        let _ = std::fs::remove_dir_all(&dir);
    }

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
