//! Gives the shared library a SONAME (`libcoif_capi.so.0` on Linux), so a
//! program linked against it records that name and finds the library by
//! it at run time; the number is the ABI's major version, raised when a
//! public struct's layout or a call's meaning changes.

fn main() {
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    if os == "linux" {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libcoif_capi.so.0");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
