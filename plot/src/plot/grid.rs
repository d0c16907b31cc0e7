//! Cell grids: panels side by side, each a table of rows × columns whose cells are shaded by a
//! fraction in [0, 1] and carry a short text (e.g. the formation study's success rates).

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{Figure, PlotError, label_font, tick_font, title_font};

/// Side of one cell (px).
const CELL: u32 = 58;
/// Width of the row labels (px).
const ROW_LABELS: u32 = 80;
/// Height of a panel's title and column labels (px).
const HEAD: u32 = 62;
/// Height of the figure's title (px).
const TITLE: u32 = 40;
/// Height of the note under the panels (px).
const FOOT: u32 = 34;
/// Gap between panels (px).
const GAP: u32 = 24;

/// One cell: its shade (a fraction in [0, 1]; NaN leaves it grey) and its text.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// The fraction that sets the shade.
    pub fraction: f64,
    /// Text drawn in the cell.
    pub text: String,
}

/// One panel: a title and a table of cells (`None`: no data, left blank).
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// Panel title.
    pub title: String,
    /// Row labels, top to bottom.
    pub rows: Vec<String>,
    /// Column labels, left to right.
    pub columns: Vec<String>,
    /// `cells[row][column]`.
    pub cells: Vec<Vec<Option<Cell>>>,
}

/// Panels of cell tables side by side, with a title and a note.
#[derive(Debug, Clone, PartialEq)]
pub struct CellGrid {
    /// Figure title.
    pub title: String,
    /// What the rows and the columns are (drawn in each panel's corner).
    pub corner: String,
    /// The panels, left to right.
    pub panels: Vec<Panel>,
    /// A line under the panels (what the shade and the text mean).
    pub note: String,
}

impl Panel {
    fn width(&self) -> u32 {
        ROW_LABELS + CELL * self.columns.len().max(1) as u32
    }

    fn height(&self) -> u32 {
        HEAD + CELL * self.rows.len().max(1) as u32
    }
}

/// The shade of fraction `f`: white at 0 to a saturated blue at 1; grey when not a number.
fn shade(f: f64) -> RGBColor {
    if !f.is_finite() {
        return RGBColor(200, 200, 200);
    }
    let f = f.clamp(0.0, 1.0);
    let mix = |a: f64, b: f64| (a + (b - a) * f).round() as u8;
    RGBColor(mix(255.0, 33.0), mix(255.0, 102.0), mix(255.0, 172.0))
}

impl Figure for CellGrid {
    fn size(&self) -> (u32, u32) {
        let w: u32 = self.panels.iter().map(|p| p.width() + GAP).sum::<u32>() + GAP;
        let h = self.panels.iter().map(Panel::height).max().unwrap_or(HEAD);
        (w.max(400), TITLE + h + FOOT)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let centre = Pos::new(HPos::Center, VPos::Center);
        let left = Pos::new(HPos::Left, VPos::Center);
        let (w, h) = root.dim_in_pixel();
        root.draw(&Text::new(
            self.title.clone(),
            (w as i32 / 2, TITLE as i32 / 2),
            title_font().pos(centre),
        ))?;
        let mut x0 = GAP as i32;
        for p in &self.panels {
            let y0 = TITLE as i32;
            root.draw(&Text::new(
                p.title.clone(),
                (x0 + p.width() as i32 / 2, y0 + 12),
                label_font().pos(centre),
            ))?;
            root.draw(&Text::new(
                self.corner.clone(),
                (x0, y0 + HEAD as i32 - 16),
                tick_font().pos(left),
            ))?;
            let cx = |c: usize| x0 + ROW_LABELS as i32 + (c as u32 * CELL) as i32;
            let cy = |r: usize| y0 + HEAD as i32 + (r as u32 * CELL) as i32;
            for (c, name) in p.columns.iter().enumerate() {
                root.draw(&Text::new(
                    name.clone(),
                    (cx(c) + CELL as i32 / 2, y0 + HEAD as i32 - 16),
                    tick_font().pos(centre),
                ))?;
            }
            for (r, name) in p.rows.iter().enumerate() {
                root.draw(&Text::new(
                    name.clone(),
                    (x0, cy(r) + CELL as i32 / 2),
                    tick_font().pos(left),
                ))?;
                for c in 0..p.columns.len() {
                    let (a, b) = (
                        (cx(c), cy(r)),
                        (cx(c) + CELL as i32 - 2, cy(r) + CELL as i32 - 2),
                    );
                    let Some(cell) = p.cells.get(r).and_then(|row| row.get(c)).cloned().flatten()
                    else {
                        root.draw(&Rectangle::new(
                            [a, b],
                            RGBColor(235, 235, 235).stroke_width(1),
                        ))?;
                        continue;
                    };
                    root.draw(&Rectangle::new([a, b], shade(cell.fraction).filled()))?;
                    root.draw(&Rectangle::new(
                        [a, b],
                        RGBColor(190, 190, 190).stroke_width(1),
                    ))?;
                    let ink = if cell.fraction.is_finite() && cell.fraction > 0.6 {
                        WHITE
                    } else {
                        BLACK
                    };
                    root.draw(&Text::new(
                        cell.text,
                        (cx(c) + CELL as i32 / 2 - 1, cy(r) + CELL as i32 / 2 - 1),
                        tick_font().color(&ink).pos(centre),
                    ))?;
                }
            }
            x0 += (p.width() + GAP) as i32;
        }
        root.draw(&Text::new(
            self.note.clone(),
            (GAP as i32, (h - FOOT / 2) as i32),
            tick_font().pos(left),
        ))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_cells_blanks_and_the_note() {
        let dir = tempfile::tempdir().unwrap();
        let fig = CellGrid {
            title: "t".into(),
            corner: "start \\ goal".into(),
            panels: vec![Panel {
                title: "N = 3".into(),
                rows: vec!["row".into(), "ring".into()],
                columns: vec!["ring".into(), "grid".into()],
                cells: vec![
                    vec![
                        Some(Cell {
                            fraction: 1.0,
                            text: "3/3".into(),
                        }),
                        None,
                    ],
                    vec![
                        Some(Cell {
                            fraction: f64::NAN,
                            text: "n/a".into(),
                        }),
                        Some(Cell {
                            fraction: 0.0,
                            text: "0/3".into(),
                        }),
                    ],
                ],
            }],
            note: "shade: fraction solved".into(),
        };
        let files = super::super::save(&fig, &dir.path().join("grid")).unwrap();
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        for t in ["N = 3", "3/3", "0/3", "n/a", "fraction solved"] {
            assert!(svg.contains(t), "{t}");
        }
        assert_eq!(shade(0.0), RGBColor(255, 255, 255));
        assert_eq!(shade(1.0), RGBColor(33, 102, 172));
    }
}
