//! A legend drawn as a strip of entries (symbol + text), usually below a chart so it never
//! hides data.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor;

use super::{PlotError, label_font};

/// The symbol of a legend entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Symbol {
    /// A line of this colour and stroke width.
    Line(RGBColor, u32),
    /// A filled band (e.g. a confidence band) of this colour.
    Band(RGBColor),
    /// A hollow square marker (starts).
    Square(RGBColor),
    /// A hollow circle (goal tolerances).
    Circle(RGBColor),
    /// A filled disk (agents).
    Disk(RGBColor),
    /// A series' line in its colour and dash with its marker, over a light band if `true`.
    Styled(super::style::Look, bool),
}

/// One legend entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Its symbol.
    pub symbol: Symbol,
    /// Its text.
    pub text: String,
}

impl Entry {
    /// A new entry.
    pub fn new(symbol: Symbol, text: impl Into<String>) -> Self {
        Entry {
            symbol,
            text: text.into(),
        }
    }
}

/// Height in pixels of a strip holding `entries` on a figure `width` px wide.
pub fn height(entries: &[Entry], width: u32) -> u32 {
    if entries.is_empty() {
        return 0;
    }
    rows(entries, width).len() as u32 * ROW + 8
}

const ROW: u32 = 26;
const SYMBOL_W: i32 = 30;

fn entry_width(e: &Entry) -> i32 {
    // ~9.5 px per character at 18 px DejaVu Sans, plus the symbol and a gap.
    SYMBOL_W + 8 + (e.text.chars().count() as f64 * 9.5).ceil() as i32 + 24
}

fn rows(entries: &[Entry], width: u32) -> Vec<Vec<&Entry>> {
    let mut rows: Vec<Vec<&Entry>> = vec![vec![]];
    let mut x = 10;
    for e in entries {
        let w = entry_width(e);
        if x + w > width as i32 && !rows.last().unwrap().is_empty() {
            rows.push(vec![]);
            x = 10;
        }
        rows.last_mut().unwrap().push(e);
        x += w;
    }
    rows
}

/// Draws `entries` in rows on `area` (typically the bottom strip of a figure).
pub fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
) -> Result<(), PlotError> {
    let (width, _) = area.dim_in_pixel();
    for (ri, row) in rows(entries, width).iter().enumerate() {
        let y = 4 + ri as i32 * ROW as i32 + ROW as i32 / 2;
        let mut x = 10;
        for e in row {
            let (x0, x1) = (x, x + SYMBOL_W);
            let xm = (x0 + x1) / 2;
            match e.symbol {
                Symbol::Line(c, w) => {
                    area.draw(&PathElement::new(vec![(x0, y), (x1, y)], c.stroke_width(w)))?;
                }
                Symbol::Band(c) => {
                    area.draw(&Rectangle::new(
                        [(x0, y - 7), (x1, y + 7)],
                        c.mix(0.3).filled(),
                    ))?;
                    area.draw(&PathElement::new(vec![(x0, y), (x1, y)], c.stroke_width(2)))?;
                }
                Symbol::Square(c) => {
                    area.draw(&Rectangle::new(
                        [(xm - 6, y - 6), (xm + 6, y + 6)],
                        c.stroke_width(2),
                    ))?;
                }
                Symbol::Circle(c) => area.draw(&Circle::new((xm, y), 7, c.stroke_width(2)))?,
                Symbol::Disk(c) => area.draw(&Circle::new((xm, y), 7, c.filled()))?,
                Symbol::Styled(look, band) => {
                    if band {
                        area.draw(&Rectangle::new(
                            [(x0, y - 7), (x1, y + 7)],
                            look.color.mix(0.12).filled(),
                        ))?;
                    }
                    super::style::draw_line(area, vec![(x0, y), (x1, y)], &look, 2)?;
                    super::style::draw_marker(area, (xm, y), &look, 4)?;
                }
            }
            let style = label_font().pos(text_anchor::Pos::new(
                text_anchor::HPos::Left,
                text_anchor::VPos::Center,
            ));
            area.draw(&Text::new(e.text.clone(), (x1 + 8, y), style))?;
            x += entry_width(e);
        }
    }
    Ok(())
}
