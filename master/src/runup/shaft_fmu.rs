//! The rotor FMU of a flexible rotor: `rotor.fmu` with the design's shaft in its resources
//! (`resources/shaft.json`, read by the FMU when it is instantiated: `fmu_rotor::flexible`).
//! The same binary and modelDescription.xml, so any master that runs `rotor.fmu` runs it; the
//! shaft travels inside the archive, so a run folder's system file names one file that holds
//! all of its rotor.
//!
//! The file is named by a checksum of the base FMU and the shaft (`rotor-shaft-HASH.fmu`) and
//! kept in `FMU_DIR/shafts/` (or the temporary folder where FMU_DIR cannot be written): a sweep's
//! run-ups of one shaft share it, and a rebuilt base FMU or another shaft gives another file.

use crate::design::shaft::ShaftSpec;
use fmu_rotor::flexible::{FlexibleSpec, RESOURCE_FILE};
use std::io::{Cursor, Read, Write};
use std::path::{Path, PathBuf};

/// The flexible rotor the FMU reads.
pub fn spec_of(shaft: &ShaftSpec) -> FlexibleSpec {
    FlexibleSpec {
        shaft: shaft.model.clone(),
        bearing_nodes: shaft.bearing_nodes,
        cutoff_hz: None,
    }
}

/// FNV-1a, 64 bits: a name for the content, not a security measure.
fn fnv1a(parts: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in parts {
        for b in p.iter() {
            h ^= *b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// The rotor FMU with `shaft` inside, written if it is not there yet; returns its path.
pub fn rotor_fmu_with_shaft(fmu_dir: &Path, shaft: &ShaftSpec) -> Result<PathBuf, String> {
    let base_path = fmu_dir.join("rotor.fmu");
    let base = std::fs::read(&base_path)
        .map_err(|e| format!("{}: cannot be read: {e}", base_path.display()))?;
    let json = serde_json::to_string_pretty(&spec_of(shaft)).expect("a shaft is plain data");
    let name = format!("rotor-shaft-{:016x}.fmu", fnv1a(&[&base, json.as_bytes()]));
    let mut last_error = String::new();
    for dir in [
        fmu_dir.join("shafts"),
        std::env::temp_dir().join("airring-shaft-fmus"),
    ] {
        let path = dir.join(&name);
        if path.is_file() {
            return Ok(path);
        }
        match std::fs::create_dir_all(&dir)
            .and_then(|()| pack(&base, &json).map_err(std::io::Error::other))
            .and_then(|bytes| write_atomically(&path, &bytes))
        {
            Ok(()) => return Ok(path),
            Err(e) => last_error = format!("{}: {e}", path.display()),
        }
    }
    Err(format!(
        "the rotor FMU with the shaft could not be written: {last_error}"
    ))
}

/// Writes `bytes` to `path` through a temporary file of this process: the run-ups of a sweep
/// may write the same file at once, each renaming a whole copy into place.
fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(name);
    let written = std::fs::File::create(&tmp).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()
    });
    if let Err(e) = written.and_then(|()| std::fs::rename(&tmp, path)) {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    Ok(())
}

/// `base` (an FMU archive) with `resources/shaft.json` = `json` added (one it had replaced).
fn pack(base: &[u8], json: &str) -> Result<Vec<u8>, String> {
    let entry = format!("resources/{RESOURCE_FILE}");
    let mut archive =
        zip::ZipArchive::new(Cursor::new(base)).map_err(|e| format!("rotor.fmu: {e}"))?;
    let mut out = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for i in 0..archive.len() {
        let file = archive
            .by_index_raw(i)
            .map_err(|e| format!("rotor.fmu: {e}"))?;
        if file.name() == entry {
            continue;
        }
        out.raw_copy_file(file)
            .map_err(|e| format!("rotor.fmu: {e}"))?;
    }
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    out.start_file(entry.as_str(), options)
        .and_then(|()| out.write_all(json.as_bytes()).map_err(Into::into))
        .map_err(|e| e.to_string())?;
    let bytes = out.finish().map_err(|e| e.to_string())?.into_inner();
    Ok(bytes)
}

/// The shaft a rotor FMU carries, if any (tests, `airring` messages).
pub fn shaft_in(fmu: &Path) -> Result<Option<FlexibleSpec>, String> {
    let bytes = std::fs::read(fmu).map_err(|e| format!("{}: {e}", fmu.display()))?;
    let mut archive =
        zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| format!("{}: {e}", fmu.display()))?;
    let mut file = match archive.by_name(&format!("resources/{RESOURCE_FILE}")) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(format!("{}: {e}", fmu.display())),
    };
    let mut text = String::new();
    file.read_to_string(&mut text)
        .map_err(|e| format!("{}: {e}", fmu.display()))?;
    serde_json::from_str(&text)
        .map(Some)
        .map_err(|e| format!("{}: {e}", fmu.display()))
}
