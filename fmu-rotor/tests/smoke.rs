use fmu_rotor::*;

#[test]
fn runup_smoke() {
    let mut r = Rotor::new(RotorParams::paper()).unwrap();
    let mut t = 0.0;
    let h = 1e-5;
    let t0 = std::time::Instant::now();
    let mut tot = StepStats::default();
    for _ in 0..2000 {
        let s = r.advance(t, h, &|_t| BearingForces::default()).unwrap();
        tot.accumulate(&s);
        t += h;
    }
    let el = t0.elapsed();
    let o = r.outputs();
    println!("{:?}\n{:?}\n{:?} per advance {:?}", o, tot, el, el / 2000);
    println!("{:?}", r.output_derivatives());
}
