//! The search tree: node states, the edge into each node, cost-to-come and child links.
//!
//! Storage is struct-of-arrays with the agent positions of all nodes in one flat vector, so a
//! two-agent node costs 32 B of state + 32 B of control (θ_B, α, G_x, G_y) + 24 B of links,
//! period count and cost. The arrays grow by a quarter at a time rather than doubling, so the
//! slack stays small. Removed nodes (SST's pruning) go to a free list and their slots are reused.

use magbench_env::{Control, Vec2};

use crate::{Plan, Problem};

/// No node (the root's parent, the end of a child list).
pub const NONE: u32 = u32::MAX;

/// A tree of team states joined by (control, duration) edges.
#[derive(Debug, Clone)]
pub struct Tree {
    agents: usize,
    states: Vec<Vec2>,
    parent: Vec<u32>,
    control: Vec<[f64; 4]>,
    periods: Vec<u32>,
    cost: Vec<f64>,
    first_child: Vec<u32>,
    next_sibling: Vec<u32>,
    free: Vec<u32>,
}

impl Tree {
    /// A tree holding only the root `start` (node 0, cost 0).
    pub fn new(start: &[Vec2]) -> Self {
        let mut t = Tree {
            agents: start.len(),
            states: Vec::new(),
            parent: Vec::new(),
            control: Vec::new(),
            periods: Vec::new(),
            cost: Vec::new(),
            first_child: Vec::new(),
            next_sibling: Vec::new(),
            free: Vec::new(),
        };
        t.states.extend_from_slice(start);
        t.parent.push(NONE);
        t.control.push([0.0; 4]);
        t.periods.push(0);
        t.cost.push(0.0);
        t.first_child.push(NONE);
        t.next_sibling.push(NONE);
        t
    }

    /// Nodes in the tree (slots in use).
    pub fn len(&self) -> usize {
        self.parent.len() - self.free.len()
    }

    /// Always false: the root is never removed.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Number of slots, used or free (node ids are below this).
    pub fn slots(&self) -> usize {
        self.parent.len()
    }

    /// The state of node `i`.
    #[inline]
    pub fn state(&self, i: u32) -> &[Vec2] {
        let a = i as usize * self.agents;
        &self.states[a..a + self.agents]
    }

    /// Mutable state of node `i` (rewiring moves a node to where its new edge ends).
    #[inline]
    pub fn state_mut(&mut self, i: u32) -> &mut [Vec2] {
        let a = i as usize * self.agents;
        &mut self.states[a..a + self.agents]
    }

    /// The parent of node `i` ([`NONE`] for the root).
    #[inline]
    pub fn parent(&self, i: u32) -> u32 {
        self.parent[i as usize]
    }

    /// The control of the edge into node `i`.
    #[inline]
    pub fn control(&self, i: u32) -> Control {
        let [theta, alpha, gx, gy] = self.control[i as usize];
        Control {
            theta,
            alpha,
            grad: [gx, gy],
        }
    }

    /// The duration of the edge into node `i`, in control periods.
    #[inline]
    pub fn periods(&self, i: u32) -> u32 {
        self.periods[i as usize]
    }

    /// Cost-to-come of node `i`.
    #[inline]
    pub fn cost(&self, i: u32) -> f64 {
        self.cost[i as usize]
    }

    /// Sets the cost-to-come of node `i`.
    #[inline]
    pub fn set_cost(&mut self, i: u32, c: f64) {
        self.cost[i as usize] = c;
    }

    /// Adds a node reached from `parent` by `control` held for `periods` control periods.
    pub fn add(
        &mut self,
        parent: u32,
        state: &[Vec2],
        control: Control,
        periods: u32,
        cost: f64,
    ) -> u32 {
        debug_assert_eq!(state.len(), self.agents);
        let id = match self.free.pop() {
            Some(id) => {
                let i = id as usize;
                self.state_mut(id).copy_from_slice(state);
                self.parent[i] = parent;
                self.control[i] = stored(&control);
                self.periods[i] = periods;
                self.cost[i] = cost;
                self.first_child[i] = NONE;
                id
            }
            None => {
                let id = self.parent.len() as u32;
                self.reserve();
                self.states.extend_from_slice(state);
                self.parent.push(parent);
                self.control.push(stored(&control));
                self.periods.push(periods);
                self.cost.push(cost);
                self.first_child.push(NONE);
                self.next_sibling.push(NONE);
                id
            }
        };
        self.link(parent, id);
        id
    }

