//! `sphlab forces`: where a saved state's forces come from. [`balance`] splits each fluid
//! particle's pair forces by term and partner from the CPU reference's own neighbour walk
//! (`cpu::momentum::acceleration_pairs`), sums them in a window around the contact point and
//! measures the tension a band carries across a vertical cut; [`report`] reads a `sphlab run`
//! output folder and prints that balance as Markdown (and CSV).

pub mod balance;
pub mod report;
