//! The shared library carries a SONAME (`capi/build.rs`): read with
//! `readelf -d` from the `.so` this `cargo test` built beside the test
//! executable (skipped, saying so, where `readelf` or the library is absent
//! or the target is not Linux).

use std::process::Command;

#[test]
fn the_shared_library_has_a_soname() {
    if !cfg!(target_os = "linux") {
        eprintln!("skipping: SONAMEs are checked on Linux only");
        return;
    }
    let exe = std::env::current_exe().expect("test executable path");
    let deps = exe.parent().expect("target/<profile>/deps");
    let Some(lib) = [
        deps.join("libcoif_capi.so"),
        deps.join("../libcoif_capi.so"),
    ]
    .into_iter()
    .find(|p| p.exists()) else {
        eprintln!("skipping: no libcoif_capi.so beside {}", deps.display());
        return;
    };
    let Ok(out) = Command::new("readelf").arg("-d").arg(&lib).output() else {
        eprintln!("skipping: readelf does not run");
        return;
    };
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("Library soname: [libcoif_capi.so.0]"),
        "{}: {text}",
        lib.display()
    );
}
