//! Least damping ratios of the linear analysis kept on disk, so that a sweep's run-ups reuse what
//! its linear prediction (`sweep --predict-first`) and each other already analysed.
//!
//! Why: a run-up plans its calm macro steps (`crate::calm_steps`) from the linear analysis at
//! every 50 Hz, ~17 ms per speed on the coarse mesh, ~0.6 s of a 5 s stable run-up. The sweep's
//! prediction analyses every point at every 100 Hz on the same mesh: half of those speeds, with
//! the same model parameters, already done.
//!
//! An entry holds one speed's least damping ratio (or that the analysis failed there), under a key
//! that is everything the analysis depends on: the rotor's and both films' parameters as the
//! linear analysis takes them (`stability::params_of`; the films' time-integration tolerances,
//! which it does not read, left out), the speed, and the `airring` build (the
//! executable's size and modification time: a rebuilt analysis may compute something else). A
//! parameter that differs in any bit is a different key, so a hit is the value the analysis would
//! return; a file whose key text differs from the one asked for (a hash collision, a file from
//! elsewhere) is a miss. Values are kept as their f64 bits: nothing is lost in a decimal round
//! trip. Entries are written to a temporary file and renamed, so two run-ups writing the same
//! entry at once leave one whole file.

use fmu_airfilm::BearingParams;
use fmu_rotor::RotorParams;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A folder of analysed speeds (created when opened).
#[derive(Clone, Debug)]
pub struct LinearCache {
    dir: PathBuf,
    build: String,
}

/// The key of one speed's analysis.
#[derive(Serialize)]
struct Key<'a> {
    build: &'a str,
    rotor: &'a RotorParams,
    films: &'a [BearingParams; 2],
    speed_hz_bits: u64,
}

/// A film's parameters as the linear analysis reads them: its time-integration tolerances (`rtol`,
/// `atol_pa`, read by the transient integrator only) set to the film's defaults. A run-up whose
/// mesh comes with its own tolerance (`runup::film_mesh_for`: 10 x 2 at 6e-4 / 60 Pa) plans its
/// calm steps on the predictions' coarse mesh, and finds the analyses a sweep's predictions made
/// there with the default tolerance.
fn without_time_integration_tolerance(mut film: BearingParams) -> BearingParams {
    let defaults = BearingParams::paper();
    (film.rtol, film.atol_pa) = (defaults.rtol, defaults.atol_pa);
    film
}

/// One entry file.
#[derive(Serialize, Deserialize)]
struct Entry {
    key: String,
    /// Least damping ratio's bits; None where the analysis failed at this speed.
    least_damping_bits: Option<u64>,
    /// The same value for people reading the file.
    least_damping: Option<f64>,
}

impl LinearCache {
    /// The cache in `dir` for this build of `airring`.
    pub fn open(dir: &Path) -> Result<Self, String> {
        let build = build_identity()?;
        Self::open_for_build(dir, &build)
    }

    /// The cache in `dir` for a named build (the tests' other build).
    pub fn open_for_build(dir: &Path, build: &str) -> Result<Self, String> {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        Ok(LinearCache {
            dir: dir.to_path_buf(),
            build: build.to_string(),
        })
    }

    fn key(&self, rotor: &RotorParams, films: &[BearingParams; 2], speed_hz: f64) -> String {
        serde_json::to_string(&Key {
            build: &self.build,
            rotor,
            films: &films.clone().map(without_time_integration_tolerance),
            speed_hz_bits: speed_hz.to_bits(),
        })
        .expect("parameters serialize")
    }

    fn path_of(&self, key: &str) -> PathBuf {
        self.dir
            .join(format!("{:016x}.json", fnv1a(key.as_bytes())))
    }

    /// The least damping ratio analysed at `speed_hz` with these parameters: Some(Some(ratio)),
    /// Some(None) where the analysis failed there, None where it was not analysed.
    pub fn get(
        &self,
        rotor: &RotorParams,
        films: &[BearingParams; 2],
        speed_hz: f64,
    ) -> Option<Option<f64>> {
        let key = self.key(rotor, films, speed_hz);
        let text = std::fs::read_to_string(self.path_of(&key)).ok()?;
        let entry: Entry = serde_json::from_str(&text).ok()?;
        (entry.key == key).then(|| entry.least_damping_bits.map(f64::from_bits))
    }

