//! Short-time spectra: the waterfall plots' spectrogram and the whirl-frequency estimate.

use rustfft::{num_complex::Complex, FftPlanner};

/// A one-sided amplitude spectrogram.
///
/// `magnitude[i][k]` belongs to segment `i` (centred at `times_s[i]`) and frequency `freqs_hz[k]`.
/// Scaling: amplitude spectrum of the Hann-windowed, mean-removed segment, `2 |X_k| / sum(w)` for the
/// interior bins and `|X_k| / sum(w)` for DC and Nyquist, so a sine of amplitude A centred on a bin
/// reads A. The segment mean is removed because the journal's static sag would otherwise swamp the
/// low bins of a waterfall plot.
#[derive(Debug, Clone, Default)]
pub struct Spectrogram {
    pub times_s: Vec<f64>,
    pub freqs_hz: Vec<f64>,
    pub magnitude: Vec<Vec<f64>>,
    /// Samples per segment (the FFT length).
    pub n_fft: usize,
    /// Sum of the window weights (undoes the scaling above when needed).
    pub window_sum: f64,
}

/// Periodic Hann window of length n (the form that makes overlapped segments sum to a constant).
pub fn hann(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / n as f64).cos())
        .collect()
}

/// Spectrogram of a uniformly sampled `signal` (interval `dt_s`), Hann window of `window_s`,
/// segments every `hop_s`. Segments that would run past the end are not formed; a signal shorter than
/// one window gives an empty spectrogram (with `freqs_hz` still filled).
pub fn spectrogram(signal: &[f64], dt_s: f64, window_s: f64, hop_s: f64) -> Spectrogram {
    assert!(
        dt_s > 0.0 && window_s > 0.0 && hop_s > 0.0,
        "spectrogram: dt, window and hop must be positive"
    );
    let n = ((window_s / dt_s).round() as usize).max(2);
    let hop = ((hop_s / dt_s).round() as usize).max(1);
    let w = hann(n);
    let wsum: f64 = w.iter().sum();
    let n_bins = n / 2 + 1;
    let freqs_hz = (0..n_bins).map(|k| k as f64 / (n as f64 * dt_s)).collect();
    let fft = FftPlanner::<f64>::new().plan_fft_forward(n);
    let mut buf = vec![Complex::new(0.0, 0.0); n];
    let mut times_s = Vec::new();
    let mut magnitude = Vec::new();
    let mut start = 0;
    while start + n <= signal.len() {
        let seg = &signal[start..start + n];
        let mean = seg.iter().sum::<f64>() / n as f64;
        for i in 0..n {
            buf[i] = Complex::new((seg[i] - mean) * w[i], 0.0);
        }
        fft.process(&mut buf);
        let row = (0..n_bins)
            .map(|k| {
                let edge = k == 0 || (n & 1 == 0 && k == n / 2);
                buf[k].norm() * if edge { 1.0 } else { 2.0 } / wsum
            })
            .collect();
        magnitude.push(row);
        times_s.push((start as f64 + 0.5 * (n - 1) as f64) * dt_s);
        start += hop;
    }
    Spectrogram {
        times_s,
        freqs_hz,
        magnitude,
        n_fft: n,
        window_sum: wsum,
    }
}

/// Dominant frequency of a complex whirl signal z = x + i y (already detrended), in Hz, signed:
/// positive for forward whirl (counter-clockwise in x, y, the sense of Omega > 0), negative for backward.
/// Hann window, zero-padded to at least `min_fft` points, parabolic interpolation of the log magnitude
/// around the peak. Only |f| >= `f_min_hz` is searched (below it lies what the detrending left of the drift).
pub fn dominant_whirl_hz(x: &[f64], y: &[f64], dt_s: f64, f_min_hz: f64, min_fft: usize) -> f64 {
    WhirlFrequency::new(min_fft).dominant_hz(x, y, dt_s, f_min_hz)
}

