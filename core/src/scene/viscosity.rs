//! How the viscous pair term turns a pair's relative velocity into a force (docs/PHYSICS.md §4,
//! §4.1): the thesis's Laplacian sum (T70) or the projected sum, which takes out the
//! continuum's `2η e:e` where an inviscid neighbour phase leaves a free surface.

use serde::{Deserialize, Serialize};

/// The viscous pair form of every scene (`viscous_form`, top level).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ViscousForm {
    /// T70 (Hu–Adams, Morris): `v_ij` summed as it is.
    #[default]
    Laplacian,
    /// `(d + 2)(v_ij·x_ij) x_ij / r²` summed in place of `v_ij` (Monaghan–Cleary).
    Projected,
}

impl ViscousForm {
    /// True for the default, the thesis's T70.
    pub fn is_laplacian(&self) -> bool {
        *self == ViscousForm::Laplacian
    }
}
