//! `rooms`: the field split into a grid of rooms by thin walls, joined by one door per edge
//! of a random spanning tree (a maze of rooms); start in a corner room, goal in the room
//! farthest from it through the doors.

use std::collections::VecDeque;

use rand::RngExt;

use super::place::{pair_in_box, passage, rect};
use super::{Family, Refusal, Rng};
use crate::declare_params;
use crate::params::Reals;
use crate::physics::PhysicalParams;
use crate::scenario::Draft;
use crate::world::Obstacle;

declare_params! {
    /// The parameters of `rooms`.
    #[derive(Debug, Clone)]
    pub struct Rooms {
        /// Field width (BL).
        #[param("width", Reals::closed(8.0, 500.0))]
        pub width: f64 = 30.0,
        /// Field height (BL).
        #[param("height", Reals::closed(8.0, 500.0))]
        pub height: f64 = 20.0,
        /// Number of rooms (laid out as the grid columns × rows = rooms closest to square rooms).
        #[param("rooms", 2..=200)]
        pub rooms: usize = 4,
        /// Width of each door (BL).
        #[param("door", Reals::closed(0.5, 50.0))]
        pub door: f64 = 3.0,
        /// Thickness of the walls (BL).
        #[param("wall", Reals::closed(0.1, 5.0))]
        pub wall: f64 = 0.5,
    }
}

/// Free wall (BL) kept at each end of a door.
const DOOR_END: f64 = 0.25;

impl Rooms {
    /// The grid (columns, rows) with columns × rows = rooms whose rooms are closest to square.
    fn grid(&self) -> (usize, usize) {
        (1..=self.rooms)
            .filter(|c| self.rooms.is_multiple_of(*c))
            .map(|c| (c, self.rooms / c))
            .min_by(|a, b| {
                let skew = |(c, r): (usize, usize)| {
                    ((self.width / c as f64) / (self.height / r as f64))
                        .ln()
                        .abs()
                };
                skew(*a).total_cmp(&skew(*b))
            })
            .expect("rooms ≥ 2 has a divisor")
    }

    /// The smallest room side that holds a door with its wall ends.
    fn smallest_side(&self) -> f64 {
        self.door + self.wall + 2.0 * DOOR_END
    }
}

impl Family for Rooms {
    fn feasible(&self, physics: &PhysicalParams) -> Result<(), Refusal> {
        passage("door", "a door", self.door, physics)?;
        let (c, r) = self.grid();
        let side = (self.width / c as f64).min(self.height / r as f64);
        if side < self.smallest_side() {
            return Err(Refusal::new(
                "rooms",
                format!(
                    "{} rooms do not fit in a {} x {} BL field: as a {c} x {r} grid their rooms are {side:.2} BL across, \
                     less than the {:.2} BL a {} BL door needs (door + wall + 2 x {DOOR_END} BL)",
                    self.rooms,
                    self.width,
                    self.height,
                    self.smallest_side(),
                    self.door
                ),
            ));
        }
        Ok(())
    }

    fn build(&self, rng: &mut Rng, physics: &PhysicalParams) -> Result<Draft, Refusal> {
        let (nc, nr) = self.grid();
        let (sx, sy) = (self.width / nc as f64, self.height / nr as f64);
        let t = self.wall;
        let id = |c: usize, r: usize| r * nc + c;
        // a random spanning tree by depth-first search from room 0
        let mut door = std::collections::BTreeSet::new();
        let mut seen = vec![false; nc * nr];
        let mut stack = vec![0usize];
        seen[0] = true;
        while let Some(&room) = stack.last() {
            let (c, r) = (room % nc, room / nc);
            let mut next = Vec::new();
            if c > 0 {
                next.push(id(c - 1, r));
            }
            if c + 1 < nc {
                next.push(id(c + 1, r));
            }
            if r > 0 {
                next.push(id(c, r - 1));
            }
            if r + 1 < nr {
                next.push(id(c, r + 1));
            }
            next.retain(|n| !seen[*n]);
            if next.is_empty() {
                stack.pop();
                continue;
            }
            let n = next[rng.random_range(0..next.len())];
            seen[n] = true;
            door.insert((room.min(n), room.max(n)));
            stack.push(n);
        }
        // a wall between two rooms, along x (vertical) or y, with its door if the tree has one
        let mut obstacles: Vec<Obstacle> = Vec::new();
        let mut wall =
            |rng: &mut Rng, a: usize, b: usize, vertical: bool, at: f64, lo: f64, hi: f64| {
                let (lo, hi) = ((lo - t / 2.0).max(0.0), hi + t / 2.0);
                let piece = |p: f64, q: f64| {
                    if vertical {
                        rect(at - t / 2.0, p, at + t / 2.0, q)
                    } else {
                        rect(p, at - t / 2.0, q, at + t / 2.0)
                    }
                };
                if door.contains(&(a.min(b), a.max(b))) {
                    let half = self.door / 2.0;
                    let margin = t + DOOR_END + half;
                    let centre = rng.random_range(lo + margin..=(hi - margin).max(lo + margin));
                    obstacles.push(piece(lo, centre - half));
                    obstacles.push(piece(centre + half, hi));
                } else {
                    obstacles.push(piece(lo, hi));
                }
            };
        for r in 0..nr {
            for c in 1..nc {
                let (lo, hi) = (r as f64 * sy, ((r + 1) as f64 * sy).min(self.height));
                wall(rng, id(c - 1, r), id(c, r), true, c as f64 * sx, lo, hi);
            }
        }
        for r in 1..nr {
            for c in 0..nc {
                let (lo, hi) = (c as f64 * sx, ((c + 1) as f64 * sx).min(self.width));
                wall(rng, id(c, r - 1), id(c, r), false, r as f64 * sy, lo, hi);
            }
        }
        // the goal room: the farthest from room 0 through the doors (the last found)
        let mut depth = vec![usize::MAX; nc * nr];
        let mut queue = VecDeque::from([0usize]);
        depth[0] = 0;
        let mut far = 0;
        while let Some(room) = queue.pop_front() {
            far = room;
            for &(a, b) in &door {
                let other = if a == room {
                    b
                } else if b == room {
                    a
                } else {
                    continue;
                };
                if depth[other] == usize::MAX {
                    depth[other] = depth[room] + 1;
                    queue.push_back(other);
                }
            }
        }
        let inside = |room: usize| {
            let (c, r) = ((room % nc) as f64, (room / nc) as f64);
            (
                c * sx + t / 2.0,
                r * sy + t / 2.0,
                (c + 1.0) * sx - t / 2.0,
                (r + 1.0) * sy - t / 2.0,
            )
        };
        Ok(Draft {
            name: String::new(),
            description: format!(
                "rooms: {} rooms ({nc} x {nr}) in a {} x {} BL field, {} BL doors, {t} BL walls; goal {} doors away",
                self.rooms, self.width, self.height, self.door, depth[far]
            ),
            width: self.width,
            height: self.height,
            obstacles,
            medium: None,
            start: pair_in_box(rng, inside(0), physics),
            goal: pair_in_box(rng, inside(far), physics),
            tolerance: 0.5,
        })
    }

    fn hardest(&self) -> &'static str {
        "door"
    }
}
