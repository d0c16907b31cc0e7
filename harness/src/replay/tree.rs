//! A planner's search tree as data: every node's team state, its parent, and the control and
//! duration of the edge into it. `plan --tree FILE` writes it as JSON (format
//! `magbench-tree`, docs/replay.md); the replay page draws it projected on the team's centroid.

use std::path::Path;

use magbench_planners::tree::{NONE, Tree};
use magbench_planners::{Planner, Problem};
use serde::{Deserialize, Serialize};

/// The value of the `format` field of a tree file.
pub const FORMAT: &str = "magbench-tree";

/// One leg's tree with its nodes numbered 0.. in slot order (the root is node 0; slots a
/// planner freed, as SST's pruning does, are left out).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LegTree {
    /// The leg (1-based).
    pub leg: usize,
    /// Each node's team state: one `[x, y]` per agent (BL).
    pub states: Vec<Vec<[f64; 2]>>,
    /// Each node's parent (-1 for the root).
    pub parent: Vec<i64>,
    /// The control of the edge into each node: `[theta, alpha, gx, gy]` (rad, rad, T/m, T/m);
    /// zeros for the root.
    pub control: Vec<[f64; 4]>,
    /// The duration of the edge into each node (s); 0 for the root.
    pub duration_s: Vec<f64>,
    /// Each node's cost-to-come under the problem's objective.
    pub cost: Vec<f64>,
}

impl LegTree {
    /// The tree of `planner`'s last solve of `problem` (leg `leg`, 0-based), if it keeps one.
    pub fn of_planner(planner: &dyn Planner, problem: &Problem, leg: usize) -> Option<LegTree> {
        planner.tree().map(|t| LegTree::of(t, problem, leg))
    }

    /// `tree`, grown for `problem` (leg `leg`, 0-based).
    pub fn of(tree: &Tree, problem: &Problem, leg: usize) -> LegTree {
        let slots = tree.slots();
        // slot -> node number; the root and every slot with a parent are in use
        let mut id = vec![-1i64; slots];
        let mut used = vec![];
        for (s, slot) in id.iter_mut().enumerate() {
            if s == 0 || tree.parent(s as u32) != NONE {
                *slot = used.len() as i64;
                used.push(s as u32);
            }
        }
        let mut t = LegTree {
            leg: leg + 1,
            states: Vec::with_capacity(used.len()),
            parent: Vec::with_capacity(used.len()),
            control: Vec::with_capacity(used.len()),
            duration_s: Vec::with_capacity(used.len()),
            cost: Vec::with_capacity(used.len()),
        };
        for &s in &used {
            t.states
                .push(tree.state(s).iter().map(|p| [p.x, p.y]).collect());
            let p = tree.parent(s);
            t.parent.push(if p == NONE { -1 } else { id[p as usize] });
            let u = tree.control(s);
            t.control.push([u.theta, u.alpha, u.grad[0], u.grad[1]]);
            t.duration_s.push(problem.periods(tree.periods(s)));
            t.cost.push(tree.cost(s));
        }
        t
    }

    /// Nodes in the tree.
    pub fn nodes(&self) -> usize {
        self.parent.len()
    }

    /// The team's centroid at node `i`.
    pub fn centroid(&self, i: usize) -> [f64; 2] {
        let s = &self.states[i];
        let n = s.len().max(1) as f64;
        [
            s.iter().map(|p| p[0]).sum::<f64>() / n,
            s.iter().map(|p| p[1]).sum::<f64>() / n,
        ]
    }

    /// At most `max` edges `(parent centroid, child centroid)`, evenly chosen over the nodes.
    pub fn centroid_edges(&self, max: usize) -> Vec<([f64; 2], [f64; 2])> {
        let children: Vec<usize> = (0..self.nodes()).filter(|&i| self.parent[i] >= 0).collect();
        let stride = children.len().div_ceil(max.max(1)).max(1);
        children
            .iter()
            .step_by(stride)
            .map(|&i| (self.centroid(self.parent[i] as usize), self.centroid(i)))
            .collect()
    }
}

/// A tree file: the trees of every planned leg.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TreeFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// The format's version (1).
    pub version: u32,
    /// The scenario's name.
    pub scenario: String,
    /// The planner's name.
    pub planner: String,
    /// Agents in the team (the length of every state).
    pub agents: usize,
    /// One tree per planned leg (empty when the planner keeps no tree).
    pub legs: Vec<LegTree>,
}

impl TreeFile {
    /// The file of `legs`, planned by `planner` on `scenario` with `agents` agents.
    pub fn new(scenario: &str, planner: &str, agents: usize, legs: Vec<LegTree>) -> TreeFile {
        TreeFile {
            format: FORMAT.into(),
            version: 1,
            scenario: scenario.into(),
            planner: planner.into(),
            agents,
            legs,
        }
    }

    /// Writes it as JSON to `path`.
    pub fn write(&self, path: &Path) -> Result<(), crate::Error> {
        let text = serde_json::to_string(self).expect("a tree serializes");
        std::fs::write(path, text)
            .map_err(|e| crate::Error::Failed(format!("{}: {e}", path.display())))
    }
}

#[cfg(test)]
mod tests {
    use magbench_env::{Control, Vec2};
    use magbench_planners::PlanningSetup;

    use super::*;

    #[test]
    fn freed_slots_are_left_out_and_parents_renumbered() {
        let s = magbench_env::Scenario::load("open-field").unwrap();
        let problem = PlanningSetup::default().problem(&s, 0, None, 0);
        let start = [Vec2::new(1.0, 1.0), Vec2::new(3.0, 1.0)];
        let mut tree = Tree::new(&start);
        let u = Control {
            theta: 0.5,
            alpha: 0.0,
            grad: [0.1, -0.2],
        };
        let a = tree.add(0, &[Vec2::new(2.0, 1.0), Vec2::new(4.0, 1.0)], u, 3, 1.0);
        let b = tree.add(a, &[Vec2::new(2.0, 2.0), Vec2::new(4.0, 2.0)], u, 2, 2.0);
        let c = tree.add(0, &[Vec2::new(1.0, 2.0), Vec2::new(3.0, 2.0)], u, 1, 1.0);
        tree.add(c, &[Vec2::new(1.0, 3.0), Vec2::new(3.0, 3.0)], u, 4, 2.0);
        tree.remove_leaf(b);
        assert_eq!(tree.slots(), 5);
        let t = LegTree::of(&tree, &problem, 0);
        assert_eq!(t.nodes(), 4);
        assert_eq!(t.parent, [-1, 0, 0, 2]);
        assert_eq!(t.control[1], [0.5, 0.0, 0.1, -0.2]);
        assert_eq!(t.duration_s[3], problem.periods(4));
        assert_eq!(t.centroid(3), [2.0, 3.0]);
        assert_eq!(t.centroid_edges(2).len(), 2);
    }
}
