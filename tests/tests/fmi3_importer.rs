//! Our FMI 3.0 importer (`fmi3::importer`) on the packed twins (`target/fmu/fmi3`): the
//! description it reads, input polynomials answered through intermediate update (bit for bit the
//! FMI 2.0 FMU's input derivatives), and FMU states.

use fmi2::importer::Slave as Slave2;
use fmi3::importer::{Fmu as Fmu3, Slave as Slave3};
use fmu_airfilm::shell::vr;
use integration_tests::{fmu_path, initialized, load, LogBook};
use std::f64::consts::TAU;

const OMEGA: f64 = TAU * 1000.0;
const WHIRL: f64 = TAU * 400.0;
const R: f64 = 0.3 * 20e-6;
const INPUTS: [u32; 5] = [vr::DX, vr::DY, vr::VX, vr::VY, vr::OMEGA];

/// Values of the inputs on a circular whirl orbit of radius R about (0, -R/2), and their first and
/// second time derivatives as (value references, orders, values).
fn orbit(t: f64) -> ([f64; 5], [u32; 8], [i32; 8], [f64; 8]) {
    let (c, s, w) = ((WHIRL * t).cos(), (WHIRL * t).sin(), WHIRL);
    (
        [R * c, -R / 2.0 + R * s, -R * w * s, R * w * c, OMEGA],
        [
            vr::DX,
            vr::DY,
            vr::VX,
            vr::VY,
            vr::DX,
            vr::DY,
            vr::VX,
            vr::VY,
        ],
        [1, 1, 1, 1, 2, 2, 2, 2],
        [
            -R * w * s,
            R * w * c,
            -R * w * w * c,
            -R * w * w * s,
            -R * w * w * c,
            -R * w * w * s,
            R * w * w * w * s,
            -R * w * w * w * c,
        ],
    )
}

fn load3(id: &str) -> Fmu3 {
    Fmu3::load(&fmu_path(&format!("fmi3/{id}"))).expect("the packed FMI 3.0 twin loads")
}

fn start3(fmu: &Fmu3, book: &LogBook, name: &str) -> Slave3 {
    let s = fmu
        .instantiate(name, false, book.handler())
        .expect("instantiate");
    s.setup_experiment(None, 0.0, None).unwrap();
    s.enter_initialization_mode().unwrap();
    s.set_float64(&INPUTS, &orbit(0.0).0).unwrap();
    s.exit_initialization_mode().unwrap();
    s
}

fn forces2(s: &Slave2) -> [u64; 2] {
    let mut f = [0.0; 2];
    s.get_real(&[vr::FX, vr::FY], &mut f).unwrap();
    f.map(f64::to_bits)
}

fn forces3(s: &Slave3) -> [u64; 2] {
    let mut f = [0.0; 2];
    s.get_float64(&[vr::FX, vr::FY], &mut f).unwrap();
    f.map(f64::to_bits)
}

#[test]
fn the_importer_reads_the_twins_description() {
    let fmu = load3("airfilm");
    let md = &fmu.description;
    assert_eq!(md.fmi_version, "3.0");
    assert!(
        md.can_interpolate_inputs,
        "intermediate update on every input"
    );
    assert!(fmu.extras.provides_intermediate_update);
    let mut iu = fmu.extras.intermediate_update_vrs.clone();
    iu.sort_unstable();
    assert_eq!(iu, INPUTS.to_vec());
    // The same names, value references and units as the FMI 2.0 FMU (units through declared types).
    let md2 = load("airfilm").description;
    for v2 in md2
        .variables
        .iter()
        .filter(|v| v.var_type == fmi_core::variables::VarType::Real)
    {
        let v3 = md.variable(&v2.name).expect("same variable");
        assert_eq!(
            (v3.vr, v3.causality, &v3.unit),
            (v2.vr, v2.causality, &v2.unit),
            "{}",
            v2.name
        );
        assert_eq!(v3.display_unit, v2.display_unit, "{}", v2.name);
    }
}

