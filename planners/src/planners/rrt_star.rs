//! stub
use crate::{Planner, PlannerResult, Problem};
/// RRT*.
#[derive(Debug, Clone, Default)]
pub struct RrtStar {
    informed: bool,
}
impl RrtStar {
    /// informed
    pub fn informed() -> Self {
        RrtStar { informed: true }
    }
}
impl Planner for RrtStar {
    fn name(&self) -> &str {
        if self.informed {
            "informed-rrt-star"
        } else {
            "rrt-star"
        }
    }
    fn solve(&mut self, _problem: &Problem) -> PlannerResult {
        todo!()
    }
}
