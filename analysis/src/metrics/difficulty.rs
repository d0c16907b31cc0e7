//! The difficulty measures of a run's scenario ([`magbench_env::scenario::difficulty`]) as
//! `runs.csv` columns, declared once in a table like the metrics: each entry's column, label,
//! unit, the field of [`Difficulty`] it reads and whether the plots against difficulty use it
//! as an x axis. The measures belong to the scenario: a sweep measures each scenario once and
//! copies its [`Measures`] into every run of it; `runs.csv` writes them after the metric
//! columns (see `results::store`).

use super::slot::Slot;
use magbench_env::scenario::Scenario;
use magbench_env::scenario::difficulty::{Difficulty, measure};

/// Declares [`Measure`] (one variant per entry) and [`TABLE`] (the entries, in the same order).
macro_rules! measures {
    ($( $(#[doc = $doc:literal])+
        $id:ident($name:literal, $label:literal, $unit:literal, axis = $axis:literal)
        = $value:expr; )*) => {
        /// A difficulty measure of the table.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Measure {
            $( $(#[doc = $doc])+ $id, )*
        }

        impl Measure {
            /// Every measure, in column order.
            pub const ALL: &'static [Measure] = &[$(Measure::$id,)*];
        }

        /// Every measure's declaration, indexed by [`Measure`].
        pub static TABLE: [MeasureDef; Measure::ALL.len()] = [$(
            MeasureDef {
                column: concat!("difficulty_", $name),
                name: $name,
                label: $label,
                unit: $unit,
                value: $value,
                axis: $axis,
                doc: concat!($($doc, "\n"),+),
            },
        )*];
    };
}

/// One difficulty measure's declaration.
#[derive(Debug, Clone, Copy)]
pub struct MeasureDef {
    /// The `runs.csv` column: `difficulty_` and [`Self::name`].
    pub column: &'static str,
    /// The name in `magbench_env::scenario::difficulty::COLUMNS`, used in plot file names.
    pub name: &'static str,
    /// Short human name (plot axis).
    pub label: &'static str,
    /// Unit (`BL`, `deg`; empty for fractions, ratios and counts).
    pub unit: &'static str,
    /// The value of a measured scenario (`None`: undefined, e.g. no path).
    pub value: fn(&Difficulty) -> Option<f64>,
    /// An x axis of the plots against difficulty; false for the settings of the measurement
    /// (grid, the pair's width, the assumed clearance).
    pub axis: bool,
    /// The definition (the entry's doc comment).
    pub doc: &'static str,
}

impl MeasureDef {
    /// `label (unit)`, or the label of a unitless measure: a plot axis.
    pub fn axis_label(&self) -> String {
        if self.unit.is_empty() {
            self.label.to_string()
        } else {
            format!("{} ({})", self.label, self.unit)
        }
    }
}

measures! {
    /// Fraction of the world's area outside obstacles (the smallest over the legs' maps).
    FreeFraction("free_fraction", "free-space fraction", "", axis = true)
        = |d| Some(d.free_fraction);
    /// Grid cell side the measures used (BL).
    GridBl("grid_bl", "grid cell", "BL", axis = false) = |d| Some(d.grid_bl);
    /// The pair's turning width `r_min + 1` (BL).
    MinWidthBl("min_width_bl", "pair's turning width", "BL", axis = false)
        = |d| Some(d.min_width_bl);
    /// Clearance the centre-of-mass path keeps, `min_width_bl / 2` (BL).
    PathClearanceBl("path_clearance_bl", "assumed path clearance", "BL", axis = false)
        = |d| Some(d.path_clearance_bl);
    /// The narrowest passage between start and goal centroids (BL).
    NarrowestPassageBl("narrowest_passage_bl", "narrowest passage", "BL", axis = true)
        = |d| Some(d.narrowest_passage_bl);
    /// `narrowest_passage_bl / min_width_bl`: below 1 the pair cannot pass turning freely.
    PassageRatio("passage_ratio", "passage / pair's turning width", "", axis = true)
        = |d| Some(d.passage_ratio);
    /// Length of a shortest centre-of-mass path at the assumed clearance (BL; empty: none).
    PathLengthBl("path_length_bl", "shortest COM path length", "BL", axis = true)
        = |d| d.path_length_bl;
    /// Turns of that path (empty: no path).
    PathTurns("path_turns", "turns of the COM path", "", axis = true)
        = |d| d.path_turns.map(|t| t as f64);
    /// Total heading change along that path (degrees; empty: no path).
    PathTurningDeg("path_turning_deg", "heading change of the COM path", "deg", axis = true)
        = |d| d.path_turning_deg;
    /// Straight-line distance from the start centroid to the goal centroid (BL).
    CentroidMoveBl("centroid_move_bl", "centroid move", "BL", axis = true)
        = |d| Some(d.centroid_move_bl);
    /// Twice the RMS distance of the agents from their centroid at the start (BL).
    SpanStartBl("span_start_bl", "span at the start", "BL", axis = true)
        = |d| Some(d.span_start_bl);
    /// The same at the goal (BL).
    SpanGoalBl("span_goal_bl", "span at the goal", "BL", axis = true)
        = |d| Some(d.span_goal_bl);
    /// Rotation of the formation from start to goal, in (−180, 180] (degrees).
    RotationDeg("rotation_deg", "formation rotation", "deg", axis = true)
        = |d| Some(d.rotation_deg);
    /// RMS distance of the goal formation from the rotated start formation (BL).
    ShapeChangeBl("shape_change_bl", "shape change", "BL", axis = true)
        = |d| Some(d.shape_change_bl);
}

impl Measure {
    /// Its declaration.
    pub fn def(self) -> &'static MeasureDef {
        &TABLE[self as usize]
    }
}

/// The value of every difficulty measure of a run's scenario (`None`: an empty CSV cell,
/// undefined or not recorded, as in files of versions without these columns).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measures([Slot; Measure::ALL.len()]);

impl Default for Measures {
    fn default() -> Self {
        Measures([Slot::EMPTY; Measure::ALL.len()])
    }
}

impl Measures {
    /// The measures of `d`.
    pub fn from_difficulty(d: &Difficulty) -> Measures {
        let mut m = Measures::default();
        for k in Measure::ALL {
            m.set(*k, (k.def().value)(d));
        }
        m
    }

    /// Measures scenario `s` (see [`measure`]).
    pub fn of(s: &Scenario) -> Measures {
        Measures::from_difficulty(&measure(s))
    }

    /// The value of `k`.
    pub fn get(&self, k: Measure) -> Option<f64> {
        self.0[k as usize].get()
    }

    /// Sets the value of `k`.
    pub fn set(&mut self, k: Measure, v: Option<f64>) {
        self.0[k as usize] = Slot::new(v);
    }

    /// True when no measure has a value (a run of a file without the columns).
    pub fn is_empty(&self) -> bool {
        self.0.iter().all(|s| s.get().is_none())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use magbench_env::scenario::difficulty::COLUMNS;

    #[test]
    fn the_table_covers_every_measure_of_the_environment_in_order() {
        let names: Vec<&str> = Measure::ALL.iter().map(|m| m.def().name).collect();
        assert_eq!(names, COLUMNS);
        for m in Measure::ALL {
            let d = m.def();
            assert_eq!(d.column, format!("difficulty_{}", d.name));
            assert!(!d.doc.trim().is_empty());
        }
    }

    #[test]
    fn values_match_the_environments_text_columns() {
        let sc = Scenario::load("narrow-passage").unwrap();
        let d = measure(&sc);
        let m = Measures::from_difficulty(&d);
        for (k, (name, text)) in Measure::ALL.iter().zip(d.columns()) {
            assert_eq!(k.def().name, name);
            match m.get(*k) {
                Some(v) => {
                    let back: f64 = text.parse().unwrap();
                    assert!((v - back).abs() <= 5e-5, "{name}: {v} vs {text}");
                }
                None => assert!(text.is_empty(), "{name}"),
            }
        }
        let narrow = m.get(Measure::NarrowestPassageBl).unwrap();
        assert!((narrow - 3.0).abs() < 0.25, "{narrow}");
        assert!(!m.is_empty() && Measures::default().is_empty());
    }
}
