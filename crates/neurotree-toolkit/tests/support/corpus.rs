//! Where the tests find the trees of the repository's `corpus/` folder.

use std::path::PathBuf;

/// `corpus/<relative>` at the repository's root. It must exist: a missing file or folder
/// fails the test, naming the path, instead of letting a loop over no files pass.
pub fn corpus(relative: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../corpus")
        .join(relative);
    assert!(
        path.exists(),
        "{} is missing: the tests read the trees of the repository's corpus/ folder",
        path.display()
    );
    path
}
