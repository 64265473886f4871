//! The `kansei` command line.
fn main() {}
