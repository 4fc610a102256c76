//! AlwaysSuccess and AlwaysFailure: leaves with a fixed outcome, for stubs and tests.
//!
//! - **AlwaysSuccess**: Success, every tick.
//! - **AlwaysFailure**: Failure, every tick.

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn fixed_outcomes() {
        let (mut tree, _) = build(|b| b.always_success("s"));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        let (mut tree, _) = build(|b| b.always_failure("f"));
        assert_eq!(tick(&mut tree), Ok(Status::Failure));
    }
}
