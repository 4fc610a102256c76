//! The folder the studio was started in: the only place the page may read or write files.
//!
//! A path from the page is relative and `/`-separated; an absolute path, a `..` component,
//! or a path that leaves the folder through a symbolic link is refused before any file is
//! opened.

use std::fs;
use std::io;
use std::path::{Component, Path, PathBuf};
use std::time::UNIX_EPOCH;

use serde::Serialize;

/// The most files [`Workspace::list`] returns: a page lists a project, not a disk.
pub const MAX_LISTED: usize = 5_000;
/// How deep [`Workspace::list`] looks.
const MAX_DEPTH: usize = 8;
/// The largest file the page may open or save (a 1,111-node tree is about 100 KB).
pub const MAX_FILE_BYTES: u64 = 16 * 1024 * 1024;

/// Why a path from the page was not served.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum PathError {
    /// Absolute, with `..`, empty, or leading out of the folder.
    #[error("`{0}` is outside the folder the studio was started in: give a path relative to it, without `..`")]
    Outside(String),
    /// No such file.
    #[error("`{0}` does not exist")]
    NotFound(String),
    /// Larger than 16 MiB, the most the page opens or saves.
    #[error("`{0}` is larger than {MAX_FILE_BYTES} bytes")]
    TooLarge(String),
    /// Reading or writing failed.
    #[error("`{path}`: {source}")]
    Io {
        /// The path as given.
        path: String,
        /// What the system said.
        source: io::Error,
    },
}

neurotree_core::debug_shows_message!(enum PathError {
    Outside(source),
    NotFound(source),
    TooLarge(source),
    Io { path, source },
});

/// What a listed file holds, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FileKind {
    /// BehaviorTree.CPP XML.
    Tree,
    /// A `--jsonl` trace.
    Trace,
    /// A `.btlog` (BehaviorTree.CPP's FileLogger2).
    Btlog,
    /// A SQLite log with BehaviorTree.CPP's schema.
    Sqlite,
    /// A `--coverage-json` file (or any JSON).
    Coverage,
}

impl FileKind {
    /// The kind of `path`, if the studio opens such files.
    pub fn of(path: &Path) -> Option<FileKind> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "xml" => FileKind::Tree,
            "jsonl" => FileKind::Trace,
            "btlog" => FileKind::Btlog,
            "db" | "db3" | "btdb" | "sqlite" | "sqlite3" => FileKind::Sqlite,
            "json" => FileKind::Coverage,
            _ => return None,
        })
    }
}

/// A file the page can open.
#[derive(Clone, Debug, Serialize)]
pub struct FileEntry {
    /// Relative to the folder, `/`-separated.
    pub path: String,
    /// What it holds.
    pub kind: FileKind,
}

/// The folder the page works in.
#[derive(Clone, Debug)]
pub struct Workspace {
    root: PathBuf,
}

impl Workspace {
    /// The folder `root` (made absolute and resolved, so that later checks compare real
    /// paths).
    pub fn new(root: impl AsRef<Path>) -> io::Result<Self> {
        Ok(Self {
            root: fs::canonicalize(root)?,
        })
    }

