//! Scenario generators: families of problems drawn from a few declared parameters and a seed.
//!
//! Each family is its own file: a struct of parameters declared with
//! [`declare_params!`](crate::declare_params) (so listing, `key=value` parsing, ranges and
//! error messages come from the declaration) and an `impl` [`Family`]; [`families`] names
//! them. Adding a family is its file plus its `mod` line and one [`Entry`] in [`families`].
//!
//! [`generate`] draws one problem: the family's [`Family::feasible`] refuses parameters that
//! cannot give a valid problem (naming the parameter and the reason), [`Family::build`]
//! draws a [`Draft`] from a ChaCha8 stream (seed `seed`, stream `index`: the same seed and
//! index give the same bytes, whatever the count), and the file is kept only if it passes the
//! scenario validation of `magbench scenario check` and a grid search finds a free corridor
//! for the team's centre of mass (see [`corridor_clearance`]).

mod clutter;
mod corridor;
mod place;
mod rooms;
mod serpentine;
mod short_moves;
mod team;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::freespace::FreeGrid;
use super::{Draft, Scenario, parse_scenario};
use crate::error::InputError;
use crate::math::{Vec2, centroid};
use crate::params::{ParamSet, apply};
use crate::physics::PhysicalParams;
use crate::registry::{Entry, Registry};

/// The version of the generators: it changes whenever a family draws differently from the
/// same parameters and seed. Every generated file names it in its header.
pub const GENERATOR_VERSION: u32 = 1;

/// Draws of one problem before a family gives up (a draw is discarded when the validation or
/// the corridor check refuses it).
pub const ATTEMPTS: usize = 20;

/// The random stream of a family.
pub type Rng = ChaCha8Rng;

/// Why a family's parameters cannot give a valid problem: the parameter and the reason.
#[derive(Debug, Clone, PartialEq)]
pub struct Refusal {
    /// The parameter's key.
    pub param: &'static str,
    /// Why.
    pub reason: String,
}

impl Refusal {
    /// A refusal of parameter `param` for `reason`.
    pub fn new(param: &'static str, reason: impl Into<String>) -> Self {
        Refusal {
            param,
            reason: reason.into(),
        }
    }
}

/// A family of generated problems.
pub trait Family: ParamSet {
    /// Refuses parameters that cannot give a valid problem under `physics`.
    fn feasible(&self, physics: &PhysicalParams) -> Result<(), Refusal>;
    /// Draws one problem from `rng` (name and header are filled in by [`generate`]).
    fn build(&self, rng: &mut Rng, physics: &PhysicalParams) -> Result<Draft, Refusal>;
    /// The parameter to name when no draw passes the checks in [`ATTEMPTS`] tries.
    fn hardest(&self) -> &'static str;
}

/// Every family, in the order `--list` shows them.
pub fn families() -> Registry<dyn Family> {
    type E = Entry<dyn Family>;
    let entries = [
        E::new(
            "serpentine",
            "k walls across the field with their gaps at alternate ends: the path grows as k",
            || Box::new(serpentine::Serpentine::default()),
        ),
        E::new(
            "corridor",
            "one corridor of a given width and length with right-angle bends",
            || Box::new(corridor::Corridor::default()),
        ),
        E::new(
            "clutter",
            "random polygons covering a given fraction of the field",
            || Box::new(clutter::Clutter::default()),
        ),
        E::new(
            "rooms",
            "a grid of rooms joined by doors along a random spanning tree",
            || Box::new(rooms::Rooms::default()),
        ),
        E::new(
            "short-moves",
            "a pair's relative move in open space: turn in place, swap, or shift",
            || Box::new(short_moves::ShortMoves::default()),
        ),
        E::new(
            "team",
            "N = 2…16 agents from one formation to another across an open field",
            || Box::new(team::Team::default()),
        ),
    ];
    Registry::of("family", entries).expect("the families' names are distinct and well formed")
}

/// One generated problem.
#[derive(Debug, Clone)]
pub struct Generated {
    /// The file name: the scenario name and `.toml`.
    pub file_name: String,
    /// The file's text (header comment, then the scenario).
    pub text: String,
    /// The validated scenario.
    pub scenario: Scenario,
}

/// The clearance (BL) the corridor check keeps the team's centre of mass from walls and
/// obstacles: the pair's turning clearance `(r_min + 1)/2` for two agents; for a team, the
/// farthest agent's distance from the centroid at start or goal plus its radius.
pub fn corridor_clearance(start: &[Vec2], goal: &[Vec2], physics: &PhysicalParams) -> f64 {
    if start.len() == 2 {
        return (physics.r_min + 1.0) / 2.0;
    }
    let reach = |s: &[Vec2]| {
        let c = centroid(s);
        s.iter().map(|p| (p - c).norm()).fold(0.0, f64::max)
    };
    reach(start).max(reach(goal)) + 0.5
}

