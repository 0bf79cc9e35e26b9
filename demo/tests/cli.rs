//! The `coif` binary: its options write PNGs of the asked size, and bad
//! options or files fail with a message instead of a picture.

use std::path::PathBuf;
use std::process::Command;

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
    for stage in [
        "simulate",
        "ribbon",
        "lod",
        "shade",
        "rasterise ribbon",
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
        vec!["--view", "0,0,0"],
        vec!["--groom", "/nonexistent/hair.tfx"],
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
}
