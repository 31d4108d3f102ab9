//! One 10 us communication step through the C ABI of the packed FMUs (fmi2SetReal +
//! fmi2SetRealInputDerivatives + fmi2DoStep + fmi2GetReal), as a master pays it.
//! Air film: whirl orbit eps 0.3, whirl 400 Hz, Omega 1000 Hz. Rotor: during the run-up.
//! Run with `cargo bench -p integration-tests` after `cargo xtask fmus`; prints medians.

use fmi2::importer::Slave;
use integration_tests::{initialized, load, LogBook};
use std::f64::consts::TAU;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn report(name: &str, samples_us: Vec<f64>) {
    let n = samples_us.len();
    let mean = samples_us.iter().sum::<f64>() / n as f64;
    let mut s = samples_us.clone();
    s.sort_by(f64::total_cmp);
    println!(
        "{name}: median {:.1} us, mean {mean:.1} us, p10 {:.1} us, p90 {:.1} us ({n} steps)",
        median(samples_us),
        s[n / 10],
        s[9 * n / 10]
    );
}

fn airfilm() {
    use fmu_airfilm::shell::vr;
    let fmu = load("airfilm");
    let book = LogBook::default();
    let (r, w, omega) = (0.3 * 20e-6, TAU * 400.0, TAU * 1000.0);
    let set = |s: &Slave, t: f64| {
        let (c, sn) = ((w * t).cos(), (w * t).sin());
        s.set_real(
            &[vr::DX, vr::DY, vr::VX, vr::VY, vr::OMEGA],
            &[r * c, r * sn, -r * w * sn, r * w * c, omega],
        )
        .unwrap();
        s.set_real_input_derivatives(
            &[vr::DX, vr::DY, vr::VX, vr::VY],
            &[1, 1, 1, 1],
            &[-r * w * sn, r * w * c, -r * w * w * c, -r * w * w * sn],
        )
        .unwrap();
    };
    let s = initialized(&fmu, "bench", &book, |s| set(s, 0.0));
    let h = 1e-5;
    let mut f = [0.0; 2];
    let mut samples = vec![];
    for k in 0..3000 {
        let t = k as f64 * h;
        let start = Instant::now();
        set(&s, t);
        s.do_step(t, h).unwrap();
        s.get_real(&[vr::FX, vr::FY], &mut f).unwrap();
        // The first 2.5 ms (one orbit) build up the film and are not measured.
        if k >= 1000 {
            samples.push(start.elapsed().as_secs_f64() * 1e6);
        }
    }
    report("airfilm.fmu 10 us step (whirl orbit, C ABI)", samples);
}

fn rotor() {
    use fmu_rotor::shell::vr;
    let fmu = load("rotor");
    let book = LogBook::default();
    let s = initialized(&fmu, "bench", &book, |_| {});
    let h = 1e-5;
    let mut out = [0.0; 9];
    let outs = [
        vr::DX_C,
        vr::DY_C,
        vr::VX_C,
        vr::VY_C,
        vr::DX_T,
        vr::DY_T,
        vr::VX_T,
        vr::VY_T,
        vr::OMEGA,
    ];
    let mut samples = vec![];
    for k in 0..5000 {
        let t = k as f64 * h;
        let start = Instant::now();
        // Film-like restoring forces with a first-order extrapolation polynomial.
        s.set_real(
            &[vr::F_C_X, vr::F_C_Y, vr::F_T_X, vr::F_T_Y],
            &[-2e6 * out[0], -2e6 * out[1], -2e6 * out[4], -2e6 * out[5]],
        )
        .unwrap();
        s.set_real_input_derivatives(
            &[vr::F_C_X, vr::F_C_Y, vr::F_T_X, vr::F_T_Y],
            &[1, 1, 1, 1],
            &[-2e6 * out[2], -2e6 * out[3], -2e6 * out[6], -2e6 * out[7]],
        )
        .unwrap();
        s.do_step(t, h).unwrap();
        s.get_real(&outs, &mut out).unwrap();
        if k >= 1000 {
            samples.push(start.elapsed().as_secs_f64() * 1e6);
        }
    }
    report("rotor.fmu 10 us step (run-up, C ABI)", samples);
}

fn main() {
    // `cargo test --benches` runs this too; keep it to a smoke run there.
    if std::env::args().any(|a| a == "--bench") {
        airfilm();
        rotor();
    } else {
        println!("abi bench: run with `cargo bench -p integration-tests`");
    }
}
