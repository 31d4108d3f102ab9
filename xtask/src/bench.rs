//! `cargo xtask bench runup`: the whole run-up as a benchmark. Runs `airring runup` several times
//! (release build) and prints, per run and as medians, the wall time, the macro steps, the time
//! inside each FMU, the master's own share and how the films were stepped, all read from each
//! run's summary.json. `--load` keeps one busy thread running beside the run-ups (a competing
//! process on a 2-core machine), so the figure under load is one command too.

use crate::{cargo, pack, root, run, target_dir};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

pub struct Options {
    pub preset: String,
    pub stop_s: f64,
    pub runs: usize,
    pub load: bool,
    pub fmu_dir: Option<String>,
    /// A design file (`--design`), e.g. a flexible rotor's `[shaft]`.
    pub design: Option<String>,
}

impl Options {
    pub fn parse(args: &[String]) -> Result<Options, String> {
        let mut o = Options {
            preset: "path1".into(),
            stop_s: 0.3,
            runs: 3,
            load: false,
            fmu_dir: None,
            design: None,
        };
        let mut it = args.iter();
        while let Some(a) = it.next() {
            let mut value = |name: &str| {
                it.next()
                    .cloned()
                    .ok_or_else(|| format!("bench runup: {name} expects a value"))
            };
            match a.as_str() {
                "--preset" => o.preset = value("--preset")?,
                "--stop" => {
                    let v = value("--stop")?;
                    o.stop_s = v
                        .parse()
                        .ok()
                        .filter(|s: &f64| s.is_finite() && *s > 0.0)
                        .ok_or_else(|| format!("bench runup: --stop {v}: expected seconds > 0"))?;
                }
                "--runs" => {
                    let v = value("--runs")?;
                    o.runs = v
                        .parse()
                        .ok()
                        .filter(|n| (1..=50).contains(n))
                        .ok_or_else(|| format!("bench runup: --runs {v}: expected 1 to 50"))?;
                }
                "--load" => o.load = true,
                "--fmu-dir" => o.fmu_dir = Some(value("--fmu-dir")?),
                "--design" => o.design = Some(value("--design")?),
                other => return Err(format!("bench runup: unknown argument '{other}'")),
            }
        }
        Ok(o)
    }
}

/// What one run-up reported.
struct Sample {
    wall_s: f64,
    macro_steps: f64,
    /// Of those, the calm (long) ones; 0 without a calm window.
    calm_steps: f64,
    /// (FMU instance, seconds in its doStep)
    fmus: Vec<(String, f64)>,
    master_s: f64,
    master_percent: f64,
    stepping: String,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn read_summary(path: &std::path::Path) -> Result<Sample, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let s: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let num = |k: &str| {
        s[k].as_f64()
            .ok_or_else(|| format!("{}: no number '{k}'", path.display()))
    };
    if s["status"] != "completed" {
        return Err(format!(
            "{}: the run-up did not complete: {}",
            path.display(),
            s["error"]
        ));
    }
    let fmus = s["wall_in_fmus_s"]
        .as_object()
        .map(|m| {
            m.iter()
                .map(|(k, v)| (k.clone(), v.as_f64().unwrap_or(f64::NAN)))
                .collect()
        })
        .unwrap_or_default();
    let g = &s["group_stepping"];
    let stepping = if g.is_object() {
        format!(
            "{} ({} threaded / {} serial steps)",
            g["choice"].as_str().unwrap_or("?"),
            g["parallel_steps"],
            g["serial_steps"]
        )
    } else {
        "-".into()
    };
    Ok(Sample {
        wall_s: num("wall_time_s")?,
        macro_steps: num("macro_steps")?,
        calm_steps: s["long_macro_steps"].as_f64().unwrap_or(0.0),
        fmus,
        master_s: num("master_overhead_s")?,
        master_percent: num("master_overhead_percent")?,
        stepping,
    })
}

