//! Every built-in node, as its module declares it, goes through the loader and the writer
//! with all its declared ports, and the `TreeNodesModel` export lists it as declared.

use neurotree_toolkit::nodes::built_ins;
use neurotree_toolkit::xml::{escape, write_xml, SaveOptions, XmlLoader};
use neurotree_toolkit::{Arity, NodeDecl, PortDecl, PortDirection, Registry};

/// A value for `port` that the node accepts, other than its default.
fn sample(decl: &NodeDecl, port: &PortDecl) -> String {
    if port.direction == PortDirection::Output {
        return "{out}".into();
    }
    let text = match (decl.name, port.name, port.type_name) {
        (_, "queue", _) => "{queue}",
        (_, "variable", _) => "{v}",
        (_, "entry", _) => "{e}",
        (_, "output_key" | "key", _) => "k",
        (_, "value", _) => "1",
        ("Script", "code", _) => "x := 1",
        (_, "code" | "if", _) => "true",
        (_, "else", _) => "SUCCESS",
        (_, "if_empty", _) => "FAILURE",
        (_, "failure_count", _) => "-1",
        (_, "hysteresis", _) => "1.5",
        (_, "score", _) => "hunger * 2",
        (_, name, _) if name.starts_with("case_") => return name.replace("case_", ""),
        (_, _, "i32") => "2",
        (_, _, "u64") => "7",
        (_, _, "bool") if port.default == Some("true") => "false",
        (_, _, "bool") => "true",
        (name, port, ty) => panic!("no sample for {name}.{port} of type {ty}"),
    };
    text.to_string()
}

/// The node with every declared port set, and enough children.
fn element(decl: &NodeDecl) -> String {
    let attrs: String = decl
        .ports
        .iter()
        .map(|p| format!(" {}=\"{}\"", p.name, escape(&sample(decl, p))))
        .collect();
    let children = match decl.arity {
        Arity::Leaf => 0,
        Arity::One => 1,
        Arity::Range { min, .. } => min,
        Arity::AtLeast(min) => min.max(3),
    };
    if children == 0 {
        return format!("<{}{attrs}/>", decl.name);
    }
    let kids = "<AlwaysSuccess/>".repeat(children as usize);
    format!("<{}{attrs}>{kids}</{}>", decl.name, decl.name)
}

fn document(body: &str) -> String {
    format!(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">{body}</BehaviorTree></root>"#)
}

#[test]
fn every_declared_port_of_every_built_in_round_trips_through_the_writer_and_the_loader() {
    let registry = Registry::<()>::new();
    let opts = SaveOptions::default();
    for decl in built_ins() {
        let mut loader = XmlLoader::new(&registry);
        loader
            .load_str(&document(&element(decl)), "declared.xml")
            .unwrap_or_else(|e| panic!("{}: {e}", decl.name));
        let first = loader.build("Main").unwrap();
        let saved = write_xml(&first, &registry, &opts);
        for p in decl.ports {
            let attr = format!(" {}=\"{}\"", p.name, escape(&sample(decl, p)));
            assert!(
                saved.contains(&attr),
                "{}: `{attr}` not written:\n{saved}",
                decl.name
            );
        }
        let mut again = XmlLoader::new(&registry);
        again
            .load_str(&saved, "saved.xml")
            .unwrap_or_else(|e| panic!("{}: {e}\n{saved}", decl.name));
        let second = again.build_main().unwrap();
        assert_eq!(write_xml(&second, &registry, &opts), saved, "{}", decl.name);
    }
}

#[test]
fn a_port_left_out_takes_its_declared_default_or_is_required() {
    let registry = Registry::<()>::new();
    for decl in built_ins() {
        for left_out in decl
            .ports
            .iter()
            .filter(|p| p.direction != PortDirection::Output)
        {
            let without = element(decl).replacen(
                &format!(" {}=\"{}\"", left_out.name, escape(&sample(decl, left_out))),
                "",
                1,
            );
            let mut loader = XmlLoader::new(&registry);
            let built = loader
                .load_str(&document(&without), "declared.xml")
                .and_then(|()| loader.build("Main"));
            // The engine's nodes need their ports when they are made; the std nodes read
            // theirs when they run (as BehaviorTree.CPP's `getInput`), so only a default is
            // checked for them.
            let engine = neurotree_core::nodes::BUILT_INS.contains(&decl);
            match (left_out.default, built) {
                (Some(_), Err(e)) => panic!("{}.{}: {e}", decl.name, left_out.name),
                (None, Ok(_)) if engine => {
                    panic!("{}.{} is required", decl.name, left_out.name)
                }
                _ => {}
            }
        }
    }
}

#[test]
fn the_model_of_the_built_ins_is_their_declarations() {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(&document("<AlwaysSuccess/>"), "a.xml")
        .unwrap();
    let opts = SaveOptions {
        builtin_models: true,
        ..SaveOptions::default()
    };
    let xml = write_xml(&loader.build("Main").unwrap(), &registry, &opts);
    for decl in built_ins() {
        let tag = decl.category.as_str();
        let open = format!("<{tag} ID=\"{}\"", decl.name);
        assert!(xml.contains(&open), "{open} missing:\n{xml}");
        assert!(xml.contains(&escape(decl.summary)), "{}", decl.name);
        for p in decl.ports {
            let mut port = format!(
                "<{} name=\"{}\" type=\"{}\"",
                p.direction.model_tag(),
                p.name,
                p.type_name
            );
            if let Some(d) = p.default {
                port.push_str(&format!(" default=\"{}\"", escape(d)));
            }
            port.push_str(&format!(">{}<", escape(p.description)));
            assert!(xml.contains(&port), "{}: {port} missing", decl.name);
        }
    }
}
