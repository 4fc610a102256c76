//! Reading XML text into a [`Document`]: the text kept once, its elements in a flat arena of
//! byte ranges into it, lines and columns worked out only when an error is reported.
//!
//! BehaviorTree.CPP's parser accepts a bare `&` inside an attribute (scripts write
//! `a && b`), which strict XML forbids: such an `&` is kept as written, while entities
//! (`&amp;`, `&#38;`, ...) are decoded.
//!
//! Two readers fill the arena. The quick one reads, straight from the text and with no
//! allocation per element or attribute, the XML that tree files are made of: elements,
//! attributes, comments, an XML declaration, the predefined entities and character
//! references. On anything else (a DTD, CDATA, processing instructions, namespaces,
//! non-ASCII names, nesting deeper than [`MAX_NESTING`], and every malformed document) it
//! gives up, and the complete reader (roxmltree, on a copy of the text whose bare `&`s are
//! escaped) reads the text instead. So what loads, and every error with its message and
//! position, are the complete reader's; the quick one only has to agree with it on the
//! documents it accepts, which a property test checks.

mod bytes;
mod complete;
mod document;
mod entities;
mod quick;

use super::{LoadError, LoadErrorKind};
use complete::complete;
pub(crate) use document::{Document, Element};
use quick::quick;

/// The deepest element nesting read: far beyond any tree's depth limit, and low enough that
/// no reader needs a deep stack.
const MAX_NESTING: usize = 1024;

/// The longest text read, so that every offset and count of a document fits in 32 bits
/// (the text and the values decoded from it), far beyond any tree file (the loader reads
/// files of up to 32 MiB by default).
pub const MAX_TEXT_BYTES: usize = 1 << 30;

/// Refuses a text longer than [`MAX_TEXT_BYTES`].
fn check_size(len: usize, file: &str) -> Result<(), LoadError> {
    if len > MAX_TEXT_BYTES {
        return Err(LoadError::at_file(
            LoadErrorKind::TooLarge,
            file,
            format!("the text is {len} bytes, more than the {MAX_TEXT_BYTES} a document may have; split it into files"),
        ));
    }
    Ok(())
}

/// Parses `text` (from `file`) into a document.
pub(crate) fn parse(text: &str, file: &str) -> Result<Document, LoadError> {
    check_size(text.len(), file)?;
    match quick(text, file) {
        Some(doc) => Ok(doc),
        None => complete(text, file),
    }
}

#[cfg(test)]
mod tests {
    use super::bytes::text_end;
    use super::complete::make_strict;
    use super::*;
    use proptest::prelude::*;
    use std::path::Path;

    #[test]
    fn a_text_past_the_size_limit_is_refused_by_name() {
        assert_eq!(check_size(MAX_TEXT_BYTES, "t.xml"), Ok(()));
        let e = check_size(MAX_TEXT_BYTES + 1, "big.xml").unwrap_err();
        assert_eq!(e.file, "big.xml");
        assert_eq!(
            e.message,
            format!(
                "the text is {} bytes, more than the {MAX_TEXT_BYTES} a document may have; split it into files",
                MAX_TEXT_BYTES + 1
            )
        );
    }

