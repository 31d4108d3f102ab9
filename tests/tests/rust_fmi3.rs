//! rust-fmi 0.8 (the `fmi` crate our users name), an independent FMI 3.0 importer (its own unzip,
//! its own modelDescription.xml schema, its own bindgen bindings), loads the FMI 3.0 twins
//! `target/fmu/fmi3/{airfilm,rotor}.fmu` and steps them; every output equals, bit for bit, what our
//! importer reads from the FMI 2.0 FMU for the same calls (inputs held over each step on both
//! sides: FMI 3.0 has no input derivatives).

use fmi08::fmi3::import::Fmi3Import;
use fmi08::fmi3::instance::InstanceCS;
use fmi08::fmi3::{CoSimulation, Common, Fmi3Model, GetSet};
use fmi08::traits::FmiImport;
use fmi2::importer::Slave;
use integration_tests::{fmu_path, load, LogBook};

struct Theirs {
    import: Fmi3Import,
    inst: InstanceCS,
}

impl Theirs {
    fn new(id: &str) -> Theirs {
        let import: Fmi3Import =
            fmi08::import::from_path(fmu_path(&format!("fmi3/{id}"))).expect("rust-fmi imports");
        assert_eq!(import.model_description().fmi_version, "3.0");
        let mut inst = import
            .instantiate_cs(&format!("{id}-rust-fmi"), false, false, false, false, &[])
            .expect("rust-fmi instantiates");
        inst.enter_initialization_mode(None, 0.0, None).unwrap();
        Theirs { import, inst }
    }
    /// The value reference rust-fmi's own parser finds for `name`.
    fn vr(&self, name: &str) -> u32 {
        self.import
            .model_description()
            .model_variables
            .iter_abstract()
            .find(|v| v.name() == name)
            .unwrap_or_else(|| panic!("rust-fmi finds no variable '{name}'"))
            .value_reference()
    }
    fn set(&mut self, name: &str, v: f64) {
        let vr = self.vr(name);
        self.inst.set_float64(&[vr], &[v]).unwrap();
    }
    fn get(&mut self, name: &str) -> f64 {
        let vr = self.vr(name);
        let mut v = [0.0];
        self.inst.get_float64(&[vr], &mut v).unwrap();
        v[0]
    }
    fn step(&mut self, t: f64, h: f64) {
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        self.inst
            .do_step(
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
            .expect("rust-fmi doStep");
        assert!(!event && !terminate && !early && last == t + h);
    }
}

struct Ours {
    fmu: fmi2::importer::Fmu,
    slave: Slave,
}

impl Ours {
    fn new(id: &str) -> Ours {
        let fmu = load(id);
        let slave = fmu
            .instantiate(&format!("{id}-ours"), false, LogBook::default().handler())
            .unwrap();
        slave.setup_experiment(None, 0.0, None).unwrap();
        slave.enter_initialization_mode().unwrap();
        Ours { fmu, slave }
    }
    fn vr(&self, name: &str) -> u32 {
        self.fmu.description.variable(name).unwrap().vr
    }
    fn set(&mut self, name: &str, v: f64) {
        self.slave.set_real(&[self.vr(name)], &[v]).unwrap();
    }
    fn get(&mut self, name: &str) -> f64 {
        let mut v = [0.0];
        self.slave.get_real(&[self.vr(name)], &mut v).unwrap();
        v[0]
    }
    fn step(&mut self, t: f64, h: f64) {
        self.slave.do_step(t, h).expect("doStep");
    }
}

/// Both importers: the same inputs (a journal whirling at 400 Hz in the film), the same steps,
/// outputs compared bit for bit after every step.
#[test]
fn airfilm_twin_through_rust_fmi_equals_the_fmi2_fmu() {
    let (mut a, mut b) = (Theirs::new("airfilm"), Ours::new("airfilm"));
    a.set("omega", 6283.0);
    b.set("omega", 6283.0);
    a.inst.exit_initialization_mode().unwrap();
    b.slave.exit_initialization_mode().unwrap();
    let h = 1e-5;
    let outputs = ["Fx", "Fy", "eps", "h_min", "p_max", "friction_torque"];
    for k in 0..100 {
        let t = k as f64 * h;
        let phase = std::f64::consts::TAU * 400.0 * t;
        let (dx, dy) = (6e-6 * phase.cos(), 6e-6 * phase.sin());
        for (n, v) in [("dx", dx), ("dy", dy)] {
            a.set(n, v);
            b.set(n, v);
        }
        a.step(t, h);
        b.step(t, h);
        for n in outputs {
            let (va, vb) = (a.get(n), b.get(n));
            assert_eq!(
                va.to_bits(),
                vb.to_bits(),
                "{n} at {} s: {va:e} vs {vb:e}",
                t + h
            );
        }
    }
    assert!(a.get("p_max") > 101325.0);
}

/// The rotor under constant bearing forces that nearly carry its weight: positions, speed and
/// spin angle equal bit for bit over 200 steps of the run-up.
#[test]
fn rotor_twin_through_rust_fmi_equals_the_fmi2_fmu() {
    let (mut a, mut b) = (Theirs::new("rotor"), Ours::new("rotor"));
    a.inst.exit_initialization_mode().unwrap();
    b.slave.exit_initialization_mode().unwrap();
    let h = 1e-5;
    for k in 0..200 {
        let t = k as f64 * h;
        for (n, v) in [("F_C_y", 3.0), ("F_T_y", 4.5), ("F_C_x", 0.1)] {
            a.set(n, v);
            b.set(n, v);
        }
        a.step(t, h);
        b.step(t, h);
        for n in [
            "x_JC",
            "y_JC",
            "y_JT",
            "x_RC",
            "omega",
            "spin_angle",
            "dx_C",
            "vy_T",
        ] {
            let (va, vb) = (a.get(n), b.get(n));
            assert_eq!(
                va.to_bits(),
                vb.to_bits(),
                "{n} at {} s: {va:e} vs {vb:e}",
                t + h
            );
        }
    }
    assert!(a.get("omega") > 0.0);
}
