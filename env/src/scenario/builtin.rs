//! Built-in scenarios: the files in `scenarios/`, compiled in and addressable by name.

/// (name, TOML source) of every built-in scenario.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "micro-factory",
        include_str!("../../../scenarios/micro-factory.toml"),
    ),
    (
        "cargo-delivery",
        include_str!("../../../scenarios/cargo-delivery.toml"),
    ),
    (
        "open-field",
        include_str!("../../../scenarios/open-field.toml"),
    ),
    (
        "narrow-passage",
        include_str!("../../../scenarios/narrow-passage.toml"),
    ),
    ("trio-row", include_str!("../../../scenarios/trio-row.toml")),
    (
        "trio-triangle",
        include_str!("../../../scenarios/trio-triangle.toml"),
    ),
    (
        "trio-maze",
        include_str!("../../../scenarios/trio-maze.toml"),
    ),
    (
        "quad-square",
        include_str!("../../../scenarios/quad-square.toml"),
    ),
];

/// The TOML source of a built-in scenario.
pub fn builtin_source(name: &str) -> Option<&'static str> {
    BUILTIN.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

/// Names of the built-in scenarios.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN.iter().map(|(n, _)| *n).collect()
}
