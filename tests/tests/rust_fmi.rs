//! An independent Rust importer, the `fmi` crate (rust-fmi), loads `rotor.fmu` and `airfilm.fmu`
//! (its own unzip, its own modelDescription.xml parser for the value references, its own dlopen
//! bindings) and steps them; every output equals, bit for bit, the one our importer
//! (`fmi2::importer`) reads for the same call sequence.
//!
//! Version 0.2.2 on purpose: 0.3 to 0.8 generate their FMI bindings with bindgen in `fmi-sys`'s
//! build script and so need libclang wherever the tests are built; 0.2.2 has hand-written FMI 2.0
//! bindings and needs only a C compiler (for its variadic logger). It offers no
//! `fmi2SetRealInputDerivatives`, so both importers hold the inputs over each step here, and it
//! declares fmi2Integer as a 64-bit C long instead of int, so Integers go one at a time. Its XML
//! reader also requires the attribute `generationDateAndTime`, which FMI 2.0 makes optional and our
//! FMUs omit (their modelDescription.xml is reproducible): rust-fmi gets a copy of the FMU with that
//! one attribute added; the binary and everything else are the packed FMU's. And it keys variables by
//! value reference alone, while FMI 2.0 numbers them per type (as ours do: Real 0.., Integer 0..,
//! Boolean 0..), so a variable sharing its number with a later one of another type is invisible to
//! it: for airfilm.fmu r, b, C, dH, phi_t, alpha, eta, n_lobes and n_elem_phi. The film test sets
//! n_elem_z and atol instead of C.

use fmi::{CoSimulation, Common, Import, InstanceCS, Value, Var};
use fmi2::importer::Slave;
use integration_tests::{fmu_path, load, LogBook};
use std::f64::consts::TAU;
use std::io::{Read, Write};
use std::path::PathBuf;

/// One FMU instance behind either importer, by variable name.
trait Driver {
    fn set(&self, name: &str, v: f64);
    fn set_int(&self, name: &str, v: i32);
    fn get(&self, name: &str) -> f64;
    fn step(&self, t: f64, h: f64);
}

struct Theirs {
    import: Import,
    inst: InstanceCS,
}

impl Theirs {
    /// Instantiates with rust-fmi; `params` are set before initialization mode.
    fn new(id: &str, params: &[(&str, Value)]) -> Theirs {
        let import = Import::new(with_generation_date(id)).expect("rust-fmi imports the FMU");
        let inst = InstanceCS::new(&import, &format!("{id}-rust-fmi"), false, false)
            .expect("rust-fmi instantiates");
        let me = Theirs { import, inst };
        me.inst.setup_experiment(None, 0.0, None).unwrap();
        for (name, v) in params {
            me.var(name).set(v).unwrap();
        }
        me.inst.enter_initialization_mode().unwrap();
        me
    }
    fn var(&self, name: &str) -> Var<'_, InstanceCS> {
        let (_, sv) = self
            .import
            .descr
            .get_model_variables()
            .find(|(_, sv)| sv.name == name)
            .unwrap_or_else(|| panic!("rust-fmi finds no variable '{name}'"));
        Var::from_scalar_variable(&self.inst, sv)
    }
    fn start(&self) {
        self.inst.exit_initialization_mode().unwrap();
    }
}

impl Driver for Theirs {
    fn set(&self, name: &str, v: f64) {
        self.var(name).set(&Value::Real(v)).unwrap();
    }
    fn set_int(&self, name: &str, v: i32) {
        // rust-fmi 0.2.2 declares fmi2Integer as C long (64 bits; the standard says int): one value
        // per call, non-negative, reads and writes the right low 32 bits on little-endian x86_64.
        self.var(name).set(&Value::Integer(v.into())).unwrap();
    }
    fn get(&self, name: &str) -> f64 {
        match self.var(name).get().unwrap() {
            Value::Real(x) => x,
            Value::Integer(i) => i as f64,
            other => panic!("{name}: unexpected {other:?}"),
        }
    }
    fn step(&self, t: f64, h: f64) {
        self.inst.do_step(t, h, true).expect("rust-fmi doStep");
    }
}

/// A copy of the packed FMU whose modelDescription.xml carries `generationDateAndTime`.
fn with_generation_date(id: &str) -> PathBuf {
    let src = fmu_path(id);
    let mut zin = zip::ZipArchive::new(std::fs::File::open(&src).unwrap()).unwrap();
    let out = std::env::temp_dir().join(format!("rust-fmi-{id}-{}.fmu", std::process::id()));
    let mut zout = zip::ZipWriter::new(std::fs::File::create(&out).unwrap());
    for i in 0..zin.len() {
        let mut entry = zin.by_index(i).unwrap();
        let mut bytes = vec![];
        entry.read_to_end(&mut bytes).unwrap();
        if entry.name() == "modelDescription.xml" {
            let xml = String::from_utf8(bytes).unwrap();
            let patched = xml.replacen(
                "<fmiModelDescription ",
                "<fmiModelDescription generationDateAndTime=\"2000-01-01T00:00:00Z\" ",
                1,
            );
            assert_ne!(patched, xml);
            bytes = patched.into_bytes();
        }
        zout.start_file(entry.name(), zip::write::SimpleFileOptions::default())
            .unwrap();
        zout.write_all(&bytes).unwrap();
    }
    zout.finish().unwrap();
    out
}

struct Ours {
    fmu: fmi2::importer::Fmu,
    slave: Slave,
}

