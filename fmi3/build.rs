// The fmi2 instance logs through a C-variadic callback that stable Rust cannot define: a few lines of
// C (src/log_bridge.c) format its message and pass it on to the FMI 3.0 logger.
fn main() {
    println!("cargo:rerun-if-changed=src/log_bridge.c");
    cc::Build::new()
        .file("src/log_bridge.c")
        .warnings(true)
        .compile("fmi3_log_bridge");
}
