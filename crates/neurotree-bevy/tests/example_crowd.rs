//! The crowd example, small: its last line parses, and every agent-frame is in exactly
//! one behaviour.

#[path = "../examples/crowd.rs"]
#[allow(dead_code)]
mod crowd;

#[test]
fn the_crowd_examples_last_line_counts_every_agent_frame_once() {
    let (agents, frames) = (400, 600);
    let mut progress = Vec::new();
    let (tally, ms) = crowd::run(agents, frames, &mut progress).unwrap();
    let line = crowd::summary(agents, frames, tally, ms);
    let json: serde_json::Value = serde_json::from_str(&line).unwrap();
    let count = |key: &str| json[key].as_u64().unwrap();
    assert_eq!((count("agents"), count("frames")), (400, 600));
    assert!(json["ms_per_frame"].as_f64().is_some());
    // Resting agents sleep: fewer are ticked per frame than there are agents.
    let awake = json["awake_per_frame"].as_f64().unwrap();
    assert!(awake > 0.0 && awake < 400.0, "{line}");
    let behaviours = ["patrol", "chase", "flee", "regroup", "rest"].map(count);
    assert_eq!(behaviours.iter().sum::<u64>(), 400 * 600);
    // The target crosses the field: some agents see it, chase it, are hurt and flee, and
    // walk back home; those it is far from rest.
    assert!(behaviours.iter().all(|&n| n > 0), "{line}");
    let progress = String::from_utf8(progress).unwrap();
    assert_eq!(
        progress.lines().filter(|l| l.starts_with("frame")).count(),
        10
    );
}
