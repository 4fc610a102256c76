//! A reason given by a registered action in a tree loaded from XML reaches
//! `Tree::last_failure`, through the Fallback that tried it and the Retry that ran out.

use std::sync::Arc;

use neurotree::{ManualClock, Registry, Status, Tree, XmlLoader};

const XML: &str = r#"
<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="navigate">
      <Fallback name="follow_or_recover">
        <FollowPath name="follow"/>
        <RetryUntilSuccessful name="recover" num_attempts="2">
          <Spin name="spin"/>
        </RetryUntilSuccessful>
      </Fallback>
    </Sequence>
  </BehaviorTree>
</root>"#;

#[test]
fn a_registered_action_gives_its_reason_from_xml() {
    let mut registry = Registry::<()>::new();
    registry
        .register_action("FollowPath", vec![], |h| h.fail_with(106, "blocked"))
        .unwrap();
    registry
        .register_action("Spin", vec![], |h| h.fail_with(3, "collision ahead"))
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(XML, "reasons.xml").unwrap();
    let bp = Arc::new(loader.build_main().unwrap());
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
    let failure = tree.last_failure().unwrap();
    assert_eq!(
        failure.to_string(),
        "navigate\n\
         \x20 navigate/follow_or_recover\n\
         \x20   tried navigate/follow_or_recover/follow: blocked (error 106)\n\
         \x20   tried navigate/follow_or_recover/recover: collision ahead (error 3)\n\
         \x20   navigate/follow_or_recover/recover: gave up after 2 attempts\n\
         \x20     navigate/follow_or_recover/recover/spin: collision ahead (error 3)"
    );
    assert_eq!(failure.reason().unwrap().code(), 3);
}
