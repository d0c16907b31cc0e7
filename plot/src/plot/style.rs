//! How a series looks: a colour from its family (planners or trackers), a dash pattern and a
//! marker, so that lines drawn on top of each other (e.g. `rrt-star` under
//! `informed-rrt-star`) stay distinguishable in colour, in grey and for colour-blind readers.

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::palette;

/// The family a series belongs to; each has its own colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Planning-only configurations (Tol's bright colours, solid first).
    Planner,
    /// Tracked configurations (Tol's muted colours, dashed first).
    Tracker,
}

/// A dash pattern.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dash {
    /// A continuous line.
    Solid,
    /// Long dashes.
    Dashed,
    /// Short dots.
    Dotted,
}

/// A marker drawn at staggered points along a line and in the legend.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// A hollow circle.
    Circle,
    /// A filled triangle.
    Triangle,
    /// A hollow square.
    Square,
    /// A cross.
    Cross,
    /// A filled disk.
    Disk,
}

/// How one series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Look {
    /// Its colour.
    pub color: RGBColor,
    /// Its dash pattern.
    pub dash: Dash,
    /// Its marker.
    pub marker: Marker,
}

const MARKERS: [Marker; 5] = [
    Marker::Circle,
    Marker::Triangle,
    Marker::Square,
    Marker::Cross,
    Marker::Disk,
];

/// The look of series `i` of `family`: colours in the family's order, markers cycling with a
/// different period than the dashes, so neighbours differ in all three.
pub fn look(family: Family, i: usize) -> Look {
    let (color, dashes): (RGBColor, [Dash; 3]) = match family {
        Family::Planner => (
            palette::PLANNERS[i % palette::PLANNERS.len()],
            [Dash::Solid, Dash::Dashed, Dash::Dotted],
        ),
        Family::Tracker => (
            palette::TRACKERS[i % palette::TRACKERS.len()],
            [Dash::Dashed, Dash::Solid, Dash::Dotted],
        ),
    };
    Look {
        color,
        dash: dashes[i % dashes.len()],
        marker: MARKERS[i % MARKERS.len()],
    }
}

/// The looks of `n` series of one family.
pub fn looks(family: Family, n: usize) -> Vec<Look> {
    (0..n).map(|i| look(family, i)).collect()
}

/// Draws a polyline of backend pixel coordinates in `look`'s colour and dash, `width` px wide.
pub fn draw_line<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    pts: Vec<(i32, i32)>,
    look: &Look,
    width: u32,
) -> Result<(), super::PlotError> {
    let style = look.color.stroke_width(width);
    match look.dash {
        Dash::Solid => area.draw(&PathElement::new(pts, style))?,
        Dash::Dashed => area.draw(&DashedPathElement::new(pts, 9, 5, style))?,
        Dash::Dotted => area.draw(&DashedPathElement::new(pts, 2, 4, style))?,
    }
    Ok(())
}

/// Draws `look`'s marker centred on pixel `(x, y)`, `r` px in radius.
pub fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (x, y): (i32, i32),
    look: &Look,
    r: i32,
) -> Result<(), super::PlotError> {
    let c = look.color;
    match look.marker {
        Marker::Circle => area.draw(&Circle::new((x, y), r, c.stroke_width(2)))?,
        Marker::Disk => area.draw(&Circle::new((x, y), r, c.filled()))?,
        Marker::Triangle => area.draw(&Polygon::new(
            vec![(x, y - r - 1), (x - r - 1, y + r), (x + r + 1, y + r)],
            c.filled(),
        ))?,
        Marker::Square => area.draw(&Rectangle::new(
            [(x - r, y - r), (x + r, y + r)],
            c.stroke_width(2),
        ))?,
        Marker::Cross => {
            area.draw(&PathElement::new(
                vec![(x - r, y - r), (x + r, y + r)],
                c.stroke_width(2),
            ))?;
            area.draw(&PathElement::new(
                vec![(x - r, y + r), (x + r, y - r)],
                c.stroke_width(2),
            ))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_differ_and_families_do_not_share_colours() {
        for f in [Family::Planner, Family::Tracker] {
            let l = looks(f, 6);
            for w in l.windows(2) {
                assert_ne!(w[0].color, w[1].color);
                assert_ne!(w[0].dash, w[1].dash);
                assert_ne!(w[0].marker, w[1].marker);
            }
        }
        for p in palette::PLANNERS {
            assert!(!palette::TRACKERS.contains(&p), "{p:?}");
        }
        assert_eq!(look(Family::Tracker, 0).dash, Dash::Dashed);
    }
}
