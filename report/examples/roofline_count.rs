//! Runs one roofline kernel's in-cache batch `reps` times (or the floors'
//! mixed loop) inside `coif_report::roofline::counted_region`, for
//! `valgrind --tool=callgrind --toggle-collect='*counted_region*'`;
//! `report/roofline_count.sh` drives it. Prints the elements per run.
//!
//! `cargo run --release -p coif-report --example roofline_count -- "<kernel>" <reps>`
//! (`mixed <iterations>` for the mixed loop, `list` for the names, `time
//! <kernel>` for its in-cache time without callgrind).

use coif_report::roofline;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map(String::as_str).unwrap_or("list");
    let reps: usize = args.get(1).and_then(|r| r.parse().ok()).unwrap_or(1);
    match name {
        "list" => {
            for k in roofline::KERNELS {
                println!("{}", k.name);
            }
        }
        "time" => {
            // `time <kernel>`: the in-cache median ns per element (no callgrind).
            let kernel = args.get(1).map(String::as_str).unwrap_or("");
            match roofline::time_in_cache(kernel, 60) {
                Some(t) => println!(
                    "{kernel}: {:.2} ns per element (min {:.2})",
                    t.median, t.min
                ),
                None => eprintln!("unknown kernel {kernel:?}"),
            }
        }
        "mixed" => {
            roofline::mixed_loop_for_count(reps);
            println!("{reps}");
        }
        _ => match roofline::run_for_count(name, reps) {
            Some(elements) => println!("{elements}"),
            None => {
                eprintln!("unknown kernel {name:?} (try `list`)");
                std::process::exit(2);
            }
        },
    }
}
