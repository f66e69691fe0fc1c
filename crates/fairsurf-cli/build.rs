//! Links the `fairsurf` command as a position-dependent executable on
//! Linux: a position-independent one has ~15,000 relative relocations
//! that the dynamic loader applies at every start (`LD_DEBUG=statistics`:
//! 1.3 M of its 1.7 M cycles), touching the pages they lie in; without
//! them the loader takes 0.2 M cycles and a start has 60 fewer page
//! faults (`perf stat`, `fairsurf --version`: 202 → 139).

fn main() {
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-link-arg-bins=-no-pie");
    }
}
