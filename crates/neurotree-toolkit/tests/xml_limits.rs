//! The loader's limits: a node budget that refuses subtrees expanding past it before they
//! are built, and files that are not regular files or are too large.

use neurotree::{LoadError, XmlLoader};

use crate::shared;
use shared::registry;

/// A file of `levels` trees `T0`..`T{levels-1}`, one a line after `<root>`, each using the
/// next one twice, and a leaf `T{levels}`: 2 KB that would expand to 2^(levels+2) nodes.
fn doubling_subtrees(levels: usize) -> String {
    let mut xml = String::from("<root BTCPP_format=\"4\" main_tree_to_execute=\"T0\">\n");
    for i in 0..levels {
        let next = i + 1;
        xml.push_str(&format!(
            "<BehaviorTree ID=\"T{i}\"><Sequence><SubTree ID=\"T{next}\"/><SubTree ID=\"T{next}\"/></Sequence></BehaviorTree>\n"
        ));
    }
    xml.push_str(&format!(
        "<BehaviorTree ID=\"T{levels}\"><AlwaysSuccess/></BehaviorTree>\n</root>\n"
    ));
    xml
}

/// The nodes tree `T1` of [`doubling_subtrees`] expands to: each level is a Sequence and two
/// SubTree nodes over two copies of the next, so `3 + 2 * next`, from 1 for the leaf.
fn doubling_size(levels: u32) -> u64 {
    (1u64 << (levels + 1)) - 3
}

#[test]
fn subtrees_using_each_other_twice_over_are_refused_at_the_first_subtree() {
    let r = registry();
    for levels in [24, 30] {
        let xml = doubling_subtrees(levels);
        assert!(xml.len() < 3_200, "{} bytes", xml.len());
        let mut loader = XmlLoader::new(&r);
        loader.load_str(&xml, "doubling.xml").unwrap();
        let expected = format!(
            "doubling.xml:2:33: error: the tree expands past the limit of 2000000 nodes here: \
             SubTree `T1` adds {} nodes to the 2 counted so far (each use of a subtree is a \
             copy of it); raise the limit with XmlLoader::max_nodes if the tree is meant to be \
             this big",
            doubling_size(levels as u32)
        );
        let built = loader.build_main().unwrap_err();
        assert_eq!(built.to_string(), expected);
        assert_eq!(loader.validate("T0").unwrap_err().to_string(), expected);
        // Validating every error goes past the first SubTree to the second, and expands
        // neither.
        let all = loader.validate_all("T0", 20);
        assert_eq!(all.len(), 2, "{all:?}");
        assert_eq!(all[0].to_string(), expected);
        assert_eq!((all[1].line, all[1].col), (2, 51));
    }
}

#[test]
fn the_node_budget_counts_expanded_subtrees_exactly() {
    let r = registry();
    let xml = doubling_subtrees(4);
    // T0 is a Sequence and two SubTree nodes over two copies of T1.
    let size = 3 + 2 * doubling_size(4) as usize;
    assert_eq!(size, 61);
    let mut loader = XmlLoader::new(&r).max_nodes(size);
    loader.load_str(&xml, "doubling.xml").unwrap();
    assert_eq!(loader.build_main().unwrap().len(), size);
    let mut loader = XmlLoader::new(&r).max_nodes(size - 1);
    loader.load_str(&xml, "doubling.xml").unwrap();
    let e = loader.build_main().unwrap_err();
    assert_eq!((e.line, e.col), (2, 51));
    assert!(
        e.message.starts_with(&format!(
            "the tree expands past the limit of {} nodes here: SubTree `T1` adds 29 nodes to the 32 counted so far",
            size - 1
        )),
        "{e}"
    );
    // A tree's own elements count too: the sixth node of five is refused where it is.
    let mut loader = XmlLoader::new(&r).max_nodes(5);
    loader
        .load_str(
            "<root main_tree_to_execute=\"T\"><BehaviorTree ID=\"T\"><Sequence>\n<Succ/><Succ/><Succ/><Succ/><Succ/></Sequence></BehaviorTree></root>",
            "wide.xml",
        )
        .unwrap();
    assert_eq!(
        loader.build_main().unwrap_err().to_string(),
        "wide.xml:2:29: error: the tree expands past the limit of 5 nodes here; raise the limit with XmlLoader::max_nodes if the tree is meant to be this big"
    );
}

