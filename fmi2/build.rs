// The importer's logger must be C-variadic (fmi2CallbackLogger), which stable Rust cannot define:
// a few lines of C format the message with vsnprintf and hand it to Rust.
fn main() {
    #[cfg(feature = "importer")]
    {
        println!("cargo:rerun-if-changed=src/importer/logger_shim.c");
        cc::Build::new()
            .file("src/importer/logger_shim.c")
            .warnings(true)
            .compile("fmi2_logger_shim");
    }
}
