//! Where the tools write the files the commands read: a folder inside the one the server
//! was started in (the only folder it touches), removed when the server stops.

use std::io;
use std::path::Path;

/// The server's scratch folder, removed when dropped.
pub struct Scratch(tempfile::TempDir);

impl Scratch {
    /// A new hidden folder in the current one, `.neurotree-mcp-XXXXXX`.
    pub fn in_current_dir() -> io::Result<Self> {
        let here = std::env::current_dir()?;
        tempfile::Builder::new()
            .prefix(".neurotree-mcp-")
            .tempdir_in(here)
            .map(Scratch)
    }

    /// Its path.
    pub fn dir(&self) -> &Path {
        self.0.path()
    }
}