    /// Grows every array by a quarter when full (doubling would leave up to half unused).
    fn reserve(&mut self) {
        let len = self.parent.len();
        if len < self.parent.capacity() {
            return;
        }
        let more = (len / 4).max(64);
        self.states.reserve_exact(more * self.agents);
        self.parent.reserve_exact(more);
        self.control.reserve_exact(more);
        self.periods.reserve_exact(more);
        self.cost.reserve_exact(more);
        self.first_child.reserve_exact(more);
        self.next_sibling.reserve_exact(more);
    }

    fn link(&mut self, parent: u32, child: u32) {
        self.next_sibling[child as usize] = self.first_child[parent as usize];
        self.first_child[parent as usize] = child;
    }

    fn unlink(&mut self, parent: u32, child: u32) {
        let mut c = self.first_child[parent as usize];
        if c == child {
            self.first_child[parent as usize] = self.next_sibling[child as usize];
            return;
        }
        while c != NONE {
            let next = self.next_sibling[c as usize];
            if next == child {
                self.next_sibling[c as usize] = self.next_sibling[child as usize];
                return;
            }
            c = next;
        }
        debug_assert!(false, "node {child} is not a child of {parent}");
    }

    /// Gives node `i` a new incoming edge from `parent` (rewiring).
    pub fn reparent(&mut self, i: u32, parent: u32, control: Control, periods: u32) {
        self.unlink(self.parent[i as usize], i);
        let k = i as usize;
        self.parent[k] = parent;
        self.control[k] = stored(&control);
        self.periods[k] = periods;
        self.link(parent, i);
    }

    /// Every edge `(parent, child)` of the tree, children in slot order.
    pub fn edges(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        (1..self.parent.len() as u32).filter_map(|i| {
            let p = self.parent[i as usize];
            (p != NONE).then_some((p, i))
        })
    }

    /// The children of node `i`.
    pub fn children(&self, i: u32) -> Children<'_> {
        Children {
            tree: self,
            next: self.first_child[i as usize],
        }
    }

    /// True when node `i` has no children.
    #[inline]
    pub fn is_leaf(&self, i: u32) -> bool {
        self.first_child[i as usize] == NONE
    }

    /// Removes leaf `i` (not the root); its slot is reused by a later [`Tree::add`].
    pub fn remove_leaf(&mut self, i: u32) {
        assert!(
            i != 0 && self.is_leaf(i),
            "only non-root leaves are removed"
        );
        self.unlink(self.parent[i as usize], i);
        self.parent[i as usize] = NONE;
        self.free.push(i);
    }

    /// The nodes of the subtree under `i` (itself first), parents before children.
    pub fn subtree(&self, i: u32, out: &mut Vec<u32>) {
        out.clear();
        out.push(i);
        let mut k = 0;
        while k < out.len() {
            let mut c = self.first_child[out[k] as usize];
            while c != NONE {
                out.push(c);
                c = self.next_sibling[c as usize];
            }
            k += 1;
        }
    }

    /// The plan from the root to node `i`, by backtracking (the seed's computePlan).
    pub fn plan_to(&self, i: u32, problem: &Problem) -> Plan {
        let mut path = vec![i];
        let mut k = i;
        while self.parent(k) != NONE {
            k = self.parent(k);
            path.push(k);
        }
        path.reverse();
        let mut plan = Plan::at(self.state(path[0]));
        plan.flow = problem.model.flow;
        for &k in &path[1..] {
            plan.push(
                self.control(k),
                problem.periods(self.periods(k)),
                self.state(k).to_vec(),
            );
        }
        plan
    }

    /// Heap bytes held by the tree's arrays (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        self.states.capacity() * size_of::<Vec2>()
            + (self.parent.capacity() + self.periods.capacity() + self.first_child.capacity())
                * size_of::<u32>()
            + (self.next_sibling.capacity() + self.free.capacity()) * size_of::<u32>()
            + self.control.capacity() * size_of::<[f64; 4]>()
            + self.cost.capacity() * size_of::<f64>()
    }
}

/// The stored form of a control.
fn stored(u: &Control) -> [f64; 4] {
    [u.theta, u.alpha, u.grad[0], u.grad[1]]
}

/// Iterator over a node's children.
pub struct Children<'a> {
    tree: &'a Tree,
    next: u32,
}

impl Iterator for Children<'_> {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        if self.next == NONE {
            return None;
        }
        let c = self.next;
        self.next = self.tree.next_sibling[c as usize];
        Some(c)
    }
}
