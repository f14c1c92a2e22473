//! `cornertree` command-line front: parse, call into the library, print.

fn main() -> anyhow::Result<()> {
    Ok(())
}