impl Driver for Ours {
    fn set(&self, name: &str, v: f64) {
        let vr = self.fmu.description.variable(name).unwrap().vr;
        self.slave.set_real(&[vr], &[v]).unwrap();
    }
    fn set_int(&self, name: &str, v: i32) {
        let vr = self.fmu.description.variable(name).unwrap().vr;
        self.slave.set_integer(&[vr], &[v]).unwrap();
    }
    fn get(&self, name: &str) -> f64 {
        let var = self.fmu.description.variable(name).unwrap();
        if var.var_type == fmi_core::variables::VarType::Integer {
            let mut v = [0];
            self.slave.get_integer(&[var.vr], &mut v).unwrap();
            return v[0] as f64;
        }
        let mut v = [0.0];
        self.slave.get_real(&[var.vr], &mut v).unwrap();
        v[0]
    }
    fn step(&self, t: f64, h: f64) {
        self.slave.do_step(t, h).expect("doStep");
    }
}

fn ours(id: &str, reals: &[(&str, f64)], ints: &[(&str, i32)]) -> Ours {
    let fmu = load(id);
    // Parameters before initialization mode, as for rust-fmi above.
    let slave = fmu
        .instantiate(&format!("{id}-ours"), false, LogBook::default().handler())
        .unwrap();
    slave.setup_experiment(None, 0.0, None).unwrap();
    let me = Ours { fmu, slave };
    for (n, v) in reals {
        me.set(n, *v);
    }
    for (n, v) in ints {
        me.set_int(n, *v);
    }
    me.slave.enter_initialization_mode().unwrap();
    me
}

/// Inputs at time t from a reader of the driver's own outputs: (variable, value) pairs.
type Inputs = dyn Fn(f64, &dyn Fn(&str) -> f64) -> Vec<(&'static str, f64)>;

/// Runs `steps` communication steps of `h` on both drivers with inputs from `inputs(t, read)` (which
/// may read the driver's own outputs: a closed loop) and compares `outputs` after every step.
fn compare(
    a: &dyn Driver,
    b: &dyn Driver,
    steps: usize,
    h: f64,
    inputs: &Inputs,
    outputs: &[&str],
) -> Vec<f64> {
    let mut last = vec![];
    for k in 0..steps {
        let t = k as f64 * h;
        for d in [a, b] {
            for (n, v) in inputs(t, &|name| d.get(name)) {
                d.set(n, v);
            }
            d.step(t, h);
        }
        last = outputs.iter().map(|n| a.get(n)).collect();
        for (n, va) in outputs.iter().zip(&last) {
            let vb = b.get(n);
            assert!(
                va.to_bits() == vb.to_bits(),
                "{n} at t = {} s: rust-fmi {va:e}, fmi2::importer {vb:e}",
                t + h
            );
        }
    }
    last
}

#[test]
fn airfilm_through_rust_fmi_equals_our_importer() {
    // The paper mesh: rust-fmi cannot reach the mesh Integers (their value references are
    // repeated by Booleans, docs/fmu-guide.md).
    let theirs = Theirs::new("airfilm", &[("atol", Value::Real(20.0))]);
    let mine = ours("airfilm", &[("atol", 20.0)], &[]);
    // Circular whirl, eps 0.3 about (0, -eps C / 2), 400 Hz, rotor at 1000 Hz (C = 20 um).
    let (r, w) = (0.3 * 20e-6, TAU * 400.0);
    let orbit = move |t: f64, _: &dyn Fn(&str) -> f64| {
        vec![
            ("dx", r * (w * t).cos()),
            ("dy", -r / 2.0 + r * (w * t).sin()),
            ("vx", -r * w * (w * t).sin()),
            ("vy", r * w * (w * t).cos()),
            ("omega", TAU * 1000.0),
        ]
    };
    for (n, v) in orbit(0.0, &|_| 0.0) {
        theirs.set(n, v);
        mine.set(n, v);
    }
    theirs.start();
    mine.slave.exit_initialization_mode().unwrap();
    let outs = [
        "Fx",
        "Fy",
        "eps",
        "h_min",
        "p_max",
        "F_contact",
        "n_substeps",
        "n_newton",
    ];
    let last = compare(&theirs, &mine, 300, 1e-5, &orbit, &outs);
    // Not trivial: after 3 ms of whirl the film carries newtons.
    assert!(last[0].hypot(last[1]) > 1.0, "{last:?}");
}

#[test]
fn rotor_through_rust_fmi_equals_our_importer() {
    let params = [("f_max", 2000.0), ("t_ramp", 0.01)];
    let theirs = Theirs::new("rotor", &params.map(|(n, v)| (n, Value::Real(v))));
    let mine = ours("rotor", &params, &[]);
    theirs.start();
    mine.slave.exit_initialization_mode().unwrap();
    // Each importer closes the loop with linear film springs and dampers on its own outputs.
    let (k, c) = (2e6, 200.0);
    let springs = move |_: f64, get: &dyn Fn(&str) -> f64| {
        let mut f = vec![];
        for (side, fx, fy) in [("C", "F_C_x", "F_C_y"), ("T", "F_T_x", "F_T_y")] {
            let d = |q: &str| get(&format!("{q}_{side}"));
            f.push((fx, -k * d("dx") - c * d("vx")));
            f.push((fy, -k * d("dy") - c * d("vy")));
        }
        f
    };
    let outs = [
        "dx_C",
        "dy_C",
        "vx_C",
        "vy_C",
        "dx_T",
        "dy_T",
        "vx_T",
        "vy_T",
        "omega",
        "x_RC",
        "y_RC",
        "spin_angle",
        "n_newton",
    ];
    let last = compare(&theirs, &mine, 400, 1e-5, &springs, &outs);
    // The rotor sags into the springs and spins up (600 Hz at 3 ms, 800 Hz at 4 ms).
    assert!(last[1] < -1e-6, "{last:?}");
    assert!(
        (last[8] - TAU * 800.0).abs() < 1e-6 * TAU * 800.0,
        "{last:?}"
    );
}
