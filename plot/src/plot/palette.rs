//! Colours: one per agent (the seed's cyan and green for the first two), black for tracked
//! paths, and two colour-blind-safe families for series: Paul Tol's *bright* scheme for
//! planners and his *muted* scheme for trackers (P. Tol, "Colour schemes", SRON/EPS/TN/09-002).

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

/// Planner colours (Tol's bright scheme: blue, red, green, purple, cyan, yellow, grey); the
/// yellow comes late because it has the least contrast on white.
pub const PLANNERS: [RGBColor; 7] = [
    RGBColor(0x44, 0x77, 0xAA),
    RGBColor(0xEE, 0x66, 0x77),
    RGBColor(0x22, 0x88, 0x33),
    RGBColor(0xAA, 0x33, 0x77),
    RGBColor(0x66, 0xCC, 0xEE),
    RGBColor(0xCC, 0xBB, 0x44),
    RGBColor(0xBB, 0xBB, 0xBB),
];

/// Tracker colours (Tol's muted scheme, darker tones first: indigo, teal, wine, olive, rose,
/// sand, cyan, green).
pub const TRACKERS: [RGBColor; 8] = [
    RGBColor(0x33, 0x22, 0x88),
    RGBColor(0x44, 0xAA, 0x99),
    RGBColor(0x88, 0x22, 0x55),
    RGBColor(0x99, 0x99, 0x33),
    RGBColor(0xCC, 0x66, 0x77),
    RGBColor(0xDD, 0xCC, 0x77),
    RGBColor(0x88, 0xCC, 0xEE),
    RGBColor(0x11, 0x77, 0x33),
];

/// Series colours for other categories: the planners' family.
pub const SERIES: [RGBColor; 7] = PLANNERS;

/// The colour of series `i` (the planners' family).
pub fn series(i: usize) -> RGBColor {
    SERIES[i % SERIES.len()]
}

/// Tracked paths.
pub const TRACKED: RGBColor = RGBColor(0, 0, 0);
/// Obstacle fill.
pub const OBSTACLE: RGBColor = RGBColor(150, 150, 150);
/// Tree edges.
pub const TREE: RGBColor = RGBColor(200, 200, 200);