    /// The folder itself.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// The file `rel` names, if it stays inside the folder. The file need not exist (a
    /// save may create it), but its parent folder must, and must be inside too.
    pub fn resolve(&self, rel: &str) -> Result<PathBuf, PathError> {
        let outside = || PathError::Outside(rel.to_string());
        if rel.is_empty() || rel.contains('\0') || rel.contains('\\') {
            return Err(outside());
        }
        let path = Path::new(rel);
        if !path.components().all(|c| matches!(c, Component::Normal(_))) {
            return Err(outside());
        }
        let joined = self.root.join(path);
        // Symbolic links are followed, then the real path is checked.
        let real = match fs::canonicalize(&joined) {
            Ok(real) => real,
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                let parent = joined.parent().ok_or_else(outside)?;
                let name = joined.file_name().ok_or_else(outside)?;
                match fs::canonicalize(parent) {
                    Ok(p) => p.join(name),
                    Err(_) => return Err(PathError::NotFound(rel.to_string())),
                }
            }
            Err(source) => {
                return Err(PathError::Io {
                    path: rel.to_string(),
                    source,
                })
            }
        };
        if real.starts_with(&self.root) {
            Ok(real)
        } else {
            Err(outside())
        }
    }

    /// `abs` relative to the folder, `/`-separated, if it is inside.
    pub fn relative(&self, abs: &Path) -> Option<String> {
        let real = fs::canonicalize(abs).ok()?;
        let rel = real.strip_prefix(&self.root).ok()?;
        let parts: Vec<&str> = rel
            .components()
            .map(|c| c.as_os_str().to_str())
            .collect::<Option<_>>()?;
        Some(parts.join("/"))
    }

    /// The text of `rel`.
    pub fn read(&self, rel: &str) -> Result<String, PathError> {
        let path = self.existing(rel)?;
        fs::read_to_string(&path).map_err(|source| PathError::Io {
            path: rel.to_string(),
            source,
        })
    }

    /// The bytes of `rel`.
    pub fn read_bytes(&self, rel: &str) -> Result<Vec<u8>, PathError> {
        let path = self.existing(rel)?;
        fs::read(&path).map_err(|source| PathError::Io {
            path: rel.to_string(),
            source,
        })
    }

    /// When `rel` was last written, in milliseconds since the Unix epoch.
    pub fn mtime(&self, rel: &str) -> Result<u64, PathError> {
        let path = self.existing(rel)?;
        let io = |source| PathError::Io {
            path: rel.to_string(),
            source,
        };
        let modified = fs::metadata(&path).and_then(|m| m.modified()).map_err(io)?;
        Ok(modified
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_millis() as u64))
    }

    /// Writes `text` to `rel` (through a temporary file beside it, so that a reader never
    /// sees half a file).
    pub fn write(&self, rel: &str, text: &str) -> Result<(), PathError> {
        if text.len() as u64 > MAX_FILE_BYTES {
            return Err(PathError::TooLarge(rel.to_string()));
        }
        let path = self.resolve(rel)?;
        let io = |source| PathError::Io {
            path: rel.to_string(),
            source,
        };
        let mut tmp = path.clone().into_os_string();
        tmp.push(".studio-save");
        let tmp = PathBuf::from(tmp);
        fs::write(&tmp, text).map_err(io)?;
        fs::rename(&tmp, &path).map_err(io)
    }

    /// The files the page can open, sorted, skipping hidden folders and build output.
    pub fn list(&self) -> Vec<FileEntry> {
        let mut out = Vec::new();
        self.walk(&self.root, 0, &mut out);
        out.sort_by(|a, b| a.path.cmp(&b.path));
        out
    }

    fn walk(&self, dir: &Path, depth: usize, out: &mut Vec<FileEntry>) {
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        let mut entries: Vec<_> = entries.flatten().collect();
        entries.sort_by_key(|e| e.file_name());
        for entry in entries {
            if out.len() >= MAX_LISTED {
                return;
            }
            let name = entry.file_name();
            let Some(name) = name.to_str() else { continue };
            // `file_type` does not follow links: a linked folder is not walked, so the
            // listing stays inside and finite.
            let Ok(file_type) = entry.file_type() else {
                continue;
            };
            let path = entry.path();
            if file_type.is_dir() {
                if depth < MAX_DEPTH
                    && !name.starts_with('.')
                    && !matches!(name, "target" | "node_modules")
                {
                    self.walk(&path, depth + 1, out);
                }
            } else if let Some(kind) = FileKind::of(&path) {
                if let Ok(rel) = path.strip_prefix(&self.root) {
                    let parts: Option<Vec<&str>> =
                        rel.components().map(|c| c.as_os_str().to_str()).collect();
                    if let Some(parts) = parts {
                        out.push(FileEntry {
                            path: parts.join("/"),
                            kind,
                        });
                    }
                }
            }
        }
    }

    fn existing(&self, rel: &str) -> Result<PathBuf, PathError> {
        let path = self.resolve(rel)?;
        let meta = fs::metadata(&path).map_err(|_| PathError::NotFound(rel.to_string()))?;
        if !meta.is_file() {
            return Err(PathError::NotFound(rel.to_string()));
        }
        if meta.len() > MAX_FILE_BYTES {
            return Err(PathError::TooLarge(rel.to_string()));
        }
        Ok(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder() -> (tempfile::TempDir, Workspace) {
        let dir = tempfile::tempdir().unwrap();
        fs::create_dir(dir.path().join("trees")).unwrap();
        fs::write(dir.path().join("trees/a.xml"), "<root/>").unwrap();
        fs::write(dir.path().join("run.jsonl"), "").unwrap();
        fs::write(dir.path().join("notes.txt"), "").unwrap();
        let ws = Workspace::new(dir.path()).unwrap();
        (dir, ws)
    }

    #[test]
    fn relative_paths_inside_are_served() {
        let (_dir, ws) = folder();
        assert_eq!(ws.read("trees/a.xml").unwrap(), "<root/>");
        ws.write("trees/b.xml", "<root></root>").unwrap();
        assert_eq!(ws.read("trees/b.xml").unwrap(), "<root></root>");
    }

    #[test]
    fn absolute_and_parent_paths_are_refused() {
        let (_dir, ws) = folder();
        for bad in [
            "/etc/passwd",
            "../x.xml",
            "trees/../../x.xml",
            "",
            "a\\b.xml",
        ] {
            assert!(
                matches!(ws.resolve(bad), Err(PathError::Outside(_))),
                "{bad}"
            );
        }
        assert!(matches!(
            ws.write("../escape.xml", "x"),
            Err(PathError::Outside(_))
        ));
    }

    #[cfg(unix)]
    #[test]
    fn a_link_out_of_the_folder_is_refused() {
        let (dir, ws) = folder();
        let outside = tempfile::tempdir().unwrap();
        fs::write(outside.path().join("secret.xml"), "s").unwrap();
        std::os::unix::fs::symlink(outside.path(), dir.path().join("link")).unwrap();
        assert!(matches!(
            ws.read("link/secret.xml"),
            Err(PathError::Outside(_))
        ));
        assert!(matches!(
            ws.write("link/new.xml", "x"),
            Err(PathError::Outside(_))
        ));
        // Nor is it listed.
        assert!(ws.list().iter().all(|f| !f.path.starts_with("link")));
    }

    #[test]
    fn listing_has_the_files_the_page_opens() {
        let (_dir, ws) = folder();
        let listed: Vec<(String, FileKind)> =
            ws.list().into_iter().map(|f| (f.path, f.kind)).collect();
        assert_eq!(
            listed,
            [
                ("run.jsonl".to_string(), FileKind::Trace),
                ("trees/a.xml".to_string(), FileKind::Tree),
            ]
        );
    }
}
