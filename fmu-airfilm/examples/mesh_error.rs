//! Where a coarse film mesh's error sits along the lobe: steady pressure fields of path 1's bore
//! (C 20 um, dH 40 um) on `n x 3` meshes against a 64 x 3 one (the same width mesh, so only the
//! resolution along the lobe differs), at a few journal positions and 1500 Hz.
//! `cargo run --release -p fmu-airfilm --example mesh_error`
use fmu_airfilm::params::BearingParams;
use fmu_airfilm::steady::steady_state;
use fmu_airfilm::JournalState;

fn main() {
    let mut base = BearingParams::paper();
    base.bore.c_m = 20e-6;
    base.bore.dh_m = 40e-6;
    base.n_elem_z = 3;
    let omega = std::f64::consts::TAU * 1500.0;
    let fine_n = 64;
    for &(eps, ang_deg) in &[(0.5, 0.0f64), (0.9, 30.0), (0.9, 75.0), (1.1, 60.0)] {
        let a = ang_deg.to_radians();
        let j = JournalState::at(eps * 20e-6 * a.cos(), eps * 20e-6 * a.sin(), omega);
        let solve = |n: usize| {
            let mut p = base.clone();
            p.n_elem_phi = n;
            steady_state(&p, j)
        };
        let fine = match solve(fine_n) {
            Ok(f) => f,
            Err(e) => {
                println!("eps {eps} at {ang_deg} deg: {e}");
                continue;
            }
        };
        let ff = (fine.outputs.fx_n, fine.outputs.fy_n);
        println!(
            "eps {eps} at {ang_deg} deg: fine force ({:.3}, {:.3}) N, p_max {:.0} Pa",
            ff.0, ff.1, fine.outputs.p_max_pa
        );
        for n in [12, 14, 16, 20, 32] {
            let c = solve(n).expect("the fine mesh solved this position");
            let df = ((c.outputs.fx_n - ff.0).hypot(c.outputs.fy_n - ff.1)) / ff.0.hypot(ff.1);
            print!("  {n:2} x 3: force error {:.3} %", 100.0 * df);
            if fine_n % n == 0 {
                // Pointwise error on the coarse mesh's nodes, mid-plane line (j = 0), lobe by lobe;
                // the column (element along the lobe) where the largest error sits.
                let r = fine_n / n;
                let (mc, mf) = (&c.mesh, &fine.mesh);
                let mut worst = Vec::new();
                for k in 0..mc.n_blocks {
                    let mut col_err = vec![0.0f64; n];
                    for node in 0..mc.npb {
                        if mc.node_j[node] != 0 {
                            continue;
                        }
                        let line = mc.node_line[node] as usize;
                        let fnode = (0..mf.npb)
                            .find(|&q| mf.node_line[q] as usize == line * r && mf.node_j[q] == 0)
                            .unwrap();
                        let e = (c.p_rel[k * mc.npb + node] - fine.p_rel[k * mf.npb + fnode]).abs();
                        let col = (line / 2).min(n - 1);
                        col_err[col] = col_err[col].max(e);
                    }
                    let tot: f64 = col_err.iter().sum();
                    let shares: Vec<String> = col_err
                        .iter()
                        .map(|e| format!("{:.0}", 100.0 * e / tot.max(1e-300)))
                        .collect();
                    worst.push(format!(
                        "lobe {k}: max {:.2e}, per column % [{}]",
                        col_err.iter().cloned().fold(0.0, f64::max),
                        shares.join(" ")
                    ));
                }
                println!();
                for w in worst {
                    println!("      {w}");
                }
            } else {
                println!();
            }
        }
    }
}
