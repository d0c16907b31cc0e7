//! Colours: one per agent (the seed's cyan and green for the first two), black for tracked paths.

use plotters::style::RGBColor;

/// Agent colours in order; agent `i` uses `AGENTS[i % AGENTS.len()]`.
pub const AGENTS: [RGBColor; 8] = [
    RGBColor(0, 170, 220),  // cyan
    RGBColor(20, 160, 60),  // green
    RGBColor(200, 40, 160), // magenta
    RGBColor(240, 140, 0),  // orange
    RGBColor(40, 70, 200),  // blue
    RGBColor(200, 30, 30),  // red
    RGBColor(120, 60, 170), // purple
    RGBColor(130, 90, 40),  // brown
];

/// The colour of agent `i`.
pub fn agent(i: usize) -> RGBColor {
    AGENTS[i % AGENTS.len()]
}

/// Series colours for planners and other categories (colour-blind friendly, Okabe–Ito).
pub const SERIES: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(213, 94, 0),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(240, 228, 66),
    RGBColor(0, 0, 0),
];

/// The colour of series `i`.
pub fn series(i: usize) -> RGBColor {
    SERIES[i % SERIES.len()]
}

/// Tracked paths.
pub const TRACKED: RGBColor = RGBColor(0, 0, 0);
/// Obstacle fill.
pub const OBSTACLE: RGBColor = RGBColor(150, 150, 150);
/// Tree edges.
pub const TREE: RGBColor = RGBColor(200, 200, 200);
