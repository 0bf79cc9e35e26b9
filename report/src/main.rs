//! `cargo run --release -p coif-report -- [--quick] [--out DIR] [--from-csv FILE]`:
//! measures every kernel's run time against its error and writes
//! `results.csv`, `summary.md` and one SVG plot per kernel into DIR
//! (default `target/report/`, beside the build; `--out docs/report` replaces the committed run). With `--from-csv`, nothing is measured: the rows
//! are read from a `results.csv` written before and the summary and plots
//! drawn again into DIR (the CSV is not rewritten). With `--family NAME`
//! and `--from-csv FILE`, that family alone is measured again and its rows
//! replace its old ones among the file's; everything is written into DIR
//! (CSV included). See the `coif_report` crate documentation.

use coif_report::{self as report, Options};
use std::path::PathBuf;

const USAGE: &str =
    "usage: report [--quick] [--out DIR] [--from-csv FILE [--family NAME]] [--roofline-only]";

/// The machine line when `/proc/cpuinfo` cannot say (and for redraws from a
/// CSV, whose run this process did not see).
const MACHINE: &str = "a 2-core AMD EPYC, build x86-64-v3 (AVX2 + FMA)";

/// The 1-minute load average from `/proc/loadavg` (Linux), if readable.
fn load_average() -> Option<String> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    text.split_whitespace().next().map(str::to_string)
}

/// The machine measured on: core count and CPU model (from
/// `/proc/cpuinfo`, else [`MACHINE`]), the build, and the 1-minute load
/// average before and after the run (other work shares the cores).
fn machine(load_before: Option<String>) -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo").ok().and_then(|t| {
        t.lines()
            .find(|l| l.starts_with("model name"))
            .and_then(|l| l.split(':').nth(1))
            .map(|m| m.trim().to_string())
    });
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let mut line = match model {
        Some(m) if cores > 0 => format!(
            "a {cores}-core {m}, build x86-64-v3 (AVX2 + FMA), {} lanes",
            coif::kernels::LANES
        ),
        _ => MACHINE.to_string(),
    };
    if let (Some(before), Some(after)) = (load_before, load_average()) {
        line += &format!(", 1-minute load average {before} before the run and {after} after it");
    }
    line
}

/// The machine line of the summary beside `csv` (`summary.md` in the same
/// folder), if it has one.
fn previous_machine(csv: &std::path::Path) -> Option<String> {
    let text = std::fs::read_to_string(csv.with_file_name("summary.md")).ok()?;
    let line = text.lines().find(|l| l.starts_with("Measured by"))?;
    let start = line.find("` on ")? + "` on ".len();
    let end = line.find(". Time is")?;
    line.get(start..end).map(str::to_string)
}

fn main() {
    let mut quick = false;
    let mut roofline_only = false;
    let mut from_csv: Option<PathBuf> = None;
    let mut family: Option<String> = None;
    let mut out = PathBuf::from("target/report");
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--quick" => quick = true,
            "--roofline-only" => roofline_only = true,
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
            "--family" => match args.next() {
                Some(f) => family = Some(f),
                None => {
                    eprintln!("--family needs a family's name");
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
    if roofline_only {
        let load_before = load_average();
        let md = report::roofline_markdown(Options { quick }, &machine(load_before));
        match report::write_roofline(&md, &out) {
            Ok(path) => println!(
                "wrote {} in {:.1} s",
                path.display(),
                t0.elapsed().as_secs_f64()
            ),
            Err(e) => {
                eprintln!("cannot write the roofline into {}: {e}", out.display());
                std::process::exit(1);
            }
        }
        return;
    }
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
            match family.as_deref() {
                Some(name) => {
                    let Some(f) = report::FAMILIES.iter().find(|f| f.name == name) else {
                        let names: Vec<&str> = report::FAMILIES.iter().map(|f| f.name).collect();
                        eprintln!("no family {name:?}; the families: {names:?}");
                        std::process::exit(2);
                    };
                    let load_before = load_average();
                    let mut rows: Vec<report::Row> = rows
                        .into_iter()
                        .filter(|r| report::family_of(&r.kernel).is_none_or(|g| g.name != f.name))
                        .collect();
                    rows.extend((f.measure)(Options { quick }));
                    // The other families' machine, from the summary beside
                    // the CSV, and this run's for the family.
                    let mut before = previous_machine(&file).unwrap_or(MACHINE.to_string());
                    // This family's own earlier re-run is replaced, not kept.
                    let again = format!("; the {} family measured again", f.name);
                    if let Some(at) = before.find(&again) {
                        before.truncate(at);
                    }
                    let line = format!(
                        "{before}; the {} family measured again alone on {}",
                        f.name,
                        machine(load_before)
                    );
                    let written = report::write(&rows, &out, &line);
                    (rows, written)
                }
                None => {
                    // The CSV stays as measured: its spread column is not
                    // recoverable to the last digit from the rounded min
                    // and max.
                    let written = report::write_figures(&rows, &out, MACHINE);
                    (rows, written)
                }
            }
        }
        None => {
            if family.is_some() {
                eprintln!("--family goes with --from-csv; {USAGE}");
                std::process::exit(2);
            }
            let load_before = load_average();
            let rows = report::run(Options { quick });
            let roofline =
                report::roofline_markdown(Options { quick }, &machine(load_before.clone()));
            let written = report::write(&rows, &out, &machine(load_before)).and_then(|mut w| {
                w.push(report::write_roofline(&roofline, &out)?);
                Ok(w)
            });
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
