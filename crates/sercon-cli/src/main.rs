//! `sercon`: the command line of the sercon project.

fn main() {
    println!("sercon");
}