/// The parameters of `family` (the defaults with `params` applied), checked; errors name
/// `source` and the field (`family`, `param.KEY`).
pub fn family(
    source: &str,
    family: &str,
    params: &[(String, String)],
) -> Result<Box<dyn Family>, InputError> {
    let mut f = families().lookup(source, family)?.make();
    apply(source, family, &mut *f, params)?;
    f.feasible(&PhysicalParams::default())
        .map_err(|r| InputError::new(source, format!("param.{}", r.param), r.reason))?;
    Ok(f)
}

/// The header comment of a generated file.
fn header(family: &str, f: &dyn Family, seed: u64, index: u64) -> String {
    let params: Vec<String> = f
        .params()
        .iter()
        .map(|p| format!("{}={}", p.name, p.value))
        .collect();
    let sets: String = params.iter().map(|p| format!(" --set {p}")).collect();
    format!(
        "Generated by magbench scenario generate (generator version {GENERATOR_VERSION}).\n\
         family {family}, seed {seed}, index {index}\n\
         params {}\n\
         again: magbench scenario generate {family}{sets} --seed {seed} --count {} --out DIR",
        params.join(" "),
        index + 1
    )
}

/// Generates problem `index` of `family` with `params` from `seed`, named
/// `FAMILY-sSEED-INDEX`. Errors name `source` (a file or `<command line>`), the field
/// (`family`, `param.KEY`) and the reason.
pub fn generate(
    source: &str,
    family_name: &str,
    params: &[(String, String)],
    seed: u64,
    index: u64,
) -> Result<Generated, InputError> {
    let name = format!("{family_name}-s{seed}-{index}");
    generate_named(source, family_name, params, seed, index, &name)
}

/// [`generate`], with the scenario (and its file) named `name`; the name does not change the
/// draw.
pub fn generate_named(
    source: &str,
    family_name: &str,
    params: &[(String, String)],
    seed: u64,
    index: u64,
    name: &str,
) -> Result<Generated, InputError> {
    let f = family(source, family_name, params)?;
    let physics = PhysicalParams::default();
    let mut rng = Rng::seed_from_u64(seed);
    rng.set_stream(index);
    let name = name.to_string();
    let file_name = format!("{name}.toml");
    let head = header(family_name, &*f, seed, index);
    let mut last = String::new();
    for _ in 0..ATTEMPTS {
        let mut draft = f
            .build(&mut rng, &physics)
            .map_err(|r| InputError::new(source, format!("param.{}", r.param), r.reason))?;
        draft.name = name.clone();
        let text = draft.to_toml(&head);
        match parse_scenario(&text, &file_name) {
            Ok(scenario) => match check(&scenario, &physics) {
                Ok(()) => {
                    return Ok(Generated {
                        file_name,
                        text,
                        scenario,
                    });
                }
                Err(e) => last = e.to_string(),
            },
            Err(e) => last = e.to_string(),
        }
    }
    Err(InputError::new(
        source,
        format!("param.{}", f.hardest()),
        format!("{family_name}: no valid problem in {ATTEMPTS} draws (the last: {last})"),
    ))
}

/// Why a drawn problem is thrown away.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Unsolvable {
    /// The start already lies inside the goal.
    #[error("the start is already inside the goal")]
    StartInGoal,
    /// A grid search finds no corridor for the centre of mass.
    #[error("no corridor for the centre of mass at clearance {clearance:.3} BL")]
    NoCorridor {
        /// The clearance searched at (BL).
        clearance: f64,
    },
}

/// The checks beyond the file's validation: the start is not already in the goal, and a grid
/// search finds a corridor for the centre of mass at [`corridor_clearance`].
fn check(s: &Scenario, physics: &PhysicalParams) -> Result<(), Unsolvable> {
    let goal = s.final_goal();
    if goal.contains(&s.start) {
        return Err(Unsolvable::StartInGoal);
    }
    let clearance = corridor_clearance(&s.start, &goal.agents, physics);
    FreeGrid::new(&s.world)
        .grid_path(centroid(&s.start), centroid(&goal.agents), clearance)
        .map(|_| ())
        .ok_or(Unsolvable::NoCorridor { clearance })
}

/// Every family's name, summary and parameters with their defaults.
pub fn list() -> String {
    let mut s = String::new();
    for e in families().iter() {
        s += &format!("{}\n    {}\n", e.name(), e.summary());
        for p in e.make().params() {
            s += &p.listing_line([12, 8, 22]);
        }
    }
    s
}

#[cfg(test)]
mod tests;
