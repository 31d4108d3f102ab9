//! The run-up flags that are text ("X,Y" pairs, "NxM" meshes) and the clearance and step height
//! checked against the bore's bounds, with messages that name the flag and its unit.

/// "X,Y" as two numbers (spaces allowed).
fn number_pair(text: &str) -> Option<(f64, f64)> {
    let (x, y) = text.split_once(',')?;
    Some((x.trim().parse().ok()?, y.trim().parse().ok()?))
}

/// `--step-control`: "off" or "RTOL,ATOL_N" (finite, >= 0, not both 0).
pub fn parse_step_control(text: &str) -> Result<Option<[f64; 2]>, String> {
    if text.trim() == "off" {
        return Ok(None);
    }
    let (r, a) = number_pair(text).ok_or_else(|| {
        format!("--step-control '{text}': expected RTOL,ATOL_N (e.g. 0.1,1) or off")
    })?;
    let c = cosim::StepControl::new(r, a).map_err(|e| format!("--step-control '{text}': {e}"))?;
    Ok(Some([c.rtol, c.atol]))
}

/// `--film-tolerance`: "RTOL,ATOL_PA" (0 < RTOL < 1, ATOL_PA > 0).
pub fn parse_film_tolerance(text: &str) -> Result<[f64; 2], String> {
    let (r, a) = number_pair(text).ok_or_else(|| {
        format!("--film-tolerance '{text}': expected RTOL,ATOL_PA (e.g. 1e-4,10)")
    })?;
    if !(r > 0.0 && r < 1.0 && a > 0.0 && a.is_finite()) {
        return Err(format!(
            "--film-tolerance '{text}': RTOL must lie in (0, 1) and ATOL_PA be finite and > 0"
        ));
    }
    Ok([r, a])
}

/// A film mesh per lobe written "NxM" (elements along the lobe x across the half width).
pub fn parse_mesh(text: &str, flag: &str) -> Result<(u32, u32), String> {
    let bad = || format!("{flag} '{text}': expected NxM, e.g. 20x6");
    let (p, z) = text.split_once('x').ok_or_else(bad)?;
    let (p, z): (u32, u32) = (
        p.trim().parse().map_err(|_| bad())?,
        z.trim().parse().map_err(|_| bad())?,
    );
    // Checked here too, so that no flag reaches a run or a prediction that every film would
    // refuse.
    if let Some(why) = mesh_out_of_bounds(p.into(), z.into()) {
        return Err(format!("{flag} '{text}': mesh {why}"));
    }
    Ok((p, z))
}

/// Why a film mesh of `phi` x `z` elements per lobe is outside the air-film FMU's own bounds
/// (n_elem_phi 4-2000, n_elem_z 2-500), if it is.
pub(super) fn mesh_out_of_bounds(phi: u64, z: u64) -> Option<&'static str> {
    if phi < 4 || z < 2 {
        Some("too coarse (at least 4x2 elements per lobe)")
    } else if phi > 2000 || z > 500 {
        Some("too fine (at most 2000x500 elements per lobe)")
    } else {
        None
    }
}

/// A number as a message shows it: plainly where that is short, else with an exponent ("1e-300"
/// rather than 300 digits, "2e16" rather than seventeen).
pub fn fmt_number(x: f64) -> String {
    cosim::number::short(x)
}

/// `--clearance` within the bore's own bounds (`bearing::Bore::validate`), in the flag's unit.
pub fn check_clearance_um(c_um: f64) -> Result<(), String> {
    if !(c_um.is_finite() && c_um > 0.0) {
        return Err(format!(
            "--clearance = {} um must be a finite number > 0",
            fmt_number(c_um)
        ));
    }
    if !(0.01..=1e4).contains(&c_um) {
        return Err(format!(
            "--clearance = {} um must lie between 0.01 um and 10000 um",
            fmt_number(c_um)
        ));
    }
    Ok(())
}

/// `--dh` within the bore's own bounds, in the flag's unit.
pub fn check_dh_um(dh_um: f64) -> Result<(), String> {
    if !(dh_um.is_finite() && dh_um >= 0.0) {
        return Err(format!(
            "--dh = {} um must be a finite number >= 0",
            fmt_number(dh_um)
        ));
    }
    if dh_um > 1e4 {
        return Err(format!(
            "--dh = {} um must lie between 0 um and 10000 um",
            fmt_number(dh_um)
        ));
    }
    Ok(())
}
