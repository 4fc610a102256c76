//! The common path from BehaviorTree.CPP XML to a tree that ticks, in one call on the
//! [`Registry`]. [`XmlLoader`] stays the lower-level way in, for what this path fixes:
//! which tree to build, mocks, limits, warnings, one blueprint shared by many trees.

use std::path::Path;
use std::sync::Arc;

use neurotree_core::{Clock, Tree};

use crate::registry::Registry;
use crate::xml::{LoadErrors, XmlLoader};

impl<C: 'static> Registry<C> {
    /// Loads the BehaviorTree.CPP file at `path`, with the files it `<include>`s, and
    /// returns its main tree (its `main_tree_to_execute`, or its only tree) ready to tick
    /// on `clock`.
    ///
    /// A file that does not load gives its first error (it cannot be read, is not XML, or
    /// is not shaped as BehaviorTree.CPP expects); a main tree that does not build gives
    /// all its errors (unknown nodes, ports, values, child counts: up to
    /// [`MAX_ERRORS`](crate::xml::MAX_ERRORS)), in a [`LoadErrors`] that iterates over
    /// them and prints them one per line as `file:line:col: error: message`, as
    /// `neurotree check` does. Warnings (deprecated node names) are not reported;
    /// [`XmlLoader::warnings`] has them.
    ///
    /// ```no_run
    /// use neurotree::prelude::*;
    ///
    /// let registry = Registry::<()>::new();
    /// let mut tree = registry
    ///     .load_file("patrol.xml", SystemClock::new())
    ///     .unwrap_or_else(|e| panic!("{e}"));
    /// tree.tick_once(&mut ()).unwrap();
    /// ```
    pub fn load_file(
        &self,
        path: impl AsRef<Path>,
        clock: impl Clock + 'static,
    ) -> Result<Tree<C>, LoadErrors> {
        let mut loader = XmlLoader::new(self);
        loader.load_file(path)?;
        Ok(Tree::with_clock(
            Arc::new(loader.build_main_all_errors()?),
            clock,
        ))
    }

    /// Loads BehaviorTree.CPP XML `text` and returns its main tree ready to tick on
    /// `clock`, as [`load_file`](Self::load_file) does, with all the main tree's errors;
    /// `file` names the text in errors and anchors its relative `<include>`s.
    ///
    /// ```
    /// use neurotree::prelude::*;
    ///
    /// let registry = Registry::<()>::new();
    /// let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
    ///                <Script code="n := 41 + 1"/>
    ///              </BehaviorTree></root>"#;
    /// let mut tree = registry.load_str(xml, "main.xml", ManualClock::new()).unwrap();
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    /// assert_eq!(tree.blackboard().get::<i32>("n"), Ok(42));
    ///
    /// let bad = r#"<root><BehaviorTree ID="Main"><Nope/></BehaviorTree></root>"#;
    /// let error = registry.load_str(bad, "bad.xml", ManualClock::new()).unwrap_err();
    /// assert_eq!(
    ///     error.to_string(),
    ///     "bad.xml:1:31: error: unknown node type `Nope`; register it in the Registry before loading"
    /// );
    /// ```
    pub fn load_str(
        &self,
        text: &str,
        file: &str,
        clock: impl Clock + 'static,
    ) -> Result<Tree<C>, LoadErrors> {
        let mut loader = XmlLoader::new(self);
        loader.load_str(text, file)?;
        Ok(Tree::with_clock(
            Arc::new(loader.build_main_all_errors()?),
            clock,
        ))
    }
}

#[cfg(test)]
mod tests {
    use std::fs;

    use neurotree_core::{ManualClock, Status};

    use crate::registry::Registry;

    /// A directory of its own under the system's temporary one, removed when dropped.
    struct TempDir(std::path::PathBuf);

