//! The `coif` binary: its options write PNGs of the asked size, and bad
//! options or files fail with a message instead of a picture.

use std::path::PathBuf;
use std::process::Command;

/// The shipped Sintel files.
const SINTEL_GROOM: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../assets/sintel/sintel_lite.tfx"
);
const SINTEL_BUST: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../assets/sintel/sintel_bust.obj"
);

/// Width and height from a PNG's IHDR chunk (bytes 16..24), after checking
/// the signature.
fn png_size(path: &PathBuf) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{}", path.display());
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

fn out_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("coif_cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn the_binary_writes_the_picture_and_the_contact_sheet() {
    let dir = out_dir();
    let (image, sheet) = (dir.join("hair.png"), dir.join("sheet.png"));
    let _ = std::fs::remove_file(&image);
    let _ = std::fs::remove_file(&sheet);
    let out = Command::new(env!("CARGO_BIN_EXE_coif"))
        .args([
            "--size",
            "96x80",
            "--frames",
            "6",
            "--density",
            "8",
            "--render-every",
            "0",
        ])
        .args(["--shading", "marschner", "--output"])
        .arg(&image)
        .arg("--sheet")
        .arg(&sheet)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(png_size(&image), (96, 80));
    // 3 x 2 tiles of 96 x 80 with 4-pixel gaps.
    assert_eq!(png_size(&sheet), (3 * 96 + 4 * 4, 2 * 80 + 3 * 4));
    assert!(stdout.contains("Sintel (c) Blender Foundation"), "{stdout}");
    for stage in [
        "simulate",
        "lod",
        "shade",
        "rasterise body",
        "rasterise hair",
    ] {
        assert!(
            stdout.contains(stage),
            "the timing table lists {stage}:\n{stdout}"
        );
    }
}

#[test]
fn no_ribbon_leaves_the_ribbons_out() {
    let image = out_dir().join("no_ribbon.png");
    let run = |extra: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_coif"))
            .args(["--scene", "sphere"])
            .args(["--size", "64x64", "--frames", "3", "--density", "8"])
            .args(["--render-every", "0", "--output"])
            .arg(&image)
            .args(extra)
            .output()
            .unwrap();
        assert!(out.status.success());
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let with = run(&[]);
    assert!(
        with.contains("2 ribbons") && with.contains("rasterise ribbon"),
        "{with}"
    );
    let without = run(&["--no-ribbon"]);
    assert!(
        without.contains("0 ribbons") && !without.contains("rasterise ribbon"),
        "{without}"
    );
}

