//! The `sphlab` command line.
fn main() {}