    impl TempDir {
        fn new(name: &str) -> Self {
            let dir = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
            fs::create_dir_all(&dir).unwrap();
            TempDir(dir)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    #[test]
    fn a_file_and_its_includes_load_in_one_call() {
        let dir = TempDir::new("neurotree-load-file");
        fs::write(
            dir.0.join("main.xml"),
            r#"<root BTCPP_format="4" main_tree_to_execute="Main">
                 <include path="sub/count.xml"/>
                 <BehaviorTree ID="Main">
                   <Repeat num_cycles="3"><SubTree ID="Count"/></Repeat>
                 </BehaviorTree>
               </root>"#,
        )
        .unwrap();
        fs::create_dir_all(dir.0.join("sub")).unwrap();
        fs::write(
            dir.0.join("sub/count.xml"),
            r#"<root BTCPP_format="4">
                 <BehaviorTree ID="Count"><Bump/></BehaviorTree>
               </root>"#,
        )
        .unwrap();
        let mut registry = Registry::<u32>::new();
        registry
            .register_action("Bump", vec![], |h| {
                *h.ctx_mut() += 1;
                Status::Success
            })
            .unwrap();
        let mut tree = registry
            .load_file(dir.0.join("main.xml"), ManualClock::new())
            .unwrap();
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
        assert_eq!(n, 3);
    }

    #[test]
    fn errors_name_the_file_line_and_column() {
        let dir = TempDir::new("neurotree-load-error");
        let path = dir.0.join("bad.xml");
        fs::write(
            &path,
            "<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"Main\">\n    <Bump/>\n  </BehaviorTree>\n</root>\n",
        )
        .unwrap();
        let registry = Registry::<u32>::new();
        let errors = registry.load_file(&path, ManualClock::new()).unwrap_err();
        assert_eq!(errors.len(), 1);
        let error = errors.first();
        assert_eq!((error.line, error.col), (3, 5));
        let printed = error.to_string();
        assert!(
            printed.starts_with(&format!("{}:3:5: error: ", path.display())),
            "{printed}"
        );
        let missing = registry
            .load_file(dir.0.join("absent.xml"), ManualClock::new())
            .unwrap_err();
        assert!(missing.to_string().contains("absent.xml"), "{missing}");
    }

    #[test]
    fn every_error_of_the_main_tree_is_reported_in_document_order() {
        let mut registry = Registry::<u32>::new();
        registry
            .register_action("Bump", vec![], |_| Status::Success)
            .unwrap();
        let xml = "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">
  <BehaviorTree ID=\"Main\">
    <Sequence>
      <Bump/>
      <Nope/>
      <Repeat num_cycles=\"many\"><Bump/></Repeat>
      <Bump speed=\"3\"/>
      <SubTree ID=\"Side\"/>
      <SubTree ID=\"Side\" name=\"again\"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID=\"Side\">
    <Inverter><Bumpp/></Inverter>
  </BehaviorTree>
</root>";
        let errors = registry
            .load_str(xml, "main.xml", ManualClock::new())
            .unwrap_err();
        let seen: Vec<_> = errors
            .iter()
            .map(|e| (e.kind(), e.file.as_str(), e.line, e.col))
            .collect();
        use crate::xml::LoadErrorKind::*;
        // The subtree used twice has its error reported once.
        assert_eq!(
            seen,
            [
                (UnknownNode, "main.xml", 5, 7),
                (BadValue, "main.xml", 6, 7),
                (UnknownPort, "main.xml", 7, 7),
                (UnknownNode, "main.xml", 13, 15),
            ]
        );
        assert_eq!(errors.len(), 4);
        assert_eq!(errors.kind(), UnknownNode);
        assert!(errors.first().message.contains("`Nope`"), "{errors}");
        let printed = errors.to_string();
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(lines.len(), 4);
        assert!(lines[0].starts_with("main.xml:5:7: error: unknown node type `Nope`"));
        assert!(lines[3]
            .starts_with("main.xml:13:15: error: unknown node type `Bumpp`; did you mean `Bump`?"));

        // One error alone is one error.
        let one = xml.replace("<Nope/>", "").replace("\"many\"", "\"2\"");
        let one = one.replace(" speed=\"3\"", "").replace("Bumpp", "Bump");
        let one = one.replace("<Sequence>", "<Sequence><Nope/>");
        let errors = registry
            .load_str(&one, "one.xml", ManualClock::new())
            .unwrap_err();
        assert_eq!(errors.len(), 1, "{errors}");
        assert_eq!((errors.first().line, errors.first().col), (3, 15));
        assert_eq!(errors.kind(), UnknownNode);
        let fixed = one.replace("<Nope/>", "");
        let mut tree = registry
            .load_str(&fixed, "fixed.xml", ManualClock::new())
            .unwrap();
        // The subtree's Inverter turns its Bump's Success into Failure.
        assert_eq!(tree.tick_once(&mut 0), Ok(Status::Failure));
    }
}
