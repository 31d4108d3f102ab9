use fmu_rotor::linear::*;
use fmu_rotor::*;
#[test]
fn probe() {
    let mut p = RotorParams::paper();
    p.c_c_n_m = 5e5;
    p.c_t_n_m = 5e5;
    p.d_c_n_s_m = 0.0;
    p.d_t_n_s_m = 0.0;
    let films = [FilmCoefficients::isotropic(2e6, 0.0); 2];
    for f in [0.0, 250.0, 500.0, 750.0, 1000.0, 1250.0, 1500.0, 2000.0] {
        let lm = lateral_matrices(&p, 2.0 * std::f64::consts::PI * f, &films);
        if f == 500.0 {
            println!("G row2 {:?}\nK {:?}", lm.g[2], lm.k[2]);
        }
        let ms = modes(&lm).unwrap();
        let s: Vec<String> = ms
            .iter()
            .map(|m| {
                format!(
                    "{:.1}{} ",
                    m.freq_hz,
                    if m.whirl == Whirl::Forward { "f" } else { "b" }
                )
            })
            .collect();
        println!("{f:6} Hz: {}", s.join(" "));
        if f == 1000.0 {
            for m in &ms {
                println!("   {:.1} {:?} {}", m.freq_hz, m.whirl, m.shape.describe());
            }
        }
    }
}
