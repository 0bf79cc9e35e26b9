//! Builds `examples/hang.c`, `examples/engine.c`, `examples/jobs.c` and
//! `examples/world.c` (C99, `jobs.c` with `-pthread`), `examples/sintel.c`
//! (C11: it times its frames with `timespec_get`, which C99 lacks) and
//! `examples/hang.cpp` and `examples/world.cpp` (C++17, with `-pthread`) against the static library and the committed
//! header with the system C and C++ compilers (`-Wall -Wextra -Werror
//! -pedantic`), runs them (with the shared groom `sintel_lite.tfx` as
//! argument when it is there), and checks their exit code and output. Also
//! compiles the header alone as C99 and as C++17.
//!
//! `cargo test -p coif-capi` builds `libcoif_capi.a` (a crate type of this
//! package) into `target/<profile>/deps/`, beside this test's executable.
//! The tests are skipped, saying so, only when no compiler runs (`CC` / `CXX`
//! override `cc` / `c++`).

use std::path::{Path, PathBuf};
use std::process::Command;

fn capi_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The static library this `cargo test` built: `cargo test` writes it into
/// `target/<profile>/deps/` beside this test executable (`cargo build` copies
/// it up to `target/<profile>/`, the fallback).
fn static_lib() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let deps = exe.parent().expect("target/<profile>/deps");
    let candidates = [deps.join("libcoif_capi.a"), deps.join("../libcoif_capi.a")];
    candidates
        .iter()
        .find(|p| p.exists())
        .cloned()
        .unwrap_or_else(|| {
            panic!(
                "libcoif_capi.a not found beside {}: build it with `cargo build -p coif-capi` (same profile)",
                exe.display()
            )
        })
}

/// The compiler named by `var` (else `default`) if it runs.
fn compiler(var: &str, default: &str) -> Option<String> {
    let cc = std::env::var(var).unwrap_or_else(|_| default.to_string());
    let runs = Command::new(&cc)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if runs {
        Some(cc)
    } else {
        eprintln!("SKIPPED: no C/C++ compiler `{cc}` found (set {var})");
        None
    }
}

