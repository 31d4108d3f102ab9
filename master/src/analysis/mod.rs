//! Run-up analysis: onset detection, spectra, classification.
