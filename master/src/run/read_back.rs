//! What a run folder says about the bearings it simulated: each air film's bore, read from the
//! folder's own system file through the film FMU's variable table (the same conversion the run
//! applied), never from a default. Works on run folders of earlier versions too: they all keep
//! the system file they ran.

use bearing::Bore;
use std::path::Path;

/// The air-film instances of a run-up, in the analysis order [C, T].
pub const FILM_INSTANCES: [&str; 2] = ["film_C", "film_T"];

/// The bores [C, T] of the air films `film_C` and `film_T` of a system file; None when the
/// system has no such pair (not a run-up).
pub fn bores_of_system(system: &Path) -> Result<Option<[Bore; 2]>, String> {
    let sys = cosim::System::load(system).map_err(|e| e.to_string())?;
    let mut bores = Vec::with_capacity(2);
    for inst in FILM_INSTANCES {
        let Some(entry) = sys.file.fmu.iter().find(|e| e.name.get_ref() == inst) else {
            return Ok(None);
        };
        let values: Vec<(String, toml::Value)> = entry
            .parameters
            .iter()
            .map(|(name, value)| (name.clone(), value.get_ref().clone()))
            .collect();
        let store = crate::fmu_params::store_for(inst, &values)
            .map_err(|e| format!("{}: {inst}: {e}", system.display()))?;
        bores.push(fmu_airfilm::shell::params_from(&store).bore);
    }
    Ok(Some([bores[0].clone(), bores[1].clone()]))
}

/// The bores of the run folder `dir` (its `system.toml`).
pub fn bores_of_run(dir: &Path) -> Result<Option<[Bore; 2]>, String> {
    bores_of_system(&dir.join("system.toml"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("airring-runfolder-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("system.toml");
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn each_films_bore_comes_from_its_own_parameters() {
        let p = write(
            "two",
            r#"
[[fmu]]
name = "film_C"
path = "airfilm.fmu"
parameters = { C = "20 um", dH = 4.5e-5 }

[[fmu]]
name = "film_T"
path = "airfilm.fmu"
parameters = { C = "25 um", n_lobes = 4, phi_t = "80 deg" }

[algorithm]
macro_step = "20 us"
stop_time = "1 s"
"#,
        );
        let [c, t] = bores_of_system(&p).unwrap().unwrap();
        // Converted as the run converts them (through the FMU's display unit um).
        let si = |key: &str, text: &str| match crate::fmu_params::FmuParameter::parse(key, text)
            .unwrap()
            .value
        {
            crate::fmu_params::Value::Real(v) => v,
            other => panic!("{other:?}"),
        };
        assert_eq!(c.c_m, si("film_C.C", "20 um"));
        assert_eq!(c.dh_m, 4.5e-5);
        assert_eq!(t.c_m, si("film_T.C", "25 um"));
        assert_eq!(t.n_lobes, 4);
        assert!((t.phi_t_rad - 80f64.to_radians()).abs() < 1e-15);
        // What the system file does not set is the FMU's default.
        assert_eq!(t.dh_m, Bore::paper().dh_m);
    }

    #[test]
    fn a_system_without_the_two_films_is_not_a_runup() {
        let p = write(
            "none",
            r#"
[[fmu]]
name = "a"
path = "oscillator.fmu"

[algorithm]
macro_step = "1 ms"
stop_time = "1 s"
"#,
        );
        assert_eq!(bores_of_system(&p).unwrap(), None);
    }
}