fn run(cmd: &mut Command) -> std::process::Output {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{cmd:?} did not start: {e}"));
    assert!(
        out.status.success(),
        "{cmd:?} failed ({}):\nstdout:\n{}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Compiles `source` with `cc` and `flags`, links the static library, runs
/// the program with `args` and returns its standard output.
fn build_and_run(cc: &str, flags: &[&str], source: &str, name: &str, args: &[PathBuf]) -> String {
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let include = capi_dir().join("include");
    run(Command::new(cc)
        .args(flags)
        .args(["-Wall", "-Wextra", "-Werror", "-pedantic"])
        .arg("-I")
        .arg(&include)
        .arg(capi_dir().join("examples").join(source))
        .arg(static_lib())
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe));
    let out = run(Command::new(&exe).args(args));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn hang_c_runs_and_passes_its_checks() {
    let Some(cc) = compiler("CC", "cc") else {
        return;
    };
    let stdout = build_and_run(&cc, &["-std=c99"], "hang.c", "hang_c", &[]);
    assert!(stdout.contains("hang: all checks passed"), "{stdout}");
}

#[test]
fn hang_cpp_runs_and_passes_its_checks() {
    let Some(cxx) = compiler("CXX", "c++") else {
        return;
    };
    let groom: Vec<PathBuf> = coif_testkit::groom_path("sintel_lite.tfx")
        .into_iter()
        .collect();
    let stdout = build_and_run(
        &cxx,
        &["-std=c++17", "-pthread"],
        "hang.cpp",
        "hang_cpp",
        &groom,
    );
    assert!(stdout.contains("all checks passed"), "{stdout}");
    assert!(stdout.contains("render vertices shaded"), "{stdout}");
    assert!(stdout.contains("hang.cpp: cloth blended"), "{stdout}");
    assert!(
        stdout.contains("hang.cpp: 64 strands on std::thread workers = coif_step bit for bit"),
        "{stdout}"
    );
    if !groom.is_empty() {
        assert!(
            stdout.contains("hang.cpp: groom of 228 strands"),
            "{stdout}"
        );
    }
}

#[test]
fn engine_c_runs_and_passes_its_checks() {
    let Some(cc) = compiler("CC", "cc") else {
        return;
    };
    let groom: Vec<PathBuf> = coif_testkit::groom_path("sintel_lite.tfx")
        .into_iter()
        .collect();
    let stdout = build_and_run(&cc, &["-std=c99"], "engine.c", "engine_c", &groom);
    assert!(stdout.contains("engine: all checks passed"), "{stdout}");
    assert!(stdout.contains("cloth: 4 x 9 patch, 60 steps"), "{stdout}");
    if !groom.is_empty() {
        // sintel_lite: 228 strands of 32 vertices; every 10th is a guide.
        assert!(
            stdout.contains("groom: 228 strands, 7296 vertices; 23 guides"),
            "{stdout}"
        );
    }
}

/// The groom-to-pixels example on the project's shipped Sintel groom:
/// resampled guides, the fitted head, the scalp triangles, render hairs, a
/// head turn by `coif_strands_set_head_pose`, vertices and colours; a bad
/// pose refused with a message that says why.
#[test]
fn sintel_c_goes_from_a_groom_file_to_shaded_vertices() {
    let Some(cc) = compiler("CC", "cc") else {
        return;
    };
    let groom = capi_dir().join("../assets/sintel/sintel_lite.tfx");
    // C11, not C99: its timer is `timespec_get`.
    let stdout = build_and_run(&cc, &["-std=c11"], "sintel.c", "sintel_c", &[groom]);
    assert!(stdout.contains("sintel.c: all checks passed"), "{stdout}");
    assert!(stdout.contains("sintel.c: 228 strands, "), "{stdout}");
    assert!(
        stdout.contains(
            "sintel.c: a scaled pose: the transform's 3 x 3 part is not a rotation (determinant 8"
        ),
        "{stdout}"
    );
}

#[test]
fn jobs_c_steps_on_a_pthread_pool_as_coif_step_does() {
    let Some(cc) = compiler("CC", "cc") else {
        return;
    };
    let stdout = build_and_run(&cc, &["-std=c99", "-pthread"], "jobs.c", "jobs_c", &[]);
    assert!(stdout.contains("jobs: all checks passed"), "{stdout}");
    assert!(
        stdout.contains("72 strands, 300 steps on the pool = coif_step bit for bit"),
        "{stdout}"
    );
    assert!(stdout.contains("5 patches stepped on the pool"), "{stdout}");
    assert!(
        stdout.contains("1003 vertices shaded on the pool"),
        "{stdout}"
    );
}

/// The lines both world examples print about the field: it built, went into
/// the set, and no vertex ended inside it (the examples fail, exiting
/// non-zero, when the field does not build).
fn check_world_field(stdout: &str, name: &str) {
    assert!(
        stdout.contains(&format!(
            "{name}: field of 8 triangles built, in a set of 1"
        )),
        "{stdout}"
    );
    let prefix = format!("{name}: nearest vertex ");
    let nearest: f32 = stdout
        .lines()
        .find_map(|l| l.strip_prefix(&prefix)?.strip_suffix(" m from the field"))
        .unwrap_or_else(|| panic!("no `{prefix}... m from the field` line:\n{stdout}"))
        .parse()
        .unwrap_or_else(|e| panic!("{name}: the field distance does not parse ({e}):\n{stdout}"));
    assert!(
        nearest > -0.001,
        "{name}: a vertex is {nearest} m inside the field:\n{stdout}"
    );
}

#[test]
fn world_c_blows_hair_over_a_capsule_onto_a_field() {
    let Some(cc) = compiler("CC", "cc") else {
        return;
    };
    let stdout = build_and_run(&cc, &["-std=c99"], "world.c", "world_c", &[]);
    assert!(stdout.contains("world: all checks passed"), "{stdout}");
    assert!(stdout.contains("m downwind; nearest vertex"), "{stdout}");
    check_world_field(&stdout, "world");
}

#[test]
fn world_cpp_blows_hair_over_a_capsule_onto_a_field() {
    let Some(cxx) = compiler("CXX", "c++") else {
        return;
    };
    let stdout = build_and_run(
        &cxx,
        &["-std=c++17", "-pthread"],
        "world.cpp",
        "world_cpp",
        &[],
    );
    assert!(stdout.contains("world.cpp: all checks passed"), "{stdout}");
    assert!(
        stdout.contains("world.cpp: on 3 std::thread workers = coif_step_colliders bit for bit"),
        "{stdout}"
    );
    check_world_field(&stdout, "world.cpp");
}

#[test]
fn header_alone_compiles_as_c99_and_cpp17() {
    let header = capi_dir().join("include").join("coif.h");
    let strict = ["-Wall", "-Wextra", "-Werror", "-pedantic", "-fsyntax-only"];
    if let Some(cc) = compiler("CC", "cc") {
        run(Command::new(cc)
            .args(["-std=c99", "-x", "c"])
            .args(strict)
            .arg(&header));
    }
    if let Some(cxx) = compiler("CXX", "c++") {
        run(Command::new(cxx)
            .args(["-std=c++17", "-x", "c++"])
            .args(strict)
            .arg(&header));
    }
}