/// [`dominant_whirl_hz`] for many windows: the Hann window, the FFT plan and its buffer are made
/// once per window length and kept. A run-up's classification takes the whirl frequency of both
/// bearings in every whirl window; a new plan per call computed its twiddle factors (a sine and
/// cosine each) and a new window every time. The same plan and window for the same lengths, so
/// the same frequencies, bit for bit.
pub struct WhirlFrequency {
    min_fft: usize,
    /// Window length the window and plan below are for (0: none yet).
    n: usize,
    window: Vec<f64>,
    fft: Option<std::sync::Arc<dyn rustfft::Fft<f64>>>,
    buf: Vec<Complex<f64>>,
}

impl WhirlFrequency {
    pub fn new(min_fft: usize) -> WhirlFrequency {
        WhirlFrequency {
            min_fft,
            n: 0,
            window: Vec::new(),
            fft: None,
            buf: Vec::new(),
        }
    }

    /// See [`dominant_whirl_hz`].
    pub fn dominant_hz(&mut self, x: &[f64], y: &[f64], dt_s: f64, f_min_hz: f64) -> f64 {
        let n = x.len().min(y.len());
        if n < 4 {
            return 0.0;
        }
        let nfft = n.max(self.min_fft).next_power_of_two();
        if self.n != n || self.fft.is_none() {
            self.window = hann(n);
            self.fft = Some(FftPlanner::<f64>::new().plan_fft_forward(nfft));
            self.n = n;
        }
        let (w, buf) = (&self.window, &mut self.buf);
        buf.clear();
        buf.resize(nfft, Complex::new(0.0, 0.0));
        for i in 0..n {
            buf[i] = Complex::new(x[i] * w[i], y[i] * w[i]);
        }
        self.fft.as_ref().expect("planned above").process(buf);
        let df = 1.0 / (nfft as f64 * dt_s);
        let freq = |k: usize| {
            if k <= nfft / 2 {
                k as f64 * df
            } else {
                (k as f64 - nfft as f64) * df
            }
        };
        let mut best = None;
        for k in 0..nfft {
            if freq(k).abs() < f_min_hz {
                continue;
            }
            let m = buf[k].norm_sqr();
            match best {
                Some((_, bm)) if bm >= m => {}
                _ => best = Some((k, m)),
            }
        }
        let Some((k, _)) = best else { return 0.0 };
        let lm = |j: usize| buf[j % nfft].norm_sqr().max(1e-300).ln();
        let (a, b, c) = (lm(k + nfft - 1), lm(k), lm(k + 1));
        let denom = a - 2.0 * b + c;
        let shift = if denom < 0.0 {
            (0.5 * (a - c) / denom).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        freq(k) + shift * df
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// One `WhirlFrequency` over windows of changing lengths (each change plans again) gives the
    /// same bits as a fresh plan and window per call, and finds the whirl.
    #[test]
    fn a_kept_plan_gives_the_fresh_plans_frequencies_bit_for_bit() {
        let dt = 5e-5;
        let z = |i: usize, f: f64| {
            let t = i as f64 * dt;
            (
                (TAU * f * t).cos() + 0.1 * (TAU * 37.0 * t).sin(),
                (TAU * f * t).sin(),
            )
        };
        let mut kept = WhirlFrequency::new(4096);
        for (n, f) in [
            (400, 310.0),
            (400, -255.0),
            (333, 480.0),
            (1000, 190.0),
            (400, 310.0),
        ] {
            let (x, y): (Vec<f64>, Vec<f64>) = (0..n).map(|i| z(i, f)).unzip();
            let fresh = dominant_whirl_hz(&x, &y, dt, 20.0, 4096);
            let reused = kept.dominant_hz(&x, &y, dt, 20.0);
            assert_eq!(fresh.to_bits(), reused.to_bits(), "window of {n} samples");
            let bin = 1.0 / (4096.0_f64.max(n as f64).log2().ceil().exp2() * dt);
            assert!(
                (reused - f).abs() < bin,
                "{reused} Hz for a whirl at {f} Hz"
            );
        }
    }

    #[test]
    fn pure_sine_peak_within_one_bin_and_amplitude() {
        let dt = 1e-4;
        let f0 = 437.0; // deliberately between bins (bin width 1/(0.04 s) = 25 Hz)
        let a = 3e-6;
        let sig: Vec<f64> = (0..20_000)
            .map(|i| 1e-5 + a * (TAU * f0 * i as f64 * dt).sin())
            .collect();
        let sg = spectrogram(&sig, dt, 0.04, 0.01);
        assert_eq!(sg.n_fft, 400);
        assert!(sg.times_s.len() > 150);
        let df = sg.freqs_hz[1] - sg.freqs_hz[0];
        for row in &sg.magnitude {
            let (k, peak) =
                row.iter()
                    .enumerate()
                    .fold((0, 0.0), |b, (k, m)| if *m > b.1 { (k, *m) } else { b });
            assert!(
                (sg.freqs_hz[k] - f0).abs() <= df,
                "peak at {} Hz",
                sg.freqs_hz[k]
            );
            // Hann scalloping loss is at most 1.42 dB (factor 0.85) between bins.
            assert!(
                peak > 0.84 * a && peak <= 1.0001 * a,
                "peak amplitude {peak}"
            );
        }
    }

    #[test]
    fn sine_on_bin_reads_its_amplitude_and_time_axis_is_centred() {
        let dt = 1e-3;
        let sig: Vec<f64> = (0..1000)
            .map(|i| 2.0 * (TAU * 50.0 * i as f64 * dt).cos())
            .collect();
        let sg = spectrogram(&sig, dt, 0.1, 0.1);
        assert_eq!(sg.magnitude.len(), 10);
        assert!((sg.times_s[0] - 0.0495).abs() < 1e-12);
        let k = sg
            .freqs_hz
            .iter()
            .position(|f| (*f - 50.0).abs() < 1e-9)
            .unwrap();
        assert!((sg.magnitude[3][k] - 2.0).abs() < 1e-9);
    }

    #[test]
    fn parseval_one_sided_energy_matches_windowed_signal_energy() {
        // sum_k |X_k|^2 = N sum_i (w_i x_i)^2 for the full two-sided DFT; the one-sided magnitudes
        // carry a factor 2 on interior bins, which is undone here.
        let dt = 1e-4;
        let sig: Vec<f64> = (0..1000)
            .map(|i| {
                let t = i as f64 * dt;
                (TAU * 310.0 * t).sin()
                    + 0.4 * (TAU * 1234.5 * t + 0.3).cos()
                    + 0.1 * ((i * 7919 % 101) as f64 / 101.0 - 0.5)
            })
            .collect();
        let sg = spectrogram(&sig, dt, 0.05, 0.05);
        let n = sg.n_fft;
        let w = hann(n);
        for (s, row) in sg.magnitude.iter().enumerate() {
            let seg = &sig[s * n..(s + 1) * n];
            let mean = seg.iter().sum::<f64>() / n as f64;
            let time_energy: f64 = seg
                .iter()
                .zip(&w)
                .map(|(x, w)| ((x - mean) * w).powi(2))
                .sum();
            let mut freq_energy = 0.0;
            for (k, m) in row.iter().enumerate() {
                let edge = k == 0 || k == n / 2;
                let xk = m * sg.window_sum / if edge { 1.0 } else { 2.0 };
                freq_energy += xk * xk * if edge { 1.0 } else { 2.0 };
            }
            let rel = (freq_energy / n as f64 - time_energy).abs() / time_energy;
            assert!(rel < 1e-10, "Parseval mismatch {rel}");
        }
    }

    #[test]
    fn whirl_direction_and_frequency() {
        let dt = 2e-5;
        let n = 2000; // 40 ms
        let f = 345.6;
        let x: Vec<f64> = (0..n).map(|i| (TAU * f * i as f64 * dt).cos()).collect();
        let y: Vec<f64> = (0..n).map(|i| (TAU * f * i as f64 * dt).sin()).collect();
        let fw = dominant_whirl_hz(&x, &y, dt, 20.0, 8192);
        assert!((fw - f).abs() < 2.0, "forward whirl read as {fw}");
        let yb: Vec<f64> = y.iter().map(|v| -v).collect();
        let bw = dominant_whirl_hz(&x, &yb, dt, 20.0, 8192);
        assert!((bw + f).abs() < 2.0, "backward whirl read as {bw}");
    }
}