    #[test]
    fn bare_ampersands_are_accepted_and_entities_kept() {
        let (strict, inserted) = make_strict(r#"<S code="a && b &amp; c &#38; d"/>"#);
        assert_eq!(strict, r#"<S code="a &amp;&amp; b &amp; c &#38; d"/>"#);
        assert_eq!(inserted.len(), 2);
        let doc = parse(r#"<S code="a && b"/>"#, "t.xml").unwrap();
        assert_eq!(doc.root().attr("code"), Some("a && b"));
    }

    #[test]
    fn positions_are_in_the_original_text() {
        let text = "<root>\n  <A x=\"&&\"/>\n  <B/>\n</root>";
        let doc = parse(text, "t.xml").unwrap();
        let children: Vec<Element<'_>> = doc.root().children().collect();
        assert_eq!(children[0].line_col(), (2, 3));
        assert_eq!(children[1].line_col(), (3, 3));
    }

    #[test]
    fn syntax_errors_name_file_line_and_column() {
        let e = parse("<root>\n  <A x=\"&&\">\n</root>", "bad.xml").unwrap_err();
        assert_eq!(e.file, "bad.xml");
        assert_eq!(e.line, 3);
        assert!(e.message.starts_with("malformed XML"), "{}", e.message);
        assert!(e.to_string().starts_with("bad.xml:3:"), "{e}");
    }

    #[test]
    fn text_ends_at_the_first_lt_and_sees_marks_before_it() {
        for (text, expected) in [
            ("<", Some((0, false))),
            ("        <", Some((8, false))),
            ("   &    x<", Some((9, true))),
            ("0123456>89<", Some((10, true))),
            ("0123<567>9abcdef<", Some((4, false))),
            ("0123&<67", Some((5, true))),
            ("0<234567", Some((1, false))),
            ("0123456789ab>", None),
            ("", None),
        ] {
            assert_eq!(text_end(text.as_bytes(), 0), expected, "{text:?}");
        }
    }

    /// Everything a document says, element by element, with positions.
    fn dump(doc: &Document) -> Vec<String> {
        (0..doc.nodes.len())
            .map(|id| {
                let el = doc.element(id);
                let attrs: Vec<_> = el.attrs().collect();
                let children: Vec<usize> = el.children().map(|c| c.id()).collect();
                format!(
                    "{} {:?} {:?} {:?} {} {:?}",
                    el.tag(),
                    el.text(),
                    attrs,
                    children,
                    el.child_count(),
                    el.line_col()
                )
            })
            .collect()
    }

    /// The quick reader accepts only what the complete one accepts, and reads the same.
    fn agree(text: &str) -> bool {
        let Some(quick) = quick(text, "t.xml") else {
            return false;
        };
        match complete(text, "t.xml") {
            Ok(full) => assert_eq!(dump(&quick), dump(&full), "{text:?}"),
            Err(e) => panic!("only the quick reader accepts {text:?}: {e}"),
        }
        true
    }

    #[test]
    fn the_quick_reader_reads_tree_files() {
        let text = "\u{FEFF}<?xml version=\"1.0\" encoding='UTF-8' ?>\r\n<!-- c -->\n\
            <root BTCPP_format=\"4\" >\r\n  <BehaviorTree ID=\"T\">\n\
            <Script code=\"a := 1 &amp;&amp; b &lt; 2;  c && d &#65;&#x42; &foo\tx\r\ny\"/>\n\
            <Sequence name='s'>text &lt; &#x263A; here<A/>tail<!-- c --></Sequence >\n\
            <input_port>\r\n desc\r\nline </input_port><p> a\r\nb\rc </p>\n\
            </BehaviorTree></root><!-- end -->\n";
        assert!(agree(text));
        let doc = quick(text, "t.xml").unwrap();
        let script = doc.element(2);
        assert_eq!(
            script.attr("code"),
            Some("a := 1 && b < 2;  c && d AB &foo x y")
        );
        assert_eq!(doc.element(3).text(), "text < \u{263A} here");
        assert_eq!(doc.element(5).text(), "desc\nline");
        assert_eq!(doc.element(6).text(), "a\nb\nc");
        let tree1111 =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../corpus/bench/tree1111.xml");
        let text = std::fs::read_to_string(&tree1111)
            .unwrap_or_else(|e| panic!("{}: {e}", tree1111.display()));
        assert!(agree(&text));
    }

    #[test]
    fn the_readers_agree_on_the_corpus() {
        fn walk(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
            let entries =
                std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
            for path in entries.flatten().map(|e| e.path()) {
                if path.is_dir() {
                    walk(&path, out);
                } else if path.extension().is_some_and(|e| e == "xml") {
                    out.push(path);
                }
            }
        }
        let mut files = Vec::new();
        walk(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../corpus"),
            &mut files,
        );
        assert!(files.len() >= 60, "only {} corpus files found", files.len());
        // Every corpus file is ordinary enough for the quick reader, and `agree` checks
        // that both readers see the same elements.
        for file in &files {
            let text =
                std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            assert!(
                agree(&text),
                "the quick reader left {} to the complete one",
                file.display()
            );
        }
    }

    #[test]
    fn the_quick_reader_leaves_the_rest_to_the_complete_one() {
        for text in [
            "<a><![CDATA[x]]></a>",
            "<!DOCTYPE a><a/>",
            "<a><?pi x?></a>",
            "<?xml version='1.0'?><?pi?><a/>",
            "<x:a xmlns:x='u'/>",
            "<a xmlns='u'/>",
            "<a x='1' x='2'/>",
            "<a x='1'y='2'/>",
            "<a>&foo;</a>",
            "<a x='&#0;'/>",
            "<a x='&#xD800;'/>",
            "<a x='a<b'/>",
            "<a>]]></a>",
            "<a><!-- a -- b --></a>",
            "<a><!-- a ---></a>",
            "<a></b>",
            "<a>",
            "<a/><b/>",
            "<a/>x",
            "x<a/>",
            "",
            "<é/>",
            "<a\u{1}/>",
            "<a>\u{FFFE}</a>",
            "<a>&amp;\r</a>",
            "<?xml encoding='x'?><a/>",
            "<?xml version='1'encoding='x'?><a/>",
        ] {
            assert!(!agree(text), "{text:?}");
        }
        let deep = format!(
            "{}{}",
            "<a>".repeat(MAX_NESTING + 1),
            "</a>".repeat(MAX_NESTING + 1)
        );
        assert!(!agree(&deep));
        let e = parse(&deep, "deep.xml").unwrap_err();
        assert!(e.message.contains("nest deeper than 1024 levels"), "{e}");
    }

    /// Text made of the pieces of XML, well-formed or not.
    fn xml_like() -> impl Strategy<Value = String> {
        let piece = prop_oneof![
            Just("<a>".to_string()),
            Just("</a>".to_string()),
            Just("<b x=\"1\" y='&amp;&&#65;'>".to_string()),
            Just("</b>".to_string()),
            Just("<c/>".to_string()),
            Just("<c z=\"\t\r\n&#10;&lt;&gt;&quot;&apos;\"  />".to_string()),
            Just("<!-- x -->".to_string()),
            Just("<?xml version=\"1.0\"?>".to_string()),
            Just("&".to_string()),
            Just("&#x41;".to_string()),
            Just("\r\n".to_string()),
            Just("]]>".to_string()),
            "[a-c<>/=\"' \t\r\n&#;!?x:-]{0,8}",
        ];
        prop::collection::vec(piece, 0..24).prop_map(|parts| parts.concat())
    }

    /// A well-formed element, rendered with random spacing, texts, comments and entities.
    fn element() -> impl Strategy<Value = String> {
        let leaf = ("[a-c]", "[ -~]{0,6}").prop_map(|(tag, attr)| {
            let attr = attr
                .replace('&', "&amp;")
                .replace('<', "&lt;")
                .replace('"', "&quot;");
            format!("<{tag} v=\"{attr} && x\"/>")
        });
        leaf.prop_recursive(6, 64, 6, |inner| {
            (
                "[a-c]",
                prop::collection::vec(inner, 0..6),
                "[ \na-z&;#0-9]{0,6}",
                any::<bool>(),
            )
                .prop_map(|(tag, children, text, comment)| {
                    let text = text.replace('&', "&amp;");
                    let comment = if comment { "<!--c-->" } else { "" };
                    format!(
                        "<{tag} k='1'\r\n>{text}{}{comment}</{tag} >",
                        children.concat()
                    )
                })
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        #[test]
        fn the_readers_agree_on_xml_like_text(text in xml_like()) {
            agree(&text);
        }

        #[test]
        fn the_readers_agree_on_well_formed_text(el in element(), cut in any::<prop::sample::Index>()) {
            prop_assert!(agree(&el), "{el:?}");
            let cut = cut.index(el.len() + 1);
            if el.is_char_boundary(cut) {
                agree(&el[..cut]);
            }
        }
    }
}
