//! The loader opens plain elements (no attributes, no mock or substitution rule, a type
//! without ports) by a path of their own: it must build exactly what the general path
//! builds, which a substitution rule matching no node forces.

use neurotree::xml::{Substitute, Substitutions};
use neurotree::{Blueprint, XmlLoader};

use crate::corpus_dir;
use corpus_dir::corpus;

use crate::signature as support;
use support::signature;

use crate::shared;
use shared::registry;

/// The main tree of `text` built by each path.
fn both(text: &str) -> (Blueprint<Vec<String>>, Blueprint<Vec<String>>) {
    let r = registry();
    let mut plain = XmlLoader::new(&r);
    plain.load_str(text, "plain.xml").unwrap();
    let mut rules = Substitutions::new();
    rules.add_rule("NoNodeIsNamedSo", Substitute::Node("AlwaysSuccess".into()));
    let mut general = XmlLoader::new(&r).substitute(rules);
    general.load_str(text, "general.xml").unwrap();
    (plain.build_main().unwrap(), general.build_main().unwrap())
}

#[test]
fn tree1111_is_built_alike_by_both_paths() {
    let text = std::fs::read_to_string(corpus("bench/tree1111.xml")).unwrap();
    let (plain, general) = both(&text);
    assert_eq!(plain.len(), 1111);
    assert_eq!(signature(&plain), signature(&general));
    assert_eq!(plain.structure_hash(), general.structure_hash());
}

#[test]
fn plain_elements_among_others_are_built_alike_by_both_paths() {
    // Plain registered conditions and built-ins beside named ones, ports, defaults,
    // scripts, a SubTree and a built-in whose ports are required.
    let text = r#"
        <root BTCPP_format="4" main_tree_to_execute="Main">
          <BehaviorTree ID="Main">
            <Sequence>
              <Succ/>
              <Succ name="named"/>
              <Fallback>
                <Fail/>
                <Inverter><Fail/></Inverter>
                <Succ _skipIf="false"/>
              </Fallback>
              <Produce out="{x}"/>
              <Repeat num_cycles="2"><Succ/></Repeat>
              <ReactiveSequence><Succ/><AlwaysSuccess/></ReactiveSequence>
              <SubTree ID="Child"/>
              <Parallel success_count="1"><Succ/><Fail/></Parallel>
            </Sequence>
          </BehaviorTree>
          <BehaviorTree ID="Child">
            <Fallback><Fail/><Say message="hi"/><Succ/></Fallback>
          </BehaviorTree>
        </root>"#;
    let (plain, general) = both(text);
    assert_eq!(signature(&plain), signature(&general));
    assert_eq!(plain.structure_hash(), general.structure_hash());
    // A registered condition keeps its type; a built-in its own.
    let succ = plain.ids().find(|&id| plain.name(id) == "Succ").unwrap();
    assert_eq!(plain.type_id(succ), "Succ");
    let fallback = plain
        .ids()
        .find(|&id| plain.name(id) == "Fallback")
        .unwrap();
    assert_eq!(plain.type_id(fallback), "Fallback");
}
