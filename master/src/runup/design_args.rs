//! The flags that describe a rotor and its bearings (a preset, a design file, the bearing flags,
//! `--set`), shared by `runup`, `stability`, `orbits` and a study's keys, and the run-up settings
//! they make.

use super::RunupSettings;
use crate::design::Design;
use std::path::PathBuf;

/// The flags that describe the rotor and its bearings, shared by `airring runup` and `airring
/// stability` (a study's keys are the same flags): a preset, a design file over it, then the
/// flags, then `--set` (each later one wins).
#[derive(clap::Args, Clone, Debug)]
pub struct DesignArgs {
    /// Paper Section 3 parameter set: path1 (c = 1000 N/mm), path2a (500 N/mm), path2b (100 N/mm, 150 g rings).
    #[arg(long, default_value = "path1")]
    pub preset: String,
    /// A design file (TOML: [bearing], [bearing.compressor], [bearing.turbine], [rotor]; see
    /// docs/design.md) applied over the preset; the flags below override it.
    #[arg(long)]
    pub design: Option<PathBuf>,
    /// Ring mount stiffness c [N/mm] (both bearings).
    #[arg(long)]
    pub c: Option<f64>,
    /// Ring mount damping d [N s/m] (both bearings).
    #[arg(long)]
    pub d: Option<f64>,
    /// Ring mass m_R [g] (each ring).
    #[arg(long)]
    pub m_r: Option<f64>,
    /// Nominal clearance C [um] (both bearings).
    #[arg(long)]
    pub clearance: Option<f64>,
    /// Step height dH [um] (both bearings).
    #[arg(long)]
    pub dh: Option<f64>,
    /// Air-film mesh per lobe, uniform, e.g. 20x6 (elements along the lobe x across the half
    /// width; --set film.mesh_grading=G grades it toward each lobe's trailing edge). Default: the
    /// paper's 20x6; a run-up without it takes 10x2 or 10x3 graded by 0.8, 20x4 or 20x6 by the
    /// largest bearing number of its films, 10x2 with film tolerance 6e-4,60 (docs/convergence.md,
    /// "A graded film mesh along the lobe", "Two elements across the half width").
    #[arg(long)]
    pub mesh: Option<String>,
    /// Any other FMU parameter, repeatable: PREFIX.NAME=VALUE with PREFIX rotor, film (both
    /// films), film_C or film_T; VALUE a number (SI) or "number unit" (e.g. --set film.eta=1.9e-5,
    /// --set "rotor.c_C=1500 N/mm"). Replaces a value the run-up would set itself.
    #[arg(long = "set", value_name = "FMU.NAME=VALUE")]
    pub set: Vec<String>,
}

impl DesignArgs {
    /// The settings these flags describe (checked with `RunupSettings::validate`).
    pub fn settings(&self) -> Result<RunupSettings, String> {
        let mut s = RunupSettings::preset(&self.preset)?;
        let mut design = match &self.design {
            Some(p) => Design::load(p)?,
            None => Design::default(),
        };
        // A flag given explicitly overrides the design's entries of the same variables.
        let overridden: [(bool, &[&str]); 5] = [
            (self.c.is_some(), &["rotor.c_C", "rotor.c_T"]),
            (self.d.is_some(), &["rotor.d_C", "rotor.d_T"]),
            (self.m_r.is_some(), &["rotor.m_R_C", "rotor.m_R_T"]),
            (self.clearance.is_some(), &["film.C"]),
            (self.dh.is_some(), &["film.dH"]),
        ];
        for (given, keys) in overridden {
            if given {
                design = design.without(keys);
            }
        }
        s.c_n_per_mm = self.c.unwrap_or(s.c_n_per_mm);
        s.d_n_s_per_m = self.d.unwrap_or(s.d_n_s_per_m);
        s.m_r_g = self.m_r.unwrap_or(s.m_r_g);
        s.clearance_um = self.clearance.unwrap_or(s.clearance_um);
        s.dh_um = self.dh.unwrap_or(s.dh_um);
        if let Some(m) = &self.mesh {
            (s.n_elem_phi, s.n_elem_z) = super::parse_mesh(m, "--mesh")?;
        }
        s.design = self.design.clone();
        s.shaft = design.shaft;
        s.fmu_parameters = design.entries;
        s.fmu_parameters
            .extend(crate::fmu_params::parse_set_flags(&self.set)?);
        Ok(s)
    }
}
