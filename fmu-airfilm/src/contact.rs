//! Mixed-lubrication penalty contact (paper Section 2.2, MODEL.md section 3): the law and its
//! force integral live in the `bearing` crate, shared with the rotor (which evaluates the same
//! law itself with `contact = true`). Where h < h_con = h_con_rel C, a contact pressure
//! p_con = c_con (h_con - h) acts on the journal; it enters the force integral only (not the
//! Reynolds equation), integrated over the contact band, independent of the film's mesh.

pub use bearing::contact::{contact_force_at_n, contact_force_n, ContactLaw};