#[test]
fn input_polynomials_reach_the_twin_through_intermediate_update_bit_for_bit() {
    let book = LogBook::default();
    let fmu2 = load("airfilm");
    let fmu3 = load3("airfilm");
    let s2 = initialized(&fmu2, "film2", &book, |s| {
        s.set_real(&INPUTS, &orbit(0.0).0).unwrap()
    });
    let s3 = start3(&fmu3, &book, "film3");
    let held = start3(&fmu3, &book, "held");
    let h = 2e-5;
    let mut largest_difference_held = 0.0f64;
    for k in 0..40 {
        let t = k as f64 * h;
        let (values, dvrs, orders, dvalues) = orbit(t);
        s2.set_real(&INPUTS, &values).unwrap();
        s2.set_real_input_derivatives(&dvrs, &orders, &dvalues)
            .unwrap();
        s3.set_float64(&INPUTS, &values).unwrap();
        s3.set_input_derivatives(&dvrs, &orders, &dvalues).unwrap();
        held.set_float64(&INPUTS, &values).unwrap();
        for r in [s2.do_step(t, h), s3.do_step(t, h), held.do_step(t, h)] {
            r.unwrap();
        }
        assert_eq!(forces2(&s2), forces3(&s3), "step {k}");
        let f = forces2(&s2).map(f64::from_bits);
        let g = forces3(&held).map(f64::from_bits);
        largest_difference_held =
            largest_difference_held.max((f[0] - g[0]).hypot(f[1] - g[1]) / f[0].hypot(f[1]));
    }
    // Every internal time asked the master (at least one per step), and it mattered: the inputs
    // held over the step give other forces.
    assert!(
        s3.intermediate_updates() >= 40,
        "{}",
        s3.intermediate_updates()
    );
    assert_eq!(held.intermediate_updates(), 0);
    assert!(
        largest_difference_held > 1e-4,
        "{largest_difference_held:e}"
    );
    assert!(book.is_empty(), "{:?}", book.last());
}

#[test]
fn a_serialized_state_continues_bit_for_bit_in_another_instance() {
    let book = LogBook::default();
    let fmu = load3("airfilm");
    let a = start3(&fmu, &book, "a");
    let b = start3(&fmu, &book, "b");
    let h = 2e-5;
    let step = |s: &Slave3, k: usize| {
        let t = k as f64 * h;
        let (values, dvrs, orders, dvalues) = orbit(t);
        s.set_float64(&INPUTS, &values).unwrap();
        s.set_input_derivatives(&dvrs, &orders, &dvalues).unwrap();
        s.do_step(t, h).unwrap();
    };
    for k in 0..10 {
        step(&a, k);
    }
    let bytes = a.serialize_state(&a.get_state().unwrap()).unwrap();
    let mut reference = vec![];
    for k in 10..20 {
        step(&a, k);
        reference.push(forces3(&a));
    }
    b.set_state(&b.deserialize_state(&bytes).unwrap()).unwrap();
    for (k, f) in (10..20).zip(reference) {
        step(&b, k);
        assert_eq!(forces3(&b), f, "step {k}");
    }
    // A derivative for an input whose value was never set is refused, not started from 0.
    assert!(b.set_input_derivatives(&[999], &[1], &[1.0]).is_err());
}

/// The rotor twin refuses a start time other than 0 in fmi3EnterInitializationMode, which
/// carries it in FMI 3.0 (not only in fmi3ExitInitializationMode), naming it.
#[test]
fn the_rotor_twin_refuses_a_late_start_where_it_is_given() {
    let fmu = load3("rotor");
    let book = LogBook::default();
    // Logging on: an FMI 3.0 instance logs nothing without it.
    let s = fmu.instantiate("late", true, book.handler()).unwrap();
    s.setup_experiment(None, 0.25, None).unwrap();
    assert!(s.enter_initialization_mode().is_err());
    assert!(
        book.contains("fmi3EnterInitializationMode")
            && book.contains("startTime 0.25 s is not supported"),
        "{:?}",
        book.0.lock().unwrap()
    );
}
