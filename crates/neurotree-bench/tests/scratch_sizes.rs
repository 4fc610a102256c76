#[test]
fn sizes() {
    let bp = neurotree_bench::agent_tree();
    let crowd = neurotree_bench::agent_crowd(2, 1, neurotree::ManualClock::new());
    eprintln!(
        "nodes {} state {} slot {} inst {}",
        bp.len(),
        crowd.iter().next().unwrap().tree().state_bytes(),
        crowd.slot_bytes(),
        bp.instance_state_bytes()
    );
    eprintln!(
        "tree {} agent {}",
        std::mem::size_of::<neurotree::Tree<neurotree_bench::Agent>>(),
        std::mem::size_of::<Option<neurotree_bench::Agent>>()
    );
}
