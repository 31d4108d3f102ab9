//! The analytic Jacobian dF/dP of the Reynolds residual (`reynolds`), assembled four elements at
//! a time, one per vector lane.
//!
//! An element matrix is a sum over the 9 Gauss points of three outer products (coefficients of
//! N_b, dN_b/dphi and dN_b/dzeta), 2 187 multiply-adds per element. Written per element, its
//! loops run over the 9 columns of a row: two 4-wide vectors and a scalar remainder, broadcasts
//! of each row's coefficients, 70 us per lobe (a Jacobian, assembly and factorization, was a
//! quarter of film_C's time in path 1, and with both films in threads each film's Jacobians are
//! on the critical path). Four elements side by side fill every lane with the same arithmetic:
//! every sum keeps the order of the per-element formulation, so the result is bit-identical to
//! it (tested) and on every CPU.

use crate::geometry::GapField;
use crate::linsolve::BandLu;
#[cfg(test)]
use crate::mesh::gather;
use crate::mesh::Mesh;
use crate::reynolds::Coeffs;

/// Elements assembled side by side: one per f64 lane of an AVX2 vector (the residual's too).
pub(crate) const ELEM_LANES: usize = 4;

/// The elements `0..ne` in groups of [`ELEM_LANES`]: (first element, elements used, the element
/// of each lane). The last group repeats its last element in the unused lanes (computed there,
/// never added).
#[inline(always)]
pub(crate) fn element_groups(
    ne: usize,
) -> impl Iterator<Item = (usize, usize, [usize; ELEM_LANES])> {
    (0..ne).step_by(ELEM_LANES).map(move |e0| {
        let used = (ne - e0).min(ELEM_LANES);
        (e0, used, std::array::from_fn(|l| e0 + l.min(used - 1)))
    })
}

/// `reynolds::jacobian`'s body, inlined into its runtime dispatch.
#[inline(always)]
pub(crate) fn jacobian_element_lanes(
    mesh: &Mesh,
    gap: &GapField,
    k: usize,
    co: Coeffs,
    p: &[f64],
    lu: &mut BandLu,
) {
    const L: usize = ELEM_LANES;
    lu.zero();
    let b = &mesh.basis;
    let sy = 2.0 / mesh.dzeta_e;
    let nq = 3 * mesh.ne_phi;
    let (lam, tau, c0) = (co.lambda, co.tau_s, co.c0_per_s);
    // The physical gradients of the shape functions at the Gauss points per lane (the same
    // products the per-element loop formed for every element), and the Gauss weights times the
    // element's Jacobian. On a uniform mesh they are the same in every lane and every group.
    let scales = |dphi: [f64; L]| -> ([[[f64; L]; 9]; 9], [[f64; L]; 9]) {
        let sx: [f64; L] = std::array::from_fn(|l| 2.0 / dphi[l]);
        let nxs = std::array::from_fn(|q| {
            std::array::from_fn(|a| std::array::from_fn(|l| b.dx[q][a] * sx[l]))
        });
        let w = std::array::from_fn(|q| {
            std::array::from_fn(|l| b.w[q] * (0.25 * dphi[l] * mesh.dzeta_e))
        });
        (nxs, w)
    };
    let mut nys = [[0.0; 9]; 9];
    for q in 0..9 {
        for a in 0..9 {
            nys[q][a] = b.dy[q][a] * sy;
        }
    }
    let uniform = (!mesh.graded).then(|| scales([mesh.dphi_e; L]));
    for (e0, used, lane_elem) in element_groups(mesh.elem.len()) {
        let graded;
        let (nxs, wq) = match &uniform {
            Some(u) => (&u.0, &u.1),
            None => {
                graded = scales(std::array::from_fn(|l| {
                    mesh.col_dphi[mesh.elem_col[lane_elem[l]] as usize]
                }));
                (&graded.0, &graded.1)
            }
        };
        let mut pe = [[0.0; L]; 9];
        for (l, &e) in lane_elem.iter().enumerate() {
            for (a, &node) in mesh.elem[e].iter().enumerate() {
                pe[a][l] = p[node as usize];
            }
        }
        let gap_at: [usize; L] =
            std::array::from_fn(|l| k * nq + 3 * mesh.elem_col[lane_elem[l]] as usize);
        let mut ke = [[[0.0; L]; 9]; 9];
        for q in 0..9 {
            let (n, nx, ny) = (&b.n[q], &nxs[q], &nys[q]);
            let (mut h, mut hphi, mut ht) = ([0.0; L], [0.0; L], [0.0; L]);
            for l in 0..L {
                let gi = gap_at[l] + q / 3;
                (h[l], hphi[l], ht[l]) = (gap.h[gi], gap.h_phi[gi], gap.h_t[gi]);
            }
            let (mut pq, mut px, mut py) = ([0.0; L], [0.0; L], [0.0; L]);
            for a in 0..9 {
                for l in 0..L {
                    pq[l] += n[a] * pe[a][l];
                    px[l] += nx[a][l] * pe[a][l];
                    py[l] += ny[a] * pe[a][l];
                }
            }
            let w = &wq[q];
            let (mut a3, mut lamh, mut cb_flux, mut cb_src) =
                ([0.0; L], [0.0; L], [0.0; L], [0.0; L]);
            for l in 0..L {
                let h3 = h[l] * h[l] * h[l];
                a3[l] = w[l] * pq[l] * h3;
                lamh[l] = w[l] * lam * h[l];
                // Coefficient of N_b in row a, and of the gradients of N_b.
                cb_flux[l] = w[l] * h3;
                cb_src[l] = w[l] * (lam * hphi[l] + tau * (c0 * h[l] + ht[l]));
            }
            for a in 0..9 {
                let (mut ca, mut gx, mut gy) = ([0.0; L], [0.0; L], [0.0; L]);
                for l in 0..L {
                    ca[l] = cb_flux[l] * (px[l] * nx[a][l] + py[l] * ny[a]) + cb_src[l] * n[a];
                    gx[l] = a3[l] * nx[a][l] + lamh[l] * n[a];
                    gy[l] = a3[l] * ny[a];
                }
                let row = &mut ke[a];
                for bb in 0..9 {
                    for l in 0..L {
                        row[bb][l] += ca[l] * n[bb] + gx[l] * nx[bb][l] + gy[l] * ny[bb];
                    }
                }
            }
        }
        // Into the band element by element, rows in order: the additions of the per-element
        // formulation, in its order.
        for l in 0..used {
            let nodes = &mesh.elem[e0 + l];
            for a in 0..9 {
                let row: [f64; 9] = std::array::from_fn(|bb| ke[a][bb][l]);
                lu.add_row(nodes[a] as usize, &nodes[..], &row);
            }
        }
    }
    for (i, d) in mesh.dirichlet.iter().enumerate() {
        if *d {
            lu.set_identity_row(i);
        }
    }
}

