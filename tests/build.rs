//! Writes the large chains of four-bars used by `tests/chain.rs` into
//! `OUT_DIR` (100 and 250 loops would be thousands of lines by hand).

#[path = "src/four_bar_chain.rs"]
#[allow(dead_code)]
mod four_bar_chain;

fn main() {
    let Some(out) = std::env::var_os("OUT_DIR") else {
        return;
    };
    let out = std::path::PathBuf::from(out);
    for (name, n) in [("Chain20", 20), ("Chain100", 100), ("Chain250", 250)] {
        let path = out.join(format!("{}.rs", name.to_lowercase()));
        let text = four_bar_chain::source(name, n);
        if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
            if let Err(e) = std::fs::write(&path, text) {
                println!("cargo::error=cannot write {}: {e}", path.display());
            }
        }
    }
    println!("cargo::rerun-if-changed=src/four_bar_chain.rs");
    println!("cargo::rerun-if-changed=build.rs");
}
