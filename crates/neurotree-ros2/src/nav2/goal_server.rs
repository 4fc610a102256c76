//! An action served one goal at a time, on ros2-client's plain `ActionServer`: the
//! bookkeeping that the navigator and the simulator's servers share.
//!
//! - A goal is accepted when it arrives; one that arrives while another runs preempts it
//!   (the old one ends Aborted), as Nav2's servers let a new goal replace the current one.
//! - A cancel request cancels the running goal. (ros2-client keeps the goal id of a cancel
//!   request to itself, so a request is taken as meant for the only goal there is.)
//! - Result requests wait for their goal's end; the last results are kept for requests that
//!   come late.
//! - The goals' statuses are published on every change, for clients that follow them.
//!
//! Nothing here blocks: [`GoalServer::poll`] reads what arrived and answers what can be.

use ros2_client::action::{GetResultResponse, GoalId, GoalStatusEnum, SendGoalResponse};
use ros2_client::action_msgs::{
    CancelGoalResponse, CancelGoalResponseEnum, GoalInfo, GoalStatus, GoalStatusArray,
};
use ros2_client::builtin_interfaces::Time;
use ros2_client::service::RmwRequestId;

use crate::{Ros2Error, RosAction, RosActionServer, RosNode};

/// Results kept for result requests still to come.
const KEPT_RESULTS: usize = 8;

/// What a client asked for since the last poll.
#[derive(Debug)]
pub(crate) enum Request<G> {
    /// A new goal, accepted and now the running one.
    Goal(G),
    /// The running goal is to be cancelled: end it with [`GoalServer::finish`].
    Cancel,
}

/// One goal at a time of action `A`; see the [module](self).
pub(crate) struct GoalServer<A: RosAction> {
    name: String,
    server: RosActionServer<A>,
    running: Option<GoalInfo>,
    waiting: Vec<(RmwRequestId, GoalId)>,
    ended: Vec<(GoalInfo, GetResultResponse<A::Result>)>,
}

impl<A: RosAction> GoalServer<A>
where
    A::Result: Default,
{
    /// Serves action `name` on `ros`.
    pub(crate) fn new(ros: &RosNode, name: &str) -> Result<Self, Ros2Error> {
        Ok(Self {
            name: name.to_owned(),
            server: ros.action_server::<A>(name)?,
            running: None,
            waiting: Vec::new(),
            ended: Vec::new(),
        })
    }

    /// Reads the requests that arrived, accepting goals and answering cancels; sends the
    /// results that were asked for and are known.
    pub(crate) fn poll(&mut self) -> Result<Vec<Request<A::Goal>>, Ros2Error> {
        let mut requests = Vec::new();
        let mut undecodable = 0;
        loop {
            let (id, sent) = match self.server.receive_goal() {
                Ok(Some(request)) => request,
                Ok(None) => break,
                // A goal in another layout (a client of another Nav2 release) cannot be
                // read, nor answered without its id: it is dropped, and the client's wait for
                // an answer times out. The bound keeps a reader that fails again and again
                // from holding the loop.
                Err(ros2_client::ReadError::Deserialization { .. }) if undecodable < 64 => {
                    undecodable += 1;
                    continue;
                }
                Err(e) => return Err(self.fail("goal")(e)),
            };
            if self.running.is_some() {
                // Preempted by the new goal.
                self.finish(GoalStatusEnum::Aborted, A::Result::default());
            }
            let stamp = Time::now();
            let response = SendGoalResponse {
                accepted: true,
                stamp,
            };
            self.server
                .send_goal_response(id, response)
                .map_err(self.fail("goal response"))?;
            self.running = Some(GoalInfo {
                goal_id: sent.goal_id,
                stamp,
            });
            self.publish_statuses();
            requests.retain(|r| !matches!(r, Request::Goal(..)));
            requests.push(Request::Goal(sent.goal));
        }
        while let Some((id, _)) = self
            .server
            .receive_cancel_request()
            .map_err(self.fail("cancel request"))?
        {
            let response = match &self.running {
                Some(goal) => {
                    requests.push(Request::Cancel);
                    CancelGoalResponse {
                        return_code: CancelGoalResponseEnum::None,
                        goals_canceling: vec![goal.clone()],
                    }
                }
                None => CancelGoalResponse {
                    return_code: CancelGoalResponseEnum::UnknownGoal,
                    goals_canceling: Vec::new(),
                },
            };
            self.server
                .send_cancel_response(id, response)
                .map_err(self.fail("cancel response"))?;
        }
        while let Some((id, request)) = self
            .server
            .receive_result_request()
            .map_err(self.fail("result request"))?
        {
            self.waiting.push((id, request.goal_id));
        }
        self.answer_result_requests();
        Ok(requests)
    }

    /// Sends feedback for the running goal.
    pub(crate) fn feedback(&self, feedback: A::Feedback) {
        if let Some(goal) = &self.running {
            // Feedback is best effort: a lost one is replaced by the next.
            let _ = self.server.send_feedback(goal.goal_id, feedback);
        }
    }

    /// Ends the running goal with `status` and `result`.
    pub(crate) fn finish(&mut self, status: GoalStatusEnum, result: A::Result) {
        let Some(goal) = self.running.take() else {
            return;
        };
        if self.ended.len() == KEPT_RESULTS {
            self.ended.remove(0);
        }
        self.ended
            .push((goal, GetResultResponse { status, result }));
        self.publish_statuses();
        self.answer_result_requests();
    }

    fn answer_result_requests(&mut self) {
        let ended = &self.ended;
        let server = &self.server;
        self.waiting.retain(|(id, goal_id)| {
            match ended.iter().find(|(goal, _)| goal.goal_id == *goal_id) {
                Some((_, response)) => {
                    // A client gone since it asked does not need the answer.
                    let _ = server.send_result(*id, response.clone());
                    false
                }
                None => true,
            }
        });
    }

    fn publish_statuses(&self) {
        let ended = self.ended.iter().map(|(goal, response)| GoalStatus {
            goal_info: goal.clone(),
            status: response.status,
        });
        let running = self.running.iter().map(|goal| GoalStatus {
            goal_info: goal.clone(),
            status: GoalStatusEnum::Executing,
        });
        let statuses = GoalStatusArray {
            status_list: ended.chain(running).collect(),
        };
        // Statuses are informative; results travel on their own service.
        let _ = self.server.send_goal_statuses(statuses);
    }

    fn fail<E: std::fmt::Debug>(&self, what: &'static str) -> impl Fn(E) -> Ros2Error + '_ {
        move |e| Ros2Error::Serve {
            kind: "action server",
            name: self.name.clone(),
            message: format!("{what}: {e:?}"),
        }
    }
}
