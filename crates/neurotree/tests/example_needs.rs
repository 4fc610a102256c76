//! The needs example: the villager eats, sleeps and works in turn, never starves, and the
//! hysteresis makes it switch less.

#[path = "../../../examples/needs.rs"]
#[allow(dead_code)]
mod needs;

#[test]
fn the_villager_eats_sleeps_and_works_and_hysteresis_means_fewer_switches() {
    let steady = needs::run(0.2, 400).unwrap();
    let count = |what: &str| steady.did.iter().filter(|d| **d == what).count();
    assert_eq!(steady.did.len(), 400);
    assert!(count("eat") > 0 && count("sleep") > 0 && count("work") > 0);
    // Work is chosen most of the time, and the needs never run away.
    assert!(count("work") > 200, "{:?}", steady.did);
    assert!(steady.hunger < 0.8 && steady.fatigue < 0.8);
    let jumpy = needs::run(0.0, 400).unwrap();
    assert!(
        needs::switches(&steady.did) < needs::switches(&jumpy.did),
        "{} switches with hysteresis, {} without",
        needs::switches(&steady.did),
        needs::switches(&jumpy.did)
    );
}