    /// Keeps one speed's result; a cache that cannot be written is only slower, so errors are
    /// returned for the caller to report, never fatal.
    pub fn put(
        &self,
        rotor: &RotorParams,
        films: &[BearingParams; 2],
        speed_hz: f64,
        least_damping: Option<f64>,
    ) -> Result<(), String> {
        let key = self.key(rotor, films, speed_hz);
        let path = self.path_of(&key);
        let entry = Entry {
            key,
            least_damping_bits: least_damping.map(f64::to_bits),
            least_damping,
        };
        let tmp = path.with_extension(format!("tmp-{}", std::process::id()));
        let text = serde_json::to_string(&entry).expect("entry serializes");
        cosim::files::create_replacing(&tmp)
            .and_then(|mut f| std::io::Write::write_all(&mut f, text.as_bytes()))
            .and_then(|_| std::fs::rename(&tmp, &path))
            .map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                format!("{}: {e}", path.display())
            })
    }
}

/// This executable's size and modification time.
fn build_identity() -> Result<String, String> {
    let exe = std::env::current_exe().map_err(|e| format!("the running executable: {e}"))?;
    let meta = std::fs::metadata(&exe).map_err(|e| format!("{}: {e}", exe.display()))?;
    let modified = meta
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_nanos());
    Ok(format!("{} bytes, modified {modified} ns", meta.len()))
}

/// 64-bit FNV-1a: the file name of a key (the key itself is checked on reading).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runup::RunupSettings;

    fn params(clearance_um: f64) -> (RotorParams, [BearingParams; 2]) {
        let mut s = RunupSettings::preset("path1").unwrap();
        s.clearance_um = clearance_um;
        crate::stability::params_of(&s).unwrap()
    }

    #[test]
    fn an_entry_is_found_only_under_its_own_parameters_speed_and_build() {
        let dir = std::env::temp_dir().join(format!("airring-linear-cache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let cache = LinearCache::open_for_build(&dir, "build A").unwrap();
        let (rotor, films) = params(20.0);
        assert_eq!(cache.get(&rotor, &films, 100.0), None);
        // A value with all its bits (one whose shortest decimal needs 17 digits), and a failed
        // speed.
        let ratio = f64::from_bits(0.1f64.to_bits() + 1);
        cache.put(&rotor, &films, 100.0, Some(ratio)).unwrap();
        cache.put(&rotor, &films, 150.0, None).unwrap();
        assert_eq!(
            cache
                .get(&rotor, &films, 100.0)
                .map(|r| r.map(f64::to_bits)),
            Some(Some(ratio.to_bits()))
        );
        assert_eq!(cache.get(&rotor, &films, 150.0), Some(None));
        // Another speed (by one bit), other parameters, another build: not found.
        assert_eq!(
            cache.get(&rotor, &films, f64::from_bits(100f64.to_bits() + 1)),
            None
        );
        let (rotor_b, films_b) = params(15.0);
        assert_eq!(cache.get(&rotor_b, &films_b, 100.0), None);
        let mut films_c = films.clone();
        films_c[1].bore.c_m *= 1.0 + f64::EPSILON;
        assert_eq!(cache.get(&rotor, &films_c, 100.0), None);
        // The films' time-integration tolerances are no part of the analysis: found.
        let mut films_d = films.clone();
        (films_d[0].rtol, films_d[1].atol_pa) = (6e-4, 60.0);
        assert_eq!(cache.get(&rotor, &films_d, 150.0), Some(None));
        let other = LinearCache::open_for_build(&dir, "build B").unwrap();
        assert_eq!(other.get(&rotor, &films, 100.0), None);
        // A file under the right name but with another key is a miss, not a wrong value.
        let key = cache.key(&rotor, &films, 100.0);
        let path = cache.path_of(&key);
        let foreign = Entry {
            key: key.replace("build A", "build C"),
            least_damping_bits: Some(0.5f64.to_bits()),
            least_damping: Some(0.5),
        };
        std::fs::write(&path, serde_json::to_string(&foreign).unwrap()).unwrap();
        assert_eq!(cache.get(&rotor, &films, 100.0), None);
        // A damaged file too; writing again repairs it.
        std::fs::write(&path, "{ not json").unwrap();
        assert_eq!(cache.get(&rotor, &films, 100.0), None);
        cache.put(&rotor, &films, 100.0, Some(ratio)).unwrap();
        assert_eq!(cache.get(&rotor, &films, 100.0), Some(Some(ratio)));
        // No temporary files are left behind.
        let leftovers = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_none_or(|x| x != "json"))
            .count();
        assert_eq!(leftovers, 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
