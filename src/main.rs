//! The `tessera` command-line tool.

fn main() {
    println!("tessera");
}
