//! The test cases the element-lane kernels (residual and Jacobian) are checked on against their
//! scalar references: one table, so both kernels see the same meshes.

use crate::geometry::{GapField, Geometry};
use crate::mesh::Mesh;
use crate::params::BearingParams;
use crate::reynolds::Coeffs;
use crate::test_rng::uniform;
use crate::JournalState;

/// One case: a mesh, the gap of a random journal state on it, and random coefficients.
pub struct LaneCase {
    /// 0-5, for messages; case 1 has no time-derivative term (steady), case 3 a partly used last
    /// group of lanes on a uniform mesh.
    pub case: usize,
    pub mesh: Mesh,
    pub gap: GapField,
    pub co: Coeffs,
}

/// Lobed and plain bores, steady and transient, 20 and 7 elements along the lobe (7 leaves a
/// partly used last group of lanes), and graded meshes (a size per lane; 7 columns graded by 0.6
/// leave a partly used last group with lanes of different sizes). Draws from `seed`.
pub fn lane_cases(seed: &mut u64) -> Vec<LaneCase> {
    [
        (0, false, 20, 1.0),
        (1, false, 20, 1.0),
        (2, true, 20, 1.0),
        (3, false, 7, 1.0),
        (4, false, 10, 0.8),
        (5, false, 7, 0.6),
    ]
    .into_iter()
    .map(|(case, plain, n_elem_phi, grading)| {
        let mut prm = BearingParams::paper();
        if plain {
            prm.bore.dh_m = 0.0;
        }
        prm.n_elem_phi = n_elem_phi;
        prm.mesh_grading = grading;
        let mesh = Mesh::new(&prm);
        let geom = Geometry::new(&prm, &mesh);
        let c = prm.bore.c_m;
        let j = JournalState {
            dx_m: (uniform(seed) - 0.5) * c,
            dy_m: (uniform(seed) - 0.5) * c,
            vx_m_s: (uniform(seed) - 0.5) * 0.1,
            vy_m_s: (uniform(seed) - 0.5) * 0.1,
            omega_rad_s: 6000.0 * uniform(seed),
        };
        let mut gap = GapField::default();
        geom.update(&j, c, &mut gap);
        let co = Coeffs {
            lambda: prm.bearing_number(j.omega_rad_s),
            tau_s: prm.squeeze_time_s(),
            c0_per_s: if case == 1 { 0.0 } else { 1e5 * uniform(seed) },
        };
        LaneCase {
            case,
            mesh,
            gap,
            co,
        }
    })
    .collect()
}
