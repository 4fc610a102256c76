//! `<include path="…"/>`: another file's trees loaded into the same loader, read from disk
//! under the base directory, or from the texts given with `include_texts`.

use std::path::{Path, PathBuf};

use super::{source, LoadError, LoadErrorKind, XmlLoader};

impl<C: 'static> XmlLoader<'_, C> {
    pub(super) fn include(
        &mut self,
        doc: usize,
        element: usize,
        dir: Option<&Path>,
    ) -> Result<(), LoadError> {
        let el = self.docs[doc].element(element);
        let Some(path) = el.attr("path") else {
            return Err(el.error(LoadErrorKind::Include, "<include> needs a path attribute"));
        };
        if self.include_texts.is_some() {
            let dir = dir.unwrap_or(Path::new(""));
            return self.include_text(doc, element, joined(dir, path));
        }
        let Some(dir) = dir else {
            return Err(el.error(
                LoadErrorKind::Include,
                "<include> in text loaded without a file; load it with load_file",
            ));
        };
        let target = dir.join(path);
        let base = self
            .base_dir
            .as_ref()
            .map(|base| base.canonicalize().unwrap_or_else(|_| base.clone()));
        let outside = |base: &Path| {
            el.error(LoadErrorKind::Include, format!(
                "included file `{}` is outside the base directory `{}`; move it inside or widen the base with XmlLoader::base_dir",
                target.display(),
                base.display()
            ))
        };
        // Decided from the path alone before the file is looked for, so that the answer
        // says nothing of what exists outside the base.
        if let Some(base) = &base {
            let dir = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
            if !lexically_normal(&dir.join(path)).starts_with(base) {
                return Err(outside(base));
            }
        }
        let canonical = target.canonicalize().map_err(|e| {
            el.error(
                LoadErrorKind::Include,
                format!("included file `{}` not found: {e}", target.display()),
            )
        })?;
        // A link inside the base may still lead out of it.
        if let Some(base) = &base
            && !canonical.starts_with(base)
        {
            return Err(outside(base));
        }
        self.load_file(&target).map_err(|inner| {
            if inner.file == target.display().to_string() && inner.line == 0 {
                let el = self.docs[doc].element(element);
                el.error(
                    inner.kind(),
                    format!("in included file `{}`: {}", target.display(), inner.message),
                )
            } else {
                inner
            }
        })
    }

    /// Loads the included text at `path` from [`include_texts`](Self::include_texts).
    fn include_text(&mut self, doc: usize, element: usize, path: String) -> Result<(), LoadError> {
        let el = self.docs[doc].element(element);
        let key = PathBuf::from(&path);
        if self.loading.contains(&key) {
            return Err(el.error(
                LoadErrorKind::Include,
                format!("`{path}` includes itself (through its includes); remove the cycle"),
            ));
        }
        let text = self
            .include_texts
            .as_ref()
            .and_then(|t| t.get(&path))
            .cloned();
        let Some(text) = text else {
            return Err(el.error(
                LoadErrorKind::Include,
                format!("included file `{path}` was not read"),
            ));
        };
        self.loading.push(key);
        let root = source::parse(&text, &path);
        let result = root.and_then(|root| self.take_root(root, Path::new(&path).parent()));
        self.loading.pop();
        result
    }
}

/// `path` joined to `dir`, with `.` and `..` resolved and `/` between the parts: the name
/// an included text is served under.
pub(super) fn joined(dir: &Path, path: &str) -> String {
    let mut parts: Vec<String> = Vec::new();
    for part in dir.join(path).components() {
        match part {
            std::path::Component::CurDir => {}
            std::path::Component::ParentDir => {
                if parts.last().is_some_and(|p| p != "..") {
                    parts.pop();
                } else {
                    parts.push("..".into());
                }
            }
            other => parts.push(other.as_os_str().to_string_lossy().into_owned()),
        }
    }
    parts.join("/")
}

/// `path` with its `.` and `..` components resolved without reading the file system (a `..`
/// above the root stays at the root).
fn lexically_normal(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}