pub fn runup(o: &Options) -> Result<(), String> {
    pack::fmus(None)?;
    run(
        "build master",
        cargo().args(["build", "--release", "-p", "master"]),
    )?;
    let out = std::env::temp_dir().join(format!("airring-bench-runup-{}", std::process::id()));
    let stop = Arc::new(AtomicBool::new(false));
    let busy = o.load.then(|| {
        let stop = stop.clone();
        std::thread::spawn(move || {
            let mut x = 0u64;
            while !stop.load(Ordering::Relaxed) {
                x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
            }
        })
    });
    let mut samples = vec![];
    let result = (|| {
        for i in 0..o.runs {
            let dir: PathBuf = out.join(format!("run{i}"));
            let mut cmd = Command::new(target_dir().join("release/airring"));
            cmd.current_dir(root())
                .args(["runup", "--preset", &o.preset, "--stop"])
                .arg(o.stop_s.to_string())
                .arg("--out")
                .arg(&dir)
                .arg("--overwrite")
                .stdout(Stdio::null())
                .stderr(Stdio::null());
            if let Some(d) = &o.fmu_dir {
                cmd.args(["--fmu-dir", d]);
            }
            if let Some(d) = &o.design {
                cmd.args(["--design", d]);
            }
            let status = cmd
                .status()
                .map_err(|e| format!("airring runup: cannot start: {e}"))?;
            let sample = read_summary(&dir.join("summary.json"));
            if !status.success() {
                return Err(format!(
                    "airring runup (run {i}) failed ({status}); its folder: {}",
                    dir.display()
                ));
            }
            let s = sample?;
            eprintln!(
                "run {i}: wall {:.2} s, {} macro steps, master {:.2} s ({:.1} %), films {}",
                s.wall_s, s.macro_steps, s.master_s, s.master_percent, s.stepping
            );
            samples.push(s);
        }
        Ok(())
    })();
    stop.store(true, Ordering::Relaxed);
    if let Some(b) = busy {
        let _ = b.join();
    }
    result?;
    let _ = std::fs::remove_dir_all(&out);
    println!(
        "run-up benchmark: airring runup --preset {} --stop {} s{}{}, {} runs, medians (whole run-up as summary.json reports it):",
        o.preset,
        o.stop_s,
        o.fmu_dir
            .as_deref()
            .map(|d| format!(" --fmu-dir {d}"))
            .unwrap_or_default(),
        if o.load { ", one busy thread competing" } else { "" },
        samples.len()
    );
    let col = |f: &dyn Fn(&Sample) -> f64| median(samples.iter().map(f).collect());
    println!("  wall time           {:10.2} s", col(&|s| s.wall_s));
    println!("  macro steps         {:10.0}", col(&|s| s.macro_steps));
    println!("  of them calm (long) {:10.0}", col(&|s| s.calm_steps));
    let names: Vec<String> = samples[0].fmus.iter().map(|f| f.0.clone()).collect();
    for name in names {
        let t = col(&|s| {
            s.fmus
                .iter()
                .find(|f| f.0 == name)
                .map_or(f64::NAN, |f| f.1)
        });
        println!("  in {name:<16} {t:10.2} s");
    }
    println!(
        "  master's own work   {:10.2} s = {:.1} % of the wall time",
        col(&|s| s.master_s),
        col(&|s| s.master_percent)
    );
    println!(
        "  films stepped       {}",
        samples[samples.len() / 2].stepping
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{median, Options};

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn options_default_to_a_short_path1_run_up_and_refuse_bad_values() {
        let o = Options::parse(&[]).unwrap();
        assert_eq!(
            (o.preset.as_str(), o.stop_s, o.runs, o.load),
            ("path1", 0.3, 3, false)
        );
        let o = Options::parse(&args(&[
            "--preset",
            "path2a",
            "--stop",
            "1.5",
            "--runs",
            "5",
            "--load",
            "--fmu-dir",
            "d",
        ]))
        .unwrap();
        assert_eq!(
            (o.preset.as_str(), o.stop_s, o.runs, o.load),
            ("path2a", 1.5, 5, true)
        );
        assert_eq!(o.fmu_dir.as_deref(), Some("d"));
        for (bad, says) in [
            (&["--stop", "-1"][..], "--stop -1"),
            (&["--stop", "nan"][..], "--stop nan"),
            (&["--runs", "0"][..], "--runs 0"),
            (&["--runs"][..], "--runs expects a value"),
            (&["--fast"][..], "unknown argument '--fast'"),
        ] {
            let e = Options::parse(&args(bad)).err().unwrap();
            assert!(e.contains(says), "{e}");
        }
    }

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(vec![4.0, 1.0, 3.0, 2.0]), 2.5);
    }
}