#[test]
fn bad_options_and_files_fail_with_a_message() {
    let dir = out_dir();
    for args in [
        vec!["--size", "0x10"],
        vec!["--size", "wide"],
        vec!["--shading", "phong"],
        vec!["--hair-color", "green"],
        vec!["--view", "0,0,0"],
        vec!["--groom", "/nonexistent/hair.tfx"],
        vec!["--scene", "cube"],
        vec!["--mesh", SINTEL_BUST],
        vec!["--groom", SINTEL_GROOM, "--mesh", "/nonexistent/bust.obj"],
        vec!["--groom", SINTEL_GROOM, "--mesh", SINTEL_GROOM],
    ] {
        let image = dir.join("never.png");
        let _ = std::fs::remove_file(&image);
        let out = Command::new(env!("CARGO_BIN_EXE_coif"))
            .args(&args)
            .arg("--output")
            .arg(&image)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(!out.stderr.is_empty(), "{args:?}: a message on stderr");
        assert!(!image.exists(), "{args:?}: no picture");
    }
    // A missing groom says where it was looked for and what a groom is.
    let out = Command::new(env!("CARGO_BIN_EXE_coif"))
        .args(["--groom", "no_such_groom.tfx", "--output"])
        .arg(dir.join("never.png"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("looked at no_such_groom.tfx")
            && err.contains("shared/data/grooms/no_such_groom.tfx")
            && err.contains(".tfx or cyHair"),
        "{err}"
    );
}

/// A missing or unreadable body mesh names the file and the reason.
#[test]
fn a_bad_mesh_says_which_file_and_why() {
    let dir = out_dir();
    let run = |mesh: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_coif"))
            .args(["--groom", SINTEL_GROOM, "--mesh", mesh, "--output"])
            .arg(dir.join("never.png"))
            .output()
            .unwrap();
        assert!(!out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let err = run("/nonexistent/bust.obj");
    assert!(
        err.contains("cannot read mesh /nonexistent/bust.obj"),
        "{err}"
    );
    // The groom read as an OBJ: not a mesh.
    let err = run(SINTEL_GROOM);
    assert!(err.contains(SINTEL_GROOM) && err.contains("OBJ"), "{err}");
    // The right pair works, and says what it drew.
    let out = Command::new(env!("CARGO_BIN_EXE_coif"))
        .args(["--groom", SINTEL_GROOM, "--mesh", SINTEL_BUST])
        .args(["--size", "48x48", "--frames", "2", "--render-every", "0"])
        .arg("--output")
        .arg(dir.join("on_mesh.png"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("228 kept as guides) on "), "{stdout}");
}

/// `--timings-csv` writes the per-stage table as CSV with the four totals
/// and the finer rows; `--animation` writes an APNG of every
/// `--animation-every`-th frame (decoded here: frame count, size, delay,
/// every frame's pixels), the same bytes on a second run.
#[test]
fn timings_csv_and_the_animation() {
    let dir = out_dir();
    let (csv, anim, anim2, image) = (
        dir.join("timings.csv"),
        dir.join("motion.png"),
        dir.join("motion2.png"),
        dir.join("animated_last.png"),
    );
    let run = |anim: &PathBuf| {
        let _ = std::fs::remove_file(anim);
        let out = Command::new(env!("CARGO_BIN_EXE_coif"))
            .args(["--size", "64x48", "--frames", "7", "--density", "8"])
            .args([
                "--fps",
                "25",
                "--animation-every",
                "2",
                "--render-every",
                "3",
            ])
            .arg("--animation")
            .arg(anim)
            .arg("--timings-csv")
            .arg(&csv)
            .arg("--output")
            .arg(&image)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    };
    run(&anim);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("stage,runs,mean_ms,last_ms"));
    let rows: Vec<(String, u32, f64, f64)> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 4, "{l}");
            (
                f[0].to_string(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
            )
        })
        .collect();
    let row = |name: &str| {
        rows.iter()
            .find(|r| r.0 == name)
            .unwrap_or_else(|| panic!("no row {name}:\n{text}"))
            .clone()
    };
    // 7 frames simulate; frames 0, 2, 4, 6 (animation), 3 (render-every)
    // render: 5 frames.
    assert_eq!(row("simulate").1, 7);
    for name in [
        "prepare",
        "raster",
        "frame",
        "lod",
        "shade",
        "rasterise hair",
    ] {
        assert_eq!(row(name).1, 5, "{name}");
    }
    for r in &rows {
        assert!(r.2 >= 0.0 && r.3 >= 0.0 && r.2.is_finite(), "{r:?}");
    }
    let (prepare, raster, frame) = (row("prepare").2, row("raster").2, row("frame").2);
    assert!(
        prepare + raster <= frame * 1.01 + 0.01,
        "prepare {prepare} + raster {raster} within frame {frame}"
    );

    // The animation: 4 frames (0, 2, 4, 6) of 64 x 48, 2 / 25 s each.
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&anim).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let actl = reader.info().animation_control.expect("an animated PNG");
    assert_eq!(actl.num_frames, 4);
    assert_eq!((reader.info().width, reader.info().height), (64, 48));
    let mut buf = vec![0; reader.output_buffer_size()];
    let mut frames = Vec::new();
    for _ in 0..4 {
        reader.next_frame(&mut buf).unwrap();
        let fc = reader.info().frame_control.expect("a frame control");
        assert_eq!((fc.width, fc.height), (64, 48));
        let delay = fc.delay_num as f32 / fc.delay_den as f32;
        assert!((delay - 2.0 / 25.0).abs() < 1e-6, "delay {delay}");
        frames.push(buf.clone());
    }
    assert!(frames.windows(2).all(|w| w[0] != w[1]), "the head moves");
    run(&anim2);
    assert_eq!(
        std::fs::read(&anim).unwrap(),
        std::fs::read(&anim2).unwrap()
    );
}

