//! The drone mission example, flown on tokio's paused clock: the whole survey on a full
//! battery, and the failsafe taking over on half a battery.

#[allow(dead_code)] // `main` is the example's own.
#[path = "../../../examples/drone_mission.rs"]
mod drone_mission;

#[cfg(feature = "tokio")]
mod flights {
    use std::time::Duration;

    use super::drone_mission::{run, MissionConfig, Point};
    use neurotree::Status;

    #[tokio::test(start_paused = true)]
    async fn a_full_battery_flies_the_whole_survey() {
        let outcome = run(MissionConfig::default()).await;
        println!("{}", outcome.log.join("\n"));
        assert_eq!(outcome.status, Status::Success);
        assert_eq!(outcome.visited, [0, 1, 2]);
        assert_eq!(outcome.surveys, [(0, 2), (1, 0), (2, 3)]);
        assert_eq!(outcome.aborted_surveys, 0);
        assert!(!outcome.failsafe);
        assert_eq!(outcome.landed_at, Some(Point::new(0.0, 0.0, 0.0)));
        // 5 s climbing, 22 s between waypoints, 3 × 2 s surveying, 6 s home, 5 s down.
        assert_eq!(outcome.flight_time, Duration::from_secs(44));
        assert!(
            (outcome.battery_pct - 56.0).abs() < 1e-9,
            "{}",
            outcome.battery_pct
        );
        // One tick to start, one per 100 ms step of the 380 flown (each step's timer wakes
        // the tree), and 21 per survey: 20 periods, and the wake of the finished task.
        assert_eq!(outcome.ticks, 1 + 380 + 3 * 21);
    }

    #[tokio::test(start_paused = true)]
    async fn the_failsafe_aborts_the_survey_and_lands_at_home() {
        let outcome = run(MissionConfig::low_battery()).await;
        println!("{}", outcome.log.join("\n"));
        assert_eq!(outcome.status, Status::Failure);
        assert!(outcome.failsafe);
        assert_eq!(outcome.visited, [0, 1]);
        assert_eq!(outcome.surveys, [(0, 2)]);
        assert_eq!(outcome.aborted_surveys, 1);
        assert_eq!(outcome.landed_at, Some(Point::new(0.0, 0.0, 0.0)));
        // The reserve is passed at 22.3 s, during the second survey; then 10 s home
        // (50 m) and 5 s down.
        assert_eq!(outcome.flight_time, Duration::from_millis(37_300));
        assert!(
            (outcome.battery_pct - 12.7).abs() < 1e-9,
            "{}",
            outcome.battery_pct
        );
        assert!(outcome
            .log
            .iter()
            .any(|l| l.ends_with("FAILSAFE: battery 27.7% at the 27.75% reserve")));
        assert_eq!(outcome.ticks, 1 + (50 + 80 + 21 + 60 + 13) + (100 + 50));
    }

    #[tokio::test(start_paused = true)]
    async fn the_failsafe_stops_a_flight_where_it_is() {
        let config = MissionConfig {
            battery_pct: 40.0,
            reserve_pct: 13.25,
            ..MissionConfig::default()
        };
        let outcome = run(config).await;
        println!("{}", outcome.log.join("\n"));
        assert_eq!(outcome.status, Status::Failure);
        assert!(outcome.failsafe);
        assert_eq!(outcome.visited, [0, 1]);
        assert_eq!(outcome.surveys, [(0, 2), (1, 0)]);
        assert_eq!(outcome.aborted_surveys, 0);
        assert!(outcome
            .log
            .iter()
            .any(|l| l.ends_with("flight to waypoint 2 halted: hovering at (21.5, 30.0, 10.0)")));
        assert_eq!(outcome.landed_at, Some(Point::new(0.0, 0.0, 0.0)));
        // Halted at 26.8 s, 7.4 s home (36.9 m), 5 s down.
        assert_eq!(outcome.flight_time, Duration::from_millis(39_200));
    }
}
