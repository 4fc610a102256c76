//! Nav2's runnable conditions (custom leaves) are conditions wherever a tree is read: in the
//! blueprint, in the SVG picture, in the model, as the editor lists them.

use neurotree::render::render_svg;
use neurotree::{Category, Registry, XmlLoader};

const TREE: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveFallback>
      <GoalUpdated name="new_goal"/>
      <GlobalUpdatedGoal name="global_goal"/>
      <RateController hz="1.0"><AlwaysSuccess name="act"/></RateController>
    </ReactiveFallback>
  </BehaviorTree>
</root>"#;

/// The group `neurotree show --format svg` draws for the node whose title starts with `path`.
fn group<'a>(svg: &'a str, path: &str) -> &'a str {
    svg.split("<g id=\"n")
        .find(|g| g.contains(&format!("<title>{path} (")))
        .unwrap_or_else(|| panic!("no node {path} in {svg}"))
}

#[test]
fn goal_updated_is_a_condition_in_the_blueprint_and_the_picture() {
    let mut registry = Registry::<()>::new();
    neurotree::nav2::register_controls(&mut registry).unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(TREE, "main.xml").unwrap();
    let bp = loader.build_main().unwrap();
    let category = |path: &str| bp.kind(bp.find(path).unwrap()).category();
    assert_eq!(category("ReactiveFallback/new_goal"), Category::Condition);
    assert_eq!(
        category("ReactiveFallback/global_goal"),
        Category::Condition
    );
    assert_eq!(
        category("ReactiveFallback/RateController/act"),
        Category::Action
    );

    let svg = render_svg(&bp, None);
    for path in ["ReactiveFallback/new_goal", "ReactiveFallback/global_goal"] {
        let g = group(&svg, path);
        assert!(g.contains("class=\"node condition\""), "{g}");
        // A pill: round ends of half the two-line box's height (an action's corners are 8).
        assert!(g.contains("rx=\"20\""), "{g}");
    }
    let act = group(&svg, "ReactiveFallback/RateController/act");
    assert!(
        act.contains("class=\"node action\"") && act.contains("rx=\"8\""),
        "{act}"
    );
}
