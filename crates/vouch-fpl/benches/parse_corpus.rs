//! Benchmark: parse every XML file of `shared/fpl/corpus` (placeholder, filled below).
fn main() {}