#[test]
fn every_thread_count_writes_the_same_bytes() {
    let dir = out_dir();
    let run = |threads: &str| {
        let (image, animation) = (
            dir.join(format!("threads_{threads}.png")),
            dir.join(format!("threads_{threads}_anim.png")),
        );
        let out = Command::new(env!("CARGO_BIN_EXE_coif"))
            .args(["--size", "80x64", "--frames", "4", "--density", "12"])
            .args(["--render-every", "0", "--threads", threads, "--output"])
            .arg(&image)
            .arg("--animation")
            .arg(&animation)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "--threads {threads}: {stdout}\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let bytes = (
            std::fs::read(&image).unwrap(),
            std::fs::read(&animation).unwrap(),
        );
        (bytes, stdout)
    };
    let (one, stdout) = run("1");
    let lanes = coif::kernels::LANES;
    assert!(
        stdout.contains(&format!("; 1 thread, {lanes} lanes\n")),
        "{stdout}"
    );
    assert_eq!(png_size(&dir.join("threads_1.png")), (80, 64));
    for threads in ["2", "3"] {
        let (other, stdout) = run(threads);
        assert!(
            stdout.contains(&format!("; {threads} threads, {lanes} lanes\n")),
            "{stdout}"
        );
        assert!(other.0 == one.0, "--threads {threads}: the PNG differs");
        assert!(
            other.1 == one.1,
            "--threads {threads}: the animation differs"
        );
    }
}

#[test]
fn a_closed_pipe_ends_the_program_quietly() {
    // `coif ... | head -1`: standard output closes after the first line;
    // the run still writes every file it was asked for. Three frames on a
    // sheet of six: each frame fills two tiles.
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let path = out_dir().join("pipe.png");
    let (sheet, csv) = (out_dir().join("pipe_sheet.png"), out_dir().join("pipe.csv"));
    for p in [&path, &sheet, &csv] {
        let _ = std::fs::remove_file(p);
    }
    let mut child = Command::new(env!("CARGO_BIN_EXE_coif"))
        .args(["--size", "64x64", "--frames", "3", "--density", "8"])
        .arg("--sheet")
        .arg(&sheet)
        .arg("--timings-csv")
        .arg(&csv)
        .args(["--render-every", "0", "--output"])
        .arg(&path)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run coif");
    let mut first = String::new();
    BufReader::new(child.stdout.take().expect("stdout"))
        .read_line(&mut first)
        .expect("a first line");
    // The reader is dropped here: the pipe's read end closes.
    let out = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(first.starts_with("coif:"), "{first}");
    assert!(out.status.success(), "{:?}: {err}", out.status);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(png_size(&path), (64, 64));
    // Three tiles by two of 64 x 64, with 4 px gaps and borders.
    assert_eq!(png_size(&sheet), (3 * 64 + 4 * 4, 2 * 64 + 3 * 4));
    let timings = std::fs::read_to_string(&csv).expect("the timings CSV");
    assert!(timings.contains("simulate"), "{timings}");
}

#[test]
fn multiple_scattering_is_on_for_the_physical_models_and_can_be_turned_off() {
    let line = |args: &[&str]| {
        let dir = out_dir();
        let out = Command::new(env!("CARGO_BIN_EXE_coif"))
            .args(["--size", "48x48", "--frames", "2", "--density", "4"])
            .args(args)
            .arg("--output")
            .arg(dir.join("ms.png"))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let stdout = String::from_utf8_lossy(&out.stdout).to_string();
        stdout.lines().next().unwrap_or_default().to_string()
    };
    let default = line(&[]);
    assert!(
        default.contains("pbrt shading (brown hair, dual scattering)"),
        "{default}"
    );
    let blond = line(&["--shading", "marschner", "--hair-color", "blond"]);
    assert!(
        blond.contains("marschner shading (blond hair, dual scattering)"),
        "{blond}"
    );
    let single = line(&["--single-scattering"]);
    assert!(
        single.contains("(brown hair, single scattering)"),
        "{single}"
    );
    let kk = line(&["--shading", "kajiya-kay"]);
    assert!(kk.contains("kajiya-kay shading,"), "{kk}");
}