/// The Jacobian assembled one element at a time (the earlier assembly): the element-lane
/// assembly must equal it bit for bit (tests only).
#[cfg(test)]
pub(crate) fn jacobian_one_element_at_a_time(
    mesh: &Mesh,
    gap: &GapField,
    k: usize,
    co: Coeffs,
    p: &[f64],
    lu: &mut BandLu,
) {
    lu.zero();
    let b = &mesh.basis;
    let sy = 2.0 / mesh.dzeta_e;
    let nq = 3 * mesh.ne_phi;
    let (lam, tau, c0) = (co.lambda, co.tau_s, co.c0_per_s);
    for (e, nodes) in mesh.elem.iter().enumerate() {
        let col = mesh.elem_col[e] as usize;
        // Each column's own size (on a uniform mesh `dphi_e` itself: the same bits).
        let (sx, jac) = (
            2.0 / mesh.col_dphi[col],
            0.25 * mesh.col_dphi[col] * mesh.dzeta_e,
        );
        let pe = gather(nodes, p);
        let mut ke = [[0.0; 9]; 9];
        for q in 0..9 {
            let gi = k * nq + 3 * col + q / 3;
            let (h, hphi, ht) = (gap.h[gi], gap.h_phi[gi], gap.h_t[gi]);
            let (n, nxr, nyr) = (&b.n[q], &b.dx[q], &b.dy[q]);
            let mut nx = [0.0; 9];
            let mut ny = [0.0; 9];
            let (mut pq, mut px, mut py) = (0.0, 0.0, 0.0);
            for a in 0..9 {
                nx[a] = nxr[a] * sx;
                ny[a] = nyr[a] * sy;
                pq += n[a] * pe[a];
                px += nx[a] * pe[a];
                py += ny[a] * pe[a];
            }
            let w = b.w[q] * jac;
            let h3 = h * h * h;
            let a3 = w * pq * h3;
            let lamh = w * lam * h;
            // Coefficient of N_b in row a, and of the gradients of N_b.
            let cb_flux = w * h3;
            let cb_src = w * (lam * hphi + tau * (c0 * h + ht));
            for a in 0..9 {
                let ca = cb_flux * (px * nx[a] + py * ny[a]) + cb_src * n[a];
                let gx = a3 * nx[a] + lamh * n[a];
                let gy = a3 * ny[a];
                let row = &mut ke[a];
                for bb in 0..9 {
                    row[bb] += ca * n[bb] + gx * nx[bb] + gy * ny[bb];
                }
            }
        }
        for a in 0..9 {
            lu.add_row(nodes[a] as usize, &nodes[..], &ke[a]);
        }
    }
    for (i, d) in mesh.dirichlet.iter().enumerate() {
        if *d {
            lu.set_identity_row(i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lane_test_cases::{lane_cases, LaneCase};
    use crate::reynolds;
    use crate::test_rng::uniform;

    /// On random pressures and journal states (plain and lobed bores, steady and transient, every
    /// block, a mesh whose element count is not a multiple of the lanes), the element-lane
    /// assembly equals the per-element one bit for bit in every band entry.
    #[test]
    fn element_lanes_equal_the_per_element_assembly_bit_for_bit() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        for LaneCase {
            case,
            mesh,
            gap,
            co,
        } in lane_cases(&mut seed)
        {
            if case == 3 {
                assert_ne!(mesh.elem.len() % ELEM_LANES, 0, "a partly used last group");
            }
            let npb = mesh.npb;
            for k in 0..mesh.n_blocks {
                let p: Vec<f64> = (0..npb).map(|_| 0.5 + 2.0 * uniform(&mut seed)).collect();
                let mut new = BandLu::new(npb, mesh.kl, mesh.ku);
                let mut old = BandLu::new(npb, mesh.kl, mesh.ku);
                reynolds::jacobian(&mesh, &gap, k, co, &p, &mut new);
                jacobian_one_element_at_a_time(&mesh, &gap, k, co, &p, &mut old);
                let mut nonzero = 0;
                for r in 0..npb {
                    for col in r.saturating_sub(mesh.kl)..(r + mesh.ku + 1).min(npb) {
                        let (x, y) = (new.get(r, col), old.get(r, col));
                        assert_eq!(
                            x.to_bits(),
                            y.to_bits(),
                            "case {case}, block {k}, ({r}, {col}): {x} vs {y}"
                        );
                        nonzero += usize::from(x != 0.0);
                    }
                }
                assert!(nonzero > 9 * npb, "case {case}: {nonzero} nonzero entries");
            }
        }
    }
}
