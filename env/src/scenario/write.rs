//! Writing scenarios: a [`Draft`] (what a generator builds) as the plain TOML that
//! [`Scenario::load`](super::Scenario::load) reads.

use crate::math::Vec2;
use crate::plant::Medium;
use crate::world::Obstacle;

/// A single-goal scenario before validation: what a generator builds and [`Draft::to_toml`]
/// writes. Physics is the default preset's.
#[derive(Debug, Clone, PartialEq)]
pub struct Draft {
    /// Scenario name.
    pub name: String,
    /// Free text.
    pub description: String,
    /// World width (BL).
    pub width: f64,
    /// World height (BL).
    pub height: f64,
    /// Obstacles.
    pub obstacles: Vec<Obstacle>,
    /// The medium (`[medium]`), when the scenario sets one.
    pub medium: Option<Medium>,
    /// Start position per agent (BL).
    pub start: Vec<Vec2>,
    /// Goal centre per agent (BL).
    pub goal: Vec<Vec2>,
    /// Goal tolerance (BL).
    pub tolerance: f64,
}

/// A number as TOML writes it: the shortest text that reads back to the same `f64`, always
/// with a decimal point or an exponent (so it stays a float).
fn num(x: f64) -> String {
    format!("{x:?}")
}

fn point(p: Vec2) -> String {
    format!("[{}, {}]", num(p.x), num(p.y))
}

fn points(ps: &[Vec2]) -> String {
    let v: Vec<String> = ps.iter().map(|p| point(*p)).collect();
    format!("[{}]", v.join(", "))
}

/// A TOML basic string.
fn string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out += "\\\"",
            '\\' => out += "\\\\",
            '\n' => out += "\\n",
            c if c.is_control() => out += &format!("\\u{:04X}", c as u32),
            c => out.push(c),
        }
    }
    out + "\""
}

impl Draft {
    /// The scenario file: `header` as comment lines (each prefixed `# `), then the fields in a
    /// fixed order. The same draft always gives the same bytes.
    pub fn to_toml(&self, header: &str) -> String {
        let mut s = String::new();
        for line in header.lines() {
            s += &format!("# {line}\n").replace("# \n", "#\n");
        }
        s += &format!("name = {}\n", string(&self.name));
        s += &format!("description = {}\n\n", string(&self.description));
        s += &format!(
            "[world]\nwidth = {}\nheight = {}\n",
            num(self.width),
            num(self.height)
        );
        for o in &self.obstacles {
            s += "\n[[world.obstacles]]\n";
            s += &match o {
                Obstacle::Polygon(v) => format!("polygon = {}\n", points(v)),
                Obstacle::Circle { center, radius } => format!(
                    "circle = {{ center = {}, radius = {} }}\n",
                    point(*center),
                    num(*radius)
                ),
            };
        }
        if let Some(m) = &self.medium {
            #[derive(serde::Serialize)]
            struct WithMedium<'a> {
                medium: &'a Medium,
            }
            s += "\n";
            s += &toml::to_string(&WithMedium { medium: m }).expect("a medium serialises");
        }
        s += &format!("\n[start]\nagents = {}\n", points(&self.start));
        s += &format!(
            "\n[goal]\nagents = {}\ntolerance = {}\n",
            points(&self.goal),
            num(self.tolerance)
        );
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::DisturbancePreset;
    use crate::scenario::parse_scenario;

    #[test]
    fn a_draft_reads_back_as_the_same_scenario() {
        let d = Draft {
            name: "t \"q\"".into(),
            description: "a\\b".into(),
            width: 20.0,
            height: 10.5,
            obstacles: vec![
                Obstacle::Polygon(vec![
                    Vec2::new(9.0, 0.0),
                    Vec2::new(11.0, 0.0),
                    Vec2::new(10.0, 4.125),
                ]),
                Obstacle::Circle {
                    center: Vec2::new(10.0, 8.0),
                    radius: 1.0,
                },
            ],
            medium: Some(DisturbancePreset::hardware().medium),
            start: vec![Vec2::new(3.0, 5.0), Vec2::new(5.0, 5.0)],
            goal: vec![Vec2::new(15.0, 5.0), Vec2::new(17.1, 5.3)],
            tolerance: 0.5,
        };
        let text = d.to_toml("line one\n\nline three");
        assert!(
            text.starts_with("# line one\n#\n# line three\nname"),
            "{text}"
        );
        let s = parse_scenario(&text, "t").unwrap();
        assert_eq!(s.name, d.name);
        assert_eq!(s.description, d.description);
        assert_eq!(s.world.obstacles, d.obstacles);
        assert_eq!((s.world.width, s.world.height), (20.0, 10.5));
        assert_eq!(s.start, d.start);
        assert_eq!(s.legs[0].goal.agents, d.goal);
        assert_eq!(s.medium, d.medium);
    }
}
