//! Runs one `sercon bench` scenario for a number of cycles (for profilers such as
//! `valgrind --tool=callgrind`): `ring_profile <scenario> <cycles>`.

use sercos_sim::scenario;

fn main() {
    let mut args = std::env::args().skip(1);
    let name = args.next().unwrap_or_else(|| "ring-8".into());
    let cycles: u64 = args.next().and_then(|c| c.parse().ok()).unwrap_or(100);
    let Some(s) = scenario::all().into_iter().find(|s| s.name == name) else {
        eprintln!("no scenario {name}");
        std::process::exit(2);
    };
    match scenario::run(&s, cycles) {
        Ok(r) => println!("{}", r.to_json()),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    }
}
