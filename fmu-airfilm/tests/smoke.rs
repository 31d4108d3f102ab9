use fmu_airfilm::*;
#[test]
fn smoke() {
    let p = BearingParams::paper();
    let om = 2.0 * std::f64::consts::PI * 1000.0;
    let t = std::time::Instant::now();
    let s = steady_state(&p, JournalState::at(0.0, -0.5 * p.c_m, om)).unwrap();
    println!("{:?} iters {} in {:?}", s.outputs, s.iterations, t.elapsed());
    let s = steady_state(&p, JournalState::at(0.0, 0.0, om)).unwrap();
    println!("centred {:?}", s.outputs);
    let k = static_stiffness(&p, JournalState::at(0.0, -0.5 * p.c_m, om)).unwrap();
    println!("K N/mm {:?}", k.map(|r| r.map(|v| v * 1e-3)));
}
