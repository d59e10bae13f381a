//! The card section of `docs/deck-reference.md` is generated from the card structs' doc
//! comments (tools/docs/deck_reference.py); this test fails when someone changes a card's
//! fields without regenerating it.

use std::process::Command;

#[test]
fn deck_reference_page_is_current() {
    let root = env!("CARGO_MANIFEST_DIR");
    let out = Command::new("python3")
        .args(["tools/docs/deck_reference.py", "--check"])
        .current_dir(root)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}
