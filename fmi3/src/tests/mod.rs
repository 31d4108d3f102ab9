//! Tests through the exported C functions, with a small test model (`lag`).

mod api;
mod early_return;
mod fmu;
mod intermediate;
mod lag;
mod state;
mod xml;

// One model per binary, as in a cdylib.
crate::export_fmu!(lag::Lag);
