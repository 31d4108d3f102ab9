//! Cost of one contact-force evaluation for a journal riding on its ring (hand-written timing,
//! medians): C = 15 um, dH = 0 (paper Section 4's C15/dH0 cells, whose journals ride on their
//! rings for most of a run-up), eccentricity 0.9635 C, so the minimum gap is 0.9 h_con. The rotor
//! evaluates this in every Newton iteration while a journal touches its ring.
use bearing::bore::Bore;
use bearing::contact::{contact_force_at_n, ContactLaw};
use bearing::JournalState;
use std::time::Instant;

fn main() {
    let p = Bore {
        c_m: 15e-6,
        dh_m: 0.0,
        ..Bore::paper()
    };
    let law = ContactLaw::paper();
    let r = 0.9635 * p.c_m;
    // Journal directions all around the bore, so every lobe and both band ends are visited.
    let states: Vec<JournalState> = (0..10_000)
        .map(|i| {
            let a = i as f64 * 2.0 * std::f64::consts::PI / 10_000.0;
            JournalState::at(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect();
    let mut per_call_ns = Vec::new();
    let mut checksum = 0.0;
    for _ in 0..15 {
        let t = Instant::now();
        for j in &states {
            let f = contact_force_at_n(&p, &law, j);
            checksum += f[0] + f[1];
        }
        per_call_ns.push(t.elapsed().as_nanos() as f64 / states.len() as f64);
    }
    per_call_ns.sort_by(|a, b| a.total_cmp(b));
    println!(
        "contact force, journal riding on its ring (C 15 um, dH 0, eps 0.9635): median {:.0} ns \
         per evaluation (min {:.0}, max {:.0}; checksum {checksum:.6e} N)",
        per_call_ns[7], per_call_ns[0], per_call_ns[14]
    );
}
