//! A crowd of 100,000 served to pages a page at a time: the agents listed from their ids,
//! searched, paged, one watched by choice; a choice of an agent the crowd has not is
//! refused.

use crate::common;

use std::sync::Arc;

use common::{get, post};
use neurotree::crowd::Crowd;
use neurotree::crowd_studio::watched_frame;
use neurotree::prelude::*;
use neurotree_studio::{Studio, StudioOptions};
use serde_json::{json, Value};

const AGENTS: usize = 100_000;

fn ids(page: &Value) -> Vec<String> {
    page["agents"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["id"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn a_crowd_of_100000_is_listed_a_page_at_a_time_searched_and_one_chosen() {
    let idle = Blueprint::<()>::builder()
        .always_success("idle")
        .build_shared()
        .unwrap();
    let mut crowd = Crowd::new(ManualClock::new()).with_threads(1).unwrap();
    for _ in 0..AGENTS {
        crowd.add(Arc::clone(&idle), ());
    }
    let studio = Studio::serve(StudioOptions::default(), Registry::new).unwrap();
    let addr = studio.addr();
    // Before a crowd is watched, the pages are told there is none.
    assert_eq!(get(addr, "/api/agents").json(), json!({"crowd": false}));
    let mut watch = studio.watch_crowd("idlers");
    watched_frame(&mut crowd, &mut watch).unwrap();

    let first = get(addr, "/api/agents?limit=50");
    let page = first.json();
    assert_eq!(page["total"], AGENTS);
    assert_eq!(page["matches"], AGENTS);
    assert_eq!(
        ids(&page),
        (0..50).map(|i| i.to_string()).collect::<Vec<_>>()
    );
    assert_eq!(page["watched"]["id"], "0");
    // A page of 50 is a few kilobytes, not the crowd.
    assert!(first.body.len() < 4096, "{} bytes", first.body.len());

    // The last page.
    let last = get(addr, "/api/agents?offset=99990&limit=50").json();
    assert_eq!(
        ids(&last),
        (99_990..AGENTS).map(|i| i.to_string()).collect::<Vec<_>>()
    );
    // At most 200 to a page, whatever is asked.
    assert_eq!(
        ids(&get(addr, "/api/agents?limit=100000").json()).len(),
        200
    );

    // Searched: the ids holding 4242, in order, paged.
    let holding: Vec<String> = (0..AGENTS)
        .map(|i| i.to_string())
        .filter(|s| s.contains("4242"))
        .collect();
    let found = get(addr, "/api/agents?q=4242&limit=10").json();
    assert_eq!(found["matches"], holding.len());
    assert_eq!(ids(&found), holding[..10]);
    let next = get(addr, "/api/agents?q=4242&offset=10&limit=10").json();
    assert_eq!(ids(&next), holding[10..20]);

    // One chosen: watched from the next frame.
    assert_eq!(
        post(addr, "/api/agents/watch", &json!({"id": "64242"})).status,
        200
    );
    watched_frame(&mut crowd, &mut watch).unwrap();
    assert_eq!(watch.watched(), Some("64242"));
    assert_eq!(
        get(addr, "/api/agents?limit=1").json()["watched"]["id"],
        "64242"
    );
    // An agent the crowd has not: refused, with why; the one watched stays.
    let refused = post(addr, "/api/agents/watch", &json!({"id": "100000"}));
    assert_eq!(refused.status, 404);
    assert!(refused.json()["error"]
        .as_str()
        .unwrap()
        .contains("no agent `100000`"));
    watched_frame(&mut crowd, &mut watch).unwrap();
    assert_eq!(watch.watched(), Some("64242"));
}

#[test]
fn an_agent_watched_that_leaves_an_empty_crowd_is_no_longer_shown_watched() {
    let idle = Blueprint::<()>::builder()
        .always_success("idle")
        .build_shared()
        .unwrap();
    let mut crowd = Crowd::new(ManualClock::new());
    let only = crowd.add(idle, ());
    let studio = Studio::serve(StudioOptions::default(), Registry::new).unwrap();
    let mut watch = studio.watch_crowd("one");
    watched_frame(&mut crowd, &mut watch).unwrap();
    assert_eq!(
        get(studio.addr(), "/api/agents").json()["watched"]["id"],
        "0"
    );
    crowd.remove(only).unwrap();
    watched_frame(&mut crowd, &mut watch).unwrap();
    assert_eq!(watch.watched(), None);
    let page = get(studio.addr(), "/api/agents").json();
    assert_eq!(page["total"], 0);
    assert_eq!(page["watched"], Value::Null, "{page}");
    assert_eq!(page["awake"], Value::Null, "{page}");
}
