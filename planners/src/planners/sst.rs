//! stub
use crate::{Planner, PlannerResult, Problem};
/// SST.
#[derive(Debug, Clone, Default)]
pub struct Sst;
impl Planner for Sst {
    fn name(&self) -> &str {
        "sst"
    }
    fn solve(&mut self, _problem: &Problem) -> PlannerResult {
        todo!()
    }
}