/// Loads `path` on another thread: the result, or `None` if it took more than ten
/// seconds (a load blocked on a FIFO), so that a regression fails instead of hanging.
fn load_on_a_thread(path: &std::path::Path, base: &str) -> Option<Result<(), LoadError>> {
    let (send, receive) = std::sync::mpsc::channel();
    let path = path.to_path_buf();
    let base = base.to_string();
    std::thread::spawn(move || {
        let r = registry();
        let mut loader = XmlLoader::new(&r).base_dir(base);
        let _ = send.send(loader.load_file(&path));
    });
    receive
        .recv_timeout(std::time::Duration::from_secs(10))
        .ok()
}

#[test]
fn a_device_is_refused_as_a_file_and_as_an_include() {
    if !std::path::Path::new("/dev/zero").exists() {
        println!("note: no /dev/zero here; skipped");
        return;
    }
    let e = load_on_a_thread("/dev/zero".as_ref(), "/")
        .expect("loading /dev/zero returns")
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "/dev/zero: error: not a regular file but a character device; give the path of a tree file"
    );
    let dir = tempfile::tempdir().unwrap();
    let main = dir.path().join("main.xml");
    std::fs::write(&main, "<root>\n  <include path=\"/dev/zero\"/>\n</root>\n").unwrap();
    let e = load_on_a_thread(&main, "/")
        .expect("including /dev/zero returns")
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:2:3: error: in included file `/dev/zero`: not a regular file but a character device; give the path of a tree file",
            main.display()
        )
    );
}

#[test]
fn a_fifo_is_refused_as_a_file_and_as_an_include_without_blocking() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.xml");
    match std::process::Command::new("mkfifo").arg(&fifo).status() {
        Ok(status) if status.success() => {}
        other => {
            println!("note: mkfifo did not make a FIFO ({other:?}); skipped");
            return;
        }
    }
    let base = dir.path().display().to_string();
    let main = dir.path().join("main.xml");
    std::fs::write(&main, "<root>\n  <include path=\"pipe.xml\"/>\n</root>\n").unwrap();
    let loaded = [
        load_on_a_thread(&fifo, &base),
        load_on_a_thread(&main, &base),
    ];
    if loaded.iter().any(Option::is_none) {
        // Unblock the loads left waiting for a writer before failing.
        drop(std::fs::OpenOptions::new().write(true).open(&fifo));
        drop(std::fs::OpenOptions::new().write(true).open(&fifo));
        panic!("loading a FIFO blocked");
    }
    let [Some(Err(direct)), Some(Err(included))] = loaded else {
        panic!("a FIFO loaded: {loaded:?}");
    };
    assert_eq!(
        direct.to_string(),
        format!(
            "{}: error: not a regular file but a FIFO; give the path of a tree file",
            fifo.display()
        )
    );
    assert_eq!(
        included.to_string(),
        format!(
            "{}:2:3: error: in included file `{}`: not a regular file but a FIFO; give the path of a tree file",
            main.display(),
            fifo.display()
        )
    );
}

#[test]
fn a_file_over_the_size_limit_is_refused_and_one_at_it_loads() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("tree.xml");
    let xml =
        "<root main_tree_to_execute=\"T\"><BehaviorTree ID=\"T\"><Succ/></BehaviorTree></root>";
    std::fs::write(&file, xml).unwrap();
    let size = xml.len() as u64;
    let r = registry();
    let e = XmlLoader::new(&r)
        .max_file_bytes(size - 1)
        .load_file(&file)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}: error: the file is {size} bytes, more than the limit of {}; raise the limit (XmlLoader::max_file_bytes) if the file is meant to be this big",
            file.display(),
            size - 1
        )
    );
    let mut loader = XmlLoader::new(&r).max_file_bytes(size);
    loader.load_file(&file).unwrap();
    assert_eq!(loader.build_main().unwrap().len(), 1);
}
