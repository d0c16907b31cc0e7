//! Per-group summaries of runs (scenario, planner, tracker, preset).
