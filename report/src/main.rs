//! `cargo run --release -p coif-report -- [--quick] [--out DIR] [--from-csv FILE]`:
//! measures every kernel's run time against its error and writes
//! `results.csv`, `summary.md` and one SVG plot per kernel into DIR
//! (default `target/report/`, beside the build; `--out docs/report` replaces the committed run). With `--from-csv`, nothing is measured: the rows
//! are read from a `results.csv` written before and the summary and plots
//! drawn again into DIR (the CSV is not rewritten). See the `coif_report` crate documentation.

use coif_report::{self as report, Options};
use std::path::PathBuf;

const USAGE: &str = "usage: report [--quick] [--out DIR] [--from-csv FILE]";

const MACHINE: &str = "a 2-core Intel Xeon, build x86-64-v3 (AVX2 + FMA)";

fn main() {
    let mut quick = false;
    let mut from_csv: Option<PathBuf> = None;
    let mut out = PathBuf::from("target/report");
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--quick" => quick = true,
            "--out" => match args.next() {
                Some(d) => out = PathBuf::from(d),
                None => {
                    eprintln!("--out needs a directory");
                    std::process::exit(2);
                }
            },
            "--from-csv" => match args.next() {
                Some(f) => from_csv = Some(PathBuf::from(f)),
                None => {
                    eprintln!("--from-csv needs a results.csv file");
                    std::process::exit(2);
                }
            },
            "-h" | "--help" => {
                println!("{USAGE}");
                return;
            }
            other => {
                eprintln!("unknown argument {other:?}; {USAGE}");
                std::process::exit(2);
            }
        }
    }
    let t0 = std::time::Instant::now();
    let (rows, written) = match from_csv {
        Some(file) => {
            let rows = match std::fs::read_to_string(&file)
                .map_err(|e| e.to_string())
                .and_then(|text| report::csv::from_csv(&text))
            {
                Ok(rows) => rows,
                Err(e) => {
                    eprintln!("cannot read the rows from {}: {e}", file.display());
                    std::process::exit(1);
                }
            };
            // The CSV stays as measured: its spread column is not
            // recoverable to the last digit from the rounded min and max.
            let written = report::write_figures(&rows, &out, MACHINE);
            (rows, written)
        }
        None => {
            let rows = report::run(Options { quick });
            let written = report::write(&rows, &out, MACHINE);
            (rows, written)
        }
    };
    match written {
        Ok(files) => {
            for f in files {
                println!("wrote {}", f.display());
            }
            println!("{} rows in {:.1} s", rows.len(), t0.elapsed().as_secs_f64());
        }
        Err(e) => {
            eprintln!("cannot write the report into {}: {e}", out.display());
            std::process::exit(1);
        }
    }
}
